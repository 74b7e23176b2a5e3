//! Resampled next-event estimation at glossy metal under an environment map (beyond Mitsuba;
//! the `path` parameter `ris_candidates`).
//!
//! # Why
//!
//! Mitsuba's material previews light a rough metal object (`bsdf_roughconductor_copper`:
//! Beckmann α = 0.1) with an environment map alone. At such a vertex the path tracer takes one
//! light sample and one BSDF sample and weighs them by the power heuristic, but neither follows
//! the integrand f·cos θ·L: the map's densities (its luminance, or its product with the clamped
//! cosine) spread over the hemisphere where the lobe is a few degrees wide, so the light sample
//! rarely lands in the lobe and its weight is small where it does; the BSDF sample follows the
//! lobe but is blind to the map's bright windows inside it. The product of the two is what a
//! single direction should be drawn from.
//!
//! # The estimator (resampled importance sampling, Talbot, Cline and Egbert 2005)
//!
//! Draw `M` candidate directions ω₁ … ω_M from a density p that is cheap to sample, weigh each by
//! w_j = p̂(ω_j)/p(ω_j) for a positive target p̂ that is cheap to evaluate and close to the
//! integrand, pick one, ω_k, with probability w_k/Σw_j, and trace one shadow ray towards it:
//!
//! `⟨L_direct⟩ = f(ω_k)·cos θ_k·L(ω_k)·V(ω_k) / p̂(ω_k) · (1/M)·Σ_j w_j`
//!
//! is unbiased for ∫ f·cos θ·L·V dω wherever p̂ > 0 covers the integrand's support and p > 0
//! covers p̂'s (Talbot et al. 2005, §3; Bitterli et al. 2020, eq. 5, "unbiased contribution
//! weight"). Its variance falls towards that of sampling p̂ itself as `M` grows, for the price of
//! `M` cheap candidates and one shadow ray.
//!
//! Here, at a single-scattering `roughconductor` with incident direction ωi (cos θi > 0; below,
//! where it applies):
//!
//! * the candidates are reflections of microfacet normals drawn ∝ D(m)·cos θm (all normals,
//!   Walter et al. 2007: one logarithm and a sine and cosine each, where the visible normals'
//!   Beckmann sampler inverts an error function; on lanes, below), ω = 2(ωi·m)m − ωi, so
//!   p(ω) = D(m)·cos θm/(4 ωi·m);
//! * the target is the lobe without its Fresnel factor times the map's coarse luminance L̃
//!   ([`EnvMapLight::resampling_luminance`]: 128 × 128 octahedral cells, positive wherever the
//!   map is not black, and at least a tenth of the light in every direction):
//!   p̂(ω) = D(m)·G(ωi, ω, m)/(4 cos θi)·L̃(ω), so that D cancels in the candidates' weights,
//!   w = G·(ωi·m)/(cos θi·cos θm)·L̃(ω);
//! * the chosen direction is evaluated exactly: the full BSDF (Fresnel at every wavelength,
//!   tints, textures), the map's bilinear spectral radiance and the shadow ray's visibility
//!   (through thin sheets, as for a light sample).
//!
//! The candidates take the light sample's random numbers: the 2D light point shifted by
//! multiples of the R2 sequence's generator (Roberts 2018; a rank-1 lattice, so the candidates of
//! one vertex are spread evenly over the square, and a pixel's samples stay stratified in the
//! first), and the light choice's number selects among them (where one light is chosen per
//! vertex, what is left of it once the map is chosen; where every light is sampled, the other
//! lights' samples take the same 2D point). The sampler's dimensions per vertex are unchanged.
//!
//! # Where it applies, and MIS
//!
//! At a vertex of the path tracer ([`PathTracer::resampling_applies`]) whose BSDF is one
//! single-scattering `roughconductor` seen from its front (cos θi > 0), or a `twosided` whose
//! side facing ωi is one (its back is resampled in the mirrored frame, z ↦ −z, in which the
//! tree evaluates it; `SurfaceBsdf::single_rough_conductor`), with both roughnesses at
//! most [`MAX_RESAMPLED_ALPHA`] = 0.15, in a scene with one `envmap` (beside any other lights),
//! unless `narrow_lobes` leaves the map to BSDF sampling there (cheaper, and as good where the
//! lobe resolves the map alone).
//!
//! There the estimator takes the map's turn of next-event estimation (whenever the map is
//! chosen, divided by the probability of choosing it, or always where every light is sampled at
//! each vertex; the other lights keep their light samples) and owns the map's light arriving
//! straight at the vertex: the path's own BSDF sample from it, if it leaves the scene (possibly
//! through `thindielectric` sheets or null surfaces, which the shadow ray crosses too), adds
//! none of the map's ([`LightRef::resampled`], [`Lights::le_escaped`]). The map's light arriving
//! through smooth glass is not direct light for the shadow ray (glass blocks it), so the BSDF
//! sample that refracts its way out keeps it whole: refracted next-event estimation does not
//! start from such a vertex towards the map, and the map's density from there reads as 0
//! ([`PathTracer::straight_light_pdf`] through [`Lights::le_escaped`]); towards other lights it
//! does, as from any vertex. The `direct` integrator, polarized renders and `volpath` where the
//! scene has media keep the light sample and the BSDF sample (`volpath` without media is the
//! path tracer, and resamples).
//!
//! Wider lobes keep them too. Measured under `museum.exr` (a copper sphere, then a copper
//! floor, the pixel variance with 8 candidates over that without): 0.43–0.58 (sphere) and
//! 0.82–0.88 (floor) for α = 0.06–0.15, 0.90–1.06 at 0.2, 1.18–1.33 at 0.3 and 2.0–2.4 at 0.5:
//! eight candidates from a wide lobe cover it thinly, where the map's product with the cosine
//! (the light sample) follows it well.
//!
//! The candidates are drawn and weighed on lanes, all of a vertex's at once ([`Candidates`]:
//! 16 lanes with AVX-512, 8 with AVX2, the same numbers at every width); one at a time, in
//! scalar code, their logarithms, sines and table lookups had cost about 12 % of the copper
//! preview's CPU time (2.14 s against 1.88 s, 16 spp, one thread).
//!
//! Measured on the copper preview (`bench/RESULTS.md`): relMSE −20 % with 8 candidates (16 spp,
//! one thread, eight seeds against the 16384-spp reference; 4 candidates −13 %, 16 −22 %), for
//! 7 % more CPU time than without resampling (16 candidates: 10 %; medians of six runs on an
//! AVX-512 host), most of it the shadow ray, which a sample in the lobe traces where a light
//! sample outside it stopped at f = 0.
//!
//! [`EnvMapLight::resampling_luminance`]: crate::emitter::infinite::EnvMapLight::resampling_luminance
//! [`LightRef::resampled`]: crate::emitter::LightRef::resampled
//! [`Lights::le_escaped`]: crate::emitter::Lights::le_escaped

use super::{PathTracer, Vertex};
use crate::emitter::{EnvMapLight, Light, LightRef, ResamplingLookup};
use crate::material::{Material, RoughConductorMaterial, TwoSidedMaterial};
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::{SurfaceBsdf, twosided};
use gonio_core::frame::Frame;
use gonio_core::lanes::{self, F32s, Isa, LaneKernel, Vec3s};
use gonio_core::math::floor;
use gonio_core::microfacet::MicrofacetDistribution;
use gonio_core::rng::ONE_MINUS_EPSILON;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{BsdfContext, SampledWavelengths};

/// The widest lobe resampled, as the larger of its roughnesses α_u, α_v: wider lobes keep the
/// light sample and the BSDF sample (module docs: measured, resampling's eight candidates lose
/// to them on a sphere from α = 0.2, on a floor from 0.3).
pub const MAX_RESAMPLED_ALPHA: f32 = 0.15;

/// The most candidates (`ris_candidates` is at most this).
pub const MAX_CANDIDATES: u32 = 64;

/// The generator of the R2 sequence (1/φ₂, 1/φ₂²), φ₂ the plastic number: candidate j takes the
/// light point shifted by j times it.
const R2: Vec2 = Vec2::new(0.754_877_7, 0.569_840_3);

/// True when `material` may put a single-scattering `roughconductor` alone on a side of a
/// vertex: it is one, or a `twosided` with one on either side
/// ([`SurfaceBsdf::single_rough_conductor`]). (`bumpmap` and `normalmap` add a perturbed frame
/// to the tree, which that does not look through.)
fn may_resample(material: &Material) -> bool {
    let conductor = |m: &Material| {
        m.get::<RoughConductorMaterial>()
            .is_some_and(|c| !c.model.multiple_scattering)
    };
    conductor(material)
        || material
            .get::<TwoSidedMaterial>()
            .is_some_and(|t| conductor(&t.front) || t.back.as_ref().is_some_and(conductor))
}

impl PathTracer<'_> {
    /// Builds the map's table for resampling now, before the render's threads ask for it, where
    /// the scene may resample: one `envmap` among its lights and a material that may put a
    /// `roughconductor` alone at a vertex ([`may_resample`]). Elsewhere a table would cost its build for nothing
    /// (45–53 ms for a 512 × 256 map), or is built by its first use.
    pub(super) fn prepare_resampling(&self, materials: &[Material]) {
        if let Some((_, map)) = self.resampled_map()
            && materials.iter().any(may_resample)
        {
            map.prepare_resampling();
        }
    }

    /// The map resampled next-event estimation samples, and its index among the lights: the
    /// scene's `envmap`, if it has one and only one, and only with candidates to draw.
    fn resampled_map(&self) -> Option<(usize, &EnvMapLight)> {
        let i = self.lights.sole_envmap().filter(|_| self.ris_candidates > 0)?;
        match &self.lights.lights()[i] {
            Light::EnvMap(map) => Some((i, map)),
            _ => None,
        }
    }

    /// True when resampled next-event estimation lights `v` (module docs), given where lights are
    /// sampled from there (`r`, which says whether `narrow_lobes` leaves the lights to BSDF
    /// sampling).
    pub(super) fn resampling_applies(&self, v: &Vertex, r: &LightRef) -> bool {
        self.resampled_map()
            .is_some_and(|(i, _)| !self.lights.left_to_bsdf(r, i))
            && v.bsdf
                .single_rough_conductor(v.wi)
                .is_some_and(|(lobe, _)| lobe.alpha_u.max(lobe.alpha_v) <= MAX_RESAMPLED_ALPHA)
    }

    /// The map's direct light at `v` by resampled importance sampling (module docs): β·f·cos θ·L·V
    /// over the target, times the candidates' mean weight. `u` shifts into the candidates,
    /// `u_sel` picks one.
    pub(super) fn resampled_next_event<W: Weight>(
        &self,
        v: &Vertex,
        beta: W,
        u_sel: f32,
        u: Vec2,
        wl: &SampledWavelengths,
    ) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        // What `resampling_applies` checked, whose `LightRef` sent the vertex here.
        let (Some((lobe, back)), Some((_, map))) =
            (v.bsdf.single_rough_conductor(v.wi), self.resampled_map())
        else {
            debug_assert!(false, "resampled next-event estimation where it does not apply");
            return W::ZERO;
        };
        // The back of a `twosided` reflects in the mirrored frame (z ↦ −z): the candidates are
        // drawn there, above its surface, as for a front.
        let mirror = |w: Vec3| if back { twosided::flip(w) } else { w };
        let shading = &v.si.shading;
        let frame = Frame {
            n: if back { -shading.n } else { shading.n },
            ..*shading
        };
        let wi = mirror(v.wi);
        let m_count = self.ris_candidates.min(MAX_CANDIDATES) as usize;
        // The candidates, all at once on lanes: their normals and weights w = p̂/p.
        let mut normals = [Vec3::ZERO; MAX_CANDIDATES as usize];
        let mut weights = [0.0f32; MAX_CANDIDATES as usize];
        lanes::dispatch(Candidates {
            lobe,
            wi,
            u,
            frame: &frame,
            light: map.resampling_lookup(),
            normals: &mut normals[..m_count],
            weights: &mut weights[..m_count],
        });
        let Some((k, w_sum)) = choose(&weights[..m_count], u_sel) else {
            return W::ZERO;
        };
        // The chosen one, and the candidates' density p = D(m)·cos θm/(4 ωi·m) there.
        let (m, w) = (normals[k], weights[k]);
        let cos_im = wi.dot(m);
        let wo_lobe = 2.0 * cos_im * m - wi;
        let wo = mirror(wo_lobe);
        let pdf = lobe.d(m) * m.z / (4.0 * cos_im);
        if !(w > 0.0 && pdf > 0.0 && pdf.is_finite()) {
            return W::ZERO;
        }
        let ctx = BsdfContext::radiance();
        let f: W = v.bsdf.eval_weight(&ctx, v.wi, wo, wl).local_to_world(shading);
        if f.is_black() {
            return W::ZERO;
        }
        let dir = shading.to_world(wo);
        let le = map.le(dir, wl);
        if le.is_black() {
            return W::ZERO;
        }
        let t: W = self.visibility(v.si.spawn_ray(dir), wl, false);
        if t.is_black() {
            return W::ZERO;
        }
        // f·cos θ·L·V / p̂ · Σw/M, with p̂ = w·p at the chosen candidate.
        (beta * f).through_then_source(t, le) * (wo_lobe.z * w_sum / (m_count as f32 * w * pdf))
    }
}

/// The candidates of one vertex (module docs), computed on lanes ([`lanes::dispatch`]: 16 at a
/// time with AVX-512, 8 with AVX2): candidate j's normal m_j, drawn ∝ D(m)·cos θm from the point
/// `u` shifted by j times [`R2`], into `normals[j]`, and its weight
/// w_j = G·(ωi·m_j)/(cos θi·cos θm_j)·L̃(ω_j) into `weights[j]` (0 where ω_j does not reflect
/// above the surface), for j below their length. The lanes' logarithm and sine are Cephes'
/// polynomials ([`gonio_core::lanes::math`]); the estimator takes the chosen candidate's normal
/// and weight from here, so they need not match a scalar draw.
struct Candidates<'a> {
    lobe: MicrofacetDistribution,
    wi: Vec3,
    u: Vec2,
    frame: &'a Frame,
    light: ResamplingLookup<'a>,
    normals: &'a mut [Vec3],
    weights: &'a mut [f32],
}

impl LaneKernel for Candidates<'_> {
    type Output = ();

    #[inline(always)]
    fn run<const N: usize, X: Isa>(self) {
        let lobe = self.lobe.lanes::<N, X>();
        let wi = Vec3s::<N, X>::splat(self.wi);
        let frame = [self.frame.s, self.frame.t, self.frame.n].map(Vec3s::<N, X>::splat);
        let count = self.weights.len();
        // `x` minus its integer part (x ≥ 0 here), capped below 1: `u` shifted by j·R2 wraps
        // into [0, 1)².
        let fract = |x: F32s<N, X>| {
            F32s::<N, X>::from_fn(|k| {
                let v = x.lane(k);
                v - floor(v)
            })
            .min(ONE_MINUS_EPSILON)
        };
        for start in (0..count).step_by(N) {
            let j = F32s::<N, X>::from_fn(|k| (start + k) as f32);
            let u = [fract(self.u.x + R2.x * j), fract(self.u.y + R2.y * j)];
            let m = lobe.sample_all_normals(u);
            let cos_im = wi.dot(m);
            let wo = (2.0 * cos_im) * m - wi;
            let reflects = cos_im.gt(0.0) & wo.z.gt(0.0) & m.z.gt(0.0);
            let world = frame[0] * wo.x + frame[1] * wo.y + frame[2] * wo.z;
            // Lanes past the last candidate look nothing up (a table read is a cache miss).
            let light = F32s::<N, X>::from_fn(|k| {
                if start + k < count {
                    self.light.luminance(world.lane(k))
                } else {
                    0.0
                }
            });
            let w = lobe.g(wi, wo, m) * cos_im / (wi.z * m.z) * light;
            let w = (reflects & w.is_finite()).and_then(w.max(0.0));
            for k in 0..N.min(count - start) {
                self.normals[start + k] = m.lane(k);
                self.weights[start + k] = w.lane(k);
            }
        }
    }
}

/// The index that `u` (in [0, 1)) picks among `weights` with probability wᵢ/Σw (inverting
/// the running sum, so that a pixel's stratified `u` stays stratified over the candidates), and
/// Σw; `None` when no weight is positive.
fn choose(weights: &[f32], u: f32) -> Option<(usize, f32)> {
    let w_sum: f32 = weights.iter().sum();
    if !(w_sum > 0.0 && w_sum.is_finite()) {
        return None;
    }
    let target = u * w_sum;
    let mut acc = 0.0f32;
    let mut last = None;
    for (i, &w) in weights.iter().enumerate() {
        if w > 0.0 {
            acc += w;
            last = Some(i);
            if target < acc {
                break;
            }
        }
    }
    last.map(|i| (i, w_sum))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::uplift_emission_texel;
    use glam::Affine3A;
    use gonio_core::lanes::Portable;
    use gonio_core::microfacet::MicrofacetKind;

    /// The candidates' kernel gives the same normals and weights at every lane width (4, 8 and
    /// the width `dispatch` picks: 16 on AVX-512), bit for bit, so that an image does not depend
    /// on the CPU's vector extensions; and each is the scalar model's: the normal the scalar
    /// all-normals sampler draws from the shifted point (within the lanes' logarithm and sine),
    /// and the weight G·(ωi·m)/(cos θi·cos θm)·L̃ at that normal. Checked with 13 candidates (a
    /// partial last chunk at every width), isotropic Beckmann and anisotropic GGX, from a
    /// tilted frame over a map with a bright patch.
    #[test]
    fn the_candidates_kernel_is_the_scalar_model_at_every_lane_width() {
        let (w, h) = (64, 32);
        let rgb: Vec<[f32; 3]> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                if (20..26).contains(&x) && (8..12).contains(&y) {
                    [40.0, 30.0, 20.0]
                } else {
                    [0.2, 0.3, 0.5]
                }
            })
            .collect();
        let map = EnvMapLight::new(w, h, rgb, 1.0, Affine3A::IDENTITY, uplift_emission_texel).unwrap();
        let frame = Frame::from_normal(Vec3::new(0.3, -0.4, 0.87).normalize());
        let lobes = [
            MicrofacetDistribution::new(MicrofacetKind::Beckmann, 0.1, 0.1, false),
            MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.05, 0.12, false),
        ];
        let count = 13;
        for lobe in lobes {
            for (wi, u) in [
                (Vec3::new(0.2, 0.1, 0.97).normalize(), Vec2::new(0.31, 0.77)),
                (Vec3::new(-0.8, 0.3, 0.3).normalize(), Vec2::new(0.999, 0.002)),
            ] {
                let run = |width: usize| {
                    let (mut normals, mut weights) = ([Vec3::ZERO; 13], [0.0f32; 13]);
                    let k = Candidates {
                        lobe,
                        wi,
                        u,
                        frame: &frame,
                        light: map.resampling_lookup(),
                        normals: &mut normals,
                        weights: &mut weights,
                    };
                    match width {
                        4 => k.run::<4, Portable>(),
                        8 => k.run::<8, Portable>(),
                        _ => lanes::dispatch(k),
                    }
                    (normals, weights)
                };
                let (normals, weights) = run(0);
                for width in [4, 8] {
                    let (n, w) = run(width);
                    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                    assert_eq!(n.map(bits), normals.map(bits), "{width} lanes");
                    assert_eq!(w.map(f32::to_bits), weights.map(f32::to_bits), "{width} lanes");
                }
                let mut positive = 0;
                for j in 0..count {
                    let s = u + R2 * j as f32;
                    let uj =
                        Vec2::new(s.x - floor(s.x), s.y - floor(s.y)).min(Vec2::splat(ONE_MINUS_EPSILON));
                    let m = normals[j];
                    let expect = lobe.sample_all_normals(uj);
                    assert!(
                        (m - expect).length() < 2e-5,
                        "{lobe:?} candidate {j}: {m} vs {expect}"
                    );
                    let cos_im = wi.dot(m);
                    let wo = 2.0 * cos_im * m - wi;
                    let weight = if cos_im > 0.0 && wo.z > 0.0 && m.z > 0.0 {
                        lobe.g(wi, wo, m) * cos_im / (wi.z * m.z)
                            * map.resampling_luminance(frame.to_world(wo))
                    } else {
                        0.0
                    };
                    let got = weights[j];
                    assert!(
                        (got - weight).abs() <= 1e-5 * weight,
                        "{lobe:?} candidate {j}: {got} vs {weight}"
                    );
                    positive += usize::from(weight > 0.0);
                }
                assert!(
                    positive >= count / 2,
                    "{lobe:?}, {wi}: only {positive} candidates reflect"
                );
            }
        }
    }
}
