//! A small numeric CSV reader for data tables (fit inputs, sweep outputs).
//!
//! Format: comma-separated, the first non-comment line is the header, every other
//! non-empty line is a row with as many fields as the header. Lines whose first non-blank
//! character is `#` are comments and may appear anywhere (before the header, between rows,
//! at the end). Fields are trimmed. No quoting: the tables flapwing reads and writes hold
//! numbers and plain identifiers only.

use super::error::{StudyError, StudyResult};

/// A parsed CSV table, every cell kept as text with its line number.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Where the table came from (file path), for messages.
    pub origin: String,
    /// Column names from the header.
    pub columns: Vec<String>,
    /// Line number of the header (1-based).
    pub header_line: usize,
    /// Rows: (1-based line number, fields).
    pub rows: Vec<(usize, Vec<String>)>,
}

impl Table {
    /// Parses `text`; `origin` names the file in errors.
    pub fn parse(text: &str, origin: &str) -> StudyResult<Self> {
        let mut header: Option<(usize, Vec<String>)> = None;
        let mut rows = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line_no = i + 1;
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<String> = line.split(',').map(|f| f.trim().to_owned()).collect();
            match &header {
                None => {
                    for (k, name) in fields.iter().enumerate() {
                        if name.is_empty() {
                            return Err(StudyError::Table {
                                origin: origin.to_owned(),
                                line: line_no,
                                column: Some(format!("{}", k + 1)),
                                message: "empty column name in the header".to_owned(),
                            });
                        }
                        if fields[..k].contains(name) {
                            return Err(StudyError::Table {
                                origin: origin.to_owned(),
                                line: line_no,
                                column: Some(format!("`{name}` ({})", k + 1)),
                                message: "column name appears twice in the header".to_owned(),
                            });
                        }
                    }
                    header = Some((line_no, fields));
                }
                Some((_, names)) => {
                    if fields.len() != names.len() {
                        return Err(StudyError::Table {
                            origin: origin.to_owned(),
                            line: line_no,
                            column: None,
                            message: format!(
                                "{} fields, but the header has {} columns",
                                fields.len(),
                                names.len()
                            ),
                        });
                    }
                    rows.push((line_no, fields));
                }
            }
        }
        let Some((header_line, columns)) = header else {
            return Err(StudyError::Table {
                origin: origin.to_owned(),
                line: text.lines().count().max(1),
                column: None,
                message: "no header line: the file is empty or holds only comments".to_owned(),
            });
        };
        Ok(Self {
            origin: origin.to_owned(),
            columns,
            header_line,
            rows,
        })
    }

    /// Index of column `name`, or an error naming the file, the header line and the column.
    pub fn require(&self, name: &str) -> StudyResult<usize> {
        self.columns
            .iter()
            .position(|c| c == name)
            .ok_or_else(|| StudyError::Table {
                origin: self.origin.clone(),
                line: self.header_line,
                column: Some(format!("`{name}`")),
                message: format!(
                    "required column is missing (the header has: {})",
                    self.columns.join(", ")
                ),
            })
    }

    /// Index of column `name` if present.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }

    /// The numbers of column `col` (an index from [`Table::require`]); a cell that is not a
    /// finite number is an error naming the file, the line and the column.
    pub fn numbers(&self, col: usize) -> StudyResult<Vec<f64>> {
        self.rows
            .iter()
            .map(|(line, fields)| self.number_at(*line, fields, col))
            .collect()
    }

    fn number_at(&self, line: usize, fields: &[String], col: usize) -> StudyResult<f64> {
        let text = &fields[col];
        // A failed case of a sweep (its `status` is `failed`) has no responses.
        let failed_case = self
            .find("status")
            .filter(|&s| fields[s] == "failed")
            .map(|_| self.find("error").map_or("", |e| fields[e].as_str()));
        match (text.parse::<f64>(), failed_case) {
            (Ok(x), _) if x.is_finite() => Ok(x),
            (_, Some(why)) => Err(StudyError::Table {
                origin: self.origin.clone(),
                line,
                column: Some(format!("`{}` ({})", self.columns[col], col + 1)),
                message: format!(
                    "no value: this case failed in the sweep (status `failed`, error: {why}); leave its row out to use the others"
                ),
            }),
            _ => Err(StudyError::Table {
                origin: self.origin.clone(),
                line,
                column: Some(format!("`{}` ({})", self.columns[col], col + 1)),
                message: format!("`{text}` is not a finite number"),
            }),
        }
    }

    /// An error about the cell of row `row` (index into [`Table::rows`]) in column `col`.
    pub fn cell_error(&self, row: usize, col: usize, message: impl Into<String>) -> StudyError {
        StudyError::Table {
            origin: self.origin.clone(),
            line: self.rows[row].0,
            column: Some(format!("`{}` ({})", self.columns[col], col + 1)),
            message: message.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_anywhere_and_errors_name_line_and_column() {
        let t = Table::parse("# a comment\nx, y\n1, 2\n\n# mid\n3,4\n# end\n", "t.csv").unwrap();
        assert_eq!(t.columns, ["x", "y"]);
        assert_eq!(t.header_line, 2);
        assert_eq!(t.numbers(1).unwrap(), [2.0, 4.0]);
        assert_eq!(t.rows[1].0, 6);

        let bad = Table::parse("x,y\n1,abc\n", "t.csv").unwrap();
        let e = bad.numbers(1).unwrap_err().to_string();
        assert_eq!(
            e,
            "t.csv, line 2, column `y` (2): `abc` is not a finite number"
        );
        let e = Table::parse("x,y\n1\n", "t.csv").unwrap_err().to_string();
        assert_eq!(e, "t.csv, line 2: 1 fields, but the header has 2 columns");
        let e = bad.require("z").unwrap_err().to_string();
        assert!(e.starts_with("t.csv, line 1, column `z`: required column is missing"));
        assert!(Table::parse("# only\n", "t.csv").is_err());
        assert!(Table::parse("x,x\n", "t.csv").is_err());
        let failed = Table::parse(
            "case,x,y,status,error\n0,1,2,ok,\n1,3,,failed,no periodic motion\n",
            "s.csv",
        )
        .unwrap();
        assert_eq!(failed.numbers(1).unwrap(), [1.0, 3.0]);
        let e = failed.numbers(2).unwrap_err().to_string();
        assert!(
            e.starts_with("s.csv, line 3, column `y` (3): no value: this case failed")
                && e.contains("error: no periodic motion"),
            "{e}"
        );
        assert!(
            Table::parse("x,y\nnan,1\n", "t.csv")
                .unwrap()
                .numbers(0)
                .is_err()
        );
    }
}
