//! The error-cost frontier of the load samplings (issue 37, `wingset::sampling`): for each
//! built-in vehicle, at several steps per wingbeat, under `step_start`, `midpoint` and
//! `step_mean`, against a `step_mean` run at 3200 steps per wingbeat:
//! - open-loop free flight from its model's initial state for `DURATION` wingbeats: the
//!   error of the final attitude (deg) and velocity (relative);
//! - the main job, `hover`'s default run (trimmed, LQR-controlled, 1 s from a 5 deg pitch
//!   disturbance): the relative error of its largest excursion and of its recovery time;
//! - the hover trim: the largest relative error of its stroke amplitude, mean stroke and
//!   pitch (an actuated vehicle: of its drive amplitude, of its drive bias relative to that,
//!   and of its pitch in rad);
//! - forward flight (prescribed wings): the wing set stepped through one wingbeat with the
//!   body held at the hover trim's attitude (the model's initial one without a trim) and
//!   moving forward at an advance ratio of 0.5 (half the wings' mean tip speed 2 Phi f R;
//!   the bumblebee's 4.5 m/s is 0.56): the error of its cycle-mean force against
//!   `mean_loads`' fine mean (2000 steps), over the weight;
//! - the longitudinal Floquet exponents: the largest error relative to the largest
//!   exponent's modulus, of the exponents whose multiplier is at least `MIN_MULTIPLIER`;
//! - the wall time of the open-loop and the hover run (one run each: the times are for
//!   reading the frontier's shape, not ratios; docs/speed.md's ratios come from interleaved
//!   rounds).
//!
//! Then, per vehicle, the fewest steps per wingbeat at which `step_mean` holds [`BOUND`] at
//! that count and every larger one. Prints markdown tables.
//!
//! `cargo run --release --example frontier -- [--plot FILE.svg] [MODEL ...]` (all built-in
//! vehicles when none is given); `--plot` also draws the open-loop attitude error against
//! the steps per wingbeat, log-log, one colour per vehicle, the step-mean sampling solid,
//! the midpoint dashed-width and the step-start sampling thin.

use std::time::Instant;

use plotters::prelude::*;

use flapsim::averaged::{FrozenState, mean_loads};
use flapsim::control::{Disturbance, HoverController, LqrWeights, run_hover};
use flapsim::{FromVehicle, LoadSampling, Mode, Simulation, State, Vehicle, VehicleSpec, WingSet};
use nalgebra::Vector3;

/// Wingbeats flown per run.
const DURATION: usize = 30;
/// Steps per wingbeat of the runs compared.
const STEPS: [usize; 14] = [10, 12, 14, 16, 20, 24, 25, 30, 40, 50, 100, 200, 400, 1600];
/// Steps per wingbeat of the reference.
const REFERENCE: usize = 3200;
/// The smallest Floquet multiplier whose exponent the frontier compares. The monodromy
/// matrix is taken by finite differences of perturbations of 1e-4 to 1e-5 of each state, so
/// a mode that damps a perturbation a thousandfold in one wingbeat leaves too little of it
/// for its logarithm: the hummingbird's two fastest wing modes (multipliers about 3e-10) read
/// -580 to -790 1/s from one step count to the next, while its body modes and its
/// multiplier-0.05 wing pair converge.
const MIN_MULTIPLIER: f64 = 1e-3;
/// Simulated time of the hover runs, s (`hover`'s default).
const HOVER_S: f64 = 1.0;

/// The accuracy a vehicle's stated step count holds, against the reference: (hover's
/// largest excursion and recovery time, relative (the recovery time beyond the run's step,
/// its resolution); the Floquet exponents, relative to the largest; the trim, relative; the
/// open-loop attitude, deg, and velocity, relative; the forward-flight force, over the weight).
/// Issue 37's example bounds for the excursion (0.5 %) and the Floquet exponents (1 %);
/// the recovery time and the trim at the excursion's 0.5 %; the open-loop flight of an
/// unstable vehicle, whose errors grow over its 30 wingbeats, at 0.1 deg and 1 %; the
/// forward-flight force at 0.1 % of the weight.
const BOUND: [f64; 7] = [0.005, 0.005, 0.01, 0.005, 0.1, 0.01, 0.001];

/// What one run measured against the reference (`None`: not available, with the reason in
/// the table).
#[derive(Debug, Clone, Default)]
struct Measured {
    open_loop: Option<State>,
    open_s: f64,
    hover: Option<(f64, Option<f64>)>,
    hover_s: f64,
    /// The run's step, s (the resolution of its recovery time).
    dt_s: f64,
    trim: Option<[f64; 3]>,
    /// Whether `trim` is a drive's (amplitude and bias, V; pitch, rad).
    trim_actuated: bool,
    floquet: Option<Vec<(f64, f64)>>,
    /// The forward-flight force error over the weight (prescribed wings).
    forward: Option<f64>,
    failures: Vec<String>,
}

fn vehicle(name: &str, steps: usize, sampling: LoadSampling) -> Result<Vehicle, String> {
    let text = flapsim::builtin_model(name).ok_or_else(|| format!("no built-in {name}"))?;
    let mut spec = VehicleSpec::from_toml(text, name).map_err(|e| e.to_string())?;
    spec.sim.steps_per_wingbeat = steps;
    spec.sim.load_sampling = Some(sampling);
    spec.build(name).map_err(|e| e.to_string())
}

/// The final state and the wall time, or the error that stopped the run.
fn fly(name: &str, steps: usize, sampling: LoadSampling) -> Result<(State, f64), String> {
    let mut sim = Simulation::try_new(vehicle(name, steps, sampling)?, Mode::Free)
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    for _ in 0..steps * DURATION {
        sim.step().map_err(|e| e.to_string())?;
    }
    Ok((sim.state(), start.elapsed().as_secs_f64()))
}

/// A table cell for a run's failures: each one's first two clauses (what failed and why, e.g.
/// "trim: no hover trim for `robobee`: the balance needs a drive peaking at 103.9 V and the
/// actuator allows 100 V"), a failure whose reason repeats the one before it named only;
/// the whole messages go to stderr.
fn failures_cell(name: &str, steps: usize, sampling: LoadSampling, failures: &[String]) -> String {
    let mut cells: Vec<String> = Vec::new();
    let mut last_reason = "";
    for f in failures {
        eprintln!("{name} {} {steps}: {f}", sampling.name());
        let (what, rest) = f.split_once(": ").unwrap_or((f, ""));
        let reason = rest.split("; ").next().unwrap_or(rest);
        let short: Vec<&str> = reason.splitn(3, ": ").take(2).collect();
        let short = short.join(": ");
        if reason == last_reason {
            cells.push(format!("{what}: as above"));
        } else {
            cells.push(format!("{what}: {short}"));
        }
        last_reason = reason;
    }
    cells.join("; ")
}

/// Everything the frontier measures at one step count and sampling.
fn measure(name: &str, steps: usize, sampling: LoadSampling) -> Measured {
    let mut m = Measured::default();
    match fly(name, steps, sampling) {
        Ok((s, t)) => (m.open_loop, m.open_s) = (Some(s), t),
        Err(e) => m.failures.push(format!("open loop: {e}")),
    }
    let v = match vehicle(name, steps, sampling) {
        Ok(v) => v,
        Err(e) => {
            m.failures.push(e);
            return m;
        }
    };
    m.dt_s = 1.0 / (v.freq_hz() * steps as f64);
    let trim = flapsim::trim::trim(&v);
    if v.actuation.is_none() {
        match forward_flight(&v, trim.as_ref().ok()) {
            Ok(e) => m.forward = Some(e),
            Err(e) => m.failures.push(format!("forward: {e}")),
        }
    }
    match trim {
        Ok(trim) => {
            let c = &trim.controls;
            m.trim = Some(match &v.actuation {
                // An actuated vehicle trims its drive: its amplitude and bias, V.
                Some(a) => {
                    let d = &a.base_drives[0];
                    [
                        d.amplitude_v + c.amplitude_v,
                        d.bias_v + c.bias_v,
                        trim.pitch_rad,
                    ]
                }
                None => [c.amplitude_rad, c.mean_stroke_rad, trim.pitch_rad],
            });
            m.trim_actuated = v.actuation.is_some();
            let start = Instant::now();
            let run = HoverController::design(&v, &trim, &LqrWeights::default(), 0)
                .map_err(|e| e.to_string())
                .and_then(|c| {
                    let d = Disturbance {
                        pitch_deg: 5.0,
                        ..Disturbance::default()
                    };
                    run_hover(&v, &trim, Some(c), &d, HOVER_S, |_| true).map_err(|e| e.to_string())
                });
            m.hover_s = start.elapsed().as_secs_f64();
            match run {
                Ok(o) if o.diverged.is_none() => {
                    m.hover = Some((o.max_position_error_m, o.recovery_time_s))
                }
                Ok(o) => m
                    .failures
                    .push(format!("hover: {}", o.diverged.unwrap_or_default())),
                Err(e) => m.failures.push(format!("hover: {e}")),
            }
        }
        Err(e) => m.failures.push(format!("trim: {e}")),
    }
    match flapsim::stability::analyze(&v, true) {
        Ok(r) => m.floquet = Some(r.floquet_longitudinal.iter().map(|f| f.exponent).collect()),
        Err(e) => m.failures.push(format!("stability: {e}")),
    }
    m
}

/// The forward-flight force error over the weight (see the module documentation).
fn forward_flight(v: &Vehicle, trim: Option<&flapsim::trim::Trim>) -> Result<f64, String> {
    let (v, q) = match trim {
        Some(t) => (
            flapsim::trim::trimmed_vehicle(v, t).map_err(|e| e.to_string())?,
            t.attitude(),
        ),
        None => (v.clone(), v.initial_attitude),
    };
    let k = v.wings[0].kinematics();
    let tip_m_s = 2.0 * k.amplitude_rad * k.freq_hz * v.wings[0].geometry().r_tip_m;
    let velocity = Vector3::new(0.5 * tip_m_s, 0.0, 0.0);
    let n = v.sim.steps_per_wingbeat;
    let mut set = WingSet::from_vehicle_sized(&v).map_err(|e| e.to_string())?;
    let mut mean = Vector3::zeros();
    for j in 0..n {
        let body = State {
            position_m: velocity * (j as f64 * set.dt_s()),
            world_from_body: q,
            velocity_m_s: velocity,
            angular_velocity_body_rad_s: Vector3::zeros(),
        };
        let out = set.step(&body).map_err(|e| e.to_string())?;
        mean += (out.total.force_n - out.body_drag.force_n) / n as f64;
    }
    let frozen = FrozenState {
        world_from_body: q,
        velocity_body_m_s: q.inverse() * velocity,
        angular_velocity_body_rad_s: Vector3::zeros(),
    };
    let fine = mean_loads(&v, &frozen, 2000).map_err(|e| e.to_string())?;
    Ok((mean - fine.total.force_n).norm() / v.weight_n())
}

/// The errors of `m` against `reference`, in [`BOUND`]'s order (`NaN`: not measured).
fn errors(m: &Measured, reference: &Measured) -> [f64; 7] {
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let mut e = [f64::NAN; 7];
    if let (Some((x, r)), Some((x0, r0))) = (m.hover, reference.hover) {
        e[0] = rel(x, x0);
        // The recovery time is the step after the last one outside the band: what lies
        // within the coarser run's step of the reference is the reading's resolution.
        e[1] = match (r, r0) {
            (Some(r), Some(r0)) => ((r - r0).abs() - m.dt_s).max(0.0) / r0,
            (None, None) => 0.0,
            _ => f64::INFINITY,
        };
    }
    if let (Some(f), Some(f0)) = (&m.floquet, &reference.floquet) {
        // The exponents (sorted by real part, largest first) whose multiplier the finite
        // differences resolve; see MIN_MULTIPLIER.
        let period_s = reference.dt_s * REFERENCE as f64;
        let k = f0
            .iter()
            .take_while(|z| (z.0 * period_s).exp() >= MIN_MULTIPLIER)
            .count();
        let scale = f0[..k].iter().map(|z| z.0.hypot(z.1)).fold(0.0, f64::max);
        e[2] = if f.len() == f0.len() {
            f[..k]
                .iter()
                .zip(&f0[..k])
                .map(|(a, b)| (a.0 - b.0).hypot(a.1 - b.1) / scale)
                .fold(0.0, f64::max)
        } else {
            f64::INFINITY
        };
    }
    if let (Some(t), Some(t0)) = (m.trim, reference.trim) {
        // The mean stroke and pitch relative to the amplitude (they may be near zero); an
        // actuated vehicle's drive bias relative to its drive amplitude, its pitch in rad (a
        // relative error of a 1 rad angle: volts and radians do not divide).
        let scale = match reference.trim_actuated {
            true => [t0[0].abs(), t0[0].abs(), 1.0],
            false => [t0[0].abs(); 3],
        };
        e[3] = (0..3)
            .map(|i| (t[i] - t0[i]).abs() / scale[i])
            .fold(0.0, f64::max);
    }
    if let (Some(s), Some(s0)) = (&m.open_loop, &reference.open_loop) {
        e[4] = s.world_from_body.angle_to(&s0.world_from_body).to_degrees();
        e[5] = (s.velocity_m_s - s0.velocity_m_s).norm() / s0.velocity_m_s.norm();
    }
    // Against the fine mean, not the reference run.
    e[6] = m.forward.unwrap_or(f64::NAN);
    e
}

/// A table cell: the error, or a dash where it was not measured.
fn cell(x: f64) -> String {
    if x.is_nan() {
        "-".into()
    } else {
        format!("{x:.2e}")
    }
}

/// One run's attitude error, deg (`None`: it diverged).
type Row = (String, LoadSampling, usize, Option<f64>);

/// The frontier as an SVG (or a PNG, by the file's extension): attitude error against
/// steps per wingbeat, log-log.
fn plot(path: &str, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    if path.ends_with(".png") {
        draw(
            BitMapBackend::new(path, (900, 600)).into_drawing_area(),
            rows,
        )
    } else {
        draw(SVGBackend::new(path, (900, 600)).into_drawing_area(), rows)
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    rows: &[Row],
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "error-cost frontier: open loop, 30 wingbeats, against 3200 steps per wingbeat (step_mean)",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((8.0f64..2000.0).log_scale(), (1e-6f64..100.0).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("steps per wingbeat")
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_desc("final attitude error [deg]")
        .draw()?;
    let colors = [RED, BLUE, GREEN, MAGENTA, CYAN, BLACK];
    let mut names: Vec<&str> = Vec::new();
    for r in rows {
        if !names.contains(&r.0.as_str()) {
            names.push(&r.0);
        }
    }
    for (i, name) in names.iter().enumerate() {
        let color = colors[i % colors.len()];
        for sampling in LoadSampling::ALL {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.0 == *name && r.1 == sampling)
                .filter_map(|r| r.3.map(|e| (r.2 as f64, e.max(1e-6))))
                .collect();
            let width = match sampling {
                LoadSampling::StepMean => 3,
                LoadSampling::Midpoint => 2,
                LoadSampling::StepStart => 1,
            };
            let series = chart.draw_series(LineSeries::new(
                points.iter().copied(),
                color.stroke_width(width),
            ))?;
            series
                .label(format!("{name}, {}", sampling.name()))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(width))
                });
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()?;
    root.present()?;
    Ok(())
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let plot_path = match args.iter().position(|a| a == "--plot") {
        Some(i) if i + 1 < args.len() => {
            let p = args.remove(i + 1);
            args.remove(i);
            Some(p)
        }
        _ => None,
    };
    let mut rows: Vec<Row> = Vec::new();
    let names: Vec<&str> = if args.is_empty() {
        flapsim::BUILTIN_MODELS.to_vec()
    } else {
        args.iter().map(String::as_str).collect()
    };
    println!(
        "| vehicle | sampling | steps/wingbeat | hover excursion | recovery | Floquet | trim | open-loop attitude (deg) | open-loop velocity | forward force | open-loop wall (s) | hover wall (s) | failures |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut bounds = Vec::new();
    for name in names {
        let reference = measure(name, REFERENCE, LoadSampling::StepMean);
        if !reference.failures.is_empty() {
            println!(
                "| {name} | step_mean | {REFERENCE} (reference) | | | | | | | | | | {} |",
                failures_cell(name, REFERENCE, LoadSampling::StepMean, &reference.failures)
            );
        }
        let mut held: Option<usize> = None;
        for sampling in LoadSampling::ALL {
            for steps in STEPS {
                let m = measure(name, steps, sampling);
                let e = errors(&m, &reference);
                println!(
                    "| {name} | {} | {steps} | {} | {} | {} | {} | {} | {} | {} | {:.4} | {:.4} | {} |",
                    sampling.name(),
                    cell(e[0]),
                    cell(e[1]),
                    cell(e[2]),
                    cell(e[3]),
                    cell(e[4]),
                    cell(e[5]),
                    cell(e[6]),
                    m.open_s,
                    m.hover_s,
                    failures_cell(name, steps, sampling, &m.failures)
                );
                rows.push((name.to_owned(), sampling, steps, m.open_loop.map(|_| e[4])));
                if sampling == LoadSampling::StepMean {
                    // Every error measured on the reference within its bound (a measure the
                    // reference lacks, e.g. a vehicle without a hover trim, is not bounded).
                    // A failure the reference shares (a vehicle without a hover trim) is the
                    // vehicle's, not the step's.
                    let shared = |f: &String| {
                        let what = f.split(':').next();
                        reference
                            .failures
                            .iter()
                            .any(|r| r.split(':').next() == what)
                    };
                    let ok = e.iter().zip(BOUND).all(|(x, b)| x.is_nan() || *x <= b)
                        && m.failures.iter().all(shared);
                    held = match (ok, held) {
                        (true, None) => Some(steps),
                        (true, h) => h,
                        (false, _) => None,
                    };
                }
            }
        }
        bounds.push((name, held));
    }
    println!();
    println!("| vehicle | fewest steps per wingbeat holding the bound (step_mean) |");
    println!("|---|---|");
    for (name, held) in bounds {
        match held {
            Some(n) => println!("| {name} | {n} |"),
            None => println!("| {name} | none up to {} |", STEPS[STEPS.len() - 1]),
        }
    }
    if let Some(path) = plot_path {
        if let Err(e) = plot(&path, &rows) {
            eprintln!("error: could not draw {path}: {e}");
            std::process::exit(1);
        }
        eprintln!("wrote {path}");
    }
}
