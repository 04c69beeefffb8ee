//! Running a study's cases in parallel and writing them as CSV; merging shards.
//!
//! CSV layout: `case` (0-based case index), one column per factor (headed by its path), one
//! column per response (in the study's order), then `reynolds`, `wake_capture_clamped` (0 or
//! 1), `status` and `error`. Numbers use Rust's shortest round-trip formatting (`{:?}`), so a
//! value read back is the value computed, bit for bit, and the same case always prints the
//! same row: the row order and content do not depend on the number of threads or the
//! sharding.
//!
//! **Failed cases.** A design study explores corners where the analysis of a design can fail:
//! an actuated wing that does not settle into a periodic motion, dynamics that diverge. Such a
//! case is a row of the table like any other: `status` is `failed`, `error` says why (the
//! analysis's message, with `,` written as `;` because the table has no quoting), and the
//! responses, `reynolds` and `wake_capture_clamped` are empty. A finished case has `status` =
//! `ok` and an empty `error`. What counts as a failed case is [`is_case_failure`]: the
//! analysis could not find what it looked for ([`flapsim::Error::Analysis`]) or the run
//! diverged ([`flapsim::Error::Diverged`]). A bad study (an unknown field, a value or a
//! combination of values the model refuses) is an error, never a row: a single value is
//! refused when the study is resolved, a combination before any case of its block of
//! [`BLOCK`] cases runs.

use std::ops::Range;

use rayon::prelude::*;

use flapsim::model::Vehicle;

use super::error::{StudyError, StudyResult};
use super::responses::{HoverResponses, Response, hover_responses};
use super::spec::{Study, value_text};
use super::table::Table;

/// Columns every sweep CSV ends with.
pub const FLAG_COLUMNS: [&str; 4] = ["reynolds", "wake_capture_clamped", "status", "error"];

/// The `status` of a finished case.
pub const STATUS_OK: &str = "ok";
/// The `status` of a failed case.
pub const STATUS_FAILED: &str = "failed";

/// What became of one case.
#[derive(Debug, Clone, PartialEq)]
pub enum CaseOutcome {
    /// The evaluation finished: everything it produced.
    Done(HoverResponses),
    /// The analysis of this design failed (see [`is_case_failure`]): why, in words.
    Failed(String),
}

/// One evaluated case.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseResult {
    /// Case index.
    pub case: usize,
    /// Factor values.
    pub inputs: Vec<f64>,
    /// The evaluation's result, or why it failed.
    pub outcome: CaseOutcome,
    /// The study's responses, in order (NaN for a failed case).
    pub responses: Vec<f64>,
}

impl CaseResult {
    /// Everything the evaluation produced, unless the case failed.
    pub fn done(&self) -> Option<&HoverResponses> {
        match &self.outcome {
            CaseOutcome::Done(all) => Some(all),
            CaseOutcome::Failed(_) => None,
        }
    }

    /// Why the case failed, if it did.
    pub fn failure(&self) -> Option<&str> {
        match &self.outcome {
            CaseOutcome::Done(_) => None,
            CaseOutcome::Failed(why) => Some(why),
        }
    }
}

/// Whether an error of a case's evaluation is that design's failure (a row of the table with
/// its reason) rather than a bad study: the analysis could not find what it looked for (no
/// periodic motion of actuated wings, no trim, controls the wings cannot follow) or the
/// dynamics diverged. Model and input errors are the study's: they stop the sweep.
pub fn is_case_failure(e: &flapsim::Error) -> bool {
    matches!(
        e,
        flapsim::Error::Analysis(_) | flapsim::Error::Diverged { .. }
    )
}

/// A failure reason as one CSV cell: `,` becomes `;` and line breaks become spaces (the table
/// has no quoting).
pub fn csv_cell_text(reason: &str) -> String {
    reason
        .chars()
        .map(|c| match c {
            ',' => ';',
            '\n' | '\r' => ' ',
            c => c,
        })
        .collect()
}

/// Cases run in blocks of this many: the vehicles of a block are built and checked
/// ([`Study::check_cases`]) before any case of the block runs, then evaluated in parallel.
/// A study (or shard) of at most this many cases is refused before any case runs; the
/// vehicles of a block are built once (building one costs about as much as evaluating a
/// fixed-kinematics case) and held only while their block runs.
pub const BLOCK: usize = 1024;

impl Study {
    /// Evaluates one case. A failed analysis of the design ([`is_case_failure`]) is a
    /// [`CaseOutcome::Failed`] result; any other error (the case's vehicle cannot be built, the
    /// model does not fit the responses) is the study's and is returned.
    pub fn evaluate(&self, case: usize) -> StudyResult<CaseResult> {
        let vehicle = self.checked_vehicle(case)?;
        self.evaluate_vehicle(case, &vehicle)
    }

    /// The vehicle of `case`, refused (as the study's error) when the model rejects it or the
    /// responses cannot be evaluated on it (one wing pair only).
    fn checked_vehicle(&self, case: usize) -> StudyResult<Vehicle> {
        let vehicle = self.vehicle(case)?;
        vehicle
            .require_one_pair("flapstudy's hover responses")
            .map_err(|source| StudyError::Case {
                case,
                settings: self.settings_text(case),
                source,
            })?;
        Ok(vehicle)
    }

    /// Evaluates `case` on its (checked) vehicle.
    fn evaluate_vehicle(&self, case: usize, vehicle: &Vehicle) -> StudyResult<CaseResult> {
        let outcome = match hover_responses(vehicle, self.steps_per_wingbeat) {
            Ok(mut all) => {
                if self.responses.contains(&Response::TrimFeasible) {
                    all.trim_feasible = Some(flapsim::trim::trim(vehicle).is_ok());
                }
                CaseOutcome::Done(all)
            }
            Err(e) if is_case_failure(&e) => CaseOutcome::Failed(e.to_string()),
            Err(source) => {
                return Err(StudyError::Case {
                    case,
                    settings: self.settings_text(case),
                    source,
                });
            }
        };
        let responses = match &outcome {
            CaseOutcome::Done(all) => self.responses.iter().map(|r| all.get(r)).collect(),
            CaseOutcome::Failed(_) => vec![f64::NAN; self.responses.len()],
        };
        Ok(CaseResult {
            case,
            inputs: self.cases[case].clone(),
            outcome,
            responses,
        })
    }

    /// Checks that every case of `range` makes a vehicle the model accepts and the responses
    /// can be evaluated on (one wing pair): a bad study is an error naming the first bad case
    /// and its settings, never a failed row. It builds every vehicle (no wingbeat is
    /// evaluated); [`Study::run`] does this block by block ([`BLOCK`]).
    pub fn check_cases(&self, range: Range<usize>) -> StudyResult<()> {
        first_error(
            range
                .into_par_iter()
                .map(|i| self.checked_vehicle(i).map(drop))
                .collect(),
        )
        .map(drop)
    }

    /// Evaluates the cases `range` on the current rayon pool, calling `progress` after each
    /// case. Results are in case order, failed cases included (see the module docs); a bad
    /// study is an error before any case of its block runs ([`BLOCK`]).
    pub fn run(
        &self,
        range: Range<usize>,
        progress: &(dyn Fn(&CaseResult) + Sync),
    ) -> StudyResult<Vec<CaseResult>> {
        self.run_until(range, progress, &|| false)
    }

    /// Like [`Study::run`], but cases not yet started when `stop` returns true are skipped
    /// (e.g. on Ctrl-C): the result holds the completed cases, in case order.
    pub fn run_until(
        &self,
        range: Range<usize>,
        progress: &(dyn Fn(&CaseResult) + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> StudyResult<Vec<CaseResult>> {
        let mut out = Vec::with_capacity(range.len());
        let mut start = range.start;
        while start < range.end && !stop() {
            let end = (start + BLOCK).min(range.end);
            let vehicles = first_error(
                (start..end)
                    .into_par_iter()
                    .map(|i| self.checked_vehicle(i))
                    .collect(),
            )?;
            let results: Vec<Option<StudyResult<CaseResult>>> = vehicles
                .into_par_iter()
                .enumerate()
                .map(|(k, vehicle)| {
                    if stop() {
                        return None;
                    }
                    let r = self.evaluate_vehicle(start + k, &vehicle);
                    if let Ok(done) = &r {
                        progress(done);
                    }
                    Some(r)
                })
                .collect();
            for r in results.into_iter().flatten() {
                out.push(r?);
            }
            start = end;
        }
        Ok(out)
    }

    /// The CSV header line (without newline).
    pub fn csv_header(&self) -> String {
        let mut cols = vec!["case".to_owned()];
        cols.extend(self.factors.iter().map(|f| f.path.clone()));
        cols.extend(self.responses.iter().map(|r| r.name()));
        cols.extend(FLAG_COLUMNS.iter().map(|s| s.to_string()));
        cols.join(",")
    }

    /// One CSV row (without newline).
    pub fn csv_row(&self, r: &CaseResult) -> String {
        let mut cols = vec![r.case.to_string()];
        cols.extend(r.inputs.iter().map(|v| format!("{v:?}")));
        match &r.outcome {
            CaseOutcome::Done(all) => {
                cols.extend(r.responses.iter().map(|v| format!("{v:?}")));
                cols.push(format!("{:?}", all.reynolds));
                cols.push(if all.wake_capture_clamped { "1" } else { "0" }.to_owned());
                cols.push(STATUS_OK.to_owned());
                cols.push(String::new());
            }
            CaseOutcome::Failed(why) => {
                cols.extend(std::iter::repeat_n(String::new(), r.responses.len() + 2));
                cols.push(STATUS_FAILED.to_owned());
                cols.push(csv_cell_text(why));
            }
        }
        cols.join(",")
    }

    /// The whole CSV text of `results` (header and rows, newline-terminated).
    pub fn csv(&self, results: &[CaseResult]) -> String {
        let mut out = self.csv_header();
        out.push('\n');
        for r in results {
            out.push_str(&self.csv_row(r));
            out.push('\n');
        }
        out
    }

    /// The failed cases of `results`, as [`FailedCase`]s.
    pub fn failed_cases(&self, results: &[CaseResult]) -> Vec<FailedCase> {
        results
            .iter()
            .filter_map(|r| {
                r.failure().map(|why| FailedCase {
                    case: r.case,
                    settings: self.settings_text(r.case),
                    reason: csv_cell_text(why),
                })
            })
            .collect()
    }
}

/// The values, or the error of the lowest index.
fn first_error<T>(results: Vec<StudyResult<T>>) -> StudyResult<Vec<T>> {
    results.into_iter().collect()
}

/// A failed case, as a summary lists it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FailedCase {
    /// Case index.
    pub case: usize,
    /// `path = value` of every factor, joined by commas.
    pub settings: String,
    /// Why it failed (as in the `error` column).
    pub reason: String,
}

/// At most this many failed cases are listed one per line by [`failure_summary`].
pub const LISTED_FAILURES: usize = 10;

/// The lines that report a table's failed cases (empty when none failed): a count, then one
/// line per failed case (at most [`LISTED_FAILURES`], then how many more).
pub fn failure_summary(failed: &[FailedCase], cases: usize) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    if failed.is_empty() {
        return out;
    }
    let indices: Vec<String> = failed.iter().map(|f| f.case.to_string()).collect();
    let _ = writeln!(
        out,
        "{} of {cases} case(s) failed (status = failed; the reason is in the `error` column): case(s) {}",
        failed.len(),
        if failed.len() <= LISTED_FAILURES {
            indices.join(", ")
        } else {
            format!("{}, ...", indices[..LISTED_FAILURES].join(", "))
        }
    );
    for f in failed.iter().take(LISTED_FAILURES) {
        let _ = writeln!(out, "  case {} ({}): {}", f.case, f.settings, f.reason);
    }
    if failed.len() > LISTED_FAILURES {
        let _ = writeln!(
            out,
            "  ... and {} more failed case(s)",
            failed.len() - LISTED_FAILURES
        );
    }
    out
}

/// The failed cases of a sweep CSV (e.g. a merged table), in row order. The factor columns
/// are those between `case` and the first response or flag column. A table without a
/// `status` column (written before failed cases were recorded) has none.
pub fn failed_rows(text: &str, origin: &str) -> StudyResult<Vec<FailedCase>> {
    let t = Table::parse(text, origin)?;
    let (Some(status), Some(error)) = (t.find("status"), t.find("error")) else {
        return Ok(Vec::new());
    };
    let end = t
        .columns
        .iter()
        .position(|c| Response::parse(c).is_some() || FLAG_COLUMNS.contains(&c.as_str()))
        .unwrap_or(t.columns.len());
    let mut out = Vec::new();
    for (r, (_, fields)) in t.rows.iter().enumerate() {
        match fields[status].as_str() {
            STATUS_OK => {}
            STATUS_FAILED => {
                let case = fields[0].parse().map_err(|_| {
                    t.cell_error(r, 0, format!("`{}` is not a case index", fields[0]))
                })?;
                let settings = (1..end.max(1))
                    .map(|c| {
                        let v = fields[c]
                            .parse()
                            .map_or_else(|_| fields[c].clone(), value_text);
                        format!("{} = {v}", t.columns[c])
                    })
                    .collect::<Vec<_>>()
                    .join(", ");
                out.push(FailedCase {
                    case,
                    settings,
                    reason: fields[error].clone(),
                });
            }
            other => {
                return Err(t.cell_error(
                    r,
                    status,
                    format!("`{other}` is not a case status: `{STATUS_OK}` or `{STATUS_FAILED}`"),
                ));
            }
        }
    }
    Ok(out)
}

/// Merges sweep CSV texts (`(origin, text)` pairs, e.g. the shards of one study) into one
/// CSV sorted by case index. All parts must have the same header; a case index may appear
/// only once.
pub fn merge_csv(parts: &[(String, String)]) -> StudyResult<String> {
    let Some((first_origin, _)) = parts.first() else {
        return Err(StudyError::Fit("nothing to merge".to_owned()));
    };
    let mut header: Option<Vec<String>> = None;
    let mut rows: Vec<(usize, String, String, usize)> = Vec::new();
    for (origin, text) in parts {
        let t = Table::parse(text, origin)?;
        match &header {
            None => {
                if t.columns.first().map(String::as_str) != Some("case") {
                    return Err(StudyError::Table {
                        origin: origin.clone(),
                        line: t.header_line,
                        column: Some("1".to_owned()),
                        message: "a sweep CSV starts with a `case` column".to_owned(),
                    });
                }
                header = Some(t.columns.clone());
            }
            Some(h) if *h != t.columns => {
                return Err(StudyError::Table {
                    origin: origin.clone(),
                    line: t.header_line,
                    column: None,
                    message: format!(
                        "the header differs from that of `{first_origin}`: shards of one study have the same columns"
                    ),
                });
            }
            Some(_) => {}
        }
        for (r, (line, fields)) in t.rows.iter().enumerate() {
            let case: usize = fields[0]
                .parse()
                .map_err(|_| t.cell_error(r, 0, format!("`{}` is not a case index", fields[0])))?;
            rows.push((case, fields.join(","), origin.clone(), *line));
        }
    }
    rows.sort_by_key(|r| r.0);
    for w in rows.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(StudyError::Table {
                origin: w[1].2.clone(),
                line: w[1].3,
                column: Some("`case` (1)".to_owned()),
                message: format!(
                    "case {} also appears in `{}`, line {}: the shards overlap",
                    w[1].0, w[0].2, w[0].3
                ),
            });
        }
    }
    let mut out = header.expect("at least one part").join(",");
    out.push('\n');
    for (_, row, _, _) in &rows {
        out.push_str(row);
        out.push('\n');
    }
    Ok(out)
}
