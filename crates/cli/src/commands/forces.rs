//! `flapwing forces`: a wing on its fixed mount (a robotic wing in a tank) evaluated over a
//! few wingbeats; the cycle-mean C_L and C_D of each term over the last one, and optionally
//! the time series as CSV (the seed paper's Fig 23-24).

use std::fmt::Write as _;
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::Context;
use indicatif::ProgressBar;
use serde::Serialize;
use wingforce::cycle::CycleMean;
use wingforce::{BodyMotion, KinematicsSpec, Term, TermForce, Wing, WingForces};

use crate::cli::ForcesArgs;
use crate::commands::forces_vehicle::{self, Periodic, Subject};
use crate::commands::wake_capture;
use crate::error::input_error;
use crate::output::{create_output_file, fmt_sig, print_json, print_stdout};

/// Runs with more evaluations than this show a progress bar (on a terminal only).
const PROGRESS_THRESHOLD: u64 = 10_000_000;

/// Cycle-mean lift and drag coefficients of one term.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coefficients {
    /// Mean C_L (force along the stroke-plane normal over 0.5 rho V_ref^2 S).
    pub c_l: f64,
    /// Mean C_D (force against the stroke motion over 0.5 rho V_ref^2 S).
    pub c_d: f64,
}

impl From<&TermForce> for Coefficients {
    fn from(t: &TermForce) -> Self {
        Self {
            c_l: t.c_l,
            c_d: t.c_d,
        }
    }
}

/// The cycle means of every term and of their sum.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Means {
    /// Quasi-steady translational term.
    pub translational: Coefficients,
    /// Rotational (Van Veen) term.
    pub rotational: Coefficients,
    /// Added-mass term.
    pub added_mass: Coefficients,
    /// The paper's wake-capture term (zero when switched off).
    pub wake_capture: Coefficients,
    /// Sum of the four terms.
    pub total: Coefficients,
}

impl From<&CycleMean> for Means {
    fn from(m: &CycleMean) -> Self {
        let term = |t: Term| Coefficients::from(&m.terms[t as usize]);
        Self {
            translational: term(Term::Translational),
            rotational: term(Term::Rotational),
            added_mass: term(Term::AddedMass),
            wake_capture: term(Term::WakeCapture),
            total: (&m.total).into(),
        }
    }
}

impl Means {
    fn rows(&self) -> [(&'static str, &Coefficients); 5] {
        [
            (Term::Translational.name(), &self.translational),
            (Term::Rotational.name(), &self.rotational),
            (Term::AddedMass.name(), &self.added_mass),
            (Term::WakeCapture.name(), &self.wake_capture),
            ("total", &self.total),
        ]
    }
}

/// The JSON document of this command.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// The model's name.
    pub model: String,
    /// The model file, or `<built-in NAME>`.
    pub source: String,
    /// Which wing of the model, and how it moves.
    pub wing: String,
    /// The induced flow the wing meets (`[aero] inflow`): `off`, `frozen` or `dynamic`.
    pub induced_flow: String,
    /// The wing moves as an actuated vehicle's drive makes it (its periodic motion, with the
    /// pair's dynamic wake stepped along it), not on prescribed kinematics.
    pub periodic_motion: bool,
    /// Reynolds number in use.
    pub reynolds: f64,
    /// How Re is defined.
    pub reynolds_definition: &'static str,
    /// Reference speed V_ref (peak stroke speed at R_g), m/s.
    pub v_ref_m_s: f64,
    /// Wingbeat frequency, Hz.
    pub freq_hz: f64,
    /// The added-mass term's form (`impulse`, `paper` for eq 7-8, or `off`).
    pub added_mass_form: &'static str,
    /// Wingbeat period, s.
    pub period_s: f64,
    /// 0.5 rho V_ref^2 S, N: multiply a coefficient by it to get newtons.
    pub reference_force_n: f64,
    /// Wingbeats evaluated.
    pub cycles: u32,
    /// Time steps per wingbeat.
    pub steps_per_cycle: u32,
    /// The wake-capture model at this wing's Re, dtau_A and dtau_D; `null` when switched off.
    pub wake_capture: Option<wake_capture::Report>,
    /// True when a wake-capture input was outside the fitted range and clamped.
    pub wake_capture_clamped: bool,
    /// Means over the last wingbeat.
    pub mean_last_cycle: Means,
    /// The CSV file written, if any.
    pub csv: Option<String>,
}

/// Runs the command.
pub fn run(args: ForcesArgs) -> anyhow::Result<()> {
    let subject = build_wing(&args)?;
    let wing = &subject.wing;
    let wake = wing.options().wake_capture.as_ref().map(|model| {
        let (dtau_a, dtau_d) = forces_vehicle::acceleration_fractions(wing);
        wake_capture::Report::new(model, wing.reynolds(), dtau_a, dtau_d)
    });
    let clamped = wake.as_ref().is_some_and(|w| w.any_clamped);
    if let Some(w) = wake.as_ref().filter(|w| w.any_clamped) {
        let _ = writeln!(
            std::io::stderr(),
            "warning: wake-capture inputs outside the fitted range were clamped: {}",
            w.clamped_inputs().join(", ")
        );
    }

    // Fail before any work if an output cannot be written: both outputs checked together
    // (distinct, not the model file, existing ones only with --force).
    let model: Vec<crate::outputs::Named<'_>> = args
        .model
        .iter()
        .map(|m| crate::outputs::Named::new("--model", m))
        .collect();
    crate::outputs::check_csv_and_plot(
        &model,
        args.csv.as_deref(),
        args.plot.as_deref(),
        args.force,
    )?;
    if let Some(p) = &args.plot {
        drop(crate::output::create_output_file(p, args.force, "plot")?);
    }
    let mut csv = match &args.csv {
        Some(path) => Some(CsvWriter::create(path, args.force)?),
        None => None,
    };
    let (cycles, steps_per_cycle, freq_hz) = match &subject.periodic {
        None => (
            args.cycles.unwrap_or(forces_vehicle::DEFAULT_CYCLES),
            args.steps_per_cycle
                .unwrap_or(forces_vehicle::DEFAULT_STEPS_PER_CYCLE),
            wing.kinematics().freq_hz,
        ),
        Some(p) => (
            u32::try_from(p.cycles).unwrap_or(u32::MAX),
            u32::try_from(p.samples.len()).unwrap_or(u32::MAX),
            p.freq_hz,
        ),
    };
    let mean = match &subject.periodic {
        None => evaluate(wing, cycles, steps_per_cycle, csv.as_mut())?,
        Some(p) => periodic_mean(p, cycles, csv.as_mut())?,
    };
    if let Some(csv) = csv {
        csv.finish()?;
    }

    // wingforce validates model files, but not every coefficient of a refitted
    // wake-capture model; never report NaN means as a success.
    let means = Means::from(&mean);
    if let Some((term, c)) = means
        .rows()
        .into_iter()
        .find(|(_, c)| !(c.c_l.is_finite() && c.c_d.is_finite()))
    {
        return Err(anyhow::anyhow!(
            "the model `{}` gives non-finite forces ({term}: C_L = {}, C_D = {}); check the \
             coefficients in the file",
            subject.origin,
            c.c_l,
            c.c_d
        ));
    }

    if let Some(p) = &args.plot {
        let title = format!(
            "{}: C_L and C_D over a wingbeat (Re {:.0})",
            subject.name,
            wing.reynolds()
        );
        match &subject.periodic {
            None => super::forces_plot::plot(wing, p, &title)?,
            Some(periodic) => super::forces_plot::plot_samples(&periodic.samples, p, &title)?,
        }
    }
    let report = Report {
        model: subject.name.clone(),
        source: subject.origin.clone(),
        wing: subject.wing_label.clone(),
        induced_flow: wingforce::InflowModel::of(wing.options().induced_inflow.as_ref())
            .to_string(),
        periodic_motion: subject.periodic.is_some(),
        reynolds: wing.reynolds(),
        reynolds_definition: "Re = V_ref c_bar / nu",
        v_ref_m_s: wing.v_ref_m_s(),
        freq_hz,
        added_mass_form: wing.options().added_mass.name(),
        period_s: 1.0 / freq_hz,
        reference_force_n: wing.reference_force_n(),
        cycles,
        steps_per_cycle,
        wake_capture: wake,
        wake_capture_clamped: clamped,
        mean_last_cycle: means,
        csv: args.csv.as_ref().map(|p| p.display().to_string()),
    };
    if args.json {
        print_json(&report)
    } else {
        print_stdout(&text_report(&report)?)
    }
}

/// Loads the model, applies the command-line overrides and builds the wing.
fn build_wing(args: &ForcesArgs) -> anyhow::Result<Subject> {
    let mut loaded = match forces_vehicle::load(args)? {
        Ok(loaded) => loaded,
        Err(subject) => return Ok(subject),
    };
    let overrides = args.dtau_a.is_some() || args.dtau_d.is_some();
    if overrides {
        match &mut loaded.spec.kinematics {
            KinematicsSpec::Trapezoidal { dtau_a, dtau_d, .. } => {
                *dtau_a = args.dtau_a.unwrap_or(*dtau_a);
                *dtau_d = args.dtau_d.unwrap_or(*dtau_d);
            }
            other => {
                let family = match other {
                    KinematicsSpec::Harmonic { .. } => "harmonic",
                    KinematicsSpec::HarmonicFlip { .. } => "harmonic_flip",
                    _ => "tabulated",
                };
                return Err(input_error(format!(
                    "--dtau-a and --dtau-d need trapezoidal kinematics, but `{}` has \
                     kinematics.family = \"{family}\"",
                    loaded.origin
                )));
            }
        }
    }
    if args.no_wake_capture {
        loaded.spec.aero.wake_capture = false;
    }
    // Errors name the file, and say when a value may have come from a flag.
    let origin = if overrides {
        format!("{} with --dtau-a/--dtau-d", loaded.origin)
    } else {
        loaded.origin.clone()
    };
    let mut wing = loaded.spec.build(&origin)?;
    if let Some(re) = args.re {
        wing.set_reynolds(re)?;
    }
    Ok(Subject {
        name: loaded.spec.name,
        origin: loaded.origin,
        wing_label: "the model's wing on a fixed mount".to_owned(),
        wing,
        periodic: None,
    })
}

/// The mean over an actuated wing's periodic samples, writing each to `csv` as wingbeat
/// `cycles` (the last of the drive periods run).
fn periodic_mean(
    p: &Periodic,
    cycles: u32,
    mut csv: Option<&mut CsvWriter>,
) -> anyhow::Result<CycleMean> {
    let n = p.samples.len();
    let mut mean = CycleMean::default();
    for (k, forces) in p.samples.iter().enumerate() {
        mean.accumulate(forces, 1.0 / n as f64);
        if let Some(csv) = csv.as_mut() {
            let last = u64::from(cycles.saturating_sub(1));
            let t_s = (last as f64 + k as f64 / n as f64) / p.freq_hz;
            csv.row(t_s, last, forces)?;
        }
    }
    Ok(mean)
}

/// Evaluates `cycles` wingbeats at `steps` phases each, writing every step to `csv`; returns
/// the mean over the last wingbeat.
///
/// The samples sit at the middle of each step, phase (i + 1/2) / steps (the midpoint rule).
/// The trapezoidal family's pitch acceleration jumps where a flip starts and ends (phases like
/// 0.5 - dtau_D, usually on the k / steps grid); sampling exactly there would add about
/// jump / steps to the mean, and rounding would decide per wingbeat which side of the jump a
/// sample falls on, so the wingbeats' means would differ in the fourth decimal.
fn evaluate(
    wing: &Wing,
    cycles: u32,
    steps: u32,
    mut csv: Option<&mut CsvWriter>,
) -> anyhow::Result<CycleMean> {
    let body = BodyMotion::default();
    let total = u64::from(cycles) * u64::from(steps);
    let progress = if total > PROGRESS_THRESHOLD {
        crate::progress::progress_bar(total, "evaluating", "samples")
    } else {
        ProgressBar::hidden()
    };
    let weight = 1.0 / f64::from(steps);
    let mut mean = CycleMean::default();
    for index in 0..total {
        let cycle = index / u64::from(steps);
        let phase = (index as f64 + 0.5) / f64::from(steps);
        let forces = wing.evaluate(phase, &body);
        if cycle + 1 == u64::from(cycles) {
            mean.accumulate(&forces, weight);
        }
        if let Some(csv) = csv.as_mut() {
            csv.row(phase / wing.kinematics().freq_hz, cycle, &forces)?;
        }
        if index % 65_536 == 0 {
            progress.set_position(index);
        }
    }
    progress.finish_and_clear();
    Ok(mean)
}

/// The time-series CSV file.
struct CsvWriter {
    path: String,
    out: BufWriter<std::fs::File>,
}

impl CsvWriter {
    fn create(path: &Path, force: bool) -> anyhow::Result<Self> {
        let file = create_output_file(path, force, "CSV file")?;
        let mut w = Self {
            path: path.display().to_string(),
            out: BufWriter::new(file),
        };
        let mut header = String::from("t_s,cycle,t_star,half_stroke,phi_rad,theta_rad");
        for term in Term::ALL {
            let n = term.name();
            write!(header, ",cl_{n},cd_{n}")?;
        }
        header.push_str(",cl_total,cd_total\n");
        w.write(header.as_bytes())?;
        Ok(w)
    }

    fn row(&mut self, t_s: f64, cycle: u64, f: &WingForces) -> anyhow::Result<()> {
        let mut line = String::with_capacity(256);
        write!(
            line,
            "{},{cycle},{},{},{},{}",
            CsvNumber(t_s),
            CsvNumber(f.phase.t_star),
            f.phase.half_stroke,
            CsvNumber(f.angles.phi),
            CsvNumber(f.angles.theta)
        )?;
        for t in f.terms.iter().chain(std::iter::once(&f.total)) {
            write!(line, ",{},{}", CsvNumber(t.c_l), CsvNumber(t.c_d))?;
        }
        line.push('\n');
        self.write(line.as_bytes())
    }

    fn write(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        self.out
            .write_all(bytes)
            .with_context(|| format!("cannot write CSV file `{}`", self.path))
    }

    fn finish(mut self) -> anyhow::Result<()> {
        self.out
            .flush()
            .with_context(|| format!("cannot write CSV file `{}`", self.path))
    }
}

/// A number for the CSV file: the shortest text that reads back to the same f64, in
/// scientific notation when very small or large (never 40 zeros).
struct CsvNumber(f64);

impl std::fmt::Display for CsvNumber {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-4..1e15).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

fn text_report(r: &Report) -> anyhow::Result<String> {
    let mut s = String::new();
    let name = if r.model.is_empty() {
        "(unnamed)"
    } else {
        &r.model
    };
    writeln!(s, "model         {name} ({})", r.source)?;
    writeln!(s, "wing          {}", r.wing)?;
    let flow = match (r.induced_flow.as_str(), r.periodic_motion) {
        ("off", _) => "off (still air)",
        ("frozen", _) => "frozen (the hover downwash of the weight)",
        (_, true) => "dynamic (the pair's wake answering its loads along the motion)",
        // A lone wing meets its dynamic inflow's start; only a wing set steps the wake.
        (_, false) => {
            "dynamic, held at its start on a fixed mount (the hover downwash of the weight)"
        }
    };
    writeln!(s, "induced flow  {flow}")?;
    writeln!(
        s,
        "Re            {} ({})",
        fmt_sig(r.reynolds, 6),
        r.reynolds_definition
    )?;
    writeln!(
        s,
        "V_ref         {} m/s (peak stroke speed at R_g)",
        fmt_sig(r.v_ref_m_s, 6)
    )?;
    writeln!(
        s,
        "f             {} Hz (T = {} s)",
        fmt_sig(r.freq_hz, 6),
        fmt_sig(r.period_s, 6)
    )?;
    writeln!(
        s,
        "added mass    {}",
        wingforce::AddedMassForm::from_name(r.added_mass_form)
            .map_or(r.added_mass_form, wingforce::AddedMassForm::describe)
    )?;
    match &r.wake_capture {
        Some(w) => {
            writeln!(s, "wake capture  {}", w.model)?;
            writeln!(s)?;
            w.write_text(&mut s)?;
            if w.any_clamped {
                writeln!(s, "clamped: {}", w.clamped_inputs().join(", "))?;
            }
        }
        None => writeln!(s, "wake capture  off")?,
    }
    writeln!(s)?;
    writeln!(
        s,
        "means over wingbeat {} of {} ({} steps per wingbeat; 0.5 rho V_ref^2 S = {} N):",
        r.cycles,
        r.cycles,
        r.steps_per_cycle,
        fmt_sig(r.reference_force_n, 6)
    )?;
    writeln!(s, "{:<15} {:>10} {:>10}", "term", "C_L", "C_D")?;
    for (term, c) in r.mean_last_cycle.rows() {
        writeln!(s, "{term:<15} {:>10.5} {:>10.5}", c.c_l, c.c_d)?;
    }
    if let Some(path) = &r.csv {
        writeln!(s)?;
        writeln!(
            s,
            "time series: {path} ({} rows)",
            u64::from(r.cycles) * u64::from(r.steps_per_cycle)
        )?;
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_numbers_are_short_and_exact() {
        for (x, text) in [
            (0.0, "0"),
            (1.5707963267948966, "1.5707963267948966"),
            (-0.425, "-0.425"),
            (2.808253855804665e-34, "2.808253855804665e-34"),
            (-8.7e-17, "-8.7e-17"),
        ] {
            let s = CsvNumber(x).to_string();
            assert_eq!(s, text);
            assert_eq!(s.parse::<f64>().unwrap(), x);
        }
    }
}
