//! `gonio`: the command line. Each subcommand lives in `cmd/<name>.rs` with its clap `Args` and
//! a `run(args) -> anyhow::Result<ExitCode>`; this file only dispatches.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

mod cmd;

#[derive(Parser)]
#[command(name = "gonio", version, about = "Physically based reflection models: render, query and measure BSDFs")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Compare two images: relMSE, RMSE, MAE, block relMSE, worst block; exit 1 past a threshold.
    Compare(cmd::compare::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: anyhow::Result<ExitCode> = match cli.command {
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
