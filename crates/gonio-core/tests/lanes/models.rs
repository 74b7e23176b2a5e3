//! The BSDF lane kernels against the scalar models at each lane's wavelengths and roughness.

use super::{close, same_bits, upper_dir};
use glam::Vec2;
use gonio_core::bsdfs::roughconductor::RoughConductorLanes;
use gonio_core::bsdfs::roughplastic::{CoatAverages, RoughCoat};
use gonio_core::bsdfs::{RoughConductor, RoughDielectric, RoughPlastic};
use gonio_core::lanes::{
    BsdfSamples, F32s, Isa, LaneKernel, MicrofacetLanes, Portable, SampledSpectra, Vec3s, dispatch,
    lane_width,
};
use gonio_core::microfacet::{MicrofacetDistribution, MicrofacetKind};
use gonio_core::rng::Pcg32;
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, Spectrum};
use gonio_core::{Bsdf, BsdfContext, Ior, SampledSpectrum, SampledWavelengths};
use std::sync::Arc;

fn piecewise(pairs: &[f32]) -> Spectrum {
    Spectrum::PiecewiseLinear(Arc::new(
        PiecewiseLinear::from_interleaved(pairs, Extrapolation::Clamp).unwrap(),
    ))
}

fn gold(distribution: MicrofacetDistribution) -> RoughConductor {
    RoughConductor::new(
        piecewise(&[400.0, 1.46, 500.0, 0.97, 600.0, 0.25, 700.0, 0.16]),
        piecewise(&[400.0, 1.95, 500.0, 1.87, 600.0, 2.98, 700.0, 3.95]),
        distribution,
    )
}

/// Mitsuba's default, gold with GGX, anisotropic Beckmann sampling all normals, gold under
/// water with GGX and a tint.
fn conductors() -> Vec<RoughConductor> {
    let mut under_water = gold(MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.05, 0.4, true));
    under_water.ext_ior = Ior::Constant(1.333);
    under_water.specular_reflectance = Spectrum::Constant(0.8);
    vec![
        RoughConductor::default(),
        gold(MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.3)),
        gold(MicrofacetDistribution::new(
            MicrofacetKind::Beckmann,
            0.2,
            0.6,
            false,
        )),
        under_water,
    ]
}

/// One batch of inputs: wavelengths, wi, wo and uniforms per lane.
struct Batch<const N: usize, X: Isa = Portable> {
    wl: [SampledWavelengths; N],
    wi: Vec3s<N, X>,
    wo: Vec3s<N, X>,
    u1: F32s<N, X>,
    u2: [F32s<N, X>; 2],
}

impl<const N: usize, X: Isa> Batch<N, X> {
    fn draw(rng: &mut Pcg32) -> Self {
        Self {
            wl: std::array::from_fn(|_| SampledWavelengths::sample_visible(rng.next_f32())),
            wi: Vec3s::from_fn(|_| upper_dir(rng, 0.01)),
            wo: Vec3s::from_fn(|_| upper_dir(rng, -0.1)),
            u1: F32s::from_fn(|_| rng.next_f32()),
            u2: [
                F32s::from_fn(|_| rng.next_f32()),
                F32s::from_fn(|_| rng.next_f32()),
            ],
        }
    }
}

/// Runs `f` behind a call: each kernel call of a test is compiled as a function of its own
/// instead of inlined into the test's loop (the `#[inline(always)]` kernels made one function of
/// each test, which LLVM took most of a minute over; same code, same results).
#[inline(never)]
fn apart<R>(f: impl FnOnce() -> R) -> R {
    f()
}

fn spectra_close(a: SampledSpectrum, b: SampledSpectrum, tol: f32) -> bool {
    (0..4).all(|i| close(a[i], b[i], tol))
}

/// Compares eval, pdf and sample of `lanes` with `scalar(k)`, the scalar model of lane `k`.
/// Returns the number of lanes whose sample validity differs (a direction on the boundary of
/// the lobe, moved across it by rounding).
fn compare<const N: usize, X: Isa, B: Bsdf>(
    batch: &Batch<N, X>,
    ev: (SampledSpectra<N, X>, F32s<N, X>),
    s: &BsdfSamples<N, X>,
    scalar: impl Fn(usize) -> B,
) -> usize {
    compare_in(&BsdfContext::radiance(), batch, ev, s, scalar)
}

/// [`compare`] in a given context.
fn compare_in<const N: usize, X: Isa, B: Bsdf>(
    ctx: &BsdfContext,
    batch: &Batch<N, X>,
    (f, pdf): (SampledSpectra<N, X>, F32s<N, X>),
    s: &BsdfSamples<N, X>,
    scalar: impl Fn(usize) -> B,
) -> usize {
    let ctx = *ctx;
    let mut mismatches = 0;
    for k in 0..N {
        let model = scalar(k);
        let (wi, wo, wl) = (batch.wi.lane(k), batch.wo.lane(k), &batch.wl[k]);
        let (fs, ps) = model.eval_pdf(&ctx, wi, wo, wl);
        assert!(
            spectra_close(f.lane(k), fs, 2e-5),
            "eval wi {wi} wo {wo}: {:?} vs {fs:?}",
            f.lane(k)
        );
        assert!(
            close(pdf.lane(k), ps, 2e-5),
            "pdf wi {wi} wo {wo}: {} vs {ps}",
            pdf.lane(k)
        );
        let u2 = Vec2::new(batch.u2[0].lane(k), batch.u2[1].lane(k));
        let scalar_sample = model.sample(&ctx, wi, batch.u1.lane(k), u2, &mut wl.clone());
        match (s.valid.test(k), scalar_sample) {
            (true, Some(ss)) => {
                let wo_l = s.wo.lane(k);
                let angle = (wo_l - ss.wo).length(); // the chord, ≈ the angle
                assert!(angle < 4e-4, "sample wi {wi} u {u2}: {wo_l} vs {}", ss.wo);
                // The weight and pdf at the lane's own direction.
                let (fl, pl) = model.eval_pdf(&ctx, wi, wo_l, wl);
                assert!(
                    close(s.pdf.lane(k), pl, 1e-4),
                    "sample pdf {} vs {pl}",
                    s.pdf.lane(k)
                );
                let w = fl * (wo_l.z.abs() / pl);
                assert!(
                    spectra_close(s.weight.lane(k), w, 1e-4),
                    "weight {:?} vs {w:?}",
                    s.weight.lane(k)
                );
                assert_eq!(s.flags[k], ss.flags);
                assert_eq!(s.eta.lane(k), ss.eta);
            }
            (false, None) => {}
            _ => mismatches += 1,
        }
    }
    mismatches
}

/// A roughness per lane from 10^−2.5 to 1, as from a texture, with the model's anisotropy ratio.
fn textured_roughness<const N: usize, X: Isa>(
    d: MicrofacetLanes<N, X>,
    rng: &mut Pcg32,
) -> MicrofacetLanes<N, X> {
    let a = F32s::from_fn(|_| 10f32.powf(-2.5 * rng.next_f32()));
    MicrofacetLanes::new(d.kind, a, a * d.alpha_v / d.alpha_u, d.sample_visible)
}

fn conductor_agrees<const N: usize, X: Isa>() {
    let ctx = BsdfContext::radiance();
    let mut rng = Pcg32::new(21, N as u64);
    let (mut mismatches, mut total) = (0, 0);
    for model in conductors() {
        for round in 0..150 {
            let batch = Batch::<N, X>::draw(&mut rng);
            let mut lanes: RoughConductorLanes<N, X> = model.lanes(&batch.wl).unwrap();
            if round % 2 == 1 {
                lanes.distribution = textured_roughness(lanes.distribution, &mut rng);
            }
            let ev = apart(|| lanes.eval_pdf(&ctx, batch.wi, batch.wo));
            assert!(
                same_bits(apart(|| lanes.eval(&ctx, batch.wi, batch.wo)), ev.0),
                "eval is eval_pdf's value"
            );
            let s = apart(|| lanes.sample(&ctx, batch.wi, batch.u2));
            mismatches += compare(&batch, ev, &s, |k| {
                let mut m = model.clone();
                m.distribution = lanes.distribution.lane(k);
                m
            });
            total += N;
        }
    }
    assert!(
        mismatches * 1000 <= total,
        "{mismatches} of {total} lanes differ in validity"
    );
}

#[test]
fn roughconductor_lanes_agree_with_the_scalar_model() {
    // Each width compiles the whole kernel once more (minutes of the CI build): 4 lanes here,
    // the dispatched widths (16, 8, 4 compiled; the CPU's run) below.
    conductor_agrees::<4, Portable>();
}

/// The same comparison with the kernel compiled for this CPU's vector extension.
struct ConductorAtDispatchWidth<'a> {
    model: &'a RoughConductor,
    seed: u64,
}

impl LaneKernel for ConductorAtDispatchWidth<'_> {
    type Output = usize;
    #[inline(always)]
    fn run<const N: usize, X: Isa>(self) -> usize {
        let ctx = BsdfContext::radiance();
        let mut rng = Pcg32::new(self.seed, 3);
        let mut mismatches = 0;
        for _ in 0..200 {
            let batch = Batch::<N, X>::draw(&mut rng);
            let lanes = self.model.lanes(&batch.wl).unwrap();
            let ev = lanes.eval_pdf(&ctx, batch.wi, batch.wo);
            assert!(
                same_bits(lanes.eval(&ctx, batch.wi, batch.wo), ev.0),
                "eval is eval_pdf's value"
            );
            let s = lanes.sample(&ctx, batch.wi, batch.u2);
            mismatches += compare(&batch, ev, &s, |_| self.model.clone());
        }
        mismatches
    }
}

#[test]
fn roughconductor_lanes_agree_at_the_dispatched_width() {
    eprintln!("dispatch width on this CPU: {}", lane_width());
    for (i, model) in conductors().iter().enumerate() {
        let mismatches = dispatch(ConductorAtDispatchWidth {
            model,
            seed: 30 + i as u64,
        });
        assert!(mismatches <= 2, "{mismatches} lanes differ in validity");
    }
}

#[test]
fn multiple_scattering_has_no_lane_kernel() {
    let m = RoughConductor {
        multiple_scattering: true,
        ..Default::default()
    };
    let wl = [SampledWavelengths::sample_visible(0.3); 4];
    assert!(m.lanes::<_, Portable>(&wl).is_none());
}

/// Mitsuba's default, GGX α = 0.3 over a spectral base, and the nonlinear series with Mitsuba's
/// tables under a tint.
fn plastics() -> Vec<RoughPlastic> {
    vec![
        RoughPlastic::default(),
        RoughPlastic::new(
            piecewise(&[400.0, 0.1, 550.0, 0.8, 700.0, 0.3]),
            Spectrum::Constant(1.0),
            false,
            RoughCoat::new(
                MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.3),
                1.5,
                CoatAverages::Exact,
            ),
        ),
        RoughPlastic::new(
            Spectrum::Constant(0.7),
            Spectrum::Constant(0.6),
            true,
            RoughCoat::new(
                MicrofacetDistribution::new(MicrofacetKind::Beckmann, 0.4, 0.4, false),
                1.33,
                CoatAverages::Mitsuba,
            ),
        ),
    ]
}

fn plastic_agrees<const N: usize, X: Isa>() {
    let ctx = BsdfContext::radiance();
    let mut rng = Pcg32::new(41, N as u64);
    let (mut mismatches, mut total) = (0, 0);
    for model in plastics() {
        for _ in 0..150 {
            let batch = Batch::<N, X>::draw(&mut rng);
            let lanes = model.lanes(&batch.wl);
            let ev = apart(|| lanes.eval_pdf(&ctx, batch.wi, batch.wo));
            assert!(
                same_bits(apart(|| lanes.eval(&ctx, batch.wi, batch.wo)), ev.0),
                "eval is eval_pdf's value"
            );
            let s = apart(|| lanes.sample(&ctx, batch.wi, batch.u1, batch.u2));
            mismatches += compare(&batch, ev, &s, |_| model.clone());
            total += N;
        }
    }
    assert!(
        mismatches * 1000 <= total,
        "{mismatches} of {total} lanes differ in validity"
    );
}

#[test]
fn roughplastic_lanes_agree_with_the_scalar_model() {
    plastic_agrees::<4, Portable>();
}

/// Only the coat's lobe, only the base's: the lane kernel honours the context's lobes.
#[test]
fn roughplastic_lanes_honour_the_lobe_mask() {
    let mut rng = Pcg32::new(42, 0);
    let model = RoughPlastic::default();
    for lobes in [
        gonio_core::BsdfFlags::GLOSSY_REFLECTION,
        gonio_core::BsdfFlags::DIFFUSE_REFLECTION,
    ] {
        let ctx = BsdfContext {
            lobes,
            ..BsdfContext::radiance()
        };
        let batch = Batch::<4>::draw(&mut rng);
        let lanes = model.lanes(&batch.wl);
        let (f, pdf) = apart(|| lanes.eval_pdf(&ctx, batch.wi, batch.wo));
        let s = apart(|| lanes.sample(&ctx, batch.wi, batch.u1, batch.u2));
        for k in 0..4 {
            let (wi, wo, wl) = (batch.wi.lane(k), batch.wo.lane(k), &batch.wl[k]);
            let (fs, ps) = model.eval_pdf(&ctx, wi, wo, wl);
            assert!(spectra_close(f.lane(k), fs, 2e-5) && close(pdf.lane(k), ps, 2e-5));
            if s.valid.test(k) {
                assert_eq!(s.flags[k], lobes);
            }
        }
    }
}

/// Mitsuba's default (Beckmann α = 0.1, bk7 in air), GGX α = 0.3, anisotropic Beckmann sampling
/// all normals (Walter's widening), water in glass (η < 1) with tints.
fn dielectrics() -> Vec<RoughDielectric> {
    let mut tinted = RoughDielectric::new(
        Ior::Constant(1.333),
        Ior::Constant(1.5),
        MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.15),
    );
    tinted.specular_reflectance = Spectrum::Constant(0.7);
    tinted.specular_transmittance = piecewise(&[400.0, 0.2, 700.0, 0.9]);
    vec![
        RoughDielectric::default(),
        RoughDielectric::new(
            Ior::Constant(1.5046),
            Ior::Constant(1.000277),
            MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.3),
        ),
        RoughDielectric::new(
            Ior::Constant(1.5),
            Ior::Constant(1.0),
            MicrofacetDistribution::new(MicrofacetKind::Beckmann, 0.1, 0.5, false),
        ),
        tinted,
    ]
}

fn dielectric_agrees<const N: usize, X: Isa>(mode: gonio_core::TransportMode) {
    let ctx = BsdfContext {
        mode,
        ..BsdfContext::radiance()
    };
    let mut rng = Pcg32::new(51, N as u64);
    let (mut mismatches, mut total) = (0, 0);
    for model in dielectrics() {
        for round in 0..200 {
            let mut batch = Batch::<N, X>::draw(&mut rng);
            // wi from either side, wo anywhere on the sphere.
            for k in 0..N {
                if rng.next_f32() < 0.5 {
                    batch.wi.z.0[k] = -batch.wi.z.0[k];
                }
                let w = upper_dir(&mut rng, -1.0);
                (batch.wo.x.0[k], batch.wo.y.0[k], batch.wo.z.0[k]) = (w.x, w.y, w.z);
            }
            let mut lanes = model.lanes(&batch.wl).unwrap();
            if round % 2 == 1 {
                lanes.distribution = textured_roughness(lanes.distribution, &mut rng);
            }
            let ev = apart(|| lanes.eval_pdf(&ctx, batch.wi, batch.wo));
            assert!(
                same_bits(apart(|| lanes.eval(&ctx, batch.wi, batch.wo)), ev.0),
                "eval is eval_pdf's value"
            );
            let s = apart(|| lanes.sample(&ctx, batch.wi, batch.u1, batch.u2));
            mismatches += compare_in(&ctx, &batch, ev, &s, |k| {
                let mut m = model.clone();
                m.distribution = lanes.distribution.lane(k);
                m
            });
            total += N;
        }
    }
    assert!(
        mismatches * 1000 <= total,
        "{mismatches} of {total} lanes differ in validity"
    );
}

#[test]
fn roughdielectric_lanes_agree_with_the_scalar_model() {
    use gonio_core::TransportMode::{Importance, Radiance};
    for mode in [Radiance, Importance] {
        dielectric_agrees::<4, Portable>(mode);
    }
}

#[test]
fn dispersive_and_multiple_scattering_dielectrics_have_no_lane_kernel() {
    let wl = [SampledWavelengths::sample_visible(0.3); 4];
    let dispersive = RoughDielectric {
        int_ior: Ior::Dispersive(piecewise(&[400.0, 1.53, 700.0, 1.51])),
        ..Default::default()
    };
    assert!(dispersive.lanes::<_, Portable>(&wl).is_none());
    let walk = RoughDielectric {
        multiple_scattering: true,
        ..Default::default()
    };
    assert!(walk.lanes::<_, Portable>(&wl).is_none());
}
