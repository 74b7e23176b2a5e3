//! `gonio`: the command line. Each subcommand lives in `cmd/<name>.rs` with its clap `Args` and
//! a `run(args) -> anyhow::Result<ExitCode>`; this file only dispatches.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

mod cmd;

#[derive(Parser)]
#[command(
    name = "gonio",
    version,
    about = "Physically based reflection models: render, query and measure BSDFs"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Query one BSDF from stdin: eval, sample, albedo.
    Bsdf(cmd::bsdf::Args),
    /// Render a Mitsuba 3 XML scene (no scene: the embedded gallery of materials).
    Render(cmd::render::RenderArgs),
    /// Plot the lecture's instruments: fresnel, slice, polar, albedo (PNG and SVG).
    Plot(cmd::plot::Args),
    /// The property report of a BSDF (energy, reciprocity, isotropy, sampling, health); exit 1
    /// on a failure.
    Check(cmd::check::Args),
    /// A virtual gonioreflectometer: measure a BSDF (or a heightfield of it) into a table.
    Measure(cmd::measure::Args),
    /// The light stage: relight a scene from one-light-at-a-time renders weighted by an
    /// environment map, compared with a direct render.
    Relight(cmd::relight::Args),
    /// Compare two images: relMSE, RMSE, MAE, block relMSE, worst block; exit 1 past a threshold.
    Compare(cmd::compare::Args),
}

/// A closed stdout (`gonio compare a.exr b.exr | head -3`) ends the process quietly, as it does
/// for `cat` or `grep`, instead of `println!` panicking on EPIPE. Rust ignores SIGPIPE by default;
/// restore the default action. Output files are written atomically, so none is left half-written.
fn default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in main, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    default_sigpipe();
    let cli = Cli::parse();
    let result: anyhow::Result<ExitCode> = match cli.command {
        Command::Bsdf(args) => cmd::bsdf::run(args),
        Command::Render(args) => cmd::render::run(args),
        Command::Plot(args) => cmd::plot::run(args),
        Command::Check(args) => cmd::check::run(args),
        Command::Measure(args) => cmd::measure::run(args),
        Command::Relight(args) => cmd::relight::run(args),
        Command::Compare(args) => cmd::compare::run(args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("gonio: {e:#}");
            ExitCode::from(2)
        }
    }
}
