//! A resolved study: the base model, the factors and every case, and the vehicle of each
//! case (the base model edited at the factors' paths); shards of its cases.

use flapsim::model::{Vehicle, VehicleSpec};

use super::super::error::{StudyError, StudyResult};
use super::super::responses::Response;
use super::file::DesignKind;
use super::path::{PathStep, set_path};

/// A parsed factor.
#[derive(Debug, Clone, PartialEq)]
pub struct Factor {
    /// The dotted path as written.
    pub path: String,
    /// The path's steps.
    pub steps: Vec<PathStep>,
    /// The discrete levels (empty for a Latin hypercube factor).
    pub levels: Vec<f64>,
    /// The range (Latin hypercube).
    pub range: Option<(f64, f64)>,
}

/// A resolved study: the base model as an explicit TOML table, the factors, and every case.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// Name used for output files.
    pub name: String,
    /// The study file (for messages).
    pub origin: String,
    /// The base model's origin (file path or built-in name).
    pub base_origin: String,
    /// The base vehicle model with all defaults explicit.
    pub base: toml::Table,
    /// The design.
    pub design: DesignKind,
    /// The factors.
    pub factors: Vec<Factor>,
    /// The responses, in output order.
    pub responses: Vec<Response>,
    /// Phase samples per wingbeat for the cycle means.
    pub steps_per_wingbeat: usize,
    /// Every case's factor values (`cases[i][f]`), in case order.
    pub cases: Vec<Vec<f64>>,
}

/// A factor value for messages: plain between 1e-3 and 1e7 in magnitude (and 0), else in
/// exponent form (`3e-6`, not `0.000003`); every digit Rust's shortest round trip needs.
pub fn value_text(v: f64) -> String {
    if v == 0.0 || (1e-3..1e7).contains(&v.abs()) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Builds a vehicle from an edited model table.
pub fn vehicle_from_table(table: toml::Table, origin: &str) -> flapsim::Result<Vehicle> {
    let spec: VehicleSpec =
        toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| wingforce::Error::Parse {
                origin: origin.to_owned(),
                message: e.to_string().trim_end().to_owned(),
            })?;
    spec.build(origin)
}

impl Study {
    /// Number of cases.
    pub fn case_count(&self) -> usize {
        self.cases.len()
    }

    /// `path = value` of every factor of case `i`, joined by commas (values as
    /// [`value_text`] writes them).
    pub fn settings_text(&self, i: usize) -> String {
        self.settings_at(&self.cases[i])
    }

    /// `path = value` of every factor at `values` (one per factor), joined by commas.
    pub fn settings_at(&self, values: &[f64]) -> String {
        self.factors
            .iter()
            .zip(values)
            .map(|(f, &v)| format!("{} = {}", f.path, value_text(v)))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The vehicle of case `i`.
    pub fn vehicle(&self, i: usize) -> StudyResult<Vehicle> {
        self.vehicle_at(&self.cases[i])
            .map_err(|source| StudyError::Case {
                case: i,
                settings: self.settings_text(i),
                source,
            })
    }

    /// The vehicle with the factors at `values` (one per factor, in order): the base model
    /// edited at each factor's path, then validated.
    pub fn vehicle_at(&self, values: &[f64]) -> flapsim::Result<Vehicle> {
        assert_eq!(values.len(), self.factors.len(), "one value per factor");
        let mut t = self.base.clone();
        for (f, &v) in self.factors.iter().zip(values) {
            set_path(&mut t, &f.steps, v)
                .map_err(|m| flapsim::Error::Analysis(format!("factor `{}`: {m}", f.path)))?;
        }
        vehicle_from_table(t, &self.base_origin)
    }

    /// The interval a factor spans: its range, or its lowest and highest level.
    pub fn factor_bounds(&self, f: usize) -> (f64, f64) {
        let factor = &self.factors[f];
        factor.range.unwrap_or_else(|| {
            let lo = factor.levels.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = factor
                .levels
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        })
    }

    /// The case indices of shard `k` of `n` (1-based k): contiguous blocks, sizes differing
    /// by at most one.
    pub fn shard_range(&self, k: usize, n: usize) -> std::ops::Range<usize> {
        shard_range(self.case_count(), k, n)
    }
}

/// Case indices `[floor((k-1) N / n), floor(k N / n))` of shard `k` (1-based) of `n`.
pub fn shard_range(cases: usize, k: usize, n: usize) -> std::ops::Range<usize> {
    assert!(n >= 1 && (1..=n).contains(&k), "shard {k}/{n}");
    ((k - 1) * cases / n)..(k * cases / n)
}
