//! `gonio check BSDF [--json] [--quick]`: the property report of a BSDF — energy, reciprocity
//! (and the η² law), isotropy, sampling (χ²), consistency of weight/pdf/eval, numerical health.
//!
//! This is a thin front end over `gonio_core::check::battery`, the same code the test suite
//! runs: one implementation. One row per check with the measured figure, the threshold and the
//! verdict; exit status 0 when every row passes, 1 when one fails, 2 on bad input.

use crate::cmd::plot::{bsdf_label, load};
use clap::Args as ClapArgs;
use gonio_core::check::{CheckConfig, CheckResult, all_passed, battery};
use serde::Serialize;
use std::io::Write;
use std::process::ExitCode;

/// Arguments of `gonio check`.
#[derive(ClapArgs)]
pub struct Args {
    /// The BSDF: a Mitsuba `<bsdf>` element (inline or a file) or a measured table file.
    bsdf: String,
    /// Print the report as JSON (an array of rows) instead of a table.
    #[arg(long)]
    json: bool,
    /// 10× fewer samples and only independent uniforms in the χ² test (interactive use).
    #[arg(long)]
    quick: bool,
    /// Seed of the random streams.
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

/// Runs `gonio check`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let m = load(&args.bsdf)?;
    let mut config = if args.quick {
        CheckConfig::quick()
    } else {
        CheckConfig::default()
    };
    config.seed = args.seed;
    let rows = m.with_bsdf(|b| battery(b, &config));
    let ok = all_passed(&rows);
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", to_json(&bsdf_label(&args.bsdf), &rows, ok))?;
    } else {
        writeln!(
            out,
            "{:<4} {:<18} {:>12}    {:<12} detail",
            "", "check", "figure", "threshold"
        )?;
        for r in &rows {
            writeln!(out, "{r}")?;
        }
        let failed = rows.iter().filter(|r| !r.passed).count();
        writeln!(
            out,
            "{} rows: {} passed, {} failed",
            rows.len(),
            rows.len() - failed,
            failed
        )?;
    }
    Ok(if ok { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// The whole report, as `gonio check --json` prints it.
#[derive(Serialize)]
struct Report<'a> {
    bsdf: &'a str,
    passed: bool,
    rows: &'a [CheckResult],
}

/// The report as JSON: `{"bsdf": ..., "passed": bool, "rows": [{"name", "figure", "threshold",
/// "bound", "passed", "detail"}, ...]}`; a non-finite figure is a string ("NaN", "inf").
pub fn to_json(bsdf: &str, rows: &[CheckResult], passed: bool) -> String {
    serde_json::to_string_pretty(&Report { bsdf, passed, rows })
        .expect("a check report always serializes (string keys only)")
}
