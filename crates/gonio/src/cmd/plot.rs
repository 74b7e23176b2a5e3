//! `gonio plot fresnel|slice|polar|albedo|microfacet-albedo`: the lecture's BRDF plots as PNG and
//! SVG (`retroreflection` and `saturation` in [`super::plot_diffuse`], `stokes` in
//! [`super::plot_stokes`]).
//!
//! Every subcommand takes `-o PATH`: `PATH.png` or `PATH.svg` writes that format, a path
//! without an extension writes both. The written files are printed on stdout. A BSDF argument is
//! a Mitsuba `<bsdf>` element, inline (starting with `<`) or the path of a file holding one, or
//! a table measured by `gonio measure` (played back by the `tabulated` BSDF).
//! See `docs/instruments.md`.

use crate::cmd::bsdf::load_material;
use anyhow::{Context, anyhow, bail};
use clap::{Args as ClapArgs, Subcommand, ValueEnum};
use glam::Vec2;
use gonio_core::bsdfs::Tabulated;
use gonio_core::color::{cie_xyz, d65, linear_srgb_from_xyz, srgb_encode};
use gonio_core::instruments::albedo::{Wavelengths, directional_albedo};
use gonio_core::instruments::polar::compute_polar;
use gonio_core::instruments::slice::{Fixed, Projection, SliceSettings, compute_slice};
use gonio_core::{SampledWavelengths, TransportMode, named};
use gonio_plot::{Figure, Panel, figures};
use gonio_render::material::Material;
use gonio_render::output::write_atomically;
use gonio_render::tabulated_io::read_tabulated;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `gonio plot`.
#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    kind: Kind,
}

#[derive(Subcommand)]
enum Kind {
    /// Fresnel curves: R_s, R_p, R against angle (both sides, Brewster's and the critical angle
    /// marked), thin slab; dispersion of a glass; conductors against angle and wavelength; the
    /// degree of polarization of reflected and transmitted light and the retardance of
    /// reflection (total internal reflection, metals) against angle.
    Fresnel(FresnelArgs),
    /// A 2D slice of the BSDF over the hemisphere: fix the light or the view, vary the other.
    Slice(SliceArgs),
    /// Lobes in the plane of incidence, several BSDFs overlaid.
    Polar(PolarArgs),
    /// Directional albedo R(θ) and T(θ) with standard errors, several BSDFs.
    Albedo(AlbedoArgs),
    /// The energy single-scattering microfacets lose: albedo of a white rough conductor against
    /// roughness, Beckmann and GGX, at several incident angles (deterministic quadrature).
    MicrofacetAlbedo(MicrofacetAlbedoArgs),
    /// In-plane BRDF of Lambert, Oren–Nayar, diffuse microfacets and Lambertian spheres at
    /// grazing incidence, same reflectance: the retro-reflection of rough and porous surfaces.
    Retroreflection(super::plot_diffuse::RetroArgs),
    /// Reflectance spectra of `diffuse`, `roughdiffuse` and `lambertsphere` at the same k_d:
    /// multiple scattering saturates colour.
    Saturation(super::plot_diffuse::SaturationArgs),
    /// Albedo against roughness of a white rough conductor and a rough dielectric, single
    /// scattering against `multiple_scattering` (Heitz et al. 2016).
    MultipleScattering(super::plot_diffuse::MultipleArgs),
    /// False-colour PNGs of a Stokes EXR (channels S0.R … S3.B, Mitsuba's `stokes` integrator):
    /// S1, S2, S3 over S0 (diverging), degrees of linear and total polarization, angle of linear
    /// polarization (cyclic).
    Stokes(super::plot_stokes::StokesArgs),
}

#[derive(ClapArgs)]
struct MicrofacetAlbedoArgs {
    /// Incident angles, degrees (each within [0, 90)).
    #[arg(long, value_delimiter = ',', default_value = "0,45,80")]
    theta: Vec<f32>,
    /// Number of roughness values over [0.01, 1].
    #[arg(long, default_value_t = 25)]
    steps: usize,
    /// Also print the numbers (distribution θ α E) on stdout.
    #[arg(long)]
    print: bool,
    /// Output file (.png, .svg, or no extension for both).
    #[arg(short, long, default_value = "microfacet-albedo")]
    output: PathBuf,
}

#[derive(ClapArgs)]
#[group(required = true, multiple = false)]
struct FresnelSource {
    /// Relative index of a dielectric (a number, or a Mitsuba preset name such as `bk7`).
    #[arg(long)]
    ior: Option<String>,
    /// A dispersive glass by name (N-BK7, fused silica, SF11, ...): Sellmeier n(λ).
    #[arg(long)]
    ior_spectrum: Option<String>,
    /// A conductor by its Mitsuba `material` name (Au, Ag, Al, Cu, Cr, CuZn, W).
    #[arg(long)]
    material: Option<String>,
}

#[derive(ClapArgs)]
struct FresnelArgs {
    #[command(flatten)]
    source: FresnelSource,
    /// Output file (.png, .svg, or no extension for both).
    #[arg(short, long, default_value = "fresnel")]
    output: PathBuf,
}

#[derive(Clone, Copy, ValueEnum)]
enum FixArg {
    Light,
    View,
}

#[derive(Clone, Copy, ValueEnum)]
enum ProjectionArg {
    EqualArea,
    Parabolic,
}

#[derive(ClapArgs)]
struct SliceArgs {
    /// The BSDF: a Mitsuba `<bsdf>` element (inline or a file) or a measured table file.
    bsdf: String,
    /// Which direction is fixed.
    #[arg(long, value_enum, default_value_t = FixArg::Light)]
    fix: FixArg,
    /// Polar angle of the fixed direction, degrees (0–180; > 90 is below the surface).
    #[arg(long, default_value_t = 30.0)]
    theta: f32,
    /// Azimuth of the fixed direction, degrees.
    #[arg(long, default_value_t = 0.0)]
    phi: f32,
    /// Multiply by |cos θ| of the varying direction.
    #[arg(long)]
    cosine: bool,
    /// Show log10(1 + value) (Disney BRDF Explorer's log plot).
    #[arg(long)]
    log: bool,
    /// One wavelength, nm (default 550).
    #[arg(long, conflicts_with = "rgb")]
    lambda: Option<f32>,
    /// Show the colour of π·f under D65 (sRGB) instead of one wavelength.
    #[arg(long)]
    rgb: bool,
    /// Disk projection.
    #[arg(long, value_enum, default_value_t = ProjectionArg::EqualArea)]
    projection: ProjectionArg,
    /// Pixels across each disk.
    #[arg(long, default_value_t = 256)]
    resolution: usize,
    /// Output file (.png, .svg, or no extension for both).
    #[arg(short, long, default_value = "slice")]
    output: PathBuf,
}

#[derive(ClapArgs)]
struct PolarArgs {
    /// One or more BSDFs (Mitsuba `<bsdf>` elements, inline or files, or measured tables).
    #[arg(required = true)]
    bsdfs: Vec<String>,
    /// Polar angle of the light, degrees.
    #[arg(long, default_value_t = 30.0)]
    theta_i: f32,
    /// Multiply by |cos θo|.
    #[arg(long)]
    cosine: bool,
    /// Show log10(1 + value).
    #[arg(long)]
    log: bool,
    /// Wavelength, nm.
    #[arg(long, default_value_t = 550.0)]
    lambda: f32,
    /// Output file (.png, .svg, or no extension for both).
    #[arg(short, long, default_value = "polar")]
    output: PathBuf,
}

#[derive(Clone, Copy, ValueEnum)]
enum ModeArg {
    Radiance,
    Importance,
}

#[derive(ClapArgs)]
struct AlbedoArgs {
    /// One or more BSDFs (Mitsuba `<bsdf>` elements, inline or files, or measured tables).
    #[arg(required = true)]
    bsdfs: Vec<String>,
    /// Monte Carlo samples per angle.
    #[arg(long, default_value_t = 20_000)]
    samples: usize,
    /// Angle step, degrees.
    #[arg(long, default_value_t = 5.0)]
    step: f32,
    /// One wavelength, nm (default: the mean over 360–830 nm).
    #[arg(long)]
    lambda: Option<f32>,
    /// Transport mode (importance: fractions of power; radiance: refraction scaled by η²).
    #[arg(long, value_enum, default_value_t = ModeArg::Importance)]
    mode: ModeArg,
    /// Light from below the surface (z < 0).
    #[arg(long)]
    back: bool,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Also print the numbers (θ R σ_R T σ_T) on stdout.
    #[arg(long)]
    print: bool,
    /// Output file (.png, .svg, or no extension for both).
    #[arg(short, long, default_value = "albedo")]
    output: PathBuf,
}

/// Runs `gonio plot`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match args.kind {
        Kind::Fresnel(a) => fresnel(a),
        Kind::Slice(a) => slice(a),
        Kind::Polar(a) => polar(a),
        Kind::Albedo(a) => albedo(a),
        Kind::MicrofacetAlbedo(a) => microfacet_albedo(a),
        Kind::Retroreflection(a) => super::plot_diffuse::retroreflection(a),
        Kind::Saturation(a) => super::plot_diffuse::saturation(a),
        Kind::MultipleScattering(a) => super::plot_diffuse::multiple_scattering(a),
        Kind::Stokes(a) => super::plot_stokes::stokes(a),
    }
}

/// Encodes a figure as `path` asks (`gonio_plot::encode`) and writes each file atomically.
/// Returns the files written.
pub(crate) fn save(figure: &Figure, path: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = vec![];
    for (file, bytes) in gonio_plot::encode(figure, path)? {
        write_atomically(&file, &bytes)?;
        files.push(file);
    }
    Ok(files)
}

pub(crate) fn written(files: Vec<PathBuf>) -> anyhow::Result<ExitCode> {
    let mut out = std::io::stdout().lock();
    for f in files {
        writeln!(out, "{}", f.display())?;
    }
    Ok(ExitCode::SUCCESS)
}

fn fresnel(a: FresnelArgs) -> anyhow::Result<ExitCode> {
    let fig = if let Some(ior) = &a.source.ior {
        let (eta, name) = match ior.trim().parse::<f32>() {
            Ok(v) => (v, "dielectric".to_string()),
            Err(_) => (
                named::ior_preset(ior).ok_or_else(|| {
                    anyhow!(
                        "--ior {ior}: not a number nor a known IOR name ({})",
                        named::ior_preset_names().join(", ")
                    )
                })?,
                ior.clone(),
            ),
        };
        if !(eta.is_finite() && eta > 1.0) {
            bail!(
                "--ior {ior}: the relative index must be a finite number > 1 (the inside view is drawn too)"
            );
        }
        figures::fresnel_dielectric_figure(eta, &name)
    } else if let Some(g) = &a.source.ior_spectrum {
        let s = named::glass(g).ok_or_else(|| {
            anyhow!(
                "--ior-spectrum {g}: unknown glass ({})",
                named::glass_names().join(", ")
            )
        })?;
        figures::fresnel_dispersive_figure(&s, g)
    } else if let Some(m) = &a.source.material {
        let (eta, k) = named::conductor(m).ok_or_else(|| {
            anyhow!(
                "--material {m}: unknown conductor ({})",
                named::conductor_names().join(", ")
            )
        })?;
        figures::fresnel_conductor_figure(&eta, &k, m)
    } else {
        bail!("give one of --ior, --ior-spectrum, --material");
    };
    written(save(&fig, &a.output)?)
}

/// Checks a wavelength argument: within the visible range the spectra are defined on.
pub fn check_lambda(flag: &str, l: f32) -> anyhow::Result<()> {
    if !(360.0..=830.0).contains(&l) {
        bail!("{flag} {l}: the wavelength must be within [360, 830] nm");
    }
    Ok(())
}

/// A short name for a BSDF argument: its file stem, or the `type` of an inline element.
pub fn bsdf_label(arg: &str) -> String {
    let t = arg.trim_start();
    if t.starts_with('<') {
        if let Some(i) = t.find("type=") {
            let rest = &t[i + 5..];
            let q = rest.chars().next().unwrap_or('"');
            if let Some(end) = rest[1..].find(q) {
                return rest[1..1 + end].to_string();
            }
        }
        return "bsdf".into();
    }
    std::path::Path::new(arg)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| arg.into())
}

/// A loaded BSDF argument: a Mitsuba `<bsdf>` element, or a measured table (a file starting
/// with `gonio-tabulated`, as `gonio measure` writes), played back by the `tabulated` BSDF.
pub enum Loaded {
    /// A material of the scene reader.
    Material(Material),
    /// A measured table.
    Table(Box<Tabulated>),
}

impl Loaded {
    /// Calls `f` with the BSDF (materials at uv = (0.5, 0.5)).
    pub fn with_bsdf<R>(&self, f: impl FnOnce(&dyn gonio_core::Bsdf) -> R) -> R {
        match self {
            Loaded::Material(m) => m.with_bsdf(Vec2::splat(0.5), f),
            Loaded::Table(t) => f(t.as_ref()),
        }
    }

    /// True when the BSDF varies over the surface (a textured material).
    pub fn is_textured(&self) -> bool {
        matches!(self, Loaded::Material(m) if m.is_textured())
    }
}

/// Loads a BSDF argument: inline `<bsdf>`, a file holding one, or a measured table file.
pub fn load(arg: &str) -> anyhow::Result<Loaded> {
    let trimmed = arg.trim_start();
    if !trimmed.starts_with('<') {
        let path = std::path::Path::new(arg);
        let mut head = [0u8; 15];
        let is_table = std::fs::File::open(path)
            .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head))
            .map(|_| &head == b"gonio-tabulated")
            .unwrap_or(false);
        if is_table {
            let data = read_tabulated(path)?;
            return Ok(Loaded::Table(Box::new(Tabulated::new(data))));
        }
    }
    Ok(Loaded::Material(
        load_material(arg).with_context(|| format!("loading BSDF {}", bsdf_label(arg)))?,
    ))
}

fn slice(a: SliceArgs) -> anyhow::Result<ExitCode> {
    if !(0.0..=180.0).contains(&a.theta) {
        bail!("--theta {}: must be within [0, 180] degrees", a.theta);
    }
    if !(8..=2048).contains(&a.resolution) {
        bail!("--resolution {}: must be within [8, 2048]", a.resolution);
    }
    if let Some(l) = a.lambda {
        check_lambda("--lambda", l)?;
    }
    let m = load(&a.bsdf)?;
    let name = bsdf_label(&a.bsdf);
    let settings = SliceSettings {
        fixed: match a.fix {
            FixArg::Light => Fixed::Light,
            FixArg::View => Fixed::View,
        },
        theta_deg: a.theta,
        phi_deg: a.phi,
        cosine: a.cosine,
        resolution: a.resolution,
        projection: match a.projection {
            ProjectionArg::EqualArea => Projection::EqualArea,
            ProjectionArg::Parabolic => Projection::Parabolic,
        },
    };
    let panel = m.with_bsdf(|b| {
        if a.rgb {
            rgb_slice_panel(b, &settings, &name)
        } else {
            let l = a.lambda.unwrap_or(550.0);
            let s = compute_slice(b, &settings, &SampledWavelengths::fixed(l));
            figures::slice_panel(&s, &name, a.log, &format!("λ = {l} nm"))
        }
    });
    let width = if panel.disks.len() > 1 { 1100 } else { 760 };
    written(save(
        &Figure::single(Panel::Hemisphere(panel), (width, 580)),
        &a.output,
    )?)
}

/// The colour of π·f under D65: 16 wavelengths from 380 to 780 nm, XYZ by the CIE observer,
/// linear sRGB scaled so the brightest channel is at most 1, then sRGB-encoded.
fn rgb_slice_panel(
    b: &dyn gonio_core::Bsdf,
    settings: &SliceSettings,
    name: &str,
) -> gonio_plot::HemispherePlot {
    const N: usize = 16;
    let lambdas: Vec<f32> = (0..N)
        .map(|k| 380.0 + (k as f32 + 0.5) * 400.0 / N as f32)
        .collect();
    let mut xyz: Vec<Vec<Option<glam::Vec3>>> = vec![];
    let mut first = None;
    let norm: f32 = lambdas.iter().map(|&l| cie_xyz(l).y * d65(l)).sum();
    for chunk in lambdas.chunks(4) {
        let wl = SampledWavelengths::from_parts([chunk[0], chunk[1], chunk[2], chunk[3]], [1.0; 4]);
        let s = compute_slice(b, settings, &wl);
        if xyz.is_empty() {
            xyz = s
                .disks
                .iter()
                .map(|d| d.pixels.iter().map(|p| p.map(|_| glam::Vec3::ZERO)).collect())
                .collect();
        }
        for (acc, d) in xyz.iter_mut().zip(&s.disks) {
            for (a, p) in acc.iter_mut().zip(&d.pixels) {
                if let (Some(a), Some(v)) = (a.as_mut(), p) {
                    for (c, &l) in chunk.iter().enumerate() {
                        *a += cie_xyz(l) * d65(l) * v[c] * std::f32::consts::PI / norm;
                    }
                }
            }
        }
        first.get_or_insert(s);
    }
    let rgb: Vec<Vec<Option<[f32; 3]>>> = xyz
        .iter()
        .map(|d| {
            d.iter()
                .map(|p| p.map(|x| linear_srgb_from_xyz(x).max(glam::Vec3::ZERO).to_array()))
                .collect()
        })
        .collect();
    let peak = rgb
        .iter()
        .flatten()
        .flatten()
        .flat_map(|c| c.iter().copied())
        .fold(0.0f32, f32::max);
    let scale = if peak > 1.0 { 1.0 / peak } else { 1.0 };
    let display = rgb
        .into_iter()
        .map(|d| {
            d.into_iter()
                .map(|p| p.map(|c| c.map(|v| srgb_encode(v * scale))))
                .collect()
        })
        .collect();
    let slice = first.expect("16 wavelengths make 4 batches");
    let note = if scale < 1.0 {
        format!("colour of π·f under D65, sRGB, scaled by {scale:.3}")
    } else {
        "colour of π·f under D65, sRGB".to_string()
    };
    figures::slice_panel_rgb(&slice, display, name, &note)
}

fn polar(a: PolarArgs) -> anyhow::Result<ExitCode> {
    if !(0.0..90.0).contains(&a.theta_i) {
        bail!("--theta-i {}: must be within [0, 90) degrees", a.theta_i);
    }
    check_lambda("--lambda", a.lambda)?;
    let wl = SampledWavelengths::fixed(a.lambda);
    let mut lobes = vec![];
    for arg in &a.bsdfs {
        let m = load(arg)?;
        let lobe = m.with_bsdf(|b| compute_polar(b, a.theta_i, 721, a.cosine, &wl));
        lobes.push((bsdf_label(arg), lobe));
    }
    let fig = figures::polar_figure(&lobes, a.log, &format!("λ = {} nm", a.lambda));
    written(save(&fig, &a.output)?)
}

fn albedo(a: AlbedoArgs) -> anyhow::Result<ExitCode> {
    if !(a.step > 0.0 && a.step <= 90.0) {
        bail!("--step {}: must be within (0, 90] degrees", a.step);
    }
    if a.samples < 2 {
        bail!("--samples {}: need at least 2", a.samples);
    }
    let mut thetas = vec![];
    let mut t = 0.0f32;
    while t < 90.0 {
        thetas.push(t);
        t += a.step;
    }
    thetas.push(89.5);
    let mode = match a.mode {
        ModeArg::Radiance => TransportMode::Radiance,
        ModeArg::Importance => TransportMode::Importance,
    };
    if let Some(l) = a.lambda {
        check_lambda("--lambda", l)?;
    }
    let wls = match a.lambda {
        Some(l) => Wavelengths::Fixed(l),
        None => Wavelengths::Visible,
    };
    let mut curves = vec![];
    for arg in &a.bsdfs {
        let m = load(arg)?;
        let pts = m.with_bsdf(|b| directional_albedo(b, &thetas, a.samples, mode, wls, a.back, a.seed));
        if a.print {
            println!("# {}: theta_deg R R_stderr T T_stderr", bsdf_label(arg));
            for p in &pts {
                println!(
                    "{} {:.6} {:.6} {:.6} {:.6}",
                    p.theta_deg, p.r, p.r_stderr, p.t, p.t_stderr
                );
            }
        }
        curves.push((bsdf_label(arg), pts));
    }
    let note = format!(
        "{} samples per angle, {} mode, {}{}; bars: ±1 standard error",
        a.samples,
        if mode == TransportMode::Radiance {
            "radiance"
        } else {
            "importance"
        },
        match a.lambda {
            Some(l) => format!("λ = {l} nm"),
            None => "mean over 360–830 nm".into(),
        },
        if a.back { ", light from below" } else { "" }
    );
    written(save(&figures::albedo_figure(&curves, &note), &a.output)?)
}

fn microfacet_albedo(a: MicrofacetAlbedoArgs) -> anyhow::Result<ExitCode> {
    use gonio_core::instruments::microfacet_albedo::{albedo_vs_roughness, alpha_grid};
    use gonio_core::microfacet::MicrofacetKind;
    if let Some(t) = a.theta.iter().find(|t| !(0.0..90.0).contains(*t)) {
        bail!("--theta {t}: each angle must be within [0, 90) degrees");
    }
    if !(2..=400).contains(&a.steps) {
        bail!("--steps {}: must be within [2, 400]", a.steps);
    }
    let curves = albedo_vs_roughness(
        &[MicrofacetKind::Beckmann, MicrofacetKind::Ggx],
        &a.theta,
        &alpha_grid(0.01, 1.0, a.steps),
    );
    if a.print {
        println!("# distribution theta_deg alpha E");
        for c in &curves {
            for (alpha, e) in &c.points {
                println!("{} {} {alpha:.4} {e:.6}", c.kind.name(), c.theta_deg);
            }
        }
    }
    written(save(&figures::microfacet_energy_figure(&curves), &a.output)?)
}
