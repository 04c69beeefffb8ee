//! `flapwing replay REAL --resimulate [MODEL]`: the model flown beside a recorded flight (a
//! flapwing log, a motion-capture CSV or a ROS 2 bag), segment by segment from its recorded
//! start states under its recorded inputs; the residuals per segment on stdout (or as JSON)
//! and both flights in one MCAP (`--mcap`) and Rerun recording (`--rrd`). The work is
//! flapwing-identify's `resimulate` and flightlog's `compare`; this file parses, calls and
//! prints.

use std::path::Path;

use anyhow::Result;
use flapwing_identify::{ResimOptions, resimulate};
use flightlog::compare::Comparison;

use crate::flight_input::classify;
use crate::output::{print_json, print_stdout};

/// `replay`'s resimulation flags.
#[derive(Debug, clap::Args)]
pub struct ResimArgs {
    /// Fly MODEL (a TOML file or a built-in name; given alone, a flapwing log's own model)
    /// beside the recorded flight, segment by segment from its recorded start states under
    /// its recorded inputs, and print the residuals per segment (position, attitude, rate
    /// RMS); `--mcap`/`--rrd` write both flights in one log.
    #[arg(long, value_name = "MODEL", num_args = 0..=1, default_missing_value = "", help_heading = "Resimulation")]
    pub resimulate: Option<String>,
    /// With --resimulate: wingbeats per segment.
    #[arg(
        long = "segment-wingbeats",
        default_value_t = 4,
        help_heading = "Resimulation"
    )]
    pub segment_wingbeats: u32,
    /// With --resimulate: whether each segment's start state is fitted (model held). auto:
    /// fitted when estimated from the motion capture (a bag, a CSV), held when logged.
    #[arg(
        long = "start-states",
        value_enum,
        default_value = "auto",
        help_heading = "Resimulation"
    )]
    pub start_states: crate::commands::identify::StartStatesArg,
    /// With --resimulate: only the first this many seconds of the flight.
    #[arg(long = "duration-s", help_heading = "Resimulation")]
    pub duration_s: Option<f64>,
    /// A ROS 2 bag's roles and conventions (for --resimulate).
    #[command(flatten)]
    pub roles: crate::flight_input::BagRoleArgs,
}

/// Runs `replay FILE --resimulate` (the outputs `mcap` and `rrd` are already checked).
pub fn run(
    file: &Path,
    args: &ResimArgs,
    mcap: Option<&Path>,
    rrd: Option<&Path>,
    json: bool,
) -> Result<()> {
    let model = args.resimulate.as_deref().filter(|m| !m.is_empty());
    let (mut data, from_log) = crate::flight_input::read_flight(file, model, &args.roles, true)?;
    if let (true, Some(m)) = (from_log, model) {
        let src = crate::vehicle::read_vehicle(Some(m))?;
        crate::vehicle::build_vehicle(&src)?;
        data.model_toml = src.text;
        data.model_origin = src.origin;
    }
    if let Some(damage) = &data.damage {
        crate::output::note(&format!(
            "warning: `{}` is incomplete ({damage}); resimulating what was recovered from it",
            file.display()
        ));
    }
    let opts = ResimOptions {
        segment_wingbeats: args.segment_wingbeats,
        max_duration_s: args.duration_s,
        start_states: args.start_states.into(),
        ..ResimOptions::default()
    };
    let bar = crate::progress::progress_bar(1, "fitting start states", "simulations");
    let resim = resimulate(&data, &opts, &mut |p| {
        bar.set_length(p.max_simulations);
        bar.set_position(p.simulations);
        !crate::interrupt::requested()
    })
    .map_err(classify)?;
    bar.finish_and_clear();
    let summary_json = serde_json::to_string(&resim)?;
    let comparison = Comparison {
        real: &resim.real,
        simulated: &resim.simulated,
        residuals: &resim.residuals,
        summary_json: &summary_json,
    };
    let mut wrote = String::new();
    if let Some(out) = mcap {
        // The outputs were checked (an existing one needs --force); the SDK creates anew.
        if out.exists() {
            std::fs::remove_file(out)
                .map_err(|e| anyhow::anyhow!("cannot replace `{}`: {e}", out.display()))?;
        }
        flightlog::compare::write_mcap(out, &comparison)?;
        wrote += &format!(
            "wrote the recorded and the simulated flight to {}\n",
            out.display()
        );
    }
    if let Some(out) = rrd {
        flightlog::compare::write_rrd(out, &comparison)?;
        wrote += &format!(
            "wrote the recorded and the simulated flight to {}\n",
            out.display()
        );
    }
    if json {
        print_json(&resim)?;
    } else {
        print_stdout(&format!("{resim}{wrote}"))?;
    }
    if resim.interrupted {
        return Err(anyhow::anyhow!("interrupted by Ctrl-C"));
    }
    Ok(())
}
