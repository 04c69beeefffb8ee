//! `flapwing replay`: summarize, convert, export or re-check an MCAP log written by
//! `simulate --mcap` (or any flapwing command that records); summarize a ROS 2 bag (MCAP
//! with `ros2msg` schemas and CDR messages) or export one of its topics to CSV.
//!
//! Exit codes: 0 ok (and `--check` matched), 1 `--check` found a difference or a conversion
//! failed while running, 2 bad input (missing file, not MCAP, not a flapwing log, unknown
//! channel, a log that cannot be re-run, an existing output without --force, an output
//! that is the input log or the other output).

use std::path::PathBuf;

use anyhow::Result;
use flightlog::check::{CheckOutcome, check_log};
use flightlog::replay;
use flightlog::ros2::bag::{Bag, read_bag};
use flightlog::ros2::summary::{export_topic_csv, summarize};

use crate::error::input_error;
use crate::output::{create_output_file, print_json, print_stdout};
use crate::outputs::Named;

/// Arguments of `flapwing replay`.
#[derive(Debug, clap::Args)]
pub struct ReplayArgs {
    /// The MCAP log (a truncated log from a killed run is read up to its last complete chunk),
    /// or a ROS 2 bag (MCAP with `ros2msg` schemas and CDR messages: summary and --csv).
    #[arg(value_name = "FILE.mcap")]
    pub file: PathBuf,
    /// Print the summary as one JSON document on stdout.
    #[arg(long)]
    pub json: bool,
    /// Convert the log to a Rerun recording.
    #[arg(long, value_name = "OUT.rrd")]
    pub rrd: Option<PathBuf>,
    /// Export one channel's messages as CSV (one column per field, dotted paths), e.g.
    /// `--csv /vehicle/state state.csv` (of a ROS 2 bag: `--csv /mocap/pose pose.csv`).
    #[arg(long, num_args = 2, value_names = ["CHANNEL", "OUT.csv"])]
    pub csv: Option<Vec<String>>,
    /// Re-run the simulation from the embedded model and settings and compare the trajectory
    /// bit for bit; exit 1 on a difference, 2 if the log cannot be re-run.
    #[arg(long)]
    pub check: bool,
    /// Replace existing --rrd / --csv / --mcap output files.
    #[arg(long)]
    pub force: bool,
    /// With --resimulate: the recorded and the simulated flight as one MCAP file (frames
    /// `real` and `sim`; Foxglove layout docs/foxglove/resimulate.json).
    #[arg(long, value_name = "OUT.mcap", help_heading = "Resimulation")]
    pub mcap: Option<PathBuf>,
    /// Resimulation: `--resimulate [MODEL]` and its settings.
    #[command(flatten)]
    pub resim: crate::commands::resimulate::ResimArgs,
}

/// flightlog's bad-input errors become the CLI's bad input (exit 2).
fn classify(e: flightlog::Error) -> anyhow::Error {
    if e.is_bad_input() {
        input_error(e.to_string())
    } else {
        anyhow::Error::new(e)
    }
}

/// Runs the command.
pub fn run(args: ReplayArgs) -> Result<()> {
    if !args.file.exists() {
        return Err(input_error(format!(
            "cannot read `{}`: no such file",
            args.file.display()
        )));
    }
    // Every output is checked before any is touched: writing the input log (or one output
    // over the other) would destroy what is read.
    let csv_out = match args.csv.as_deref() {
        Some([channel, out]) => Some((channel.as_str(), PathBuf::from(out))),
        Some(_) => return Err(input_error("--csv takes a channel and an output file")),
        None => None,
    };
    let mut outputs = Vec::new();
    if let Some((_, out)) = &csv_out {
        outputs.push(Named::new("--csv", out));
    }
    if let Some(out) = &args.rrd {
        outputs.push(Named::new("--rrd", out));
    }
    if let Some(out) = &args.mcap {
        if args.resim.resimulate.is_none() {
            return Err(input_error(
                "--mcap writes the comparison of --resimulate: give --resimulate MODEL too",
            ));
        }
        outputs.push(Named::new("--mcap", out));
    }
    crate::outputs::check(&[Named::new("FILE", &args.file)], &outputs, args.force)?;
    if args.resim.resimulate.is_some() {
        if args.check || args.csv.is_some() {
            return Err(input_error(
                "--resimulate compares the recorded flight with the model: it does not combine with --check or --csv",
            ));
        }
        return crate::commands::resimulate::run(
            &args.file,
            &args.resim,
            args.mcap.as_deref(),
            args.rrd.as_deref(),
            args.json,
        );
    }
    if args.resim.roles.names_bag_roles() {
        return Err(input_error(
            "the bag role flags (--pose-topic, --roles, ...) go with --resimulate MODEL",
        ));
    }
    // Read once, failing on bad input before any output is touched; a file that is MCAP but
    // not a flapwing log is read as a ROS 2 bag if it has ROS 2 channels. (`--check` reads
    // the log itself.)
    let mut summary = None;
    if !args.check {
        match replay::read_summary(&args.file) {
            Ok(s) => summary = Some(s),
            Err(e @ flightlog::Error::NotFlapwing { .. }) => {
                let bag = read_bag(&args.file).map_err(classify)?;
                if !bag.has_ros2() {
                    return Err(classify(e));
                }
                return run_bag(&args, &bag, csv_out);
            }
            Err(e) => return Err(classify(e)),
        }
    }
    let mut did_something = false;
    if let Some((channel, out)) = &csv_out {
        if summary.is_none() {
            replay::read_summary(&args.file).map_err(classify)?;
        }
        drop(create_output_file(out, args.force, "CSV file")?);
        let stats = replay::export_csv(&args.file, channel, out).map_err(|e| {
            let _ = std::fs::remove_file(out);
            classify(e)
        })?;
        if !args.json {
            let skipped = if stats.skipped > 0 {
                format!(" ({} unreadable messages skipped)", stats.skipped)
            } else {
                String::new()
            };
            print_stdout(&format!(
                "wrote {} rows x {} columns of {channel} to {}{skipped}\n",
                stats.rows,
                stats.columns,
                out.display()
            ))?;
        }
        did_something = true;
    }
    if let Some(out) = &args.rrd {
        if summary.is_none() {
            replay::read_summary(&args.file).map_err(classify)?;
        }
        drop(create_output_file(out, args.force, "Rerun recording")?);
        let stats = replay::to_rrd(&args.file, out).map_err(classify)?;
        if !args.json {
            let mut extra = String::new();
            if stats.estimates > 0 {
                extra += &format!(", {} estimates", stats.estimates);
            }
            if stats.winds > 0 {
                extra += &format!(", {} winds", stats.winds);
            }
            print_stdout(&format!(
                "wrote {} samples{extra} and {} events to {}\n",
                stats.frames,
                stats.events,
                out.display()
            ))?;
        }
        did_something = true;
    }
    if args.check {
        let outcome = check_log(&args.file).map_err(classify)?;
        if args.json {
            print_json(&outcome)?;
        }
        return match outcome {
            CheckOutcome::Match { samples, note } => {
                if !args.json {
                    let note = note.map(|n| format!(" ({n})")).unwrap_or_default();
                    print_stdout(&format!("match: {samples} samples identical{note}\n"))?;
                }
                Ok(())
            }
            CheckOutcome::Mismatch {
                samples_matched,
                detail,
            } => {
                if !args.json {
                    print_stdout(&format!(
                        "mismatch after {samples_matched} identical samples: {detail}\n"
                    ))?;
                }
                Err(anyhow::anyhow!(
                    "the re-run does not reproduce the log: {detail}"
                ))
            }
            CheckOutcome::NotCheckable { reason } => Err(input_error(format!(
                "cannot check `{}`: {reason}",
                args.file.display()
            ))),
        };
    }
    if !did_something || args.json {
        let summary = match summary {
            Some(s) => s,
            None => replay::read_summary(&args.file).map_err(classify)?,
        };
        if args.json {
            print_json(&summary)?;
        } else {
            print_stdout(&summary.to_string())?;
        }
    }
    Ok(())
}

/// `replay` of a ROS 2 bag: its summary (a truncated bag warns on stderr and says how much
/// was recovered), and `--csv TOPIC OUT.csv`. `--rrd` and `--check` need a flapwing log.
fn run_bag(args: &ReplayArgs, bag: &Bag, csv_out: Option<(&str, PathBuf)>) -> Result<()> {
    if args.rrd.is_some() {
        return Err(input_error(format!(
            "`{}` is a ROS 2 bag: --rrd converts flapwing logs only (Rerun opens ROS 2 bags \
             itself: `rerun {}`)",
            args.file.display(),
            args.file.display()
        )));
    }
    if let Some(d) = &bag.damage {
        eprintln!("warning: `{}`: {d}", args.file.display());
    }
    let summary = summarize(bag);
    if let Some((topic, out)) = &csv_out {
        drop(create_output_file(out, args.force, "CSV file")?);
        let stats = export_topic_csv(bag, topic, out).map_err(|e| {
            let _ = std::fs::remove_file(out);
            classify(e)
        })?;
        if !args.json {
            return print_stdout(&format!(
                "wrote {} rows x {} columns of {topic} to {}\n",
                stats.rows,
                stats.columns,
                out.display()
            ));
        }
    }
    if args.json {
        print_json(&summary)
    } else {
        print_stdout(&summary.to_string())
    }
}
