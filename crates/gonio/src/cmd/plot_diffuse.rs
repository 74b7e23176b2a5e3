//! `gonio plot retroreflection|saturation|multiple-scattering`: the lecture's figures on
//! generalizations of the ideal diffuse BRDF (Lambert, Oren–Nayar, Heitz et al. 2016 diffuse
//! microfacets, d'Eon 2021 Lambertian spheres) and on the energy multiple scattering restores
//! to rough conductors and dielectrics, as PNG and SVG.

use super::plot::{check_lambda, load, save, written};
use anyhow::bail;
use clap::Args as ClapArgs;
use glam::{Quat, Vec2, Vec3};
use gonio_core::color::{cie_xyz, d65, linear_srgb_from_xyz, srgb_encode};
use gonio_core::instruments::albedo::{Wavelengths, directional_albedo};
use gonio_core::instruments::polar::compute_polar;
use gonio_core::{
    Bsdf, BsdfContext, BsdfFlags, BsdfSample, SampledSpectrum, SampledWavelengths, TransportMode,
};
use gonio_plot::diffuse_figures::{
    Curve, retroreflection_figure, saturation_figure, scattering_order_figure,
};
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `gonio plot retroreflection`.
#[derive(ClapArgs)]
pub struct RetroArgs {
    /// Incident angles, degrees (each within [0, 90)); one panel each.
    #[arg(long, value_delimiter = ',', default_value = "60,80")]
    theta: Vec<f32>,
    /// The `reflectance` of every material (k_d), within [0, 1].
    #[arg(long, default_value_t = 0.8)]
    reflectance: f32,
    /// The `alpha` (RMS slope) of both `roughdiffuse` models.
    #[arg(long, default_value_t = 1.0)]
    alpha: f32,
    /// Independent estimates averaged per angle for stochastic models (diffuse microfacets).
    #[arg(long, default_value_t = 4096)]
    estimates: usize,
    /// Wavelength, nm.
    #[arg(long, default_value_t = 550.0)]
    lambda: f32,
    /// Output file (.png, .svg, or no extension for both).
    #[arg(short, long, default_value = "retroreflection")]
    output: PathBuf,
}

/// Arguments of `gonio plot saturation`.
#[derive(ClapArgs)]
pub struct SaturationArgs {
    /// k_d as linear sRGB, three numbers within [0, 1] (upsampled to a spectrum as Mitsuba does).
    #[arg(long, default_value = "0.75,0.35,0.12")]
    reflectance: String,
    /// The `alpha` of the diffuse microfacets.
    #[arg(long, default_value_t = 1.0)]
    alpha: f32,
    /// Angle of incidence, degrees.
    #[arg(long, default_value_t = 0.0)]
    theta: f32,
    /// Monte Carlo samples per wavelength.
    #[arg(long, default_value_t = 20_000)]
    samples: usize,
    /// Also print the numbers (material λ albedo) on stdout.
    #[arg(long)]
    print: bool,
    /// Output file (.png, .svg, or no extension for both).
    #[arg(short, long, default_value = "saturation")]
    output: PathBuf,
}

/// Arguments of `gonio plot multiple-scattering`.
#[derive(ClapArgs)]
pub struct MultipleArgs {
    /// Incident angles, degrees (each within [0, 90)).
    #[arg(long, value_delimiter = ',', default_value = "0,60")]
    theta: Vec<f32>,
    /// Number of roughness values over [0.05, 1].
    #[arg(long, default_value_t = 12)]
    steps: usize,
    /// Monte Carlo samples per point.
    #[arg(long, default_value_t = 20_000)]
    samples: usize,
    /// Relative index of the dielectric.
    #[arg(long, default_value_t = 1.5)]
    eta: f32,
    /// Output file (.png, .svg, or no extension for both).
    #[arg(short, long, default_value = "multiple-scattering-albedo")]
    output: PathBuf,
}

/// An isotropic BSDF whose `eval` is the mean over `n` rotations of both directions about the
/// normal: the same value in expectation (an exact symmetry of an isotropic BSDF), and for a
/// stochastic model (seeded by its arguments) the mean of `n` independent estimates.
struct RotationAveraged<'a> {
    inner: &'a dyn Bsdf,
    n: usize,
}

impl Bsdf for RotationAveraged<'_> {
    fn flags(&self) -> BsdfFlags {
        self.inner.flags()
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let mut sum = SampledSpectrum::ZERO;
        for k in 0..self.n {
            let q = Quat::from_rotation_z(std::f32::consts::TAU * (k as f32 + 0.5) / self.n as f32);
            sum += self.inner.eval(ctx, q * wi, q * wo, wl);
        }
        sum * (1.0 / self.n as f32)
    }
    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        self.inner.pdf(ctx, wi, wo, wl)
    }
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        self.inner.sample(ctx, wi, u1, u2, wl)
    }
}

/// The four materials compared, as Mitsuba elements with a common reflectance value.
fn materials(reflectance: &str, alpha: f32) -> Vec<(String, String)> {
    vec![
        (
            "diffuse (Lambert)".into(),
            format!(r#"<bsdf type="diffuse">{reflectance}</bsdf>"#),
        ),
        (
            format!("roughdiffuse Oren–Nayar, α = {alpha}"),
            format!(r#"<bsdf type="roughdiffuse"><float name="alpha" value="{alpha}"/>{reflectance}</bsdf>"#),
        ),
        (
            format!("roughdiffuse microfacet (Beckmann, α = {alpha})"),
            format!(
                r#"<bsdf type="roughdiffuse"><string name="model" value="microfacet"/><float name="alpha" value="{alpha}"/>{reflectance}</bsdf>"#
            ),
        ),
        (
            "lambertsphere (d'Eon 2021)".into(),
            format!(r#"<bsdf type="lambertsphere">{reflectance}</bsdf>"#),
        ),
    ]
}

/// Runs `gonio plot retroreflection`.
pub fn retroreflection(a: RetroArgs) -> anyhow::Result<ExitCode> {
    if let Some(t) = a.theta.iter().find(|t| !(0.0..90.0).contains(*t)) {
        bail!("--theta {t}: each angle must be within [0, 90) degrees");
    }
    if !(0.0..=1.0).contains(&a.reflectance) {
        bail!("--reflectance {}: must be within [0, 1]", a.reflectance);
    }
    if !(a.alpha >= 0.0 && a.alpha.is_finite()) {
        bail!("--alpha {}: must be a finite number ≥ 0", a.alpha);
    }
    if !(1..=100_000).contains(&a.estimates) {
        bail!("--estimates {}: must be within [1, 100000]", a.estimates);
    }
    check_lambda("--lambda", a.lambda)?;
    let wl = SampledWavelengths::fixed(a.lambda);
    let rho = format!(r#"<float name="reflectance" value="{}"/>"#, a.reflectance);
    let mut panels = vec![];
    for &theta in &a.theta {
        let mut curves: Vec<Curve> = vec![];
        for (label, xml) in materials(&rho, a.alpha) {
            let m = load(&xml)?;
            let lobe = m.with_bsdf(|b| {
                let n = if b.pdf_is_exact() { 1 } else { a.estimates };
                compute_polar(&RotationAveraged { inner: b, n }, theta, 181, false, &wl)
            });
            let pts = lobe
                .angles_deg
                .iter()
                .zip(&lobe.values)
                .filter(|(x, _)| x.abs() < 89.9)
                .map(|(&x, v)| (x as f64, v[0] as f64))
                .collect();
            curves.push((label, pts));
        }
        panels.push((theta, curves));
    }
    let note = format!(
        "reflectance = {} for all; λ = {} nm; microfacet curves: mean of {} estimates per angle",
        a.reflectance, a.lambda, a.estimates
    );
    written(save(&retroreflection_figure(&panels, &note), &a.output)?)
}

/// Runs `gonio plot saturation`.
pub fn saturation(a: SaturationArgs) -> anyhow::Result<ExitCode> {
    let rgb: Vec<f32> = a
        .reflectance
        .split(',')
        .map(|s| s.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| anyhow::anyhow!("--reflectance {}: {e}", a.reflectance))?;
    if rgb.len() != 3 || rgb.iter().any(|v| !(0.0..=1.0).contains(v)) {
        bail!("--reflectance {}: three numbers within [0, 1]", a.reflectance);
    }
    if !(0.0..90.0).contains(&a.theta) {
        bail!("--theta {}: must be within [0, 90) degrees", a.theta);
    }
    if a.samples < 2 {
        bail!("--samples {}: need at least 2", a.samples);
    }
    let value = format!(
        r#"<rgb name="reflectance" value="{}, {}, {}"/>"#,
        rgb[0], rgb[1], rgb[2]
    );
    let lambdas: Vec<f32> = (0..=32).map(|k| 380.0 + 12.5 * k as f32).collect();
    let mut curves: Vec<Curve> = vec![];
    for (label, xml) in materials(&value, a.alpha) {
        let m = load(&xml)?;
        let mut pts = vec![];
        for (k, &l) in lambdas.iter().enumerate() {
            let p = m.with_bsdf(|b| {
                directional_albedo(
                    b,
                    &[a.theta],
                    a.samples,
                    TransportMode::Importance,
                    Wavelengths::Fixed(l),
                    false,
                    k as u64,
                )
            });
            pts.push((l as f64, p[0].r));
        }
        if a.print {
            for (l, r) in &pts {
                println!("{label}\t{l}\t{r:.5}");
            }
        }
        let [r, g, b] = srgb_of(&pts);
        curves.push((format!("{label}: sRGB ({r}, {g}, {b})"), pts));
    }
    let note = format!(
        "k_d = linear sRGB ({}) for all; θi = {}°; {} samples per wavelength; legend: the colour under D65",
        a.reflectance, a.theta, a.samples
    );
    written(save(&saturation_figure(&curves, &note), &a.output)?)
}

/// 8-bit sRGB of a reflectance spectrum (λ, value) lit by D65 (white = a perfect reflector).
fn srgb_of(pts: &[(f64, f64)]) -> [u8; 3] {
    let (mut xyz, mut norm) = (Vec3::ZERO, 0.0f32);
    for &(l, v) in pts {
        let w = cie_xyz(l as f32) * d65(l as f32);
        xyz += w * v as f32;
        norm += w.y;
    }
    let rgb = linear_srgb_from_xyz(xyz / norm.max(1e-12));
    rgb.to_array()
        .map(|c| (srgb_encode(c.clamp(0.0, 1.0)) * 255.0).round() as u8)
}

/// Runs `gonio plot multiple-scattering`: the directional albedo of a white GGX rough conductor
/// (R) and of a rough dielectric (R + T, importance mode) against α, single scattering (Mitsuba's
/// models) and with `multiple_scattering` (Heitz et al. 2016), by sampling.
pub fn multiple_scattering(a: MultipleArgs) -> anyhow::Result<ExitCode> {
    use gonio_core::Ior;
    use gonio_core::bsdfs::{RoughConductor, RoughDielectric};
    use gonio_core::instruments::microfacet_albedo::alpha_grid;
    use gonio_core::microfacet::{MicrofacetDistribution, MicrofacetKind};
    if let Some(t) = a.theta.iter().find(|t| !(0.0..90.0).contains(*t)) {
        bail!("--theta {t}: each angle must be within [0, 90) degrees");
    }
    if !(2..=200).contains(&a.steps) {
        bail!("--steps {}: must be within [2, 200]", a.steps);
    }
    if a.samples < 2 {
        bail!("--samples {}: need at least 2", a.samples);
    }
    if !(a.eta > 1.0 && a.eta.is_finite()) {
        bail!("--eta {}: must be a finite number > 1", a.eta);
    }
    let alphas = alpha_grid(0.05, 1.0, a.steps);
    let albedo = |b: &dyn Bsdf, theta: f32, seed: u64| {
        let p = directional_albedo(
            b,
            &[theta],
            a.samples,
            TransportMode::Importance,
            Wavelengths::Fixed(550.0),
            false,
            seed,
        );
        p[0].r + p[0].t
    };
    let mut conductor: Vec<Curve> = vec![];
    let mut dielectric: Vec<Curve> = vec![];
    for &theta in &a.theta {
        for ms in [false, true] {
            let order = if ms { "multiple" } else { "single" };
            let (mut c, mut d) = (vec![], vec![]);
            for (k, &alpha) in alphas.iter().enumerate() {
                let distr = MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, alpha);
                let mut rc = RoughConductor::mirror(distr);
                rc.multiple_scattering = ms;
                let mut rd = RoughDielectric::new(Ior::Constant(a.eta), Ior::Constant(1.0), distr);
                rd.multiple_scattering = ms;
                c.push((alpha as f64, albedo(&rc, theta, k as u64)));
                d.push((alpha as f64, albedo(&rd, theta, k as u64)));
            }
            conductor.push((format!("θ = {theta}°, {order}"), c));
            dielectric.push((format!("θ = {theta}°, {order}"), d));
        }
    }
    let panels = [
        ("White rough conductor (F = 1): R".to_string(), conductor),
        (format!("Rough dielectric η = {}: R + T", a.eta), dielectric),
    ];
    let note = format!(
        "GGX; solid: single scattering, dashed: multiple_scattering (Heitz et al. 2016); {} samples per point, λ = 550 nm",
        a.samples
    );
    written(save(&scattering_order_figure(&panels, &note), &a.output)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use gonio_core::bsdfs::RoughDiffuse;

    #[test]
    fn rotation_average_keeps_an_isotropic_bsdf() {
        let m = RoughDiffuse::default();
        let avg = RotationAveraged { inner: &m, n: 7 };
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = BsdfContext::radiance();
        let (wi, wo) = (Vec3::new(0.6, 0.0, 0.8), Vec3::new(-0.3, 0.4, 0.866_025_4));
        let (a, b) = (m.eval(&ctx, wi, wo, &wl)[0], avg.eval(&ctx, wi, wo, &wl)[0]);
        assert!((a - b).abs() < 1e-5 * a, "{a} vs {b}");
    }

    #[test]
    fn white_and_black_spectra_are_white_and_black() {
        let flat = |v: f64| (0..=32).map(|k| (380.0 + 12.5 * k as f64, v)).collect::<Vec<_>>();
        // 33 samples of D65 and the observer: the white point within 2/255.
        assert!(
            srgb_of(&flat(1.0)).iter().all(|&c| c >= 253),
            "{:?}",
            srgb_of(&flat(1.0))
        );
        assert_eq!(srgb_of(&flat(0.0)), [0, 0, 0]);
    }
}
