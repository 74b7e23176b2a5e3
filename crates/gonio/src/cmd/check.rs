//! `gonio check BSDF [--json] [--quick]`: the property report of a BSDF — energy, reciprocity
//! (and the η² law), isotropy, sampling (χ²), consistency of weight/pdf/eval, numerical health.
//!
//! This is a thin front end over `gonio_core::check::battery`, the same code the test suite
//! runs: one implementation. One row per check with the measured figure, the threshold and the
//! verdict; exit status 0 when every row passes, 1 when one fails, 2 on bad input.

use crate::cmd::plot::{bsdf_label, load};
use clap::Args as ClapArgs;
use gonio_core::check::{Bound, CheckConfig, CheckResult, all_passed, battery};
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

fn json_str(s: &str) -> String {
    let mut o = String::with_capacity(s.len() + 2);
    o.push('"');
    for c in s.chars() {
        match c {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            '\n' => o.push_str("\\n"),
            '\t' => o.push_str("\\t"),
            c if (c as u32) < 0x20 => o.push_str(&format!("\\u{:04x}", c as u32)),
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

fn json_num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        json_str(&x.to_string())
    }
}

/// The report as JSON: `{"bsdf": ..., "passed": bool, "rows": [{"name", "figure", "bound",
/// "threshold", "passed", "detail"}, ...]}`; a non-finite figure is a string ("NaN", "inf").
pub fn to_json(bsdf: &str, rows: &[CheckResult], passed: bool) -> String {
    let rows: Vec<String> = rows
        .iter()
        .map(|r| {
            format!(
                r#"{{"name": {}, "figure": {}, "bound": {}, "threshold": {}, "passed": {}, "detail": {}}}"#,
                json_str(r.name),
                json_num(r.figure),
                json_str(match r.bound {
                    Bound::AtMost => "at_most",
                    Bound::AtLeast => "at_least",
                }),
                json_num(r.threshold),
                r.passed,
                json_str(&r.detail)
            )
        })
        .collect();
    format!(
        "{{\"bsdf\": {}, \"passed\": {passed}, \"rows\": [\n  {}\n]}}",
        json_str(bsdf),
        rows.join(",\n  ")
    )
}
