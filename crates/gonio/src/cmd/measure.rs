//! `gonio measure BSDF -o TABLE`: the virtual gonioreflectometer
//! (`gonio_core::instruments::gonioreflectometer`). A collimated source at each incident angle,
//! photons traced to the specimen and scattered, a detector of finite aperture moved over the
//! hemisphere counting them, optional detector noise. The table (format in
//! `gonio_render::tabulated_io`, `docs/instruments.md`) plays back as `<bsdf type="tabulated">`.
//!
//! The specimen is the BSDF itself, or with `--heightfield N` a periodic N × N heightfield of
//! microfacets made of that BSDF (random heights up to `--amplitude`, or with `--alpha` a
//! Gaussian surface with Beckmann slope statistics), traced by the
//! instrument's own small intersector: multiple scattering and shadowing included; or with
//! `--spheres` a half-space sparsely filled with spheres whose surface is that BSDF.

use crate::cmd::plot::{bsdf_label, load};
use anyhow::{anyhow, bail};
use clap::Args as ClapArgs;
use glam::Vec2;
use gonio_core::Bsdf;
use gonio_core::instruments::gonioreflectometer::{
    BsdfSpecimen, GonioSettings, HeightfieldSpecimen, IncidentReadings, Sample, SphereHalfSpaceSpecimen,
    assemble, measure_incident,
};
use gonio_render::tabulated_io::write_tabulated;
use rayon::prelude::*;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

/// Arguments of `gonio measure`.
#[derive(ClapArgs)]
pub struct Args {
    /// The BSDF (or the facet material with --heightfield): a Mitsuba `<bsdf>` element, inline or
    /// a file.
    bsdf: String,
    /// The table to write.
    #[arg(short, long)]
    output: PathBuf,
    /// Number of source angles θi (midpoints of 90°/N).
    #[arg(long, default_value_t = 9)]
    incident: usize,
    /// Number of detector polar angles θo (midpoints of 90°/M).
    #[arg(long, default_value_t = 9)]
    outgoing: usize,
    /// Number of detector azimuths φd over [0°, 180°], ends included.
    #[arg(long, default_value_t = 19)]
    azimuths: usize,
    /// Half-angle of the detector's acceptance cone, degrees.
    #[arg(long, default_value_t = 3.0)]
    aperture: f32,
    /// Relative detector noise σ: each reading × (1 + σ·N(0, 1)).
    #[arg(long, default_value_t = 0.0)]
    noise: f32,
    /// Photons per source angle.
    #[arg(long, default_value_t = 1_000_000)]
    photons: u64,
    /// Wavelengths, nm, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "450,550,650")]
    lambda: Vec<f32>,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Measure an N × N periodic heightfield of facets made of the BSDF instead of the BSDF.
    #[arg(long)]
    heightfield: Option<usize>,
    /// Height range of the heightfield, in units of its period (uniform random heights).
    #[arg(long, default_value_t = 0.25, conflicts_with = "alpha")]
    amplitude: f32,
    /// Make the heightfield a Gaussian random surface whose facet slopes follow Beckmann's
    /// distribution of roughness ALPHA: the surface `roughconductor` models (N ≥ 256 advised).
    #[arg(long, requires = "heightfield")]
    alpha: Option<f32>,
    /// Measure a half-space sparsely filled with spheres whose surface is the BSDF (d'Eon 2021).
    #[arg(long, conflicts_with = "heightfield")]
    spheres: bool,
}

/// Runs `gonio measure`.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let settings = GonioSettings {
        incident: a.incident,
        outgoing: a.outgoing,
        azimuths: a.azimuths,
        aperture_deg: a.aperture,
        photons: a.photons,
        noise: a.noise,
        wavelengths: a.lambda.clone(),
        seed: a.seed,
    };
    settings
        .validate()
        .map_err(|e| anyhow!("bad measurement settings: {e}"))?;
    for &l in &a.lambda {
        crate::cmd::plot::check_lambda("--lambda", l)?;
    }
    let label = bsdf_label(&a.bsdf);
    let m = load(&a.bsdf)?;
    if m.is_textured() {
        bail!("{label}: a textured BSDF varies over the surface; measure an untextured one");
    }
    let table = m.with_bsdf(|b: &dyn Bsdf| -> anyhow::Result<_> {
        let specimen: Box<dyn Sample + '_> = match a.heightfield {
            None if a.spheres => Box::new(SphereHalfSpaceSpecimen::new(
                Arc::new(Borrowed(b)),
                10_000,
                label.clone(),
            )),
            None => Box::new(BsdfSpecimen::new(b, label.clone())),
            Some(n) => {
                if !(1..=256).contains(&n) {
                    bail!("--heightfield {n}: must be within [1, 256] cells");
                }
                if !(a.amplitude >= 0.0 && a.amplitude.is_finite()) {
                    bail!("--amplitude {}: must be finite and ≥ 0", a.amplitude);
                }
                let facet: Arc<dyn Bsdf> = Arc::new(Borrowed(b));
                Box::new(match a.alpha {
                    Some(alpha) => {
                        if n < 32 || !(alpha > 0.0 && alpha.is_finite()) {
                            bail!("--alpha {alpha} with --heightfield {n}: need α > 0 and N ≥ 32");
                        }
                        HeightfieldSpecimen::gaussian(n, alpha, a.seed, facet, label.clone())
                            .ok_or_else(|| anyhow!("invalid heightfield"))?
                    }
                    None => HeightfieldSpecimen::random(n, a.amplitude, a.seed, facet, label.clone())
                        .ok_or_else(|| anyhow!("invalid heightfield"))?,
                })
            }
        };
        let readings: Vec<IncidentReadings> = (0..settings.incident)
            .into_par_iter()
            .map(|i| measure_incident(specimen.as_ref(), &settings, i))
            .collect();
        assemble(specimen.as_ref(), &settings, readings).map_err(|e| anyhow!(e))
    })?;
    write_tabulated(&a.output, &table)?;
    let err = table.stderr.as_deref().unwrap_or(&[]);
    let (mut rel, mut n) = (0.0f64, 0usize);
    for (v, e) in table.values.iter().zip(err) {
        if *v > 0.0 {
            rel += (*e / *v) as f64;
            n += 1;
        }
    }
    let max = table.values.iter().copied().fold(0.0f32, f32::max);
    writeln!(
        std::io::stdout().lock(),
        "{}: {} readings (θi {} × θo {} × φd {} × λ {}), max f = {max:.4} 1/sr, mean relative standard error {:.2} %",
        a.output.display(),
        table.values.len(),
        table.theta_i_deg.len(),
        table.theta_o_deg.len(),
        table.phi_d_deg.len(),
        table.wavelengths_nm.len(),
        if n > 0 { 100.0 * rel / n as f64 } else { 0.0 },
    )?;
    Ok(ExitCode::SUCCESS)
}

/// A borrowed BSDF shared as `Arc<dyn Bsdf>` for the duration of a measurement.
struct Borrowed<'a>(&'a dyn Bsdf);

impl Bsdf for Borrowed<'_> {
    fn flags(&self) -> gonio_core::BsdfFlags {
        self.0.flags()
    }
    fn pdf_is_exact(&self) -> bool {
        self.0.pdf_is_exact()
    }
    fn eval(
        &self,
        ctx: &gonio_core::BsdfContext,
        wi: glam::Vec3,
        wo: glam::Vec3,
        wl: &gonio_core::SampledWavelengths,
    ) -> gonio_core::SampledSpectrum {
        self.0.eval(ctx, wi, wo, wl)
    }
    fn pdf(
        &self,
        ctx: &gonio_core::BsdfContext,
        wi: glam::Vec3,
        wo: glam::Vec3,
        wl: &gonio_core::SampledWavelengths,
    ) -> f32 {
        self.0.pdf(ctx, wi, wo, wl)
    }
    fn sample(
        &self,
        ctx: &gonio_core::BsdfContext,
        wi: glam::Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut gonio_core::SampledWavelengths,
    ) -> Option<gonio_core::BsdfSample> {
        self.0.sample(ctx, wi, u1, u2, wl)
    }
}
