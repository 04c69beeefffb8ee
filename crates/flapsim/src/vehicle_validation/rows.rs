//! The section's rows: what is compared (`Check`), the verdict, a row and the section, and
//! the builder the vehicles' checks push rows into.

use serde::Serialize;

/// How a row's model value is checked.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Check {
    /// |model / measured - 1| <= tolerance.
    Relative {
        /// The tolerance (fraction).
        tolerance: f64,
    },
    /// lo <= model <= hi.
    Within {
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// model < bound (a sign check).
    Below {
        /// The bound.
        bound: f64,
    },
}

/// A row's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Verdict {
    /// Within the tolerance.
    #[serde(rename = "pass")]
    Pass,
    /// Outside (or not computable): the row's cause says why.
    #[serde(rename = "MISS")]
    Miss,
}

impl Verdict {
    /// `pass` or `MISS`.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Miss => "MISS",
        }
    }
}

/// One row of the vehicles section.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VehicleRow {
    /// The built-in vehicle.
    pub vehicle: &'static str,
    /// What is compared, with units and the operating point.
    pub quantity: String,
    /// Where the measured value comes from (and what was NOT FOUND).
    pub source: String,
    /// The model's value (NaN when it could not be computed: then a miss).
    pub model: f64,
    /// The measured value; `None` when no published value was found.
    pub measured: Option<f64>,
    /// The check.
    pub check: Check,
    /// pass or MISS, from the numbers and the check.
    pub verdict: Verdict,
    /// For a miss: its cause, measured on the model.
    pub cause: Option<String>,
    /// A property the model must have (its misses are named apart), not a comparison with
    /// measured data.
    pub property: bool,
    /// For a vehicle with an induced flow: the same row under the other wake, dynamic for a
    /// model whose wake is frozen and frozen for one whose wake answers (issue #38's
    /// side-by-side), else `None`.
    pub other_wake: Option<OtherWake>,
}

/// A row's value, verdict and cause under the other wake ([`VehicleRow::other_wake`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OtherWake {
    /// The induced-flow model of this value.
    pub inflow: wingforce::InflowModel,
    /// The model's value.
    pub model: f64,
    /// Its verdict against the same measured value and check.
    pub verdict: Verdict,
    /// For a miss: its cause, measured on the model under this wake.
    pub cause: Option<String>,
}

impl VehicleRow {
    /// The verdict the numbers give (NaN misses).
    pub fn passes(&self) -> bool {
        let m = self.model;
        match (self.check, self.measured) {
            (Check::Relative { tolerance }, Some(x)) => (m / x - 1.0).abs() <= tolerance,
            (Check::Relative { .. }, None) => false,
            (Check::Within { lo, hi }, _) => lo <= m && m <= hi,
            (Check::Below { bound }, _) => m < bound,
        }
    }

    /// The tolerance as text.
    pub fn tolerance_text(&self) -> String {
        match self.check {
            Check::Relative { tolerance } => format!("+-{:.0}%", 100.0 * tolerance),
            Check::Within { lo, hi } => format!("in [{}, {}]", num(lo), num(hi)),
            Check::Below { bound } => format!("< {}", num(bound)),
        }
    }

    /// model / measured - 1, where there is a measured value.
    pub fn relative_error(&self) -> Option<f64> {
        self.measured.map(|x| self.model / x - 1.0)
    }
}

pub(super) fn num(x: f64) -> String {
    if x == 0.0 || (1e-3..1e4).contains(&x.abs()) {
        format!("{}", (x * 1e4).round() / 1e4)
    } else {
        format!("{x:.3e}")
    }
}

/// A parameter of a built-in model that is an estimate, not a published number.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// The vehicle.
    pub vehicle: &'static str,
    /// The model file's key (section.key).
    pub parameter: &'static str,
    /// Why it is an estimate.
    pub why: &'static str,
}

/// The vehicles section.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VehicleSection {
    /// The rows, vehicle by vehicle.
    pub rows: Vec<VehicleRow>,
    /// What the section could not compare (published values NOT FOUND), per vehicle.
    pub not_found: Vec<(&'static str, &'static str)>,
    /// The built-in vehicles' parameters that are estimates.
    pub estimates: Vec<Estimate>,
}

impl VehicleSection {
    /// Rows that pass.
    pub fn passed(&self) -> usize {
        self.rows
            .iter()
            .filter(|r| r.verdict == Verdict::Pass)
            .count()
    }
    /// Rows that miss.
    pub fn missed(&self) -> usize {
        self.rows.len() - self.passed()
    }
    /// Property rows that miss.
    pub fn missed_properties(&self) -> usize {
        self.rows
            .iter()
            .filter(|r| r.property && r.verdict == Verdict::Miss)
            .count()
    }
}

pub(super) struct RowBuilder {
    pub(super) rows: Vec<VehicleRow>,
    /// Whether every vehicle with an induced flow meets the other wake in this pass (frozen
    /// for dynamic and dynamic for frozen: [`super::other_wake`]).
    pub(super) other_wake: bool,
}

impl RowBuilder {
    /// A built-in vehicle, with this pass's wake.
    pub(super) fn vehicle(&self, name: &str) -> crate::error::Result<crate::model::Vehicle> {
        self.with_pass_wake(crate::operating_points::builtin(name)?)
    }

    /// `v` with this pass's wake (its own, or the other one: [`other_wake`]).
    pub(super) fn with_pass_wake(
        &self,
        v: crate::model::Vehicle,
    ) -> crate::error::Result<crate::model::Vehicle> {
        match other_wake(&v) {
            Some(m) if self.other_wake => v.with_inflow_model(m),
            _ => Ok(v),
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn push(
        &mut self,
        vehicle: &'static str,
        quantity: impl Into<String>,
        source: impl Into<String>,
        model: f64,
        measured: Option<f64>,
        check: Check,
        property: bool,
        cause: impl FnOnce() -> String,
    ) {
        let mut row = VehicleRow {
            vehicle,
            quantity: quantity.into(),
            source: source.into(),
            model,
            measured,
            check,
            verdict: Verdict::Miss,
            cause: None,
            property,
            other_wake: None,
        };
        if row.passes() {
            row.verdict = Verdict::Pass;
        } else {
            // Measured under this pass's wake: the other pass's cause is its miss's
            // ([`OtherWake::cause`]).
            row.cause = Some(cause());
        }
        self.rows.push(row);
    }
}

/// The wake a vehicle's rows are shown under beside its own: dynamic for frozen, frozen for
/// dynamic; an actuated or four-winged vehicle in still air beside the dynamic wake (a
/// frozen wake's disc would be a prescribed stroke, or one pair's: `model/build.rs`); none
/// for the other still-air models.
pub fn other_wake(v: &crate::model::Vehicle) -> Option<wingforce::InflowModel> {
    match v.inflow_model() {
        wingforce::InflowModel::Off if v.actuation.is_some() || v.wings.len() > 2 => {
            Some(wingforce::InflowModel::Dynamic)
        }
        wingforce::InflowModel::Off => None,
        wingforce::InflowModel::Frozen => Some(wingforce::InflowModel::Dynamic),
        wingforce::InflowModel::Dynamic => Some(wingforce::InflowModel::Frozen),
    }
}
