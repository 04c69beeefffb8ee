//! Resolving a study file against its base model: every factor and response checked, and
//! the cases generated.

use flapsim::model::VehicleSpec;

use super::super::error::{StudyError, StudyResult};
use super::super::responses::Response;
use super::design::generate_cases;
use super::file::{DesignKind, MAX_CASES, StudySpec};
use super::path::{PathStep, parse_path, set_path};
use super::study::{Factor, Study, vehicle_from_table};

impl StudySpec {
    /// Resolves the study against the base model's text: checks every factor and response,
    /// and generates the cases. `default_name` is used when the file gives no `name`.
    pub fn resolve(
        &self,
        origin: &str,
        default_name: &str,
        base_text: &str,
        base_origin: &str,
    ) -> StudyResult<Study> {
        let invalid = |message: String| StudyError::Invalid {
            origin: origin.to_owned(),
            message,
        };
        let name = self.name.clone().unwrap_or_else(|| default_name.to_owned());
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
        {
            return Err(invalid(format!(
                "`name` = {name:?}: use letters, digits, `_`, `-` and `.` only (it names output files)"
            )));
        }
        // The base, parsed by the vehicle's own rules, then written out with all defaults.
        let base_spec = VehicleSpec::from_toml(base_text, base_origin)
            .and_then(|s| s.build(base_origin).map(|_| s))
            .map_err(|e| invalid(format!("base_model `{}`: {e}", self.base_model)))?;
        let base = toml::Table::try_from(&base_spec)
            .map_err(|e| invalid(format!("base_model `{}`: {e}", self.base_model)))?;

        let mut responses = Vec::with_capacity(self.responses.len());
        if self.responses.is_empty() {
            return Err(invalid(format!(
                "`responses` is empty; choose among: {}",
                Response::all_names().join(", ")
            )));
        }
        for r in &self.responses {
            let resp = Response::parse(r).ok_or_else(|| {
                invalid(format!(
                    "unknown response `{r}`; choose among: {}",
                    Response::all_names().join(", ")
                ))
            })?;
            if responses.contains(&resp) {
                return Err(invalid(format!("response `{r}` is listed twice")));
            }
            responses.push(resp);
        }

        if self.factors.is_empty() {
            return Err(invalid(
                "no [[factor]]: a study needs at least one".to_owned(),
            ));
        }
        let lhs = self.design == DesignKind::LatinHypercube;
        let mut factors: Vec<Factor> = Vec::with_capacity(self.factors.len());
        for (i, f) in self.factors.iter().enumerate() {
            let at = |m: String| invalid(format!("factor {} (`{}`): {m}", i + 1, f.path));
            let steps = parse_path(&f.path).map_err(at)?;
            if base_spec.actuation.is_some()
                && steps.first() == Some(&PathStep::Key("kinematics".into()))
            {
                return Err(at(format!(
                    "base_model `{}` has actuated wings: their motion is an output of its \
                     [actuation] dynamics, and [kinematics] is only the nominal motion the \
                     first wingbeat starts from, so no response would move with it; vary the \
                     drive or the wings' dynamics instead (the numbers under [actuation]{})",
                    self.base_model,
                    match actuation_examples(&base) {
                        e if e.is_empty() => String::new(),
                        e => format!(", e.g. {}", e.join(", ")),
                    }
                )));
            }
            if factors.iter().any(|g| g.path == f.path) {
                return Err(at("the same path appears twice".to_owned()));
            }
            let finite = |x: f64, what: &str| {
                if x.is_finite() {
                    Ok(x)
                } else {
                    Err(at(format!("{what} {x} is not a finite number")))
                }
            };
            let (levels, range) = match (&f.levels, f.range, f.count, lhs) {
                (_, Some([lo, hi]), None, true) if f.levels.is_none() => {
                    finite(lo, "range start")?;
                    finite(hi, "range end")?;
                    if lo >= hi {
                        return Err(at(format!("range [{lo}, {hi}] must have lo < hi")));
                    }
                    (Vec::new(), Some((lo, hi)))
                }
                (_, _, _, true) => {
                    return Err(at(
                        "a latin_hypercube factor needs `range = [lo, hi]` (and no `levels` or `count`)"
                            .to_owned(),
                    ));
                }
                (Some(levels), None, None, false) => {
                    if levels.is_empty() {
                        return Err(at("`levels` is empty".to_owned()));
                    }
                    for &x in levels {
                        finite(x, "level")?;
                    }
                    let mut sorted = levels.clone();
                    sorted.sort_by(f64::total_cmp);
                    sorted.dedup();
                    if sorted.len() != levels.len() {
                        return Err(at("`levels` repeats a value".to_owned()));
                    }
                    (levels.clone(), None)
                }
                (None, Some([lo, hi]), Some(count), false) => {
                    finite(lo, "range start")?;
                    finite(hi, "range end")?;
                    if lo >= hi || count < 2 {
                        return Err(at(format!(
                            "range [{lo}, {hi}] with count {count}: need lo < hi and count >= 2"
                        )));
                    }
                    let levels = (0..count)
                        .map(|k| {
                            if k + 1 == count {
                                hi
                            } else {
                                lo + (hi - lo) * k as f64 / (count - 1) as f64
                            }
                        })
                        .collect();
                    (levels, None)
                }
                _ => {
                    return Err(at(
                        "give either `levels = [...]` or `range = [lo, hi]` with `count` (a range without count only for latin_hypercube)"
                            .to_owned(),
                    ));
                }
            };
            // Each level alone must make a valid vehicle: errors name the factor.
            let probe: Vec<f64> = if levels.is_empty() {
                let (lo, hi) = range.expect("a range when there are no levels");
                vec![lo, hi]
            } else {
                levels.clone()
            };
            for &x in &probe {
                let mut t = base.clone();
                set_path(&mut t, &steps, x).map_err(at)?;
                vehicle_from_table(t, base_origin).map_err(|e| at(format!("level {x}: {e}")))?;
            }
            factors.push(Factor {
                path: f.path.clone(),
                steps,
                levels,
                range,
            });
        }

        let cases = generate_cases(self, &factors).map_err(invalid)?;
        if cases.len() > MAX_CASES {
            return Err(invalid(format!(
                "the design has {} cases; at most {MAX_CASES} are allowed",
                cases.len()
            )));
        }
        let base_steps = base_spec.sim.steps_per_wingbeat;
        let steps_per_wingbeat = self.steps_per_wingbeat.unwrap_or(base_steps);
        if !(2..=100_000).contains(&steps_per_wingbeat) {
            return Err(invalid(format!(
                "`steps_per_wingbeat` = {steps_per_wingbeat}: an integer in [2, 100000]"
            )));
        }
        Ok(Study {
            name,
            origin: origin.to_owned(),
            base_origin: base_origin.to_owned(),
            base,
            design: self.design,
            factors,
            responses,
            steps_per_wingbeat,
            cases,
        })
    }
}

/// The base model's drive frequency and amplitude and its hinge's and stroke's stiffness,
/// as factor paths, where its `[actuation]` table has them: what an error that refuses a
/// path with no effect suggests instead.
fn actuation_examples(base: &toml::Table) -> Vec<String> {
    let Some(toml::Value::Table(act)) = base.get("actuation") else {
        return Vec::new();
    };
    [
        ("drive", "freq_hz"),
        ("drive", "amplitude_v"),
        ("hinge", "stiffness_nm_rad"),
        ("stroke", "flexure_nm_rad"),
    ]
    .into_iter()
    .filter(|(section, key)| {
        matches!(act.get(*section), Some(toml::Value::Table(t)) if t.get(*key).is_some_and(|v| v.is_float() || v.is_integer()))
    })
    .map(|(section, key)| format!("`actuation.{section}.{key}`"))
    .collect()
}
