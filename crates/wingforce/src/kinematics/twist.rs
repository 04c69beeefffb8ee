//! A measured wing's spanwise twist: the feathering (pitch) angle measured at several stations
//! along the span, where the wing's own `pitch_deg` is the feathering at one reference station.
//!
//! Insect wings are not rigid: the feathering angle changes along the span. Azuma & Watanabe
//! 1988 (J Exp Biol 137:221, Table 3) give a dragonfly's feathering series at 0.25R, 0.5R and
//! 0.75R: the forewing's first harmonic grows from 14-25 deg at 0.25R to 46-54 deg at 0.75R.
//! A table's pitch is the feathering at `reference_r_frac` (0.75R in the dragonfly files), and
//! each further station's table is stored as its offset from it, a periodic spline of the
//! wingbeat phase like the pitch's own.
//!
//! Along the span the offset is linear between neighbouring stations (the reference station's
//! offset is 0), and beyond the outermost and innermost stations the end segments are extended
//! (an estimate: the sources give no station outside 0.25-0.75R; the public reproduction of
//! Azuma & Watanabe's flights, github.com/jpecquet/dragonfly-flight-control, takes the first
//! harmonic linear along the whole span). r is measured from the stroke axis, as R.
//!
//! What the twist changes (`crate::wing`): each blade-element strip of the translational term
//! meets the air at its own feathering angle, so its angle of attack is its own; the strip's
//! lift and drag are turned back into the reference chord's axes before they are summed. The
//! rotational, added-mass and wake-capture terms keep the reference station's pitch and
//! rates (the rigid wing's), which this module's users state.

use serde::{Deserialize, Serialize};

use crate::error::{Result, Validator};
use crate::spline::PeriodicSpline;

/// Most stations a twist can have besides the reference.
pub const MAX_TWIST_STATIONS: usize = 3;

/// A tabulated wing's spanwise twist as a model file writes it (`[kinematics.twist]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwistSpec {
    /// The station the table's `pitch_deg` is measured at, as a fraction of R (the tip's
    /// distance from the stroke axis), in (0, 1].
    pub reference_r_frac: f64,
    /// The further stations, fractions of R in (0, 1], each distinct from the others and from
    /// the reference (at most [`MAX_TWIST_STATIONS`]).
    pub stations_r_frac: Vec<f64>,
    /// The feathering (pitch) angle at each station and each time of the table's `t_s`, deg:
    /// one list per station, each as long as `t_s` and periodic (its last value its first).
    pub pitch_deg: Vec<Vec<f64>>,
}

/// A twist built from a [`TwistSpec`]: the stations sorted outward, each with its offset from
/// the reference pitch (`None` for the reference itself).
#[derive(Debug, Clone, PartialEq)]
pub struct TableTwist {
    r_frac: Vec<f64>,
    offset: Vec<Option<PeriodicSpline>>,
}

/// The twist at one wingbeat phase: the stations (fractions of R, sorted outward, the
/// reference among them) and each one's feathering offset from the reference pitch, rad.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwistAt {
    n: usize,
    r_frac: [f64; MAX_TWIST_STATIONS + 1],
    offset_rad: [f64; MAX_TWIST_STATIONS + 1],
}

impl TwistSpec {
    /// Checks the twist of a table with `t_s` (`n` times, `phases` of the period) and builds
    /// it; `field` is the twist's dotted path, `pitch_rad` the table's own pitch.
    pub(crate) fn build(
        &self,
        v: &Validator,
        field: &str,
        phases: &[f64],
        pitch_rad: &[f64],
    ) -> Result<TableTwist> {
        let f = |name: &str| format!("{field}.{name}");
        let n = phases.len();
        v.within_open_low(&f("reference_r_frac"), self.reference_r_frac, 0.0, 1.0)?;
        let k = self.stations_r_frac.len();
        if !(1..=MAX_TWIST_STATIONS).contains(&k) {
            return Err(v.invalid(
                &f("stations_r_frac"),
                format!("{k} stations"),
                &format!("1 to {MAX_TWIST_STATIONS} stations besides the reference"),
            ));
        }
        if self.pitch_deg.len() != k {
            return Err(v.invalid(
                &f("pitch_deg"),
                format!("{} lists", self.pitch_deg.len()),
                &format!("one list per station in stations_r_frac ({k})"),
            ));
        }
        let mut stations: Vec<(f64, Option<PeriodicSpline>)> = vec![(self.reference_r_frac, None)];
        for (i, (&r, list)) in self.stations_r_frac.iter().zip(&self.pitch_deg).enumerate() {
            let name = format!("{}[{i}]", f("stations_r_frac"));
            v.within_open_low(&name, r, 0.0, 1.0)?;
            if stations.iter().any(|(s, _)| (s - r).abs() < 1e-9) {
                return Err(v.invalid(
                    &name,
                    r,
                    "a station distinct from the reference and from the other stations",
                ));
            }
            let list_name = format!("{}[{i}]", f("pitch_deg"));
            if list.len() != n {
                return Err(v.invalid(
                    &list_name,
                    format!("{} values", list.len()),
                    &format!("one value per time in t_s ({n})"),
                ));
            }
            for (j, &x) in list.iter().enumerate() {
                v.within(&format!("{list_name}[{j}]"), x, -360.0, 360.0)?;
            }
            if (list[n - 1] - list[0]).abs() > 1e-6 {
                return Err(v.invalid(
                    &format!("{list_name}[{}]", n - 1),
                    list[n - 1],
                    &format!(
                        "equal to the first value ({}): the table must be periodic",
                        list[0]
                    ),
                ));
            }
            let offset: Vec<f64> = list
                .iter()
                .zip(pitch_rad)
                .map(|(d, p)| d.to_radians() - p)
                .collect();
            stations.push((r, Some(PeriodicSpline::new(phases, &offset))));
        }
        stations.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (r_frac, offset) = stations.into_iter().unzip();
        Ok(TableTwist { r_frac, offset })
    }
}

impl TableTwist {
    /// The twist at table phase `tau` in [0, 1).
    pub(crate) fn at(&self, tau: f64) -> TwistAt {
        let mut t = TwistAt {
            n: self.r_frac.len(),
            r_frac: [0.0; MAX_TWIST_STATIONS + 1],
            offset_rad: [0.0; MAX_TWIST_STATIONS + 1],
        };
        for (i, (r, s)) in self.r_frac.iter().zip(&self.offset).enumerate() {
            t.r_frac[i] = *r;
            t.offset_rad[i] = s.as_ref().map_or(0.0, |s| s.value(tau));
        }
        t
    }
}

impl TwistAt {
    /// The feathering offset from the reference pitch at `r_frac` of R, rad: linear between
    /// neighbouring stations, the end segments extended beyond them (module docs).
    pub fn offset_rad(&self, r_frac: f64) -> f64 {
        let (r, o) = (&self.r_frac[..self.n], &self.offset_rad[..self.n]);
        // The segment: the first whose outer station lies beyond r, else the last.
        let i = (1..self.n - 1)
            .find(|&i| r_frac < r[i])
            .unwrap_or(self.n - 1);
        let w = (r_frac - r[i - 1]) / (r[i] - r[i - 1]);
        o[i - 1] + w * (o[i] - o[i - 1])
    }
}
