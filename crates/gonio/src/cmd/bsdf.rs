//! `gonio bsdf eval|sample|albedo BSDF`: scriptable queries of one BSDF.
//!
//! The BSDF is a Mitsuba `<bsdf>` element, inline (an argument starting with `<`) or a file.
//! Queries are whitespace-separated lines on stdin, one output line per input line, in the local
//! frame (z = normal), Mitsuba's naming (wi = arrived from, wo = sampled/evaluated):
//!
//! | command  | input line                                   | output line                        |
//! |----------|----------------------------------------------|------------------------------------|
//! | `eval`   | `wi_x wi_y wi_z wo_x wo_y wo_z lambda_nm`    | `f pdf` (f without the cosine)     |
//! | `eval --mueller` | the same                             | 16 numbers: the Mueller matrix of f, row by row |
//! | `sample` | `wi_x wi_y wi_z lambda_nm u1 u2x u2y`        | `wo_x wo_y wo_z weight pdf flags`  |
//! | `albedo` | `wi_x wi_y wi_z lambda_nm`                   | `R T` (delta lobes exact)          |
//!
//! `--mueller` prints the polarized value, the 4 × 4 Mueller matrix of f (no cosine), row by
//! row, in Mitsuba 3's convention: from the implicit Stokes basis (`stokes_basis`) of the incident
//! light's travel direction to that of the outgoing light's, in the local frame (radiance mode:
//! light travels along −wo and leaves along wi; see `gonio_core::mueller`). Its first element is
//! `f`; a depolarizing model prints diag(f, 0, 0, 0).
//!
//! Blank lines and lines starting with `#` are skipped (no output). A bad line prints a message
//! naming the line on stderr and exits with status 2. Output is flushed whenever the input
//! buffer runs dry, so the command can be driven interactively through a pipe.

use anyhow::{Context, bail};
use clap::{Args as ClapArgs, Subcommand, ValueEnum};
use glam::{Vec2, Vec3};
use gonio_core::albedo::directional_albedo;
use gonio_core::{Bsdf, BsdfContext, SampledWavelengths, TransportMode};
use gonio_render::material::Material;
use std::io::{BufRead, BufWriter, Write};
use std::process::ExitCode;

/// Arguments of `gonio bsdf`.
#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    query: Query,
}

#[derive(Subcommand)]
enum Query {
    /// `wi wo lambda_nm` → `f pdf` per line (f without the cosine); with `--mueller`, the 16
    /// elements of f's Mueller matrix, row by row.
    Eval {
        #[command(flatten)]
        common: Common,
        /// Print the polarized value: 16 numbers per query (Mitsuba's Stokes bases).
        #[arg(long)]
        mueller: bool,
    },
    /// `wi lambda_nm u1 u2x u2y` → `wo weight pdf flags` per line.
    Sample(Common),
    /// `wi lambda_nm` → `R T` per line: directional albedo, delta lobes exact.
    Albedo {
        #[command(flatten)]
        common: Common,
        /// Smooth lobes: this many stratified importance samples (rounded up to a square).
        #[arg(long, default_value_t = 65536)]
        samples: usize,
    },
}

#[derive(ClapArgs)]
struct Common {
    /// A Mitsuba `<bsdf>` element, inline (starting with `<`) or the path of a file holding one.
    bsdf: String,
    /// Transport mode: radiance (refraction scaled by η²) or importance.
    #[arg(long, value_enum, default_value_t = Mode::Radiance)]
    mode: Mode,
}

#[derive(Clone, Copy, ValueEnum)]
enum Mode {
    Radiance,
    Importance,
}

impl From<Mode> for TransportMode {
    fn from(m: Mode) -> Self {
        match m {
            Mode::Radiance => TransportMode::Radiance,
            Mode::Importance => TransportMode::Importance,
        }
    }
}

/// Loads the `<bsdf>` argument: inline XML or a file.
pub fn load_material(arg: &str) -> anyhow::Result<Material> {
    let trimmed = arg.trim_start();
    if trimmed.starts_with('<') {
        return gonio_render::xml::load_bsdf_str(trimmed).map_err(|e| anyhow::anyhow!("{e}"));
    }
    let text = std::fs::read_to_string(arg).with_context(|| format!("cannot read BSDF file {arg}"))?;
    gonio_render::xml::load_bsdf_str(&text).map_err(|e| anyhow::anyhow!("{arg}: {e}"))
}

/// Runs `gonio bsdf`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let (common, kind) = match &args.query {
        Query::Eval { common, mueller } => (common, if *mueller { Kind::EvalMueller } else { Kind::Eval }),
        Query::Sample(c) => (c, Kind::Sample),
        Query::Albedo { common, samples } => (common, Kind::Albedo((*samples as f64).sqrt().ceil() as usize)),
    };
    let material = load_material(&common.bsdf)?;
    let ctx = BsdfContext {
        mode: common.mode.into(),
        ..BsdfContext::default()
    };
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    material.with_bsdf(Vec2::splat(0.5), |bsdf| {
        serve(bsdf, &ctx, kind, stdin.lock(), stdout.lock())
    })
}

#[derive(Clone, Copy)]
enum Kind {
    Eval,
    EvalMueller,
    Sample,
    Albedo(usize),
}

fn serve(
    bsdf: &dyn Bsdf,
    ctx: &BsdfContext,
    kind: Kind,
    mut input: impl BufRead,
    output: impl Write,
) -> anyhow::Result<ExitCode> {
    let mut out = BufWriter::with_capacity(1 << 16, output);
    let mut line = String::new();
    let mut number = 0usize;
    loop {
        line.clear();
        if input.read_line(&mut line).context("reading stdin")? == 0 {
            break;
        }
        number += 1;
        let text = line.trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        match answer(bsdf, ctx, kind, text) {
            Ok(reply) => writeln!(out, "{reply}")?,
            Err(e) => {
                out.flush()?;
                eprintln!("gonio bsdf: stdin line {number}: {e}: {text:?}");
                return Ok(ExitCode::from(2));
            }
        }
        if input.fill_buf().map(|b| b.is_empty()).unwrap_or(true) {
            out.flush()?;
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

fn answer(bsdf: &dyn Bsdf, ctx: &BsdfContext, kind: Kind, text: &str) -> anyhow::Result<String> {
    let v = numbers(text)?;
    match kind {
        Kind::Eval => {
            expect_len(&v, 7, "wi_x wi_y wi_z wo_x wo_y wo_z lambda_nm")?;
            let wi = direction(&v[0..3], "wi")?;
            let wo = direction(&v[3..6], "wo")?;
            let wl = wavelength(v[6])?;
            let (f, pdf) = bsdf.eval_pdf(ctx, wi, wo, &wl);
            Ok(format!("{} {}", f[0], pdf))
        }
        Kind::EvalMueller => {
            expect_len(&v, 7, "wi_x wi_y wi_z wo_x wo_y wo_z lambda_nm")?;
            let wi = direction(&v[0..3], "wi")?;
            let wo = direction(&v[3..6], "wo")?;
            let wl = wavelength(v[6])?;
            let m = bsdf.eval_mueller(ctx, wi, wo, &wl);
            let elements: Vec<String> = (0..16)
                .map(|k| format!("{}", m.get(k / 4, k % 4)[0] + 0.0))
                .collect();
            Ok(elements.join(" "))
        }
        Kind::Sample => {
            expect_len(&v, 7, "wi_x wi_y wi_z lambda_nm u1 u2x u2y")?;
            let wi = direction(&v[0..3], "wi")?;
            let mut wl = wavelength(v[3])?;
            let u = [v[4], v[5], v[6]];
            if u.iter().any(|x| !(0.0..1.0).contains(x)) {
                bail!("u1 u2x u2y must lie in [0, 1)");
            }
            Ok(
                match bsdf.sample(ctx, wi, u[0] as f32, Vec2::new(u[1] as f32, u[2] as f32), &mut wl) {
                    // `+ 0.0` prints −0 as 0.
                    Some(s) => format!(
                        "{} {} {} {} {} {}",
                        s.wo.x + 0.0,
                        s.wo.y + 0.0,
                        s.wo.z + 0.0,
                        s.weight[0],
                        s.pdf,
                        s.flags
                    ),
                    None => "0 0 0 0 0 none".to_string(),
                },
            )
        }
        Kind::Albedo(n) => {
            expect_len(&v, 4, "wi_x wi_y wi_z lambda_nm")?;
            let wi = direction(&v[0..3], "wi")?;
            let wl = wavelength(v[3])?;
            let a = directional_albedo(bsdf, ctx.mode, wi, &wl, n);
            Ok(format!("{} {}", a.r[0], a.t[0]))
        }
    }
}

fn numbers(text: &str) -> anyhow::Result<Vec<f64>> {
    text.split_whitespace()
        .map(|t| {
            t.parse::<f64>()
                .map_err(|_| anyhow::anyhow!("{t:?} is not a number"))
        })
        .collect()
}

fn expect_len(v: &[f64], n: usize, form: &str) -> anyhow::Result<()> {
    if v.len() != n {
        bail!("expected {n} numbers ({form}), got {}", v.len());
    }
    Ok(())
}

fn direction(v: &[f64], name: &str) -> anyhow::Result<Vec3> {
    let d = Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
    if !d.is_finite() || d.length_squared() == 0.0 {
        bail!("{name} = ({}, {}, {}) is not a direction", v[0], v[1], v[2]);
    }
    Ok(d.normalize())
}

fn wavelength(l: f64) -> anyhow::Result<SampledWavelengths> {
    if !(l.is_finite() && l > 0.0) {
        bail!("lambda_nm = {l} is not a wavelength");
    }
    Ok(SampledWavelengths::fixed(l as f32))
}

#[cfg(test)]
mod tests {
    use super::*;
    use gonio_core::bsdfs::Diffuse;

    fn run_lines(kind: Kind, input: &str) -> (ExitCode, String) {
        let d = Diffuse::default();
        let mut out = Vec::new();
        let code = serve(&d, &BsdfContext::default(), kind, input.as_bytes(), &mut out).unwrap();
        (code, String::from_utf8(out).unwrap())
    }

    #[test]
    fn eval_prints_lambert_value_and_pdf() {
        let (code, out) = run_lines(Kind::Eval, "0 0 1 0 0 1 550\n# comment\n\n0 0 1 0 0 -1 550\n");
        assert_eq!(code, ExitCode::SUCCESS);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 2);
        let v: Vec<f64> = lines[0].split(' ').map(|x| x.parse().unwrap()).collect();
        assert!((v[0] - 0.5 / std::f64::consts::PI).abs() < 1e-7);
        assert!((v[1] - 1.0 / std::f64::consts::PI).abs() < 1e-7);
        assert_eq!(lines[1], "0 0");
    }

    #[test]
    fn eval_mueller_prints_sixteen_numbers_whose_first_is_f() {
        // A Lambertian depolarizes: diag(f, 0, 0, 0).
        let (code, out) = run_lines(Kind::EvalMueller, "0 0 1 0.6 0 0.8 550\n");
        assert_eq!(code, ExitCode::SUCCESS);
        let v: Vec<f64> = out.trim().split(' ').map(|x| x.parse().unwrap()).collect();
        assert_eq!(v.len(), 16);
        assert!((v[0] - 0.5 / std::f64::consts::PI).abs() < 1e-7);
        assert!(v[1..].iter().all(|x| *x == 0.0), "{v:?}");
        // A smooth-ish gold conductor polarizes at oblique incidence: the line is its matrix,
        // row by row, and its M00 is eval's f.
        let m = gonio_render::xml::load_bsdf_str(
            r#"<bsdf type="roughconductor"><string name="material" value="Au"/><float name="alpha" value="0.3"/></bsdf>"#,
        )
        .unwrap();
        let (wi, wo) = (Vec3::new(0.6, 0.0, 0.8), Vec3::new(-0.5, 0.1, 0.86).normalize());
        let line = format!("{} {} {} {} {} {} 600", wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
        m.with_bsdf(Vec2::splat(0.5), |bsdf| {
            let ctx = BsdfContext::default();
            let reply = answer(bsdf, &ctx, Kind::EvalMueller, &line).unwrap();
            let v: Vec<f32> = reply.split(' ').map(|x| x.parse().unwrap()).collect();
            let wl = SampledWavelengths::fixed(600.0);
            let mm = bsdf.eval_mueller(&ctx, wi.normalize(), wo, &wl);
            for k in 0..16 {
                assert_eq!(v[k], mm.get(k / 4, k % 4)[0] + 0.0, "element {k}");
            }
            assert_eq!(v[0], bsdf.eval(&ctx, wi.normalize(), wo, &wl)[0]);
            assert!(v[1].abs() > 1e-4 * v[0], "polarizing: {v:?}");
        });
    }

    #[test]
    fn bad_line_stops_with_status_two() {
        let (code, out) = run_lines(Kind::Eval, "0 0 1 0 0 1 550\n0 0 1 x 0 1 550\n0 0 1 0 0 1 550\n");
        assert_eq!(code, ExitCode::from(2));
        assert_eq!(
            out.lines().count(),
            1,
            "answers before the bad line are kept, none after"
        );
        let (code, _) = run_lines(Kind::Sample, "0 0 1 550 0.5 1.5 0.5\n");
        assert_eq!(code, ExitCode::from(2), "u outside [0, 1)");
        let (code, _) = run_lines(Kind::Albedo(4), "0 0 0 550\n");
        assert_eq!(code, ExitCode::from(2), "zero direction");
    }

    #[test]
    fn sample_reports_direction_weight_and_flags() {
        let (_, out) = run_lines(Kind::Sample, "0 0 1 550 0.5 0.3 0.7\n");
        let f: Vec<&str> = out.trim().split(' ').collect();
        assert_eq!(f.len(), 6);
        assert!((f[0].parse::<f32>().unwrap() + 0.282843).abs() < 1e-5);
        assert_eq!(f[3], "0.5");
        assert_eq!(f[5], "reflection|diffuse");
    }
}
