//! The Disney lane kernels (`PrincipledLanes`, `PrincipledThinLanes`) against the scalar models
//! at each lane's wavelengths and parameters: wi from both sides, wo over the whole sphere, a
//! configuration per lobe and parameters varying per lane as from textures, in radiance and
//! importance mode and with single lobes enabled.

use super::{close, same_bits, upper_dir};
use glam::Vec2;
use gonio_core::bsdfs::principled::PrincipledLanes;
use gonio_core::bsdfs::principledthin::PrincipledThinLanes;
use gonio_core::bsdfs::{Principled, PrincipledThin};
use gonio_core::lanes::{BsdfSamples, F32s, Isa, Portable, SampledSpectra, Vec3s};
#[cfg(feature = "lane-dispatch-tests")]
use gonio_core::lanes::{LaneKernel, dispatch, lane_width};
use gonio_core::rng::Pcg32;
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, Spectrum};
use gonio_core::{Bsdf, BsdfContext, BsdfFlags, SampledSpectrum, SampledWavelengths};
use std::sync::Arc;

/// One batch of inputs: wavelengths, wi (either side), wo (whole sphere) and uniforms per lane.
pub(super) struct Batch<const N: usize, X: Isa = Portable> {
    pub wl: [SampledWavelengths; N],
    pub wi: Vec3s<N, X>,
    pub wo: Vec3s<N, X>,
    pub u1: F32s<N, X>,
    pub u2: [F32s<N, X>; 2],
}

impl<const N: usize, X: Isa> Batch<N, X> {
    /// wi within 89.4° of either pole (the lower side when `both_sides` and a coin says so).
    pub fn draw(rng: &mut Pcg32, both_sides: bool) -> Self {
        Self {
            wl: std::array::from_fn(|_| SampledWavelengths::sample_visible(rng.next_f32())),
            wi: Vec3s::from_fn(|_| {
                let w = upper_dir(rng, 0.01);
                if both_sides && rng.next_f32() < 0.5 { -w } else { w }
            }),
            wo: Vec3s::from_fn(|_| upper_dir(rng, -1.0)),
            u1: F32s::from_fn(|_| rng.next_f32()),
            u2: [
                F32s::from_fn(|_| rng.next_f32()),
                F32s::from_fn(|_| rng.next_f32()),
            ],
        }
    }
}

/// The lane kernels' common interface, so that one comparison serves both models.
pub(super) trait LaneModel<const N: usize, X: Isa> {
    type Scalar: Bsdf + std::fmt::Debug;
    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>);
    fn eval(&self, ctx: &BsdfContext, wi: Vec3s<N, X>, wo: Vec3s<N, X>) -> SampledSpectra<N, X>;
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        u1: F32s<N, X>,
        u2: [F32s<N, X>; 2],
    ) -> BsdfSamples<N, X>;
    fn lane(&self, k: usize) -> Self::Scalar;
}

impl<const N: usize, X: Isa> LaneModel<N, X> for PrincipledLanes<'_, N, X> {
    type Scalar = Principled<SampledSpectrum>;
    #[inline(always)]
    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>) {
        PrincipledLanes::eval_pdf(self, ctx, wi, wo)
    }
    #[inline(always)]
    fn eval(&self, ctx: &BsdfContext, wi: Vec3s<N, X>, wo: Vec3s<N, X>) -> SampledSpectra<N, X> {
        PrincipledLanes::eval(self, ctx, wi, wo)
    }
    #[inline(always)]
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        u1: F32s<N, X>,
        u2: [F32s<N, X>; 2],
    ) -> BsdfSamples<N, X> {
        PrincipledLanes::sample(self, ctx, wi, u1, u2)
    }
    fn lane(&self, k: usize) -> Self::Scalar {
        PrincipledLanes::lane(self, k)
    }
}

impl<const N: usize, X: Isa> LaneModel<N, X> for PrincipledThinLanes<'_, N, X> {
    type Scalar = PrincipledThin<SampledSpectrum>;
    #[inline(always)]
    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>) {
        PrincipledThinLanes::eval_pdf(self, ctx, wi, wo)
    }
    #[inline(always)]
    fn eval(&self, ctx: &BsdfContext, wi: Vec3s<N, X>, wo: Vec3s<N, X>) -> SampledSpectra<N, X> {
        PrincipledThinLanes::eval(self, ctx, wi, wo)
    }
    #[inline(always)]
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        u1: F32s<N, X>,
        u2: [F32s<N, X>; 2],
    ) -> BsdfSamples<N, X> {
        PrincipledThinLanes::sample(self, ctx, wi, u1, u2)
    }
    fn lane(&self, k: usize) -> Self::Scalar {
        PrincipledThinLanes::lane(self, k)
    }
}

/// The worst deviations seen (relative as `close` measures them) and the validity mismatches.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Stats {
    pub eval: f32,
    pub pdf: f32,
    pub chord: f32,
    pub sample_pdf: f32,
    pub weight: f32,
    pub mismatches: usize,
    pub lanes: usize,
    pub valid: usize,
    /// Valid samples per lobe: diffuse reflection, glossy reflection, glossy transmission,
    /// diffuse transmission.
    pub lobes: [usize; 4],
    /// Valid samples with wi below the surface.
    pub from_below: usize,
}

impl Stats {
    pub fn merge(&mut self, o: Stats) {
        self.eval = self.eval.max(o.eval);
        self.pdf = self.pdf.max(o.pdf);
        self.chord = self.chord.max(o.chord);
        self.sample_pdf = self.sample_pdf.max(o.sample_pdf);
        self.weight = self.weight.max(o.weight);
        self.mismatches += o.mismatches;
        self.lanes += o.lanes;
        self.valid += o.valid;
        for i in 0..4 {
            self.lobes[i] += o.lobes[i];
        }
        self.from_below += o.from_below;
    }

    /// Asserts the validity mismatches are at most 0.1 % of the lanes.
    pub fn check(&self, what: &str) {
        eprintln!("{what}: {self:?}");
        assert!(
            self.mismatches * 1000 <= self.lanes,
            "{what}: {} of {} lanes differ in validity",
            self.mismatches,
            self.lanes
        );
    }
}

/// |a − b| / max(1, |a|, |b|), the measure of `close`.
fn dev(a: f32, b: f32) -> f32 {
    if a.is_nan() && b.is_nan() {
        return 0.0;
    }
    (a - b).abs() / 1f32.max(a.abs()).max(b.abs())
}

fn spectra_dev(a: SampledSpectrum, b: SampledSpectrum) -> f32 {
    (0..4).map(|i| dev(a[i], b[i])).fold(0.0, f32::max)
}

/// Compares eval, pdf and sample of `lanes` with its scalar model lane by lane under `ctx`
/// (tolerances of `models.rs`: eval and pdf 2·10⁻⁵, the sampled direction's chord 4·10⁻⁴, the
/// weight and pdf at the lane's own direction 10⁻⁴).
#[inline(always)]
pub(super) fn compare<const N: usize, X: Isa, L: LaneModel<N, X>>(
    ctx: &BsdfContext,
    batch: &Batch<N, X>,
    lanes: &L,
) -> Stats {
    let (f, pdf) = lanes.eval_pdf(ctx, batch.wi, batch.wo);
    assert!(
        same_bits(lanes.eval(ctx, batch.wi, batch.wo), f),
        "eval is eval_pdf's value"
    );
    let s = lanes.sample(ctx, batch.wi, batch.u1, batch.u2);
    let mut st = Stats {
        lanes: N,
        ..Stats::default()
    };
    for k in 0..N {
        let model = lanes.lane(k);
        let (wi, wo, wl) = (batch.wi.lane(k), batch.wo.lane(k), &batch.wl[k]);
        let (fs, ps) = model.eval_pdf(ctx, wi, wo, wl);
        st.eval = st.eval.max(spectra_dev(f.lane(k), fs));
        st.pdf = st.pdf.max(dev(pdf.lane(k), ps));
        assert!(
            (0..4).all(|i| close(f.lane(k)[i], fs[i], 2e-5)),
            "eval wi {wi} wo {wo}: {:?} vs {fs:?} ({model:?})",
            f.lane(k)
        );
        assert!(
            close(pdf.lane(k), ps, 2e-5),
            "pdf wi {wi} wo {wo}: {} vs {ps} ({model:?})",
            pdf.lane(k)
        );
        let u2 = Vec2::new(batch.u2[0].lane(k), batch.u2[1].lane(k));
        let scalar_sample = model.sample(ctx, wi, batch.u1.lane(k), u2, &mut wl.clone());
        match (s.valid.test(k), scalar_sample) {
            (true, Some(ss)) => {
                st.valid += 1;
                st.from_below += (wi.z < 0.0) as usize;
                let lobe = [
                    BsdfFlags::DIFFUSE_REFLECTION,
                    BsdfFlags::GLOSSY_REFLECTION,
                    BsdfFlags::GLOSSY_TRANSMISSION,
                    BsdfFlags::DIFFUSE_TRANSMISSION,
                ]
                .iter()
                .position(|&l| l == ss.flags);
                if let Some(i) = lobe {
                    st.lobes[i] += 1;
                }
                let wo_l = s.wo.lane(k);
                let chord = (wo_l - ss.wo).length();
                st.chord = st.chord.max(chord);
                assert!(
                    chord < 4e-4,
                    "sample wi {wi} u {u2}: {wo_l} vs {} ({model:?})",
                    ss.wo
                );
                let (fl, pl) = model.eval_pdf(ctx, wi, wo_l, wl);
                st.sample_pdf = st.sample_pdf.max(dev(s.pdf.lane(k), pl));
                assert!(
                    close(s.pdf.lane(k), pl, 1e-4),
                    "sample pdf {} vs {pl}",
                    s.pdf.lane(k)
                );
                let w = fl * (wo_l.z.abs() / pl);
                st.weight = st.weight.max(spectra_dev(s.weight.lane(k), w));
                assert!(
                    (0..4).all(|i| close(s.weight.lane(k)[i], w[i], 1e-4)),
                    "weight {:?} vs {w:?}",
                    s.weight.lane(k)
                );
                assert_eq!(s.flags[k], ss.flags, "flags wi {wi} u1 {}", batch.u1.lane(k));
                assert_eq!(s.eta.lane(k), ss.eta);
            }
            (false, None) => {}
            _ => st.mismatches += 1,
        }
    }
    st
}

/// [`compare`] behind a call: one copy of the kernels per model, not one per test.
#[inline(never)]
fn compare_once<const N: usize, X: Isa, L: LaneModel<N, X>>(
    ctx: &BsdfContext,
    batch: &Batch<N, X>,
    lanes: &L,
) -> Stats {
    compare(ctx, batch, lanes)
}

/// A value in [lo, hi] per lane, 0 in about a third of the lanes (the scalar model's
/// "parameter ≠ 0" branches).
pub(super) fn param<const N: usize, X: Isa>(rng: &mut Pcg32, lo: f32, hi: f32) -> F32s<N, X> {
    F32s::from_fn(|_| {
        if rng.next_f32() < 0.33 {
            0.0
        } else {
            lo + (hi - lo) * rng.next_f32()
        }
    })
}

/// A colour per lane and wavelength in [0, 1].
pub(super) fn colours<const N: usize, X: Isa>(rng: &mut Pcg32) -> SampledSpectra<N, X> {
    SampledSpectra::from_fn(|_| SampledSpectrum::from_fn(|_| rng.next_f32()))
}

pub(super) fn piecewise(pairs: &[f32]) -> Spectrum {
    Spectrum::PiecewiseLinear(Arc::new(
        PiecewiseLinear::from_interleaved(pairs, Extrapolation::Clamp).unwrap(),
    ))
}

/// Mitsuba's default; every lobe at once (metallic 0.3, spec_trans 0.2, clearcoat 0.5, sheen
/// 0.5, anisotropic 0.5, roughness 0.4) with tints, flatness and a spectral base colour;
/// glass-like (spec_trans 1, smooth) and a rough glass of η < 1.
fn principleds() -> Vec<Principled> {
    let all = Principled {
        metallic: 0.3,
        spec_trans: 0.2,
        clearcoat: 0.5,
        sheen: 0.5,
        anisotropic: 0.5,
        roughness: 0.4,
        ..Principled::default()
    };
    let tinted = Principled {
        spec_tint: 0.6,
        sheen_tint: 0.7,
        flatness: 0.5,
        clearcoat_gloss: 0.8,
        ..Principled::new(piecewise(&[400.0, 0.1, 550.0, 0.8, 700.0, 0.3]))
    };
    let glass = Principled {
        spec_trans: 1.0,
        roughness: 0.15,
        ..Principled::new(Spectrum::Constant(0.9))
    };
    let thin_air = Principled {
        spec_trans: 1.0,
        eta: 0.75,
        roughness: 0.6,
        ..Principled::default()
    };
    vec![Principled::default(), all, tinted, glass, thin_air]
}

/// Replaces every float parameter and the base colour by values per lane.
fn vary<const N: usize, X: Isa>(l: &mut PrincipledLanes<'_, N, X>, rng: &mut Pcg32) {
    l.base_color = colours(rng);
    l.roughness = F32s::from_fn(|_| 0.02 + 0.98 * rng.next_f32());
    l.anisotropic = param(rng, 0.0, 1.0);
    l.metallic = param(rng, 0.0, 1.0);
    l.spec_trans = param(rng, 0.0, 1.0);
    l.eta = F32s::from_fn(|_| 1.1 + rng.next_f32());
    l.spec_tint = param(rng, 0.0, 1.0);
    l.sheen = param(rng, 0.0, 1.0);
    l.sheen_tint = param(rng, 0.0, 1.0);
    l.flatness = param(rng, 0.0, 1.0);
    l.clearcoat = param(rng, 0.0, 1.0);
    l.clearcoat_gloss = param(rng, 0.0, 1.0);
}

fn principled_agrees<const N: usize, X: Isa>() -> Stats {
    let mut rng = Pcg32::new(51, N as u64);
    let mut st = Stats::default();
    for model in principleds() {
        for round in 0..200 {
            let batch = Batch::<N, X>::draw(&mut rng, true);
            let mut lanes = model.lanes(&batch.wl);
            if round % 2 == 1 {
                vary(&mut lanes, &mut rng);
            }
            let ctx = if round % 4 >= 2 {
                BsdfContext::importance()
            } else {
                BsdfContext::radiance()
            };
            st.merge(compare_once(&ctx, &batch, &lanes));
        }
    }
    st
}

#[test]
fn principled_lanes_agree_with_the_scalar_model() {
    {
        let st = principled_agrees::<4, Portable>();
        st.check("principled");
        // Every lobe was sampled, from both sides.
        assert!(st.lobes[..3].iter().all(|&n| n > 0) && st.from_below > 0);
    }
}

/// Each lobe alone, and the glossy ones together: the kernel honours the context's lobes.
#[test]
fn principled_lanes_honour_the_lobe_mask() {
    let mut rng = Pcg32::new(52, 0);
    let mut st = Stats::default();
    for lobes in [
        BsdfFlags::GLOSSY_REFLECTION,
        BsdfFlags::GLOSSY_TRANSMISSION,
        BsdfFlags::DIFFUSE_REFLECTION,
        BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::GLOSSY_TRANSMISSION,
    ] {
        let ctx = BsdfContext::radiance().with_lobes(lobes);
        for model in principleds() {
            for _ in 0..40 {
                let batch = Batch::<4>::draw(&mut rng, true);
                let mut lanes = model.lanes(&batch.wl);
                vary(&mut lanes, &mut rng);
                st.merge(compare_once(&ctx, &batch, &lanes));
            }
        }
    }
    st.check("principled, single lobes");
}

/// The same comparison with the kernel compiled for this CPU's vector extension.
#[cfg(feature = "lane-dispatch-tests")]
struct PrincipledAtDispatchWidth<'a> {
    model: &'a Principled,
    seed: u64,
}

#[cfg(feature = "lane-dispatch-tests")]
impl LaneKernel for PrincipledAtDispatchWidth<'_> {
    type Output = Stats;
    #[inline(always)]
    fn run<const N: usize, X: Isa>(self) -> Stats {
        let mut rng = Pcg32::new(self.seed, 3);
        let mut st = Stats::default();
        for round in 0..300 {
            let batch = Batch::<N, X>::draw(&mut rng, true);
            let mut lanes = self.model.lanes(&batch.wl);
            if round % 2 == 1 {
                vary(&mut lanes, &mut rng);
            }
            st.merge(compare(&BsdfContext::radiance(), &batch, &lanes));
        }
        st
    }
}

#[test]
#[cfg(feature = "lane-dispatch-tests")]
fn principled_lanes_agree_at_the_dispatched_width() {
    eprintln!("dispatch width on this CPU: {}", lane_width());
    let mut st = Stats::default();
    for (i, model) in principleds().iter().enumerate() {
        st.merge(dispatch(PrincipledAtDispatchWidth {
            model,
            seed: 60 + i as u64,
        }));
    }
    st.check("principled, dispatched width");
}

/// Mitsuba's default; every lobe at once (spec_trans 0.3, diff_trans 0.6, sheen, tints,
/// flatness, anisotropy, η 1.3, a spectral base colour); glass-like (spec_trans 1); all the
/// diffuse response transmitted (diff_trans 2).
fn thins() -> Vec<PrincipledThin> {
    let all = PrincipledThin {
        spec_trans: 0.3,
        diff_trans: 0.6,
        sheen: 0.5,
        sheen_tint: 0.4,
        spec_tint: 0.5,
        flatness: 0.3,
        anisotropic: 0.5,
        roughness: 0.4,
        eta: 1.3,
        ..PrincipledThin::new(piecewise(&[400.0, 0.1, 550.0, 0.8, 700.0, 0.3]))
    };
    let glass = PrincipledThin {
        spec_trans: 1.0,
        roughness: 0.2,
        ..PrincipledThin::default()
    };
    let translucent = PrincipledThin {
        diff_trans: 2.0,
        ..PrincipledThin::default()
    };
    vec![PrincipledThin::default(), all, glass, translucent]
}

/// Replaces every float parameter and the base colour by values per lane.
fn vary_thin<const N: usize, X: Isa>(l: &mut PrincipledThinLanes<'_, N, X>, rng: &mut Pcg32) {
    l.base_color = colours(rng);
    l.roughness = F32s::from_fn(|_| 0.02 + 0.98 * rng.next_f32());
    l.anisotropic = param(rng, 0.0, 1.0);
    l.spec_trans = param(rng, 0.0, 1.0);
    l.eta = F32s::from_fn(|_| 1.1 + rng.next_f32());
    l.spec_tint = param(rng, 0.0, 1.0);
    l.sheen = param(rng, 0.0, 1.0);
    l.sheen_tint = param(rng, 0.0, 1.0);
    l.flatness = param(rng, 0.0, 1.0);
    l.diff_trans = param(rng, 0.0, 2.0);
}

fn thin_agrees<const N: usize, X: Isa>() -> Stats {
    let mut rng = Pcg32::new(71, N as u64);
    let mut st = Stats::default();
    for model in thins() {
        for round in 0..200 {
            let batch = Batch::<N, X>::draw(&mut rng, true);
            let mut lanes = model.lanes(&batch.wl);
            if round % 2 == 1 {
                vary_thin(&mut lanes, &mut rng);
            }
            st.merge(compare_once(&BsdfContext::radiance(), &batch, &lanes));
        }
    }
    st
}

#[test]
fn principledthin_lanes_agree_with_the_scalar_model() {
    {
        let st = thin_agrees::<4, Portable>();
        st.check("principledthin");
        assert!(st.lobes.iter().all(|&n| n > 0) && st.from_below > 0);
    }
}

#[test]
fn principledthin_lanes_honour_the_lobe_mask() {
    let mut rng = Pcg32::new(72, 0);
    let mut st = Stats::default();
    for lobes in [
        BsdfFlags::GLOSSY_REFLECTION,
        BsdfFlags::GLOSSY_TRANSMISSION,
        BsdfFlags::DIFFUSE_REFLECTION,
        BsdfFlags::DIFFUSE_TRANSMISSION,
    ] {
        let ctx = BsdfContext::importance().with_lobes(lobes);
        for model in thins() {
            for _ in 0..40 {
                let batch = Batch::<4>::draw(&mut rng, true);
                let mut lanes = model.lanes(&batch.wl);
                vary_thin(&mut lanes, &mut rng);
                st.merge(compare_once(&ctx, &batch, &lanes));
            }
        }
    }
    st.check("principledthin, single lobes");
}

#[cfg(feature = "lane-dispatch-tests")]
struct ThinAtDispatchWidth<'a> {
    model: &'a PrincipledThin,
    seed: u64,
}

#[cfg(feature = "lane-dispatch-tests")]
impl LaneKernel for ThinAtDispatchWidth<'_> {
    type Output = Stats;
    #[inline(always)]
    fn run<const N: usize, X: Isa>(self) -> Stats {
        let mut rng = Pcg32::new(self.seed, 3);
        let mut st = Stats::default();
        for round in 0..300 {
            let batch = Batch::<N, X>::draw(&mut rng, true);
            let mut lanes = self.model.lanes(&batch.wl);
            if round % 2 == 1 {
                vary_thin(&mut lanes, &mut rng);
            }
            st.merge(compare(&BsdfContext::radiance(), &batch, &lanes));
        }
        st
    }
}

#[test]
#[cfg(feature = "lane-dispatch-tests")]
fn principledthin_lanes_agree_at_the_dispatched_width() {
    let mut st = Stats::default();
    for (i, model) in thins().iter().enumerate() {
        st.merge(dispatch(ThinAtDispatchWidth {
            model,
            seed: 80 + i as u64,
        }));
    }
    st.check("principledthin, dispatched width");
}
