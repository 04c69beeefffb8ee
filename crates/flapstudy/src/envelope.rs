//! The flight envelope: a vehicle trimmed over a grid of forward speeds and climb rates
//! ([`flapsim::flight`]), each point with its trim variables, its power, its margin to the
//! limit of what drives the wings, and its averaged-model modes about that trim
//! ([`flapsim::stability::analyze_trim`]). Points are independent and run in parallel
//! (rayon); a point that does not trim is kept with the reason.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use flapsim::flight::{FlightCondition, LimitMargin, TrimPoint, limit_margin, trim_point};
use flapsim::model::Vehicle;
use flapsim::stability::{ModeInfo, analyze_trim};
use flapsim::trim::{Trim, trim_at};

use crate::error::{StudyError, StudyResult as Result};

/// The grid of an envelope: every forward speed with every climb rate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnvelopeGrid {
    /// Forward speeds, m/s.
    pub speeds_m_s: Vec<f64>,
    /// Climb rates, m/s.
    pub climb_rates_m_s: Vec<f64>,
}

impl EnvelopeGrid {
    /// A grid, or an error naming `origin` (e.g. the option), the value and what is allowed:
    /// neither list empty, every value a valid [`FlightCondition`].
    pub fn new(speeds_m_s: Vec<f64>, climb_rates_m_s: Vec<f64>, origin: &str) -> Result<Self> {
        let invalid = |message: String| StudyError::Invalid {
            origin: origin.to_owned(),
            message,
        };
        if speeds_m_s.is_empty() || climb_rates_m_s.is_empty() {
            return Err(invalid(format!(
                "an empty grid ({} speeds, {} climb rates); allowed: at least one of each",
                speeds_m_s.len(),
                climb_rates_m_s.len()
            )));
        }
        for &u in &speeds_m_s {
            FlightCondition::new(u, 0.0).map_err(|e| invalid(format!("speed: {e}")))?;
        }
        for &w in &climb_rates_m_s {
            FlightCondition::new(0.0, w).map_err(|e| invalid(format!("climb rate: {e}")))?;
        }
        Ok(Self {
            speeds_m_s,
            climb_rates_m_s,
        })
    }

    /// `n` speeds evenly from `from_m_s` to `to_m_s` (both included) at climb rate 0.
    pub fn speeds(from_m_s: f64, to_m_s: f64, n: usize, origin: &str) -> Result<Self> {
        let speeds = match n {
            0 => Vec::new(),
            1 => vec![from_m_s],
            _ => (0..n)
                .map(|i| from_m_s + (to_m_s - from_m_s) * i as f64 / (n - 1) as f64)
                .collect(),
        };
        Self::new(speeds, vec![0.0], origin)
    }

    /// The conditions: for each climb rate, every speed.
    pub fn conditions(&self) -> Vec<FlightCondition> {
        self.climb_rates_m_s
            .iter()
            .flat_map(|&w| {
                self.speeds_m_s.iter().map(move |&u| FlightCondition {
                    forward_speed_m_s: u,
                    climb_rate_m_s: w,
                })
            })
            .collect()
    }
}

/// One trimmed point of the envelope.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnvelopePoint {
    /// The trim (controls, body pitch, residuals).
    pub trim: Trim,
    /// Stroke-plane angle, amplitude, power, downwash.
    pub point: TrimPoint,
    /// Margin to the stroke-amplitude or drive-voltage limit.
    pub margin: LimitMargin,
    /// Averaged-model longitudinal modes about the trim.
    pub longitudinal_modes: Vec<ModeInfo>,
    /// Averaged-model lateral modes about the trim.
    pub lateral_modes: Vec<ModeInfo>,
}

/// One row of the envelope: a condition and what came of it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnvelopeRow {
    /// The flight condition.
    pub condition: FlightCondition,
    /// The trimmed point, or `None` when it does not trim.
    pub point: Option<EnvelopePoint>,
    /// Why the point does not trim (empty when it does).
    pub no_trim_reason: String,
}

/// Trims and analyses one condition.
pub fn envelope_point(vehicle: &Vehicle, condition: &FlightCondition) -> EnvelopeRow {
    let run = || -> flapsim::Result<EnvelopePoint> {
        let trim = trim_at(vehicle, vehicle.trim_lift, condition)?;
        let point = trim_point(vehicle, &trim)?;
        let report = analyze_trim(vehicle, &trim, false)?;
        Ok(EnvelopePoint {
            margin: limit_margin(vehicle, &trim, &point),
            trim,
            point,
            longitudinal_modes: report.longitudinal_modes,
            lateral_modes: report.lateral_modes,
        })
    };
    match run() {
        Ok(p) => EnvelopeRow {
            condition: *condition,
            point: Some(p),
            no_trim_reason: String::new(),
        },
        Err(e) => EnvelopeRow {
            condition: *condition,
            point: None,
            no_trim_reason: e.to_string(),
        },
    }
}

/// The reason of a point skipped because `stop` asked.
pub const INTERRUPTED: &str = "interrupted before this point ran";

/// The envelope of `vehicle` over `grid`, in the grid's order, points in parallel;
/// `on_point` is called as each point finishes (from rayon's threads: a progress bar), and
/// once `stop` returns true the points not yet started are skipped ([`INTERRUPTED`]).
pub fn envelope(
    vehicle: &Vehicle,
    grid: &EnvelopeGrid,
    on_point: &(dyn Fn(&EnvelopeRow) + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Vec<EnvelopeRow> {
    grid.conditions()
        .par_iter()
        .map(|c| {
            let row = if stop() {
                EnvelopeRow {
                    condition: *c,
                    point: None,
                    no_trim_reason: INTERRUPTED.into(),
                }
            } else {
                envelope_point(vehicle, c)
            };
            on_point(&row);
            row
        })
        .collect()
}

/// The CSV header of [`to_csv`].
pub const CSV_HEADER: &str = "forward_speed_m_s,climb_rate_m_s,trimmed,body_pitch_deg,stroke_plane_angle_deg,stroke_amplitude_deg,mean_stroke_offset_deg,aero_power_w,aero_positive_power_w,parasite_power_w,induced_downwash_m_s,limit_quantity,limit_margin_fraction,longitudinal_sigma_max_per_s,lateral_sigma_max_per_s,longitudinal_modes,no_trim_reason";

/// The envelope as CSV (one row per condition; modes as `re+imi` joined by `;`).
pub fn to_csv(rows: &[EnvelopeRow]) -> String {
    let mut out = String::from(CSV_HEADER);
    out.push('\n');
    let modes = |m: &[ModeInfo]| {
        m.iter()
            .map(|m| format!("{:.6e}{:+.6e}i", m.re_per_s, m.im_rad_s))
            .collect::<Vec<_>>()
            .join(";")
    };
    let sigma_max = |m: &[ModeInfo]| {
        m.iter()
            .map(|m| m.re_per_s)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    for r in rows {
        let c = &r.condition;
        match &r.point {
            Some(p) => out.push_str(&format!(
                "{},{},1,{:.6},{:.6},{:.6},{:.6},{:.6e},{:.6e},{:.6e},{:.6e},{},{:.6},{:.6e},{:.6e},{},\n",
                c.forward_speed_m_s,
                c.climb_rate_m_s,
                p.trim.pitch_rad.to_degrees(),
                p.point.stroke_plane_angle_rad.to_degrees(),
                p.point.stroke_amplitude_rad.to_degrees(),
                p.trim.controls.mean_stroke_rad.to_degrees(),
                p.point.power.aero_w,
                p.point.power.aero_positive_w,
                p.point.parasite_power_w,
                p.point.induced_downwash_m_s,
                p.margin.quantity,
                p.margin.fraction,
                sigma_max(&p.longitudinal_modes),
                sigma_max(&p.lateral_modes),
                modes(&p.longitudinal_modes),
            )),
            None => out.push_str(&format!(
                "{},{},0,,,,,,,,,,,,,,\"{}\"\n",
                c.forward_speed_m_s,
                c.climb_rate_m_s,
                r.no_trim_reason.replace('"', "'")
            )),
        }
    }
    out
}
