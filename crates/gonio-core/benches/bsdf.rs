//! Cost of the BSDF calls a path tracer makes per vertex, per model (issue 2 §8), in ns per
//! call:
//!
//! * `sample_eval`: one `sample` and one `eval` at the sampled direction (the pair a path
//!   tracer with MIS needs),
//! * `sample`, `eval`: each alone.
//!
//! Every iteration draws fresh uniforms from a PCG32 (≈ 2 ns of the figure) and takes the next
//! of 1024 pre-drawn path wavelengths (drawing them, `SampledWavelengths::sample_visible`, costs
//! ≈ 0.5 µs by itself and is paid once per path, not per vertex), with an oblique `wi`; `eval`
//! queries a random direction of the upper hemisphere.
//! * `sample_eval_lanes`: the lane kernels (`gonio_core::lanes`) at the width `dispatch` picks
//!   on this CPU: per iteration, 4096 lanes of pre-drawn inputs (wavelengths, uniforms) go
//!   through the model's construction at their wavelengths, `sample` and `eval` at the sampled
//!   direction, as Mitsuba's vectorized variants are measured (`mitsuba_bsdf.py`). The figure
//!   is per iteration: divide by 4096 for ns per lane (divan's `items/s` column gives it).
//! * `sample_lanes`: the same without `eval`, beside the sample column of `mitsuba_bsdf.py`
//!   (whose sample + eval costs what its sample does: Dr.Jit traces both calls into one kernel
//!   and drops the repeated evaluation).
//!
//! Run with `cargo bench -p gonio-core --bench bsdf`.

use divan::{Bencher, black_box};
use glam::Vec3;
use gonio_core::bsdfs::lambertsphere::{AlbedoParameter, LambertSphereModel};
use gonio_core::bsdfs::roughdiffuse::RoughDiffuseModel;
use gonio_core::bsdfs::roughplastic::{CoatAverages, RoughCoat};
use gonio_core::bsdfs::{
    BlendBsdf, Conductor, Dielectric, Diffuse, LambertSphere, Plastic, Principled, PrincipledThin,
    RoughConductor, RoughDielectric, RoughDiffuse, RoughPlastic, ThinDielectric, TwoSided,
};
use gonio_core::lanes::{F32s, Isa, LaneKernel, Vec3s, dispatch};
use gonio_core::microfacet::{MicrofacetDistribution, MicrofacetKind};
use gonio_core::rng::Pcg32;
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, Spectrum};
use gonio_core::warp::square_to_cosine_hemisphere;
use gonio_core::{Bsdf, BsdfContext, Ior, SampledWavelengths};
use std::sync::Arc;

fn main() {
    divan::main();
}

const MODELS: &[&str] = &[
    "diffuse",
    "diffuse_spectral",
    "conductor_mirror",
    "conductor_au_spectral",
    "dielectric",
    "dielectric_dispersive",
    "thindielectric",
    "plastic",
    "twosided_diffuse",
    "blend_mirror_diffuse",
    "roughconductor_beckmann",
    "roughconductor_ggx_au",
    "roughdielectric",
    "roughdielectric_ggx",
    "roughplastic",
    "roughplastic_ggx",
    "principled",
    "principled_full",
    "principledthin",
    "lambertsphere",
    "lambertsphere_practical",
    "roughdiffuse_oren_nayar",
    "roughdiffuse_fast",
    "roughdiffuse_microfacet",
    "roughconductor_ms_ggx",
    "roughdielectric_ms_ggx",
];

fn piecewise(pairs: &[f32]) -> Spectrum {
    Spectrum::PiecewiseLinear(Arc::new(
        PiecewiseLinear::from_interleaved(pairs, Extrapolation::Clamp).unwrap(),
    ))
}

/// Builds the named model and hands it to `f` (children of wrappers live on this frame).
fn with_model(name: &str, f: impl FnOnce(&dyn Bsdf)) {
    match name {
        "diffuse" => f(&Diffuse::default()),
        "diffuse_spectral" => f(&Diffuse::new(piecewise(&[
            360.0, 0.05, 500.0, 0.9, 600.0, 0.2, 830.0, 0.7,
        ]))),
        "conductor_mirror" => f(&Conductor::mirror()),
        "conductor_au_spectral" => f(&Conductor::new(
            piecewise(&[400.0, 1.46, 500.0, 0.97, 600.0, 0.25, 700.0, 0.16]),
            piecewise(&[400.0, 1.95, 500.0, 1.87, 600.0, 2.98, 700.0, 3.95]),
        )),
        "dielectric" => f(&Dielectric::default()),
        "dielectric_dispersive" => f(&Dielectric::new(
            Ior::Dispersive(piecewise(&[400.0, 1.53085, 550.0, 1.51852, 700.0, 1.51306])),
            Ior::Constant(1.0),
        )),
        "thindielectric" => f(&ThinDielectric::default()),
        "plastic" => f(&Plastic::default()),
        "twosided_diffuse" => {
            let d = Diffuse::default();
            f(&TwoSided::new(&d))
        }
        "blend_mirror_diffuse" => {
            let (m, d) = (Conductor::mirror(), Diffuse::default());
            f(&BlendBsdf::new(0.5, &m, &d))
        }
        // Mitsuba's defaults (Beckmann, α = 0.1, ideal mirror), and gold with GGX α = 0.3.
        "roughconductor_beckmann" => f(&RoughConductor::default()),
        "roughconductor_ggx_au" => f(&gold_ggx()),
        // Mitsuba's defaults, and GGX α = 0.3 (the same configurations as mitsuba_bsdf.py).
        "roughdielectric" => f(&RoughDielectric::default()),
        "roughdielectric_ggx" => f(&glass_ggx()),
        "roughplastic" => f(&RoughPlastic::default()),
        "roughplastic_ggx" => f(&plastic_ggx()),
        "principled" => f(&Principled::default()),
        "principled_full" => f(&principled_full()),
        "principledthin" => f(&PrincipledThin::default()),
        "lambertsphere" => f(&LambertSphere::default()),
        "lambertsphere_practical" => f(&LambertSphere::new(
            Spectrum::Constant(0.5),
            AlbedoParameter::Reflectance,
            LambertSphereModel::Practical,
        )),
        // Mitsuba 0.6's defaults (ρ = 0.5, α = 0.2), and α = 0.8 for the walk.
        "roughdiffuse_oren_nayar" => f(&RoughDiffuse::default()),
        "roughdiffuse_fast" => f(&RoughDiffuse::new(
            Spectrum::Constant(0.5),
            0.2,
            RoughDiffuseModel::OrenNayarFast,
        )),
        "roughdiffuse_microfacet" => f(&RoughDiffuse::new(
            Spectrum::Constant(0.5),
            0.8,
            RoughDiffuseModel::Microfacet(MicrofacetKind::Ggx),
        )),
        // Heitz et al. 2016 walks: gold GGX α = 0.3 as above, and glass GGX α = 0.3.
        "roughconductor_ms_ggx" => {
            let mut c = RoughConductor::new(
                piecewise(&[400.0, 1.46, 500.0, 0.97, 600.0, 0.25, 700.0, 0.16]),
                piecewise(&[400.0, 1.95, 500.0, 1.87, 600.0, 2.98, 700.0, 3.95]),
                MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.3),
            );
            c.multiple_scattering = true;
            f(&c)
        }
        "roughdielectric_ms_ggx" => {
            let mut d = RoughDielectric::new(
                Ior::Constant(1.5046),
                Ior::Constant(1.000277),
                MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.3),
            );
            d.multiple_scattering = true;
            f(&d)
        }
        _ => unreachable!("unknown model {name}"),
    }
}

const WI: Vec3 = Vec3::new(0.48, 0.36, 0.8);

/// Models with a lane kernel.
const LANE_MODELS: &[&str] = &[
    "roughconductor_beckmann",
    "roughconductor_ggx_au",
    "roughdielectric",
    "roughdielectric_ggx",
    "roughplastic",
    "roughplastic_ggx",
    "principled",
    "principled_full",
    "principledthin",
];

/// Lanes per iteration of `sample_eval_lanes`.
const LANE_BATCH: usize = 4096;

/// Pre-drawn per-lane inputs of `sample_eval_lanes`, one array per quantity (as Mitsuba's
/// script holds them), so that a lane vector of uniforms is one load.
struct LaneInputs {
    wl: Vec<SampledWavelengths>,
    u: [Vec<f32>; 2],
}

impl LaneInputs {
    fn new() -> Self {
        let mut rng = Pcg32::new(1, 2);
        Self {
            wl: (0..LANE_BATCH)
                .map(|_| SampledWavelengths::sample_visible(rng.next_f32()))
                .collect(),
            u: [(); 2].map(|_| (0..LANE_BATCH).map(|_| rng.next_f32()).collect()),
        }
    }
}

/// A model with a lane kernel, as the bench drives it.
trait LaneBench {
    /// `sample` (u1 from the second uniform, reflected) then `eval` at the sampled direction
    /// (as the scalar `sample_eval` row and Mitsuba's script: f alone, no pdf); returns a sum
    /// of the results so that nothing is optimized away.
    fn sample_eval<const N: usize, X: Isa>(
        &self,
        wl: &[SampledWavelengths; N],
        wi: Vec3s<N, X>,
        u2: [F32s<N, X>; 2],
        with_eval: bool,
    ) -> F32s<N, X>;
}

macro_rules! lane_bench {
    ($ty:ty, |$m:ident, $wl:ident| $lanes:expr, $sample:ident) => {
        impl LaneBench for $ty {
            #[inline(always)]
            fn sample_eval<const N: usize, X: Isa>(&self, $wl: &[SampledWavelengths; N], wi: Vec3s<N, X>, u2: [F32s<N, X>; 2], with_eval: bool) -> F32s<N, X> {
                let ctx = BsdfContext::radiance();
                let $m = self;
                let lanes = $lanes;
                let s = lane_bench!(@sample $sample, lanes, ctx, wi, u2);
                let mut r = s.weight.0[0] + s.pdf + s.wo.z;
                if with_eval {
                    r += lanes.eval(&ctx, wi, s.wo).0[0];
                }
                r
            }
        }
    };
    (@sample u2_only, $l:ident, $ctx:ident, $wi:ident, $u2:ident) => {
        $l.sample(&$ctx, $wi, $u2)
    };
    (@sample u1_u2, $l:ident, $ctx:ident, $wi:ident, $u2:ident) => {
        $l.sample(&$ctx, $wi, 1.0 - $u2[1], $u2)
    };
}

lane_bench!(RoughConductor, |m, wl| m.lanes(wl).unwrap(), u2_only);
lane_bench!(RoughDielectric, |m, wl| m.lanes(wl).unwrap(), u1_u2);
lane_bench!(RoughPlastic, |m, wl| m.lanes(wl), u1_u2);
lane_bench!(Principled, |m, wl| m.lanes(wl), u1_u2);
lane_bench!(PrincipledThin, |m, wl| m.lanes(wl), u1_u2);

/// One model's kernel over a batch of lanes: one function per model, so that each stays small
/// enough for LLVM (one kernel matching over every model took a quarter of an hour to compile).
/// `EVAL`: `eval` after `sample` (`sample_eval_lanes`) or not (`sample_lanes`).
struct LaneBatch<'a, M, const EVAL: bool> {
    model: &'a M,
    inputs: &'a LaneInputs,
}

impl<M: LaneBench, const EVAL: bool> LaneKernel for LaneBatch<'_, M, EVAL> {
    type Output = f32;
    #[inline(always)]
    fn run<const N: usize, X: Isa>(self) -> f32 {
        let wi = Vec3s::<N, X>::splat(black_box(WI).normalize());
        let mut acc = F32s::<N, X>::ZERO;
        let [u0, u1] = &self.inputs.u;
        for ((wl, u0), u1) in self
            .inputs
            .wl
            .chunks_exact(N)
            .zip(u0.chunks_exact(N))
            .zip(u1.chunks_exact(N))
        {
            let wl: &[SampledWavelengths; N] = wl.try_into().unwrap();
            let u2 = [
                F32s::from_array(u0.try_into().unwrap()),
                F32s::from_array(u1.try_into().unwrap()),
            ];
            acc += self.model.sample_eval(wl, wi, u2, EVAL);
        }
        acc.sum()
    }
}

fn bench_lanes<M: LaneBench, const EVAL: bool>(bencher: Bencher, model: &M) {
    let inputs = LaneInputs::new();
    bencher
        .counter(divan::counter::ItemsCount::new(LANE_BATCH))
        .bench_local(|| {
            black_box(dispatch(LaneBatch::<M, EVAL> {
                model,
                inputs: &inputs,
            }))
        });
}

#[divan::bench(args = LANE_MODELS)]
fn sample_eval_lanes(bencher: Bencher, name: &str) {
    lane_model::<true>(bencher, name)
}

#[divan::bench(args = LANE_MODELS)]
fn sample_lanes(bencher: Bencher, name: &str) {
    lane_model::<false>(bencher, name)
}

/// The lane bench of model `name`, with or without `eval` after `sample`.
fn lane_model<const EVAL: bool>(bencher: Bencher, name: &str) {
    match name {
        "roughconductor_beckmann" => bench_lanes::<_, EVAL>(bencher, &RoughConductor::default()),
        "roughconductor_ggx_au" => bench_lanes::<_, EVAL>(bencher, &gold_ggx()),
        "roughdielectric" => bench_lanes::<_, EVAL>(bencher, &RoughDielectric::default()),
        "roughdielectric_ggx" => bench_lanes::<_, EVAL>(bencher, &glass_ggx()),
        "roughplastic" => bench_lanes::<_, EVAL>(bencher, &RoughPlastic::default()),
        "roughplastic_ggx" => bench_lanes::<_, EVAL>(bencher, &plastic_ggx()),
        "principled" => bench_lanes::<_, EVAL>(bencher, &Principled::default()),
        "principled_full" => bench_lanes::<_, EVAL>(bencher, &principled_full()),
        "principledthin" => bench_lanes::<_, EVAL>(bencher, &PrincipledThin::default()),
        _ => unreachable!("no lane kernel for {name}"),
    }
}

/// Gold (piecewise η, k) with GGX α = 0.3 (`roughconductor_ggx_au` of mitsuba_bsdf.py).
fn gold_ggx() -> RoughConductor {
    RoughConductor::new(
        piecewise(&[400.0, 1.46, 500.0, 0.97, 600.0, 0.25, 700.0, 0.16]),
        piecewise(&[400.0, 1.95, 500.0, 1.87, 600.0, 2.98, 700.0, 3.95]),
        MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.3),
    )
}

/// Mitsuba's default glass indices with GGX α = 0.3 (`roughdielectric_ggx`).
fn glass_ggx() -> RoughDielectric {
    RoughDielectric::new(
        Ior::Constant(1.5046),
        Ior::Constant(1.000277),
        MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.3),
    )
}

/// Mitsuba's default plastic with GGX α = 0.3 (`roughplastic_ggx`).
fn plastic_ggx() -> RoughPlastic {
    RoughPlastic::new(
        Spectrum::Constant(0.5),
        Spectrum::Constant(1.0),
        false,
        RoughCoat::new(
            MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.3),
            1.49 / 1.000277,
            CoatAverages::Exact,
        ),
    )
}

/// Every principled lobe on (`principled_full` of mitsuba_bsdf.py).
fn principled_full() -> Principled {
    let mut p = Principled::default();
    (p.metallic, p.spec_trans, p.clearcoat) = (0.3, 0.2, 0.5);
    (p.sheen, p.anisotropic, p.roughness) = (0.5, 0.5, 0.4);
    p
}

/// 1024 path wavelength sets, drawn once.
fn wavelength_table() -> Vec<SampledWavelengths> {
    let mut rng = Pcg32::new(7, 7);
    (0..1024)
        .map(|_| SampledWavelengths::sample_visible(rng.next_f32()))
        .collect()
}

#[divan::bench(args = MODELS)]
fn sample_eval(bencher: Bencher, name: &str) {
    with_model(name, |bsdf| {
        let ctx = BsdfContext::radiance();
        let mut rng = Pcg32::new(1, 2);
        let table = wavelength_table();
        let mut k = 0usize;
        bencher.bench_local(|| {
            k = (k + 1) & 1023;
            let mut wl = table[k];
            let u1 = rng.next_f32();
            let u2 = rng.next_vec2();
            let s = black_box(bsdf).sample(&ctx, black_box(WI), u1, u2, &mut wl);
            let wo = s.map_or(Vec3::Z, |s| s.wo);
            black_box(bsdf.eval(&ctx, WI, wo, &wl))
        });
    });
}

#[divan::bench(args = MODELS)]
fn sample(bencher: Bencher, name: &str) {
    with_model(name, |bsdf| {
        let ctx = BsdfContext::radiance();
        let mut rng = Pcg32::new(1, 2);
        let table = wavelength_table();
        let mut k = 0usize;
        bencher.bench_local(|| {
            k = (k + 1) & 1023;
            let mut wl = table[k];
            let u1 = rng.next_f32();
            let u2 = rng.next_vec2();
            black_box(black_box(bsdf).sample(&ctx, black_box(WI), u1, u2, &mut wl))
        });
    });
}

#[divan::bench(args = MODELS)]
fn eval(bencher: Bencher, name: &str) {
    with_model(name, |bsdf| {
        let ctx = BsdfContext::radiance();
        let mut rng = Pcg32::new(1, 2);
        let table = wavelength_table();
        let mut k = 0usize;
        bencher.bench_local(|| {
            k = (k + 1) & 1023;
            let wl = table[k];
            let wo = square_to_cosine_hemisphere(rng.next_vec2());
            black_box(black_box(bsdf).eval(&ctx, black_box(WI), wo, &wl))
        });
    });
}
