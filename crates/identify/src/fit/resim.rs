//! Resimulation: the model flown beside a recorded flight, segment by segment, from the
//! recorded start states under the recorded inputs, and the residuals between the two.
//!
//! The segments are the fit's ([`crate::fit`]): [`ResimOptions::segment_wingbeats`]
//! wingbeats from each wingbeat start with a known state. A flapwing log's states are its
//! `/vehicle/state` (the reference is then that logged state, and a log flown by the same
//! model resimulates to round-off); a bag's or a CSV's are estimated from the motion
//! capture, and by default (`StartStates::Auto`) fitted, with the model held (12 unknowns
//! per segment, Levenberg-Marquardt), so that what remains is the model's error and not
//! the estimate's (a quadratic through the frames misses the within-wingbeat oscillation of
//! the velocities). The reference is then the motion capture (and the IMU's gyroscope for
//! the body rates, where the record has one).
//!
//! Per segment: the RMS over its reference samples of the position error |p_sim - p_rec|
//! (m), of the attitude error, the angle of rec^-1 * sim (deg), and of the body-rate error
//! |w_sim - w_rec| (rad/s).

use flapsim::State;
use flightlog::compare::{ResidualPoint, TrackPoint};
use serde::Serialize;

use crate::data::{FlightData, StartSource};
use crate::error::{Error, Result};

use super::setup::{setup_for, step_at};
use super::types::{FitOptions, Progress, StartStates};

/// Settings of a resimulation.
#[derive(Debug, Clone)]
pub struct ResimOptions {
    /// Wingbeats per segment.
    pub segment_wingbeats: u32,
    /// Resimulate only the first `max_duration_s` of the flight.
    pub max_duration_s: Option<f64>,
    /// Whether the start states are fitted (Auto: when estimated from the motion capture).
    pub start_states: StartStates,
    /// The start-state fit's patience (see [`FitOptions::patience`]).
    pub patience: usize,
}

impl Default for ResimOptions {
    fn default() -> Self {
        Self {
            segment_wingbeats: 4,
            max_duration_s: None,
            start_states: StartStates::Auto,
            patience: 30,
        }
    }
}

/// The residuals of one segment (or of the whole flight).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SegmentSummary {
    /// Segment index (from 0).
    pub index: usize,
    /// Start and end time, s.
    pub start_s: f64,
    /// End time, s.
    pub end_s: f64,
    /// Reference samples compared.
    pub samples: usize,
    /// RMS position error, m.
    pub position_rms_m: f64,
    /// RMS attitude error, deg.
    pub attitude_rms_deg: f64,
    /// RMS body-rate error, rad/s (`None` where the record has no rates).
    pub rate_rms_rad_s: Option<f64>,
    /// The simulation diverged inside the segment (its last state is held after).
    pub diverged: bool,
}

/// A resimulation and its residuals.
#[derive(Debug, Clone, Serialize)]
pub struct Resimulation {
    /// The recorded flight's file.
    pub source: String,
    /// "mcap", "csv" or "ros2".
    pub format: &'static str,
    /// The model flown.
    pub model: String,
    /// What the simulation is compared with: "logged state" or "motion capture".
    pub reference: &'static str,
    /// Where the start states came from.
    pub start_source: StartSource,
    /// Whether they were fitted (with the model held).
    pub start_states_fitted: bool,
    /// Per segment.
    pub segments: Vec<SegmentSummary>,
    /// Over every segment.
    pub total: SegmentSummary,
    /// Ctrl-C stopped the start-state fit.
    pub interrupted: bool,
    /// The recorded body at the reference samples.
    #[serde(skip)]
    pub real: Vec<TrackPoint>,
    /// The simulated body at the same times.
    #[serde(skip)]
    pub simulated: Vec<TrackPoint>,
    /// The differences at those times.
    #[serde(skip)]
    pub residuals: Vec<ResidualPoint>,
}

/// Accumulates squared errors.
#[derive(Default)]
struct Rms {
    n: usize,
    pos: f64,
    att: f64,
    rate_n: usize,
    rate: f64,
}

impl Rms {
    fn add(&mut self, r: &ResidualPoint) {
        self.n += 1;
        self.pos += r.position_error_m.powi(2);
        self.att += r.attitude_error_deg.powi(2);
        if let Some(e) = r.rate_error_rad_s {
            self.add_rate(e);
        }
    }

    fn add_rate(&mut self, e: f64) {
        self.rate_n += 1;
        self.rate += e * e;
    }

    fn summary(&self, index: usize, start_s: f64, end_s: f64, diverged: bool) -> SegmentSummary {
        let n = self.n.max(1) as f64;
        SegmentSummary {
            index,
            start_s,
            end_s,
            samples: self.n,
            position_rms_m: (self.pos / n).sqrt(),
            attitude_rms_deg: (self.att / n).sqrt(),
            rate_rms_rad_s: (self.rate_n > 0).then(|| (self.rate / self.rate_n as f64).sqrt()),
            diverged,
        }
    }
}

fn point(t_s: f64, s: &State) -> TrackPoint {
    TrackPoint {
        t_s,
        position_m: s.position_m,
        world_from_body: s.world_from_body,
    }
}

/// Flies `data`'s model beside its recorded flight (see the module docs). `observer` sees
/// the start-state fit's progress and stops it by returning false.
pub fn resimulate(
    data: &FlightData,
    opts: &ResimOptions,
    observer: &mut dyn FnMut(&Progress) -> bool,
) -> Result<Resimulation> {
    let fit_opts = FitOptions {
        params: Vec::new(),
        segment_wingbeats: opts.segment_wingbeats,
        use_imu: false,
        fd_step: None,
        patience: opts.patience,
        max_duration_s: opts.max_duration_s,
        start_states: opts.start_states,
    };
    let setup = setup_for(data, &fit_opts, true)?;
    let mut x = vec![0.0; setup.unknowns()];
    let mut interrupted = false;
    if setup.fit_states {
        let (problem, _, _, _) = super::solve(&setup, x, &fit_opts, observer);
        interrupted = problem.stopped.get();
        x = problem.x.clone();
    }
    let trial = setup
        .trial(&x)
        .ok_or_else(|| Error::Model(format!("`{}` does not load", data.model_origin)))?;
    let dt_s = setup.dt_s;
    let logged = !data.logged_states.is_empty();
    let mut real = Vec::new();
    let mut simulated = Vec::new();
    let mut residuals = Vec::new();
    let mut segments = Vec::new();
    let mut all = Rms::default();
    let mut carried = None;
    for (k, seg) in setup.segments.iter().enumerate() {
        let start = setup.start_state(k, &x);
        let wings = setup.wings_at_start(&trial, k, carried.take());
        let (states, diverged, end) =
            setup
                .fly(&trial, k, &start, &wings)
                .unwrap_or((Vec::new(), true, None));
        carried = end;
        let last = states.last().copied().unwrap_or(start);
        let at = |j: usize| states.get(j).copied().unwrap_or(last);
        let end = seg.step0 + seg.steps as u64;
        // (local step, recorded pose, recorded rates)
        let mut refs: Vec<(usize, TrackPoint, Option<nalgebra::Vector3<f64>>)> = Vec::new();
        if logged {
            let lo = data.logged_states.partition_point(|(s, ..)| *s < seg.step0);
            for (step, s, _) in data.logged_states[lo..]
                .iter()
                .take_while(|(s, ..)| *s < end)
            {
                let t = *step as f64 * dt_s;
                refs.push((
                    (step - seg.step0) as usize,
                    point(t, s),
                    Some(s.angular_velocity_body_rad_s),
                ));
            }
        } else {
            for &(j, i) in &seg.mocap {
                let f = &data.mocap[i];
                refs.push((
                    j,
                    TrackPoint {
                        t_s: f.t_s,
                        position_m: f.position_m,
                        world_from_body: f.attitude,
                    },
                    None,
                ));
            }
        }
        let mut rms = Rms::default();
        for (j, rec, rates) in refs {
            let s = at(j);
            let t_s = (seg.step0 + j as u64) as f64 * dt_s;
            let r = ResidualPoint {
                t_s: rec.t_s,
                segment: k as u32,
                position_error_m: (s.position_m - rec.position_m).norm(),
                attitude_error_deg: rec
                    .world_from_body
                    .angle_to(&s.world_from_body)
                    .to_degrees(),
                rate_error_rad_s: rates.map(|w| (s.angular_velocity_body_rad_s - w).norm()),
            };
            rms.add(&r);
            all.add(&r);
            real.push(rec);
            simulated.push(point(t_s, &s));
            residuals.push(r);
        }
        // The gyroscope, where the record has one and no logged state.
        if !logged && !data.imu.is_empty() {
            let t0 = seg.step0 as f64 * dt_s;
            let t1 = end as f64 * dt_s;
            let lo = data.imu.partition_point(|f| f.t_s < t0 - dt_s);
            for f in data.imu[lo..].iter().take_while(|f| f.t_s < t1 + dt_s) {
                let Some(step) = step_at(f.t_s, dt_s, 1e-9) else {
                    continue;
                };
                if step < seg.step0 || step >= end {
                    continue;
                }
                let s = at((step - seg.step0) as usize);
                let e = (s.angular_velocity_body_rad_s - f.gyro_rad_s).norm();
                rms.add_rate(e);
                all.add_rate(e);
            }
        }
        segments.push(rms.summary(k, seg.step0 as f64 * dt_s, end as f64 * dt_s, diverged));
    }
    let (t0, t1) = (
        segments.first().map_or(0.0, |s| s.start_s),
        segments.last().map_or(0.0, |s| s.end_s),
    );
    let any_diverged = segments.iter().any(|s| s.diverged);
    Ok(Resimulation {
        source: data.source.display().to_string(),
        format: data.format,
        model: setup.base.name.clone(),
        reference: if logged {
            "logged state"
        } else {
            "motion capture"
        },
        start_source: data.start_source,
        start_states_fitted: setup.fit_states,
        total: all.summary(segments.len(), t0, t1, any_diverged),
        segments,
        interrupted,
        real,
        simulated,
        residuals,
    })
}

impl std::fmt::Display for Resimulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "resimulated {} ({}) with model {}: {} segments, starts from the {}{}; compared with the {}",
            self.source,
            self.format,
            self.model,
            self.segments.len(),
            match self.start_source {
                StartSource::LoggedState => "logged state",
                StartSource::Mocap => "motion capture",
            },
            if self.start_states_fitted {
                " (fitted, model held)"
            } else {
                ""
            },
            self.reference
        )?;
        writeln!(
            f,
            "{:>7}  {:>9}  {:>9}  {:>7}  {:>14}  {:>16}  {:>16}",
            "segment",
            "start_s",
            "end_s",
            "samples",
            "position_rms_m",
            "attitude_rms_deg",
            "rate_rms_rad_s"
        )?;
        let row = |f: &mut std::fmt::Formatter<'_>, name: String, s: &SegmentSummary| {
            writeln!(
                f,
                "{name:>7}  {:>9.5}  {:>9.5}  {:>7}  {:>14.4e}  {:>16.4e}  {:>16}{}",
                s.start_s,
                s.end_s,
                s.samples,
                s.position_rms_m,
                s.attitude_rms_deg,
                s.rate_rms_rad_s
                    .map_or("-".to_owned(), |r| format!("{r:.4e}")),
                if s.diverged { "  diverged" } else { "" }
            )
        };
        for s in &self.segments {
            row(f, s.index.to_string(), s)?;
        }
        row(f, "all".to_owned(), &self.total)?;
        if self.interrupted {
            writeln!(
                f,
                "interrupted (Ctrl-C): the start states are those reached so far"
            )?;
        }
        Ok(())
    }
}
