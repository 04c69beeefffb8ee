//! Study files: a base vehicle model, factors that change numeric fields of it, a design
//! that picks the cases, and the responses to evaluate.
//!
//! ```toml
//! name = "drosophila_amplitude_aoa"     # optional; the CLI uses the file stem when absent
//! base_model = "drosophila"             # a built-in name, or a vehicle TOML path (relative
//!                                       # to the study file)
//! design = "full_factorial"             # or latin_hypercube, taguchi_l9, taguchi_l18, taguchi_l27
//! responses = ["lift_over_weight", "aero_power_w"]
//! steps_per_wingbeat = 100              # optional; default: the model's sim.steps_per_wingbeat
//!
//! [[factor]]
//! path = "kinematics.amplitude_deg"     # dotted path of a numeric field; `[i]` indexes arrays
//! levels = [120.0, 140.0, 160.0]
//!
//! [[factor]]
//! path = "kinematics.mid_stroke_aoa_deg"
//! range = [30.0, 60.0]                  # with count: evenly spaced levels, ends included
//! count = 4
//! ```
//!
//! `latin_hypercube` takes `samples` and `seed` (default 0) and needs a `range` for every
//! factor. Taguchi designs assign each factor, in order, to the first free column of the
//! array with its number of levels (so three factors of 6, 3 and 3 levels on `taguchi_l18`
//! reproduce the seed paper's Table 2).
//!
//! Factors are applied to the base model after it is parsed and written back out with every
//! default made explicit, so a path may name a field the base file leaves at its default
//! (`aero.strips`, `controls.amplitude_deg`, `initial.attitude_deg[1]`). Integer fields take
//! integral levels only. The fluid's two alternatives exclude each other: setting
//! `fluid.reynolds` removes `fluid.kinematic_viscosity_m2_s` and the other way round.

use serde::Deserialize;

use super::error::{StudyError, StudyResult};
use super::responses::Response;
use super::taguchi::OrthogonalArray;
use flapsim::model::{Vehicle, VehicleSpec};

/// The most cases one study may have.
pub const MAX_CASES: usize = 1_000_000;

/// A study file as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// Name used in output file names (default: the file stem, chosen by the caller).
    #[serde(default)]
    pub name: Option<String>,
    /// Built-in vehicle name (`drosophila`, `robobee`, `bumblebee`) or a vehicle TOML path.
    pub base_model: String,
    /// The design.
    pub design: DesignKind,
    /// Latin hypercube: number of samples.
    #[serde(default)]
    pub samples: Option<usize>,
    /// Latin hypercube: random seed.
    #[serde(default)]
    pub seed: Option<u64>,
    /// Phase samples per wingbeat for the cycle means (default: the model's
    /// `sim.steps_per_wingbeat`).
    #[serde(default)]
    pub steps_per_wingbeat: Option<usize>,
    /// Names of the responses to evaluate, in output order.
    pub responses: Vec<String>,
    /// The factors.
    #[serde(rename = "factor")]
    pub factors: Vec<FactorSpec>,
}

/// How the cases are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DesignKind {
    /// Every combination of levels; the first factor varies slowest.
    FullFactorial,
    /// Latin hypercube sampling of the factor ranges.
    LatinHypercube,
    /// Taguchi L9(3^4).
    TaguchiL9,
    /// Taguchi L18(6^1 x 3^6) (first three columns: the seed paper's Table 2).
    TaguchiL18,
    /// Taguchi L27(3^13).
    TaguchiL27,
}

impl DesignKind {
    /// The snake-case name.
    pub fn name(self) -> &'static str {
        match self {
            Self::FullFactorial => "full_factorial",
            Self::LatinHypercube => "latin_hypercube",
            Self::TaguchiL9 => "taguchi_l9",
            Self::TaguchiL18 => "taguchi_l18",
            Self::TaguchiL27 => "taguchi_l27",
        }
    }
}

/// One factor as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FactorSpec {
    /// Dotted path of a numeric field of the vehicle TOML, e.g. `kinematics.amplitude_deg`.
    pub path: String,
    /// Explicit levels.
    #[serde(default)]
    pub levels: Option<Vec<f64>>,
    /// `[lo, hi]`: with `count`, evenly spaced levels; for a Latin hypercube, the range.
    #[serde(default)]
    pub range: Option<[f64; 2]>,
    /// Number of evenly spaced levels over `range`.
    #[serde(default)]
    pub count: Option<usize>,
}

/// One step of a factor path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PathStep {
    /// A table key.
    Key(String),
    /// An array index.
    Index(usize),
}

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

/// Parses `a.b[2].c` into steps.
pub fn parse_path(path: &str) -> Result<Vec<PathStep>, String> {
    let mut steps = Vec::new();
    if path.trim().is_empty() {
        return Err("the path is empty".to_owned());
    }
    for part in path.split('.') {
        let (key, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if key.is_empty()
            || !key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(format!(
                "`{part}` is not a key (letters, digits, `_` and `-`, optionally followed by [index])"
            ));
        }
        steps.push(PathStep::Key(key.to_owned()));
        while !rest.is_empty() {
            let close = rest
                .find(']')
                .ok_or_else(|| format!("unclosed `[` in `{part}`"))?;
            let idx: usize = rest[1..close]
                .parse()
                .map_err(|_| format!("`{}` in `{part}` is not an array index", &rest[1..close]))?;
            steps.push(PathStep::Index(idx));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(format!("unexpected `{rest}` after an index in `{part}`"));
            }
        }
    }
    Ok(steps)
}

/// Sets the numeric value at `steps` in `root` (see the module docs for the rules).
pub fn set_path(root: &mut toml::Table, steps: &[PathStep], value: f64) -> Result<(), String> {
    let (last, parents) = steps.split_last().ok_or("the path is empty")?;
    // Work on a copy and put it back at the end, so that errors leave `root` untouched.
    let mut scratch = toml::Value::Table(root.clone());
    let mut cur: &mut toml::Value = &mut scratch;
    let mut walked = String::new();
    for step in parents {
        cur = match step {
            PathStep::Key(k) => {
                walked.push_str(if walked.is_empty() { "" } else { "." });
                walked.push_str(k);
                let table = cur
                    .as_table_mut()
                    .ok_or_else(|| format!("`{walked}`: the parent is not a table"))?;
                table
                    .entry(k.clone())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            }
            PathStep::Index(i) => {
                walked.push_str(&format!("[{i}]"));
                let arr = cur
                    .as_array_mut()
                    .ok_or_else(|| format!("`{walked}`: not an array"))?;
                let len = arr.len();
                arr.get_mut(*i).ok_or_else(|| {
                    format!("`{walked}`: index out of range (the array has {len} entries)")
                })?
            }
        };
    }
    let slot: &mut toml::Value = match last {
        PathStep::Key(k) => {
            let table = cur
                .as_table_mut()
                .ok_or_else(|| "the parent of the last key is not a table".to_owned())?;
            if k == "reynolds" {
                table.remove("kinematic_viscosity_m2_s");
            } else if k == "kinematic_viscosity_m2_s" {
                table.remove("reynolds");
            }
            table
                .entry(k.clone())
                .or_insert(toml::Value::Float(f64::NAN))
        }
        PathStep::Index(i) => {
            let arr = cur
                .as_array_mut()
                .ok_or_else(|| "the parent of the last index is not an array".to_owned())?;
            let len = arr.len();
            arr.get_mut(*i)
                .ok_or_else(|| format!("index {i} out of range (the array has {len} entries)"))?
        }
    };
    *slot = match slot {
        toml::Value::Float(_) => toml::Value::Float(value),
        toml::Value::Integer(_) => {
            if value.fract() == 0.0 && value.abs() < 9.0e15 {
                toml::Value::Integer(value as i64)
            } else {
                return Err(format!(
                    "the field holds an integer; the level {value} is not an integer"
                ));
            }
        }
        other => {
            return Err(format!(
                "the field holds a {}, not a number",
                other.type_str()
            ));
        }
    };
    let toml::Value::Table(t) = scratch else {
        unreachable!("the root stays a table")
    };
    *root = t;
    Ok(())
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

impl StudySpec {
    /// Parses a study file (`origin` names it in errors).
    pub fn from_toml(text: &str, origin: &str) -> StudyResult<Self> {
        toml::from_str(text).map_err(|e| StudyError::Invalid {
            origin: origin.to_owned(),
            message: e.to_string().trim_end().to_owned(),
        })
    }

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

/// SplitMix64 (Steele, Lea and Flood 2014): a small, fast, well-mixed generator; the same
/// seed gives the same Latin hypercube on every platform.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// A uniform number in [0, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// A uniform integer in [0, n) (n > 0), by rejection (no modulo bias).
    pub fn below(&mut self, n: u64) -> u64 {
        let zone = u64::MAX - u64::MAX % n;
        loop {
            let x = self.next_u64();
            if x < zone {
                return x % n;
            }
        }
    }
}

/// A Latin hypercube of `n` samples over the given ranges: in every factor each of the n
/// equal strata holds exactly one sample, placed uniformly inside it (McKay, Beckman and
/// Conover 1979).
pub fn latin_hypercube(ranges: &[(f64, f64)], n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = SplitMix64::new(seed);
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(ranges.len());
    for &(lo, hi) in ranges {
        let mut perm: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            let j = rng.below(i as u64 + 1) as usize;
            perm.swap(i, j);
        }
        cols.push(
            perm.iter()
                .map(|&s| lo + (hi - lo) * (s as f64 + rng.next_f64()) / n as f64)
                .collect(),
        );
    }
    (0..n)
        .map(|i| cols.iter().map(|c| c[i]).collect())
        .collect()
}

fn generate_cases(spec: &StudySpec, factors: &[Factor]) -> Result<Vec<Vec<f64>>, String> {
    if spec.design != DesignKind::LatinHypercube && (spec.samples.is_some() || spec.seed.is_some())
    {
        return Err(format!(
            "`samples` and `seed` belong to latin_hypercube, not {}",
            spec.design.name()
        ));
    }
    let taguchi = |oa: OrthogonalArray| -> Result<Vec<Vec<f64>>, String> {
        let counts: Vec<usize> = factors.iter().map(|f| f.levels.len()).collect();
        let cols = oa.assign(&counts)?;
        Ok(oa
            .rows
            .iter()
            .map(|row| {
                factors
                    .iter()
                    .zip(&cols)
                    .map(|(f, &c)| f.levels[row[c] as usize - 1])
                    .collect()
            })
            .collect())
    };
    match spec.design {
        DesignKind::FullFactorial => {
            let total = factors
                .iter()
                .try_fold(1usize, |acc, f| acc.checked_mul(f.levels.len()))
                .filter(|&t| t <= MAX_CASES)
                .ok_or_else(|| format!("the full factorial has more than {MAX_CASES} cases"))?;
            Ok((0..total)
                .map(|mut i| {
                    let mut v = vec![0.0; factors.len()];
                    for (slot, f) in v.iter_mut().zip(factors).rev() {
                        *slot = f.levels[i % f.levels.len()];
                        i /= f.levels.len();
                    }
                    v
                })
                .collect())
        }
        DesignKind::LatinHypercube => {
            let n = spec
                .samples
                .ok_or("latin_hypercube needs `samples` (the number of cases)")?;
            if !(1..=MAX_CASES).contains(&n) {
                return Err(format!("`samples` = {n}: an integer in [1, {MAX_CASES}]"));
            }
            let ranges: Vec<(f64, f64)> = factors
                .iter()
                .map(|f| f.range.expect("latin hypercube factors have ranges"))
                .collect();
            Ok(latin_hypercube(&ranges, n, spec.seed.unwrap_or(0)))
        }
        DesignKind::TaguchiL9 => taguchi(OrthogonalArray::l9()),
        DesignKind::TaguchiL18 => taguchi(OrthogonalArray::l18()),
        DesignKind::TaguchiL27 => taguchi(OrthogonalArray::l27()),
    }
}

impl Study {
    /// Number of cases.
    pub fn case_count(&self) -> usize {
        self.cases.len()
    }

    /// `path = value` of every factor of case `i`, joined by commas.
    pub fn settings_text(&self, i: usize) -> String {
        self.factors
            .iter()
            .zip(&self.cases[i])
            .map(|(f, v)| format!("{} = {v}", f.path))
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
