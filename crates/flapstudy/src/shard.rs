//! Shards of a sweep: the study content hash, the shard file's first line, atomic writes, and
//! which shards in a directory are complete, incomplete, missing or of another study.
//!
//! A shard file `<study>-shard-K-of-N.csv` is the sweep CSV of cases `A..B`
//! ([`super::spec::shard_range`]) preceded by one comment line,
//!
//! `# flapwing study <sha256 hex> shard K/N cases A..B from <study file>`,
//!
//! which the CSV reader skips like any comment and [`merge_dir`] strips, so the merge of all
//! shards equals the unsharded CSV byte for byte. A shard is **complete** when that line parses
//! and the rows are exactly cases `A..B` in order; a file cut short (a task killed while
//! writing) is incomplete, never complete. Shards are written with [`write_atomic`] (a
//! temporary file in the same directory, fsync, rename), so a killed task leaves at most a
//! `.<name>.tmp-<pid>` file, which no scan takes for a shard.
//!
//! The **study content hash** ([`study_hash`]) is the SHA-256 of everything that determines the
//! table: the study's name, design, responses, phase samples per wingbeat, every factor's path,
//! every case's factor values (bit for bit), and the base vehicle model with all defaults
//! explicit (whatever file or built-in it came from, so an edited model file changes the hash,
//! and moving the files does not). It does not cover flapwing's own version.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::spec::{Study, shard_range};
use super::sweep::merge_csv;
use super::table::Table;

/// What can go wrong with shard files and their directory.
#[derive(Debug, thiserror::Error)]
pub enum ShardError {
    /// A file or directory cannot be read or written.
    #[error("{what} `{path}`: {source}")]
    Io {
        /// What was being done, e.g. "cannot read shard".
        what: &'static str,
        /// The path.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A shard belongs to another study (or another version of the study file).
    #[error(
        "`{file}` is a shard of a different study: its study hash is {found}, expected {expected} ({why}); remove it, or rerun that shard with --force"
    )]
    ForeignShard {
        /// The shard file.
        file: String,
        /// The hash in the file (or what was found instead).
        found: String,
        /// The hash expected.
        expected: String,
        /// Where the expected hash came from.
        why: String,
    },
    /// Some shards of a study are missing or incomplete.
    #[error("{}", missing_text(.study, .n, .missing, .incomplete, .resubmit))]
    NotComplete {
        /// The study name.
        study: String,
        /// Number of shards.
        n: usize,
        /// 1-based indices of shards without a file.
        missing: Vec<usize>,
        /// 1-based indices of shards whose file is incomplete, with the reason.
        incomplete: Vec<(usize, String)>,
        /// The command that resubmits just those shards.
        resubmit: String,
    },
    /// The directory holds no shard files.
    #[error("no shard files (<study>-shard-K-of-N.csv) in `{0}`")]
    NoShards(String),
    /// The CSV rows of complete shards do not merge (should not happen for flapwing's shards).
    #[error(transparent)]
    Merge(#[from] super::error::StudyError),
}

fn missing_text(
    study: &str,
    n: &usize,
    missing: &[usize],
    incomplete: &[(usize, String)],
    resubmit: &str,
) -> String {
    let done = n - missing.len() - incomplete.len();
    let mut s = format!("study `{study}` has {done} of {n} shards complete");
    if !missing.is_empty() {
        let _ = write!(s, "; missing shard(s) {}", join_indices(missing));
    }
    if !incomplete.is_empty() {
        let list: Vec<String> = incomplete
            .iter()
            .map(|(k, why)| format!("{k} ({why})"))
            .collect();
        let _ = write!(s, "; incomplete shard(s) {}", list.join(", "));
    }
    let _ = write!(s, "\nresubmit just those with:\n  {resubmit}");
    s
}

/// `[3, 7]` -> `"3,7"`.
pub fn join_indices(indices: &[usize]) -> String {
    indices
        .iter()
        .map(|k| k.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

/// The study content hash (lowercase hex SHA-256; see the module docs for what it covers).
pub fn study_hash(study: &Study) -> String {
    let mut h = Sha256::new();
    let mut field = |tag: &str, value: &[u8]| {
        // Length-prefixed fields, so no two different studies feed the same bytes.
        h.update(tag.as_bytes());
        h.update((value.len() as u64).to_le_bytes());
        h.update(value);
    };
    field("flapwing-study-hash", b"1");
    field("name", study.name.as_bytes());
    field("design", study.design.name().as_bytes());
    field("header", study.csv_header().as_bytes());
    field(
        "steps_per_wingbeat",
        &(study.steps_per_wingbeat as u64).to_le_bytes(),
    );
    let base = toml::to_string(&study.base).unwrap_or_else(|e| format!("unserializable: {e}"));
    field("base", base.as_bytes());
    for f in &study.factors {
        field("factor", f.path.as_bytes());
    }
    let mut cases = Vec::with_capacity(study.cases.len() * study.factors.len() * 8);
    for c in &study.cases {
        for v in c {
            cases.extend_from_slice(&v.to_bits().to_le_bytes());
        }
    }
    field("cases", &cases);
    let digest = h.finalize();
    digest.iter().fold(String::with_capacity(64), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

/// The file name of shard `k` of `n` of a study.
pub fn shard_file_name(study: &str, k: usize, n: usize) -> String {
    format!("{study}-shard-{k}-of-{n}.csv")
}

/// `<study>-shard-K-of-N.csv` -> (study, K, N).
pub fn parse_shard_file_name(file: &str) -> Option<(String, usize, usize)> {
    let stem = file.strip_suffix(".csv")?;
    let (study, rest) = stem.rsplit_once("-shard-")?;
    let (k, n) = rest.split_once("-of-")?;
    let (k, n): (usize, usize) = (k.parse().ok()?, n.parse().ok()?);
    (!study.is_empty() && n >= 1 && (1..=n).contains(&k)).then(|| (study.to_owned(), k, n))
}

/// The first line of a shard file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShardHeader {
    /// The study content hash.
    pub hash: String,
    /// 1-based shard index.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
    /// The case indices the shard holds.
    pub cases: Range<usize>,
    /// The study file the shard was run from (as given, made absolute when possible).
    pub study_file: String,
}

const HEADER_PREFIX: &str = "# flapwing study ";

impl ShardHeader {
    /// The header of shard `k` of `n` of `study`, run from `study_file`.
    pub fn new(study: &Study, hash: &str, k: usize, n: usize, study_file: &str) -> Self {
        Self {
            hash: hash.to_owned(),
            k,
            n,
            cases: shard_range(study.case_count(), k, n),
            study_file: study_file.to_owned(),
        }
    }

    /// The comment line (without newline).
    pub fn line(&self) -> String {
        format!(
            "{HEADER_PREFIX}{} shard {}/{} cases {}..{} from {}",
            self.hash, self.k, self.n, self.cases.start, self.cases.end, self.study_file
        )
    }

    /// Parses the first line of a shard file; `None` when it is not a shard header.
    pub fn parse(line: &str) -> Option<Self> {
        let rest = line.strip_prefix(HEADER_PREFIX)?;
        let mut parts = rest.splitn(6, ' ');
        let hash = parts.next()?;
        if hash.len() != 64 || !hash.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        (parts.next()? == "shard").then_some(())?;
        let (k, n) = parts.next()?.split_once('/')?;
        (parts.next()? == "cases").then_some(())?;
        let (a, b) = parts.next()?.split_once("..")?;
        let study_file = parts.next()?.strip_prefix("from ")?;
        let (k, n, a, b): (usize, usize, usize, usize) = (
            k.parse().ok()?,
            n.parse().ok()?,
            a.parse().ok()?,
            b.parse().ok()?,
        );
        ((1..=n).contains(&k) && a <= b).then(|| Self {
            hash: hash.to_owned(),
            k,
            n,
            cases: a..b,
            study_file: study_file.to_owned(),
        })
    }
}

/// What a shard file holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ShardState {
    /// Every case of the shard, in order.
    Complete(ShardHeader),
    /// A shard header, but not all of its cases (cut short or interrupted): why.
    Incomplete(ShardHeader, String),
    /// Not a flapwing shard file (no shard header on the first line): why.
    Foreign(String),
}

impl ShardState {
    /// The header, when the file has one.
    pub fn header(&self) -> Option<&ShardHeader> {
        match self {
            Self::Complete(h) | Self::Incomplete(h, _) => Some(h),
            Self::Foreign(_) => None,
        }
    }
}

/// Classifies the text of a shard file (`origin` names it in the reasons).
pub fn shard_state(text: &str, origin: &str) -> ShardState {
    let Some(header) = text.lines().next().and_then(ShardHeader::parse) else {
        return ShardState::Foreign(format!(
            "`{origin}` does not start with a `{HEADER_PREFIX}<hash> shard K/N ...` line"
        ));
    };
    if !text.ends_with('\n') {
        return ShardState::Incomplete(header, "its last line is cut short".to_owned());
    }
    let table = match Table::parse(text, origin) {
        Ok(t) => t,
        Err(e) => return ShardState::Incomplete(header, e.to_string()),
    };
    let expected = header.cases.len();
    let in_order = table
        .rows
        .iter()
        .zip(header.cases.clone())
        .all(|((_, fields), case)| fields.first().map(String::as_str) == Some(&case.to_string()));
    if table.rows.len() != expected || !in_order {
        let why = format!(
            "{} of {expected} case rows{}",
            table.rows.len(),
            if in_order { "" } else { ", out of order" }
        );
        return ShardState::Incomplete(header, why);
    }
    ShardState::Complete(header)
}

/// Writes `bytes` to `path` atomically: a temporary file `.<name>.tmp-<pid>` in the same
/// directory, written, flushed to disk (fsync), then renamed over `path`. A reader sees the
/// old file or the whole new one, never a part.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ShardError> {
    let io = |what, p: &Path| {
        let path = p.display().to_string();
        move |source| ShardError::Io { what, path, source }
    };
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir
        .unwrap_or(Path::new("."))
        .join(format!(".{name}.tmp-{}", std::process::id()));
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()
    };
    if let Err(e) = write() {
        let _ = std::fs::remove_file(&tmp);
        return Err(io("cannot write the temporary file", &tmp)(e));
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io("cannot rename the temporary file into", path)(e)
    })?;
    // Make the rename itself durable; not every file system lets a directory be synced.
    if let Ok(d) = std::fs::File::open(dir.unwrap_or(Path::new("."))) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// One shard file found in a directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShardFile {
    /// Its path.
    pub path: PathBuf,
    /// What it holds.
    pub state: ShardState,
}

/// The shard files of one study and shard count in a directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShardGroup {
    /// The study name (from the file names).
    pub study: String,
    /// Number of shards.
    pub n: usize,
    /// The files found, by 1-based shard index.
    pub files: BTreeMap<usize, ShardFile>,
}

impl ShardGroup {
    /// The hash of the lowest-index shard with a header, if any.
    pub fn first_hash(&self) -> Option<&str> {
        self.files
            .values()
            .find_map(|f| f.state.header())
            .map(|h| h.hash.as_str())
    }

    /// The study file recorded in the lowest-index shard with a header, if any.
    pub fn first_study_file(&self) -> Option<&str> {
        self.files
            .values()
            .find_map(|f| f.state.header())
            .map(|h| h.study_file.as_str())
    }
}

/// Reads every `<study>-shard-K-of-N.csv` in `dir` (temporary files and everything else are
/// ignored), grouped by study and shard count.
pub fn scan_dir(dir: &Path) -> Result<Vec<ShardGroup>, ShardError> {
    let shown = dir.display().to_string();
    let io = |source| ShardError::Io {
        what: "cannot read the directory",
        path: shown.clone(),
        source,
    };
    let mut groups: BTreeMap<(String, usize), ShardGroup> = BTreeMap::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let entry = entry.map_err(io)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some((study, k, n)) = parse_shard_file_name(&name) else {
            continue;
        };
        let path = entry.path();
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(&path).map_err(|source| ShardError::Io {
            what: "cannot read shard",
            path: origin.clone(),
            source,
        })?;
        let state = shard_state(&text, &origin);
        groups
            .entry((study.clone(), n))
            .or_insert_with(|| ShardGroup {
                study,
                n,
                files: BTreeMap::new(),
            })
            .files
            .insert(k, ShardFile { path, state });
    }
    Ok(groups.into_values().collect())
}

/// `flapwing submit STUDY --out DIR --shards N --only 3,7`, with the paths quoted for a POSIX
/// shell when they need it.
pub fn resubmit_command(study_file: &str, dir: &str, n: usize, only: &[usize]) -> String {
    format!(
        "flapwing submit {} --out {} --shards {n} --only {}",
        shell_quote(study_file),
        shell_quote(dir),
        join_indices(only)
    )
}

/// `s` as one POSIX shell word: as is when it is plain, else in single quotes.
pub fn shell_quote(s: &str) -> String {
    let plain = !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"/._-+=:,@%".contains(&b));
    if plain {
        s.to_owned()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

/// What to merge a group against.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Expected {
    /// The study content hash every shard must carry.
    pub hash: String,
    /// Where that hash came from (for messages), e.g. "the manifest `DIR/x.slurm.json`".
    pub why: String,
    /// The study file, for the resubmit command.
    pub study_file: String,
}

/// Checks that every shard of `group` is present, complete and of the expected study
/// (`expected`, or else the hash of the group's lowest-index shard), and returns the merged
/// CSV: the unsharded table, byte for byte. `dir` is shown in the resubmit command.
pub fn merge_group(
    group: &ShardGroup,
    expected: Option<&Expected>,
    dir: &str,
) -> Result<String, ShardError> {
    let (hash, why, study_file) = match expected {
        Some(e) => (e.hash.clone(), e.why.clone(), e.study_file.clone()),
        None => {
            let first = group
                .files
                .iter()
                .find_map(|(k, f)| f.state.header().map(|h| (k, h)));
            match first {
                Some((k, h)) => (
                    h.hash.clone(),
                    format!("that of shard {k}"),
                    h.study_file.clone(),
                ),
                None => {
                    // No file has a header: report the first one as foreign.
                    let (_, f) = group
                        .files
                        .iter()
                        .next()
                        .ok_or_else(|| ShardError::NoShards(dir.to_owned()))?;
                    return Err(ShardError::ForeignShard {
                        file: f.path.display().to_string(),
                        found: "no study hash".to_owned(),
                        expected: "a flapwing shard header".to_owned(),
                        why: match &f.state {
                            ShardState::Foreign(w) => w.clone(),
                            _ => String::new(),
                        },
                    });
                }
            }
        }
    };
    let mut missing = Vec::new();
    let mut incomplete = Vec::new();
    let mut parts = Vec::with_capacity(group.n);
    for k in 1..=group.n {
        let Some(f) = group.files.get(&k) else {
            missing.push(k);
            continue;
        };
        let file = f.path.display().to_string();
        let foreign = |found: String| ShardError::ForeignShard {
            file: file.clone(),
            found,
            expected: hash.clone(),
            why: why.clone(),
        };
        match &f.state {
            ShardState::Foreign(w) => return Err(foreign(format!("none ({w})"))),
            ShardState::Complete(h) | ShardState::Incomplete(h, _) if h.hash != hash => {
                return Err(foreign(h.hash.clone()));
            }
            ShardState::Incomplete(_, w) => incomplete.push((k, w.clone())),
            ShardState::Complete(_) => {
                let text = std::fs::read_to_string(&f.path).map_err(|source| ShardError::Io {
                    what: "cannot read shard",
                    path: file.clone(),
                    source,
                })?;
                parts.push((file, text));
            }
        }
    }
    if !missing.is_empty() || !incomplete.is_empty() {
        let mut redo: Vec<usize> = missing
            .iter()
            .copied()
            .chain(incomplete.iter().map(|(k, _)| *k))
            .collect();
        redo.sort_unstable();
        return Err(ShardError::NotComplete {
            study: group.study.clone(),
            n: group.n,
            missing,
            incomplete,
            resubmit: resubmit_command(&study_file, dir, group.n, &redo),
        });
    }
    Ok(merge_csv(&parts)?)
}
