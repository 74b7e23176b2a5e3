//! The work at one vertex of a camera path, while its BSDF exists: next-event estimation (or
//! resampled next-event estimation, [`super::resampled`]), manifold next-event estimation and
//! the light subpaths' connections, then the BSDF sample the path goes on with (or both lobes,
//! [`super::lobe_split`]). The loop around it is [`PathTracer::trace`] in `mod.rs`.

use super::{PathState, PathTracer, Step, Vertex, VertexOutcome, caustics, refracted};
use crate::sampler::PathSampler;
use glam::Vec2;
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{Bsdf, BsdfContext, BsdfSample, SampledWavelengths};

impl PathTracer<'_> {
    /// Next-event estimation, light-subpath connections and BSDF sampling at one vertex, while
    /// the BSDF exists.
    pub(super) fn scatter<W: Weight, L: caustics::LightWeight<W>>(
        &self,
        v: &Vertex,
        state: &PathState<W>,
        arrival: caustics::Arrival,
        light: &caustics::LightSubpath<L>,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
    ) -> VertexOutcome<W>
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        let flags = v.bsdf.flags();
        // The path samples the BSDF at every vertex it samples a light from.
        let mut light_ref = self.light_ref(v, flags, true);
        light_ref.resampled = self.resampling_applies(v, &light_ref);

        // Random numbers: a vertex with a smooth lobe takes five (light choice, light point,
        // lobe, direction), a purely delta one only its lobe choice (it samples no light and
        // needs no direction), so the sampler's structured dimensions reach the smooth vertices
        // behind glass and mirrors. The count is a function of the path, as it must be.
        let smooth = flags.has_smooth();
        let manifold_here = self.manifold_applies(state);
        let mut nee = W::ZERO;
        if smooth {
            let u_sel = sampler.next_1d();
            let u_light = sampler.next_2d();
            // What the walk through glass needs of the path, only where it can take place.
            let path = self.refracted_nee.then_some(refracted::PathContext {
                depth: state.depth,
                arrival,
                chain: state.chain,
            });
            nee = self.next_event(
                v,
                &light_ref,
                state.beta,
                u_sel,
                u_light,
                wl,
                (1.0, 1.0),
                path.as_ref(),
            );
            if manifold_here {
                // Spectral paths only (`manifold` is off in polarized mode).
                let c = self.manifold_next_event(v, u_sel, u_light, wl);
                nee += state.beta * W::from_spectrum(c);
            }
            if !light.is_empty() {
                let c: W = self.connect_light_vertices(v.bsdf, v.si, v.wi, state.depth, light, wl);
                nee += state.beta * c;
            }
        }

        let u_lobe = sampler.next_1d();
        let u_dir = if smooth {
            sampler.next_2d()
        } else {
            Vec2::splat(0.5)
        };
        // After a delta lobe, a smooth sample here needs the light tracer's density of the
        // reverse direction for the MIS ratio.
        let want_reverse = self.traces_caustics() && state.after_delta();
        if let Some(pair) = self.lobe_pair(v, u_lobe, u_dir, wl, want_reverse) {
            return VertexOutcome {
                nee,
                light_ref,
                manifold_here,
                step: Step::Split(pair),
            };
        }
        let ctx = BsdfContext::radiance();
        let sample = v
            .bsdf
            .sample_weight(&ctx, v.wi, u_lobe, u_dir, wl)
            .filter(|bs| {
                bs.weight.intensity().is_finite()
                    && !bs.weight.is_black()
                    && (bs.flags.is_delta() || bs.pdf > 0.0)
            })
            .map(|bs| BsdfSample {
                weight: bs.weight.local_to_world(&v.si.shading),
                ..bs
            });
        let reverse_pdf = match &sample {
            Some(bs) if want_reverse && !bs.flags.is_delta() => {
                v.bsdf.pdf(&BsdfContext::importance(), bs.wo, v.wi, wl)
            }
            _ => 0.0,
        };
        VertexOutcome {
            nee,
            light_ref,
            manifold_here,
            step: Step::Sampled { sample, reverse_pdf },
        }
    }
}
