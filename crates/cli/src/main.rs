//! `flapwing`: the command-line tool of the flapwing workspace.
//!
//! Exit codes: 0 ok, 1 the run failed, 2 bad input (see `error.rs` and the crate README).

mod cli;
mod commands;
mod condition;
mod error;
mod flight_input;
mod input;
mod interrupt;
mod logging;
mod output;
mod outputs;
mod pacing;
mod plot;
mod progress;
mod sensing;
mod slurm;
mod vehicle;
mod wind;

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

use crate::cli::{Cli, Command};

fn main() -> ExitCode {
    // Bad flags: clap prints its own `error: ...` with usage and exits with 2.
    let cli = Cli::parse();
    interrupt::install();
    let result = match cli.command {
        Command::WakeCapture(args) => commands::wake_capture::run(args),
        Command::Forces(args) => commands::forces::run(args),
        Command::Validate(args) => commands::validate::run(args),
        Command::Simulate(args) => commands::simulate::run(args),
        Command::Trim(args) => commands::trim::run(args),
        Command::Stability(args) => commands::stability::run(args),
        Command::Envelope(args) => commands::envelope::run(args),
        Command::Hover(args) => commands::hover::run(args),
        Command::FitWake(args) => commands::fit_wake::run(args),
        Command::Sweep(args) => commands::sweep::run(args),
        Command::Optimize(args) => commands::optimize::run(args),
        Command::Submit(args) => commands::submit::run(args),
        Command::Status(args) => commands::status::run(args),
        Command::Replay(args) => commands::replay::run(args),
        Command::Identify(args) => commands::identify::run(args),
        Command::FrequencyResponse(args) => commands::frequency_response::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Not eprintln!: it panics if stderr is closed.
            let _ = writeln!(std::io::stderr(), "error: {e:#}");
            ExitCode::from(error::exit_code(&e))
        }
    }
}
