//! The memory a run may use, when a limit is set, against what a remeshing will need:
//! an allocation failure aborts the process (Rust's global allocator does not return an
//! error), so a run under `ulimit -v`, `ulimit -d` or a cgroup's `memory.max` (Slurm's
//! `--mem`, a container's limit) whose estimate is above the limit is refused before any
//! work, naming both, as [`super::RemeshError::TooManyVertices`] is.
//!
//! The estimate is the one behind `--max-vertices`: about [`BYTES_PER_VERTEX`] per
//! output vertex (the remesher's measured growth).

use std::path::Path;

/// Bytes the remesher holds per output vertex (measured: about 0.55 KB).
pub const BYTES_PER_VERTEX: f64 = 560.0;

/// The tightest memory limit of this process, in bytes, and where it comes from; `None`
/// when none is set.
pub fn limit() -> Option<(u64, &'static str)> {
    use rustix::process::{getrlimit, Resource};
    let mut best: Option<(u64, &'static str)> = None;
    let mut take = |v: Option<u64>, from: &'static str| {
        if let Some(v) = v {
            if best.map_or(true, |(b, _)| v < b) {
                best = Some((v, from));
            }
        }
    };
    take(getrlimit(Resource::As).current, "the address-space limit (ulimit -v)");
    take(getrlimit(Resource::Data).current, "the data-segment limit (ulimit -d)");
    let cgroup = cgroup_limit(Path::new("/proc/self/cgroup"), Path::new("/sys/fs/cgroup"));
    take(cgroup, "the cgroup's memory limit");
    best
}

/// The memory limit of this process's cgroup, read under `root` at the path
/// `/proc/self/cgroup` names: v2 (`0::PATH`, `memory.max`) or v1 (`N:memory:PATH`,
/// `memory/…/memory.limit_in_bytes`); a cgroup without a limit of its own takes its
/// parent's (inside a container the path may not exist: its parents up to the root are
/// tried). `None` when no limit is set (`max`, or v1's near-2⁶³ "unlimited").
fn cgroup_limit(proc_cgroup: &Path, root: &Path) -> Option<u64> {
    let text = read_small(proc_cgroup)?;
    let mut best: Option<u64> = None;
    for line in text.lines() {
        let mut f = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(rel)) = (f.next(), f.next(), f.next()) else {
            continue;
        };
        let (base, file) = if controllers.is_empty() {
            (root.to_path_buf(), "memory.max")
        } else if controllers.split(',').any(|c| c == "memory") {
            (root.join("memory"), "memory.limit_in_bytes")
        } else {
            continue;
        };
        let mut dir = base.join(rel.trim().trim_start_matches('/'));
        loop {
            let v = read_small(&dir.join(file)).and_then(|t| t.trim().parse::<u64>().ok());
            if let Some(v) = v.filter(|&v| v < 1 << 62) {
                best = Some(best.map_or(v, |b| b.min(v)));
                break;
            }
            if dir == base || !dir.pop() || !dir.starts_with(&base) {
                break;
            }
        }
    }
    best
}

/// A small text file (at most 64 KB read).
fn read_small(path: &Path) -> Option<String> {
    use std::io::Read;
    let mut s = String::new();
    std::fs::File::open(path).ok()?.take(64 * 1024).read_to_string(&mut s).ok()?;
    Some(s)
}

/// Refuses a remeshing whose `estimate` of output vertices needs more memory than the
/// process's limit.
pub fn check(estimate: f64) -> Result<(), super::RemeshError> {
    let Some((limit, source)) = limit() else { return Ok(()) };
    let bytes = estimate * BYTES_PER_VERTEX;
    if bytes > limit as f64 {
        return Err(super::RemeshError::MemoryLimit { estimate, bytes, limit, which: source });
    }
    Ok(())
}

/// Bytes as a user reads them: `1.2 GB`, `350 MB`.
pub fn format_bytes(b: f64) -> String {
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.0} MB", (b / 1e6).max(1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cgroup's own limit, a parent's, `max` (none) and a missing file.
    #[test]
    fn the_cgroup_limit_is_read_from_the_process_cgroup_or_a_parent() {
        let d = tempfile::tempdir().unwrap();
        let root = d.path().join("cg");
        std::fs::create_dir_all(root.join("slurm/job_7/step_0")).unwrap();
        let proc = d.path().join("cgroup");
        std::fs::write(&proc, "0::/slurm/job_7/step_0\n").unwrap();
        assert_eq!(cgroup_limit(&proc, &root), None);
        std::fs::write(root.join("slurm/job_7/memory.max"), "1073741824\n").unwrap();
        assert_eq!(cgroup_limit(&proc, &root), Some(1 << 30));
        std::fs::write(root.join("slurm/job_7/step_0/memory.max"), "max\n").unwrap();
        assert_eq!(cgroup_limit(&proc, &root), Some(1 << 30), "max: the parent's applies");
        std::fs::write(root.join("slurm/job_7/step_0/memory.max"), "5000\n").unwrap();
        assert_eq!(cgroup_limit(&proc, &root), Some(5000));
        assert_eq!(cgroup_limit(&d.path().join("none"), &root), None);
        // v1: the memory controller's hierarchy; its "unlimited" is no limit.
        std::fs::write(&proc, "4:memory:/docker/abc\n0::/\n").unwrap();
        std::fs::create_dir_all(root.join("memory/docker")).unwrap();
        std::fs::write(root.join("memory/memory.limit_in_bytes"), "9223372036854771712\n").unwrap();
        assert_eq!(cgroup_limit(&proc, &root), None);
        std::fs::write(root.join("memory/docker/memory.limit_in_bytes"), "2147483648\n").unwrap();
        assert_eq!(cgroup_limit(&proc, &root), Some(2 << 30));
    }
}
