//! `flapwing validate`: every published number the model must reproduce (MODEL.md section 5,
//! the seed paper's Tables 3 and 5, Dickinson et al. 1999), computed through wingforce and the
//! built-in robofly model, one row per case; then the built-in insects at their published
//! operating points (`flapsim::operating_points`), where a row the quasi-steady model is
//! known to miss says why; then every built-in vehicle against measured data
//! (`flapsim::vehicle_validation`: pass or MISS with the miss's measured cause). Exits 1 if
//! any case fails (a known limitation or a vehicle row's MISS is not a failure; an
//! unexplained miss, or a note on a row that now agrees, is).

use std::fmt::Write;

use anyhow::anyhow;
use serde::Serialize;
use wingforce::reproduction::{Case, Rule};
use wingforce::{Wing, WingModelSpec};

use flapsim::operating_points::{OperatingPoint, Verdict, operating_points};
use flapsim::vehicle_validation::{VehicleSection, vehicle_section};

use crate::cli::{ValidateArgs, ValidateSection};
use crate::input::{BUILTIN_ROBOFLY, BUILTIN_ROBOFLY_ORIGIN};
use crate::output::{print_json, print_stdout};

/// The built-in robofly model (the paper's wing in run V3), on its fixed mount.
fn robofly() -> anyhow::Result<Wing> {
    // Not the user's input: a failure here is a failed run (exit 1), not bad input.
    WingModelSpec::from_toml(BUILTIN_ROBOFLY, BUILTIN_ROBOFLY_ORIGIN)
        .and_then(|s| s.build(BUILTIN_ROBOFLY_ORIGIN))
        .map_err(|e| anyhow!("the built-in robofly model does not build: {e}"))
}

/// Every reproduction case, computed now on the built-in robofly
/// (`wingforce::reproduction`).
fn cases() -> anyhow::Result<Vec<Case>> {
    wingforce::reproduction::cases(&robofly()?)
        .map_err(|e| anyhow!("the seed paper's reproduction: {e}"))
}

/// One row of the JSON document.
#[derive(Debug, Clone, PartialEq, Serialize)]
struct Row {
    case: String,
    source: &'static str,
    published: f64,
    computed: f64,
    error: f64,
    tolerance: f64,
    rule: String,
    pass: bool,
}

/// One operating-point row of the JSON document.
#[derive(Debug, Clone, PartialEq, Serialize)]
struct PointRow {
    case: String,
    source: &'static str,
    published: f64,
    computed: f64,
    relative_error: f64,
    relative_tolerance: f64,
    /// `pass`, `known limitation`, `FAIL` or `FAIL (stale note)`.
    verdict: &'static str,
    limitation: Option<String>,
}

fn verdict_text(v: Verdict) -> &'static str {
    match v {
        Verdict::Pass => "pass",
        Verdict::KnownLimitation => "known limitation",
        Verdict::Fail => "FAIL",
        Verdict::StaleNote => "FAIL (stale note)",
    }
}

/// The JSON document of this command: a section not asked for (`--section`) is left out.
#[derive(Debug, Clone, PartialEq, Serialize)]
struct Report {
    #[serde(skip_serializing_if = "Option::is_none")]
    cases: Option<Vec<Row>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    operating_points: Option<Vec<PointRow>>,
    /// The built-in vehicles against measured data (issue 24): rows with their verdicts
    /// (`pass` / `MISS` and the miss's cause), what was NOT FOUND, the models' estimates.
    #[serde(skip_serializing_if = "Option::is_none")]
    vehicles: Option<VehicleSection>,
    /// Vehicle rows that pass and that miss, and the misses among the property rows (a
    /// miss is reported with its cause, not counted in `failed`).
    #[serde(skip_serializing_if = "Option::is_none")]
    vehicles_passed: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    vehicles_missed: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    vehicles_property_missed: Option<usize>,
    total: usize,
    passed: usize,
    failed: usize,
    all_passed: bool,
}

/// Runs the command.
pub fn run(args: ValidateArgs) -> anyhow::Result<()> {
    let wanted = |s: ValidateSection| args.section.is_empty() || args.section.contains(&s);
    let cases = if wanted(ValidateSection::Cases) {
        cases()?
    } else {
        Vec::new()
    };
    let points = if wanted(ValidateSection::OperatingPoints) {
        operating_points().map_err(|e| anyhow!("the built-in insects' operating points: {e}"))?
    } else {
        Vec::new()
    };
    let vehicles = if wanted(ValidateSection::Vehicles) {
        Some(
            vehicle_section()
                .map_err(|e| anyhow!("the built-in vehicles against measured data: {e}"))?,
        )
    } else {
        None
    };
    let failed = cases.iter().filter(|c| !c.passes()).count()
        + points
            .iter()
            .filter(|p| matches!(p.verdict(), Verdict::Fail | Verdict::StaleNote))
            .count();
    if args.json {
        print_json(&Report {
            cases: wanted(ValidateSection::Cases).then(|| {
                cases
                    .iter()
                    .map(|c| Row {
                        case: c.name.clone(),
                        source: c.source,
                        published: c.published,
                        computed: c.computed,
                        error: c.error(),
                        tolerance: c.tolerance(),
                        rule: c.rule_text(),
                        pass: c.passes(),
                    })
                    .collect()
            }),
            operating_points: wanted(ValidateSection::OperatingPoints).then(|| {
                points
                    .iter()
                    .map(|p| PointRow {
                        case: p.name.clone(),
                        source: p.source,
                        published: p.published,
                        computed: p.computed,
                        relative_error: p.relative_error(),
                        relative_tolerance: p.relative_tolerance,
                        verdict: verdict_text(p.verdict()),
                        limitation: p.limitation.clone(),
                    })
                    .collect()
            }),
            vehicles_passed: vehicles.as_ref().map(VehicleSection::passed),
            vehicles_missed: vehicles.as_ref().map(VehicleSection::missed),
            vehicles_property_missed: vehicles.as_ref().map(VehicleSection::missed_properties),
            vehicles: vehicles.clone(),
            total: cases.len() + points.len(),
            passed: cases.len() + points.len() - failed,
            failed,
            all_passed: failed == 0,
        })?;
    } else {
        if wanted(ValidateSection::Cases) {
            print_stdout(&table(&cases)?)?;
        }
        if wanted(ValidateSection::OperatingPoints) {
            print_stdout(&points_table(&points)?)?;
        }
        if let Some(vehicles) = &vehicles {
            print_stdout(&vehicles_table(vehicles)?)?;
        }
    }
    if failed > 0 {
        return Err(anyhow!(
            "{failed} of {} reproduction cases failed",
            cases.len() + points.len()
        ));
    }
    Ok(())
}

fn table(cases: &[Case]) -> Result<String, std::fmt::Error> {
    let name_w = cases.iter().map(|c| c.name.len()).max().unwrap_or(4);
    let source_w = cases.iter().map(|c| c.source.len()).max().unwrap_or(6);
    let mut s = String::new();
    writeln!(
        s,
        "{:<name_w$}  {:<source_w$}  {:>12}  {:>12}  {:>10}  {:>9}  result",
        "case", "source", "published", "computed", "error", "tolerance"
    )?;
    for c in cases {
        let tolerance = match c.rule {
            Rule::Absolute(t) => format!("{t:.0e}"),
            Rule::SignificantDigits(n) => format!("{n} s.d."),
        };
        writeln!(
            s,
            "{:<name_w$}  {:<source_w$}  {:>12.8}  {:>12.8}  {:>10.1e}  {tolerance:>9}  {}",
            c.name,
            c.source,
            c.published,
            c.computed,
            c.error(),
            if c.passes() { "pass" } else { "FAIL" }
        )?;
    }
    let failed = cases.iter().filter(|c| !c.passes()).count();
    writeln!(s)?;
    if failed == 0 {
        writeln!(s, "all {} cases pass", cases.len())?;
    } else {
        writeln!(s, "{failed} of {} cases FAIL", cases.len())?;
    }
    Ok(s)
}

fn points_table(points: &[OperatingPoint]) -> Result<String, std::fmt::Error> {
    let name_w = points.iter().map(|c| c.name.len()).max().unwrap_or(4);
    let source_w = points.iter().map(|c| c.source.len()).max().unwrap_or(6);
    let mut s = String::new();
    writeln!(
        s,
        "\nbuilt-in insects at their published operating points (averaged analysis for the modes):"
    )?;
    writeln!(
        s,
        "{:<name_w$}  {:<source_w$}  {:>9}  {:>9}  {:>7}  {:>5}  result",
        "case", "source", "published", "computed", "error", "tol."
    )?;
    for p in points {
        writeln!(
            s,
            "{:<name_w$}  {:<source_w$}  {:>9.4}  {:>9.4}  {:>+6.0}%  {:>4.0}%  {}",
            p.name,
            p.source,
            p.published,
            p.computed,
            100.0 * p.relative_error(),
            100.0 * p.relative_tolerance,
            verdict_text(p.verdict())
        )?;
    }
    for (i, p) in points.iter().enumerate() {
        if let Some(why) = &p.limitation {
            writeln!(s, "  note {}: {why}", i + 1)?;
        }
    }
    Ok(s)
}

fn vehicles_table(v: &VehicleSection) -> Result<String, std::fmt::Error> {
    let q_w = v.rows.iter().map(|r| r.quantity.len()).max().unwrap_or(8);
    let mut s = String::new();
    writeln!(
        s,
        "\nbuilt-in vehicles against measured data (tethered runs from rest, 30 settling + 4 measured drive periods; amplitudes half peak-to-peak; phase + advanced, - delayed):"
    )?;
    writeln!(
        s,
        "(model: the built-in model as it stands; other wake: for a vehicle with an induced flow, the same row under the other wake, [aero] inflow = \"dynamic\" (the pair's wake answers its loads and the body) for a frozen one and \"frozen\" for a dynamic one; for an actuated or four-winged vehicle in still air, under \"dynamic\")"
    )?;
    writeln!(
        s,
        "{:<11}  {:<q_w$}  {:>11}  {:>22}  {:>11}  {:>16}  result",
        "vehicle", "quantity", "model", "other wake", "measured", "tolerance"
    )?;
    let mut causes = Vec::new();
    for r in &v.rows {
        let measured = match r.measured {
            Some(x) => format!("{x:>11.4}"),
            None if r.property => format!("{:>11}", "(property)"),
            None => format!("{:>11}", "NOT FOUND"),
        };
        let mut verdict = r.verdict.name().to_owned();
        if r.property && r.cause.is_some() {
            verdict = "MISS of a property".to_owned();
        }
        if let Some(c) = &r.cause {
            causes.push((causes.len() + 1, c));
            verdict = format!("{verdict} (cause {})", causes.len());
        }
        // A miss under the other wake has its own cause, measured under that wake.
        if let Some(o) = &r.other_wake
            && let Some(c) = &o.cause
        {
            causes.push((causes.len() + 1, c));
            verdict = format!("{verdict}; {}: cause {}", o.inflow, causes.len());
        }
        let value = |x: f64| {
            if x.abs() < 1e-2 && x != 0.0 {
                format!("{x:.3e}")
            } else {
                format!("{x:.4}")
            }
        };
        let model = format!("{:>11}", value(r.model));
        let other = match &r.other_wake {
            Some(f) => format!(
                "{:>22}",
                format!("{} {} {}", f.inflow, value(f.model), f.verdict.name())
            ),
            None => format!("{:>22}", ""),
        };
        writeln!(
            s,
            "{:<11}  {:<q_w$}  {model}  {other}  {measured}  {:>16}  {verdict}",
            r.vehicle,
            r.quantity,
            r.tolerance_text()
        )?;
        writeln!(s, "{:<11}    source: {}", "", r.source)?;
    }
    for (i, c) in causes {
        writeln!(s, "  cause {i}: {c}")?;
    }
    for (vehicle, what) in &v.not_found {
        writeln!(s, "  NOT FOUND ({vehicle}): {what}")?;
    }
    writeln!(s, "  estimates, not published numbers:")?;
    for e in &v.estimates {
        writeln!(s, "    {} {}: {}", e.vehicle, e.parameter, e.why)?;
    }
    writeln!(
        s,
        "{} of {} vehicle rows pass, {} MISS ({} of them a property the model must have); a miss is reported with its cause, not counted as a failed case",
        v.passed(),
        v.rows.len(),
        v.missed(),
        v.missed_properties()
    )?;
    let others: Vec<_> = v
        .rows
        .iter()
        .filter_map(|r| r.other_wake.as_ref().map(|o| (r, o)))
        .collect();
    if let Some((_, first)) = others.first() {
        let pass = |own: bool| {
            others
                .iter()
                .filter(|(r, o)| {
                    let verdict = if own { r.verdict } else { o.verdict };
                    verdict == flapsim::vehicle_validation::Verdict::Pass
                })
                .count()
        };
        writeln!(
            s,
            "the {} rows shown under another wake (the vehicles with an induced flow, and the actuated and four-winged ones in still air): {} pass as the models stand, {} under the other wake ({})",
            others.len(),
            pass(true),
            pass(false),
            first.inflow
        )?;
    }
    Ok(s)
}
