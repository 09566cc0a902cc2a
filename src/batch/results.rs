//! `DIR/results.jsonl`: one record per finished variant, appended as each finishes.
//!
//! Each record is one JSON line written by a single `write` to a file opened for
//! appending, then synced: several processes (the tasks of a HyperQueue job, the shards
//! of a Slurm array) append to one file without mixing their lines, and a run killed at
//! any moment leaves whole lines (a reader skips a last line without its newline). The
//! file is never rewritten: a variant run again gets a new record, and the last record of
//! a name is its result ([`latest`]).

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

/// Appends `record` to `path` as one line, in one write, and syncs it.
pub fn append(path: &Path, record: &ResultRecord) -> std::io::Result<()> {
    let mut line = serde_json::to_string(record).map_err(std::io::Error::other)?;
    line.push('\n');
    let mut file = std::fs::OpenOptions::new().create(true).append(true).open(path)?;
    let written = file.write(line.as_bytes())?;
    if written != line.len() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::WriteZero,
            format!("wrote {written} of the record's {} bytes", line.len()),
        ));
    }
    file.sync_data()
}

/// The records of a results file, the last of each name.
pub type Latest = HashMap<String, ResultRecord>;

/// The last record of each name in `path` (none when the file does not exist), and the
/// lines that are not records (line number and why), which the caller reports.
pub fn latest(path: &Path) -> std::io::Result<(Latest, Vec<(usize, String)>)> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        Err(e) => return Err(e),
    };
    let mut records = HashMap::new();
    let mut bad = Vec::new();
    let complete = text.rfind('\n').map_or("", |i| &text[..=i]);
    for (i, line) in complete.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        match serde_json::from_str::<ResultRecord>(line) {
            Ok(r) => {
                records.insert(r.name.clone(), r);
            }
            Err(e) => bad.push((i + 1, e.to_string())),
        }
    }
    if complete.len() < text.len() {
        bad.push((complete.lines().count() + 1, "a partial line (no newline): ignored".into()));
    }
    Ok((records, bad))
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
}
