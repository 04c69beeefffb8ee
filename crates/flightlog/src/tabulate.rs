//! Messages as a table of text cells, and that table as CSV: shared by a flapwing log's
//! channel ([`crate::replay::read_table`]) and a ROS 2 bag's topic
//! ([`crate::ros2::summary::read_topic_table`]).

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};

/// Builds a table row by row: the first column `log_time_ns`, then one column per field
/// name in first-seen order.
pub(crate) struct TableBuilder {
    columns: Vec<String>,
    index: HashMap<String, usize>,
    sparse: Vec<Vec<(usize, String)>>,
}

impl TableBuilder {
    pub(crate) fn new() -> Self {
        TableBuilder {
            columns: vec!["log_time_ns".into()],
            index: HashMap::new(),
            sparse: Vec::new(),
        }
    }

    /// Adds a row: the log time and the (field name, value text) pairs of one message.
    pub(crate) fn push_row(
        &mut self,
        log_time_ns: u64,
        fields: impl IntoIterator<Item = (String, String)>,
    ) {
        let mut row = vec![(0, log_time_ns.to_string())];
        for (k, v) in fields {
            let columns = &mut self.columns;
            let c = *self.index.entry(k.clone()).or_insert_with(|| {
                columns.push(k);
                columns.len() - 1
            });
            row.push((c, v));
        }
        self.sparse.push(row);
    }

    /// The column names and the rows, each with one cell per column (`None` where its
    /// message lacked the field).
    pub(crate) fn finish(self) -> (Vec<String>, Vec<Vec<Option<String>>>) {
        let n = self.columns.len();
        let rows = self
            .sparse
            .into_iter()
            .map(|r| {
                let mut cells = vec![None; n];
                for (c, v) in r {
                    cells[c] = Some(v);
                }
                cells
            })
            .collect();
        (self.columns, rows)
    }
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// Writes `columns` and `rows` to the CSV file `out` (replaced if it exists), a `None` cell
/// left empty.
pub(crate) fn write_csv(
    columns: &[String],
    rows: &[Vec<Option<String>>],
    out: &Path,
) -> Result<()> {
    let file = std::fs::File::create(out).map_err(|e| Error::io("cannot create", out, e))?;
    let mut w = std::io::BufWriter::new(file);
    let werr = |e| Error::io("cannot write", out, e);
    let header: Vec<String> = columns.iter().map(|c| csv_field(c)).collect();
    writeln!(w, "{}", header.join(",")).map_err(werr)?;
    for row in rows {
        let cells: Vec<String> = row
            .iter()
            .map(|c| c.as_deref().map(csv_field).unwrap_or_default())
            .collect();
        writeln!(w, "{}", cells.join(",")).map_err(werr)?;
    }
    w.flush().map_err(werr)?;
    Ok(())
}
