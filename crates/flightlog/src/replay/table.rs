//! A channel's messages as a table: read into memory ([`read_table`]) or written to a CSV
//! file ([`export_csv`]), one row per message and one column per JSON field.

use std::path::Path;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::read::read_log;
use crate::tabulate::{TableBuilder, write_csv};

/// What [`export_csv`] wrote.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct CsvStats {
    /// Data rows (one per message).
    pub rows: u64,
    /// Columns, the first being `log_time_ns`.
    pub columns: u64,
    /// Messages that were not valid JSON and were left out.
    pub skipped: u64,
}

/// The messages of one topic as a table (what [`export_csv`] writes and the Python
/// bindings turn into arrays): one row per message, the first column `log_time_ns`, then
/// one column per leaf of the decoded message named by its dotted path
/// (`pose.position.x`) in first-seen order; each cell the value's text exactly as logged
/// (numbers, true/false, strings), `None` where a message lacks the field.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct Table {
    /// Column names.
    pub columns: Vec<String>,
    /// Rows, each with one cell per column.
    pub rows: Vec<Vec<Option<String>>>,
    /// Messages that could not be decoded and were left out.
    pub skipped: u64,
}

/// Reads the messages of `topic` of the log at `path` into a [`Table`].
pub fn read_table(path: impl AsRef<Path>, topic: &str) -> Result<Table> {
    let path = path.as_ref();
    let log = read_log(path)?;
    let Some(id) = log.channel_id(topic) else {
        return Err(Error::UnknownTopic {
            path: path.to_owned(),
            topic: topic.to_owned(),
            available: log.topics(),
        });
    };
    if let Some(why) = log.undecodable(id) {
        return Err(Error::Embedded(format!(
            "`{}`: the messages of `{topic}` cannot be decoded: {why}",
            path.display()
        )));
    }
    let mut table = TableBuilder::new();
    let mut skipped = 0u64;
    for m in log.on(topic) {
        let Some(v) = log.parse(m) else {
            skipped += 1;
            continue;
        };
        let mut flat = Vec::new();
        v.flatten("", &mut flat);
        let fields = flat.into_iter().map(|(k, val)| {
            let k = if k.is_empty() { "value".to_owned() } else { k };
            (k, val)
        });
        table.push_row(m.log_time, fields);
    }
    let (columns, rows) = table.finish();
    Ok(Table {
        columns,
        rows,
        skipped,
    })
}

/// Writes the messages of `topic` to a CSV file at `out` (replaced if it exists): the
/// [`Table`] of [`read_table`], a field missing from a message left empty, numbers exactly
/// as logged, booleans as true/false.
pub fn export_csv(path: impl AsRef<Path>, topic: &str, out: impl AsRef<Path>) -> Result<CsvStats> {
    let out = out.as_ref();
    let table = read_table(path, topic)?;
    write_csv(&table.columns, &table.rows, out)?;
    Ok(CsvStats {
        rows: table.rows.len() as u64,
        columns: table.columns.len() as u64,
        skipped: table.skipped,
    })
}
