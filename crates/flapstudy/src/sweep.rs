//! Running a study's cases in parallel and writing them as CSV; merging shards.
//!
//! CSV layout: `case` (0-based case index), one column per factor (headed by its path), one
//! column per response (in the study's order), then `reynolds` and `wake_capture_clamped`
//! (0 or 1). Numbers use Rust's shortest round-trip formatting (`{:?}`), so a value read
//! back is the value computed, bit for bit, and the same case always prints the same row:
//! the row order and content do not depend on the number of threads or the sharding.

use std::ops::Range;

use rayon::prelude::*;

use super::error::{StudyError, StudyResult};
use super::responses::{HoverResponses, Response, hover_responses};
use super::spec::Study;
use super::table::Table;

/// Columns every sweep CSV ends with.
pub const FLAG_COLUMNS: [&str; 2] = ["reynolds", "wake_capture_clamped"];

/// One evaluated case.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseResult {
    /// Case index.
    pub case: usize,
    /// Factor values.
    pub inputs: Vec<f64>,
    /// Everything the evaluation produced.
    pub all: HoverResponses,
    /// The study's responses, in order.
    pub responses: Vec<f64>,
}

impl Study {
    /// Evaluates one case.
    pub fn evaluate(&self, case: usize) -> StudyResult<CaseResult> {
        let vehicle = self.vehicle(case)?;
        let mut all = hover_responses(&vehicle, self.steps_per_wingbeat).map_err(|source| {
            StudyError::Case {
                case,
                settings: self.settings_text(case),
                source,
            }
        })?;
        if self.responses.contains(&Response::TrimFeasible) {
            all.trim_feasible = Some(flapsim::trim::trim(&vehicle).is_ok());
        }
        Ok(CaseResult {
            case,
            inputs: self.cases[case].clone(),
            responses: self.responses.iter().map(|r| all.get(r)).collect(),
            all,
        })
    }

    /// Evaluates the cases `range` on the current rayon pool, calling `progress` after each
    /// case. Results are in case order; the first failing case (lowest index) is the error.
    pub fn run(
        &self,
        range: Range<usize>,
        progress: &(dyn Fn() + Sync),
    ) -> StudyResult<Vec<CaseResult>> {
        self.run_until(range, progress, &|| false)
    }

    /// Like [`Study::run`], but cases not yet started when `stop` returns true are skipped
    /// (e.g. on Ctrl-C): the result holds the completed cases, in case order.
    pub fn run_until(
        &self,
        range: Range<usize>,
        progress: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> StudyResult<Vec<CaseResult>> {
        let results: Vec<Option<StudyResult<CaseResult>>> = range
            .into_par_iter()
            .map(|i| {
                if stop() {
                    return None;
                }
                let r = self.evaluate(i);
                progress();
                Some(r)
            })
            .collect();
        results.into_iter().flatten().collect()
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
        cols.extend(r.responses.iter().map(|v| format!("{v:?}")));
        cols.push(format!("{:?}", r.all.reynolds));
        cols.push(if r.all.wake_capture_clamped { "1" } else { "0" }.to_owned());
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
