//! `gonio compare a.exr b.exr [--diff diff.png] [--max-relmse X] [--block N]`: error metrics of
//! image `a` against reference `b` (definitions in `gonio_render::compare`), an optional
//! false-colour difference image, and a pass/fail exit status.
//!
//! Exit status: 0 when within the threshold (or none given), 1 past it (or when either image has
//! non-finite pixels and a threshold is given), 2 on bad input (unreadable file, different sizes).

use anyhow::{Context, Result};
use clap::Args as ClapArgs;
use gonio_render::compare::{RELMSE_EPS, compare, diff_image};
use gonio_render::image::RgbImage;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `gonio compare`.
#[derive(ClapArgs, Debug)]
pub struct Args {
    /// The image under test (EXR, HDR, PNG or JPEG).
    pub a: PathBuf,
    /// The reference image.
    pub b: PathBuf,
    /// Write a false-colour picture of the relative difference (PNG, or EXR by extension).
    #[arg(long)]
    pub diff: Option<PathBuf>,
    /// Fail (exit status 1) when the per-pixel relMSE exceeds this.
    #[arg(long)]
    pub max_relmse: Option<f64>,
    /// Fail (exit status 1) when the relMSE of block means exceeds this.
    #[arg(long)]
    pub max_block_relmse: Option<f64>,
    /// Block size for the block relMSE and the worst block.
    #[arg(long, default_value_t = 8)]
    pub block: usize,
}

/// Runs `gonio compare`.
pub fn run(args: Args) -> Result<ExitCode> {
    let a = RgbImage::read(&args.a)?;
    let b = RgbImage::read(&args.b)?;
    let m = compare(&a, &b, args.block)
        .with_context(|| format!("comparing {} with {}", args.a.display(), args.b.display()))?;
    println!("size          {} x {}", m.size.0, m.size.1);
    println!(
        "relMSE        {:.6e}   (mean of (a-b)^2 / (b^2 + {RELMSE_EPS}))",
        m.relmse
    );
    println!(
        "relMSE {0}x{0}    {1:.6e}   (of {0}x{0} block means)",
        args.block, m.block_relmse
    );
    println!("RMSE          {:.6e}", m.rmse);
    println!("MAE           {:.6e}", m.mae);
    println!(
        "mean a        {:.6} {:.6} {:.6}",
        m.mean_a[0], m.mean_a[1], m.mean_a[2]
    );
    println!(
        "mean b        {:.6} {:.6} {:.6}",
        m.mean_b[0], m.mean_b[1], m.mean_b[2]
    );
    println!(
        "worst block   x {} y {} ({}x{}), relMSE of its mean {:.6e}",
        m.worst.x, m.worst.y, m.worst.size, m.worst.size, m.worst.relmse
    );
    if m.non_finite > 0 {
        println!("non-finite    {} pixels (excluded above)", m.non_finite);
    }
    if let Some(path) = &args.diff {
        diff_image(&a, &b)?.write(path)?;
        println!("diff          {}", path.display());
    }
    let mut fail = false;
    if let Some(t) = args.max_relmse
        && exceeds(m.relmse, t)
    {
        println!("FAIL: relMSE {:.6e} > {t:e}", m.relmse);
        fail = true;
    }
    if let Some(t) = args.max_block_relmse
        && exceeds(m.block_relmse, t)
    {
        println!("FAIL: block relMSE {:.6e} > {t:e}", m.block_relmse);
        fail = true;
    }
    if m.non_finite > 0 && (args.max_relmse.is_some() || args.max_block_relmse.is_some()) {
        println!("FAIL: {} non-finite pixels", m.non_finite);
        fail = true;
    }
    Ok(if fail {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// `v > t`, with NaN counting as past any threshold.
fn exceeds(v: f64, t: f64) -> bool {
    v.is_nan() || v > t
}
