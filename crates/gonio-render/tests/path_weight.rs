//! The path tracer is generic over what a path carries (`gonio_core::weight::Weight`), the room
//! polarization needs: a stand-in weight with a second, "polarized" component (which every
//! depolarizing BSDF and emitter leaves at zero) gives exactly the spectral path tracer's
//! radiance in its first component and zero in the second, over paths through every BSDF kind
//! the reference scenes use (diffuse, conductor, dielectric, thin sheets, plastic, two-sided).

use glam::Vec2;
use glam::Vec3;
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::rng::Pcg32;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{Bsdf, BsdfContext, BsdfSample, SampledSpectrum, SampledWavelengths};
use gonio_render::integrator::caustics::LightSubpath;
use gonio_render::render::PreparedScene;
use gonio_render::xml::load_scene_file;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign};

/// (intensity, polarized part): a depolarizing element is diag(f, 0).
#[derive(Clone, Copy, Debug, PartialEq)]
struct TwoComponent(SampledSpectrum, SampledSpectrum);

impl Mul for TwoComponent {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        TwoComponent(self.0 * o.0, self.1 * o.1)
    }
}
impl MulAssign for TwoComponent {
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}
impl Mul<f32> for TwoComponent {
    type Output = Self;
    fn mul(self, k: f32) -> Self {
        TwoComponent(self.0 * k, self.1 * k)
    }
}
impl MulAssign<f32> for TwoComponent {
    fn mul_assign(&mut self, k: f32) {
        *self = *self * k;
    }
}
impl Div<f32> for TwoComponent {
    type Output = Self;
    fn div(self, k: f32) -> Self {
        TwoComponent(self.0 / k, self.1 / k)
    }
}
impl DivAssign<f32> for TwoComponent {
    fn div_assign(&mut self, k: f32) {
        *self = *self / k;
    }
}
impl Add for TwoComponent {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        TwoComponent(self.0 + o.0, self.1 + o.1)
    }
}
impl AddAssign for TwoComponent {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}
impl Weight for TwoComponent {
    const ZERO: Self = TwoComponent(SampledSpectrum::ZERO, SampledSpectrum::ZERO);
    const ONE: Self = TwoComponent(SampledSpectrum::ONE, SampledSpectrum::ONE);
    fn from_spectrum(s: SampledSpectrum) -> Self {
        TwoComponent(s, SampledSpectrum::ZERO)
    }
    fn intensity(self) -> SampledSpectrum {
        self.0
    }
}

impl BsdfWeight<TwoComponent> for SurfaceBsdf<'_> {
    fn eval_weight(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> TwoComponent {
        TwoComponent::from_spectrum(self.eval(ctx, wi, wo, wl))
    }
    fn sample_weight(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<TwoComponent>> {
        self.sample(ctx, wi, u1, u2, wl).map(|s| BsdfSample {
            wo: s.wo,
            weight: TwoComponent::from_spectrum(s.weight),
            pdf: s.pdf,
            flags: s.flags,
            eta: s.eta,
        })
    }
    fn null_transmission_weight(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<TwoComponent> {
        self.null_transmission(wi, wl).map(TwoComponent::from_spectrum)
    }
}

#[test]
fn path_tracer_generic_weight_equals_the_spectral_one() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../testdata/mitsuba/scenes/");
    for name in ["materials", "cornell-spheres", "thin-vs-thick"] {
        let scene = load_scene_file(format!("{root}{name}.xml"), &[]).unwrap();
        let prepared = PreparedScene::new(scene).unwrap();
        let pt = prepared.integrator();
        let camera = prepared.camera();
        let (w, h) = prepared.size();
        let mut nonzero = 0;
        for k in 0..400u32 {
            let film = Vec2::new((k * 37 % w) as f32 + 0.5, (k * 53 % h) as f32 + 0.5);
            let ray = camera.generate_ray(film);
            let wl = SampledWavelengths::sample_visible((k as f32 + 0.5) / 400.0);
            let (mut wa, mut wb) = (wl, wl);
            let (mut ra, mut rb) = (Pcg32::new(k as u64, 1), Pcg32::new(k as u64, 1));
            let light = LightSubpath::new();
            let a: SampledSpectrum = pt.li(ray, &mut ra, &mut wa, &light);
            let b: TwoComponent = pt.li(ray, &mut rb, &mut wb, &light);
            assert_eq!(a, b.0, "{name}: sample {k}");
            assert_eq!(b.1, SampledSpectrum::ZERO, "{name}: sample {k}");
            assert_eq!(wa, wb);
            nonzero += !a.is_black() as u32;
        }
        assert!(nonzero > 100, "{name}: only {nonzero} paths carried light");
    }
}
