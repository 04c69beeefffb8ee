//! The command line: the clap [`Cli`] struct, one [`Command`] variant per subcommand, and
//! the value parsers that reject bad numbers before any command runs (clap exits with 2).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

/// Quasi-steady blade-element aerodynamics of flapping wings, with the seed paper's
/// wake-capture term.
#[derive(Debug, Parser)]
#[command(name = "flapwing", version, propagate_version = true)]
pub struct Cli {
    /// The subcommand to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Evaluate the paper's wake-capture regressions (eq 17-19) at given Re, dtau_A, dtau_D.
    WakeCapture(WakeCaptureArgs),
    /// Cycle-mean lift and drag coefficients of each force term of a wing on a fixed mount.
    Forces(ForcesArgs),
    /// Check every published number the model must reproduce; exits 1 if any case fails.
    Validate(ValidateArgs),
    /// Fly (or tether) a vehicle for a while and summarise the run.
    Simulate(crate::commands::simulate::SimulateArgs),
    /// Find the trim (hover, or --speed-m-s / --climb-m-s): amplitude, mean stroke angle and body pitch that balance.
    Trim(crate::commands::trim::TrimArgs),
    /// Stability about a trim (hover, or --speed-m-s / --climb-m-s): averaged-model modes and Floquet exponents.
    Stability(crate::commands::stability::StabilityArgs),
    /// The flight envelope: trim, power, limit margin and modes over a grid of speeds and climb rates.
    Envelope(crate::commands::envelope::EnvelopeArgs),
    /// The main job: trimmed, controlled hover from a disturbance (or open loop).
    Hover(crate::commands::hover::HoverArgs),
    /// Refit the paper's wake-capture regressions (eq 17-19) to a CSV of runs.
    FitWake(crate::commands::fit_wake::FitWakeArgs),
    /// Run a parameter study (full factorial, Latin hypercube or Taguchi) in parallel to CSV.
    Sweep(crate::commands::sweep::SweepArgs),
    /// Maximize lift per aerodynamic power over a study's factors while supporting the weight.
    Optimize(crate::commands::optimize::OptimizeArgs),
    /// Run a sweep's shards as a Slurm job array (sbatch), recording the job in the output directory.
    Submit(crate::commands::submit::SubmitArgs),
    /// Done, running, pending, failed and missing shards of the studies in a directory.
    Status(crate::commands::status::StatusArgs),
    /// Frequency response of a tethered actuated vehicle: stroke, pitch, phase and lift per drive frequency.
    FrequencyResponse(crate::commands::frequency_response::FrequencyResponseArgs),
    /// Summarize an MCAP log; convert it (--rrd), export a channel (--csv) or re-run it (--check).
    Replay(crate::commands::replay::ReplayArgs),
    /// Fit model parameters (inertia, CoM offset, ...) to a logged flight (MCAP or a motion-capture CSV), with confidence intervals; write the fitted model.
    Identify(crate::commands::identify::IdentifyArgs),
}

/// Arguments of `flapwing wake-capture`.
#[derive(Debug, Args)]
pub struct WakeCaptureArgs {
    /// Reynolds number, Re = V_ref c_bar / nu (the paper's definition).
    #[arg(long, value_parser = parse_reynolds)]
    pub re: f64,
    /// Acceleration time at the start of a half stroke, fraction of the period, in (0, 0.5).
    #[arg(long = "dtau-a", value_parser = parse_dtau)]
    pub dtau_a: f64,
    /// Deceleration time at the end of a half stroke, fraction of the period, in (0, 0.5).
    #[arg(long = "dtau-d", value_parser = parse_dtau)]
    pub dtau_d: f64,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `flapwing forces`.
#[derive(Debug, Args)]
pub struct ForcesArgs {
    /// Wing model file (TOML). Default: the built-in robofly model (models/robofly.toml,
    /// the paper's run V3), so the command works from any directory. A vehicle (a built-in
    /// name: drosophila, bumblebee, robobee_kinematic, dragonfly, robobee, hummingbird; or a
    /// vehicle model file) gives its left wing on a fixed mount, with the vehicle's
    /// aerodynamic options and induced flow; an actuated vehicle's wing on the periodic
    /// motion its drive gives it.
    #[arg(long, value_name = "FILE|VEHICLE")]
    pub model: Option<PathBuf>,
    /// A vehicle's wing pair, from 1 (the model file's first pair; the dragonfly's 2 is its
    /// hind pair). Default: 1.
    #[arg(long, value_name = "N")]
    pub pair: Option<usize>,
    /// Reynolds number Re = V_ref c_bar / nu; sets the fluid's viscosity (overrides the model).
    #[arg(long, value_parser = parse_reynolds)]
    pub re: Option<f64>,
    /// Acceleration fraction dtau_A of trapezoidal kinematics, in (0, 0.5) (overrides the model).
    #[arg(long = "dtau-a", value_parser = parse_dtau)]
    pub dtau_a: Option<f64>,
    /// Deceleration fraction dtau_D of trapezoidal kinematics, in (0, 0.5) (overrides the model).
    #[arg(long = "dtau-d", value_parser = parse_dtau)]
    pub dtau_d: Option<f64>,
    /// Number of wingbeats to evaluate; the means are those of the last one [default: 3]
    /// (prescribed kinematics only).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub cycles: Option<u32>,
    /// Time steps per wingbeat (forces are sampled at the middle of each step) [default:
    /// 1000] (prescribed kinematics only).
    #[arg(long = "steps-per-cycle",
          value_parser = clap::value_parser!(u32).range(2..=10_000_000))]
    pub steps_per_cycle: Option<u32>,
    /// Switch the wake-capture term off.
    #[arg(long = "no-wake-capture")]
    pub no_wake_capture: bool,
    /// Write the time series of every term's C_L and C_D to this CSV file.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Draw C_L(t*) and C_D(t*) with and without wake capture over one wingbeat (the paper's
    /// Fig 23-24) to this SVG file (PNG when it ends in .png; other extensions are refused).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Replace the --csv or --plot file if it already exists.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `flapwing validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Print one JSON document on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Check only these sections (repeat the flag, or separate with commas) [default: all
    /// three]. The paper's cases take a fraction of a second; the vehicles against measured
    /// data most of the run's seconds.
    #[arg(long, value_enum, value_delimiter = ',', value_name = "SECTION")]
    pub section: Vec<ValidateSection>,
}

/// A section of `flapwing validate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ValidateSection {
    /// The published numbers the aerodynamics reproduces (MODEL.md section 5, the seed
    /// paper's tables, Dickinson et al. 1999).
    Cases,
    /// The built-in insects at their published operating points.
    OperatingPoints,
    /// Every built-in vehicle against measured data, under the responsive and the frozen wake.
    Vehicles,
}

fn parse_finite(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number"))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("{x} is not allowed: a finite number is required"))
    }
}

/// A Reynolds number: finite and > 0.
pub fn parse_reynolds(s: &str) -> Result<f64, String> {
    let re = parse_finite(s)?;
    if re > 0.0 {
        Ok(re)
    } else {
        Err(format!("{re} is not allowed: Re must be > 0"))
    }
}

/// An acceleration or deceleration fraction of the period: finite and in (0, 0.5).
pub fn parse_dtau(s: &str) -> Result<f64, String> {
    let d = parse_finite(s)?;
    if d > 0.0 && d < 0.5 {
        Ok(d)
    } else {
        Err(format!(
            "{d} is not allowed: a fraction of the period in (0, 0.5)"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn number_parsers_reject_bad_values() {
        assert_eq!(parse_reynolds("1360"), Ok(1360.0));
        for bad in ["0", "-5", "nan", "inf", "abc", ""] {
            assert!(parse_reynolds(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_dtau("0.12"), Ok(0.12));
        for bad in ["0", "0.5", "-0.1", "NaN", "x"] {
            assert!(parse_dtau(bad).is_err(), "{bad}");
        }
    }
}
