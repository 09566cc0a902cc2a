//! `DIR/results.jsonl`: one record per finished variant, appended as each finishes.
//!
//! Each record is one JSON line written by a single `write` to a file opened for
//! appending, under an exclusive `flock` of the file, then synced: several processes (the
//! tasks of a HyperQueue job, the shards of a Slurm array) append to one file without
//! mixing their lines. A record that could not be written whole (a full disk) is cut off
//! again; an append to a file that does not end with a newline (a run killed mid-write,
//! another program's bytes) starts with one, so that a torn line never swallows the next
//! record: a reader loses only the torn bytes, and skips, with a warning, every line that
//! is not a record (bad JSON, bytes that are not UTF-8). The file is never rewritten: a
//! variant run again gets a new record, and the last record of a name is its result
//! ([`latest`]).

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

/// The file name of the results in the output directory.
pub const RESULTS: &str = "results.jsonl";

/// How a variant ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// `adapt` succeeded (converged or stopped at its iteration limit: see `converged`).
    Ok,
    /// `adapt` failed: `error` says why; the output holds the best mesh it reached, if any.
    Failed,
    /// Stopped by Ctrl-C or a termination signal before it finished.
    Interrupted,
}

/// The result of one variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultRecord {
    /// The variant's name.
    pub name: String,
    /// Its line in the manifest (0 when unknown).
    pub line: usize,
    /// How it ended.
    pub status: Status,
    /// Whether the loop converged.
    pub converged: bool,
    /// Remeshing iterations done.
    pub iterations: usize,
    /// The best mesh: vertices, triangles, share of edges of metric length in
    /// [1/√2, √2], mean and smallest metric quality (absent when no mesh was made).
    pub vertices: Option<usize>,
    /// Triangles of the best mesh.
    pub triangles: Option<usize>,
    /// Conforming share of the best mesh.
    pub conformity: Option<f64>,
    /// Mean metric quality of the best mesh.
    pub mean_quality: Option<f64>,
    /// Smallest metric quality of the best mesh.
    pub min_quality: Option<f64>,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
    /// The output mesh, history and log, relative to the output directory.
    pub output: String,
    /// The history.
    pub history: String,
    /// The run's messages (stderr).
    pub log: String,
    /// Why it failed.
    pub error: Option<String>,
    /// Content hash of the input, the recipe and the options ([`super::content_hash`]).
    pub hash: String,
}

/// Opens `path` for appending (creating it), as [`append`] does: to check, before any
/// run, that the results can be written.
pub fn open(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new().create(true).read(true).append(true).open(path)
}

/// Appends `record` to `path` as one line, in one write, and syncs it (see the module
/// documentation): under an exclusive lock of the file, after a newline when the file
/// does not end with one; a short or failed write is cut off again.
pub fn append(path: &Path, record: &ResultRecord) -> std::io::Result<()> {
    let mut line = serde_json::to_string(record).map_err(std::io::Error::other)?;
    line.push('\n');
    let mut file = open(path)?;
    // Appenders of this file (on any host whose file system has locks) take turns, so
    // that the length read below is where this record starts. Without locks (ENOLCK,
    // EOPNOTSUPP) the single `write` still keeps lines apart.
    #[cfg(unix)]
    let _ = rustix::fs::flock(&file, rustix::fs::FlockOperation::LockExclusive);
    let start = file.metadata()?.len();
    if start > 0 && !ends_with_newline(&file, start)? {
        line.insert(0, '\n');
    }
    let outcome = match file.write(line.as_bytes()) {
        Ok(n) if n == line.len() => file.sync_data(),
        Ok(n) => Err(std::io::Error::new(
            std::io::ErrorKind::WriteZero,
            format!("wrote {n} of the record's {} bytes (is the disk full?)", line.len()),
        )),
        Err(e) => Err(e),
    };
    if outcome.is_err() {
        // The torn bytes go; a reader sees the file as it was.
        let _ = file.set_len(start);
    }
    outcome
}

/// Whether the `len` bytes of `file` end with `\n`.
fn ends_with_newline(file: &std::fs::File, len: u64) -> std::io::Result<bool> {
    let mut last = [0u8];
    #[cfg(unix)]
    std::os::unix::fs::FileExt::read_exact_at(file, &mut last, len - 1)?;
    #[cfg(not(unix))]
    {
        use std::io::{Read, Seek, SeekFrom};
        let mut f = file;
        f.seek(SeekFrom::Start(len - 1))?;
        f.read_exact(&mut last)?;
    }
    Ok(last[0] == b'\n')
}

/// The records of a results file, the last of each name.
pub type Latest = HashMap<String, ResultRecord>;

/// The last record of each name in `path` (none when the file does not exist), and the
/// lines that are not records (line number and why), which the caller reports.
pub fn latest(path: &Path) -> std::io::Result<(Latest, Vec<(usize, String)>)> {
    let bytes = match std::fs::read(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Vec::new(),
        Err(e) => return Err(e),
    };
    let mut records = HashMap::new();
    let bad = read_records(&bytes, 1, |r| {
        records.insert(r.name.clone(), r);
    });
    Ok((records, bad))
}

/// Reads the whole lines of `bytes` (the first numbered `first_line`), giving each record
/// to `found`; returns the lines that are not records (number and why), a last line
/// without its newline among them.
pub fn read_records(
    bytes: &[u8],
    first_line: usize,
    mut found: impl FnMut(ResultRecord),
) -> Vec<(usize, String)> {
    let mut bad = Vec::new();
    let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let mut number = first_line;
    for line in bytes[..complete].split(|&b| b == b'\n') {
        let here = number;
        number += 1;
        if line.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        let Ok(text) = std::str::from_utf8(line) else {
            bad.push((here, "not UTF-8 text".into()));
            continue;
        };
        match serde_json::from_str::<ResultRecord>(text) {
            Ok(r) => found(r),
            Err(e) => bad.push((here, e.to_string())),
        }
    }
    // `split` gives one empty piece after the last newline.
    let last = number - 1;
    if complete < bytes.len() {
        bad.push((last, "a partial line (no newline): ignored".into()));
    }
    bad
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(name: &str, status: Status) -> ResultRecord {
        ResultRecord {
            name: name.into(),
            line: 1,
            status,
            converged: true,
            iterations: 3,
            vertices: Some(10),
            triangles: Some(12),
            conformity: Some(0.95),
            mean_quality: Some(0.9),
            min_quality: Some(0.5),
            seconds: 0.25,
            output: format!("{name}.msh"),
            history: format!("{name}.history.json"),
            log: format!("{name}.log"),
            error: None,
            hash: "abc".into(),
        }
    }

    #[test]
    fn the_last_record_of_a_name_wins_and_a_torn_line_is_skipped() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join(RESULTS);
        assert!(latest(&p).unwrap().0.is_empty());
        append(&p, &record("a", Status::Failed)).unwrap();
        append(&p, &record("b", Status::Ok)).unwrap();
        append(&p, &record("a", Status::Ok)).unwrap();
        let mut text = std::fs::read_to_string(&p).unwrap();
        text.push_str("{\"name\":\"c\",\"sta");
        std::fs::write(&p, text).unwrap();
        let (r, bad) = latest(&p).unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(r["a"], record("a", Status::Ok));
        assert_eq!(r["b"].status, Status::Ok);
        assert_eq!(bad.len(), 1);
        assert_eq!(bad[0].0, 4);
    }

    #[test]
    fn an_append_after_a_torn_line_starts_a_line_of_its_own() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join(RESULTS);
        append(&p, &record("a", Status::Ok)).unwrap();
        // A run killed mid-write (or a full disk) left half a record.
        let mut f = std::fs::OpenOptions::new().append(true).open(&p).unwrap();
        f.write_all(b"{\"name\":\"b\",\"sta").unwrap();
        drop(f);
        append(&p, &record("c", Status::Ok)).unwrap();
        let (r, bad) = latest(&p).unwrap();
        assert_eq!(r.len(), 2, "{bad:?}");
        assert_eq!(r["c"], record("c", Status::Ok));
        assert_eq!(bad.len(), 1, "only the torn bytes are lost: {bad:?}");
        assert_eq!(bad[0].0, 2);
        // A file that ends whole gets no blank line.
        let before = std::fs::read(&p).unwrap();
        append(&p, &record("d", Status::Ok)).unwrap();
        let after = std::fs::read(&p).unwrap();
        assert_eq!(after[before.len()], b'{');
    }

    #[test]
    fn a_line_that_is_not_utf8_is_skipped_not_fatal() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join(RESULTS);
        append(&p, &record("a", Status::Ok)).unwrap();
        let mut f = std::fs::OpenOptions::new().append(true).open(&p).unwrap();
        f.write_all(b"\xff\xfe garbage\n").unwrap();
        drop(f);
        append(&p, &record("b", Status::Ok)).unwrap();
        let (r, bad) = latest(&p).unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(bad, vec![(2, "not UTF-8 text".to_string())]);
    }
}
