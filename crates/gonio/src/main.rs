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
enum Command {}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: anyhow::Result<ExitCode> = match cli.command {};
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("gonio: {e:#}");
            ExitCode::from(2)
        }
    }
}
