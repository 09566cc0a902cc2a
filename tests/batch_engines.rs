//! `smartmesh batch` on the engines that run it at scale, unchanged: a HyperQueue job of
//! one task per manifest line (HQ_ENTRY, as `hq submit --each-line` sets it) on a real
//! local cluster, killed mid-run and completed by `--resume`; a Slurm job array of
//! shards (`--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`). Each test skips,
//! saying so, where its engine is missing (HyperQueue: the PyPI `hyperqueue` module, made
//! mandatory by SMARTMESH_REQUIRE_INTEROP=1; Slurm: `sbatch` on PATH, which
//! `tests/engines/slurm-single-node.sh` sets up).

#[path = "support/cli.rs"]
mod cli;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use cli::{bundled, smartmesh, streams};
use serde_json::Value;

const SMARTMESH: &str = env!("CARGO_BIN_EXE_smartmesh");

/// A manifest of `n` variants of the bundled cylinder: one or two iterations, three
/// sizes of the far field.
fn manifest(dir: &Path, n: usize) -> PathBuf {
    let lines: Vec<String> = (0..n)
        .map(|k| {
            format!(
                r#"{{"name":"cyl-{k:02}","input":"{}","recipe":"{}","options":{{"max_iterations":{},"hmax":{}}}}}"#,
                bundled("cylinder.msh"),
                bundled("cylinder.toml"),
                1 + k % 2,
                [0.15, 0.2, 0.25][k % 3]
            )
        })
        .collect();
    let m = dir.join("variants.jsonl");
    std::fs::write(&m, lines.join("\n") + "\n").unwrap();
    m
}

fn records(dir: &Path) -> Vec<Value> {
    match std::fs::read_to_string(dir.join("results.jsonl")) {
        Ok(t) => t.lines().map(|l| serde_json::from_str(l).unwrap()).collect(),
        Err(_) => Vec::new(),
    }
}

/// Every variant's last record is ok, and agrees with the history and the mesh it names.
fn check_complete(out: &Path, n: usize) -> BTreeMap<String, Value> {
    let latest: BTreeMap<String, Value> =
        records(out).into_iter().map(|r| (r["name"].as_str().unwrap().to_string(), r)).collect();
    assert_eq!(latest.len(), n, "{:?}", latest.keys());
    for (name, r) in &latest {
        assert_eq!(r["status"], "ok", "{r}");
        let line: usize = name[4..].parse::<usize>().unwrap() + 1;
        assert_eq!(r["line"], line, "{r}");
        let h: Value = serde_json::from_str(
            &std::fs::read_to_string(out.join(r["history"].as_str().unwrap())).unwrap(),
        )
        .unwrap();
        let best = &h["iterations"][h["best_iteration"].as_u64().unwrap() as usize];
        assert_eq!(r["vertices"], best["vertices"], "{name}");
        assert_eq!(r["conformity"], best["conforming_share"], "{name}");
        assert_eq!(r["iterations"], 1 + (line - 1) % 2, "{name}");
        let info = smartmesh(
            &["info", out.join(name).with_extension("msh").to_str().unwrap(), "--json"],
            None,
        );
        let info: Value = serde_json::from_str(&cli::ok(&info)).unwrap();
        assert_eq!(info["points"], r["vertices"], "{name}");
    }
    latest
}

/// Whether python3 imports `hyperqueue`; else says the test skips (or fails, when
/// SMARTMESH_REQUIRE_INTEROP=1).
fn hyperqueue() -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import hyperqueue.cluster"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        smartmesh_test_support::skip::missing_tool(
            "python3 cannot import `hyperqueue` (pip install hyperqueue)",
        );
    }
    ok
}

#[test]
fn a_hyperqueue_job_killed_mid_run_is_completed_by_resume() {
    if !hyperqueue() {
        return;
    }
    let n = 20;
    let d = tempfile::tempdir().unwrap();
    let m = manifest(d.path(), n);
    let out = d.path().join("out");
    let work = d.path().join("hq");
    std::fs::create_dir_all(&work).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/engines/hq_cluster.py");
    let mut cluster = Command::new("python3");
    cluster
        .arg(&script)
        .args([SMARTMESH, m.to_str().unwrap(), out.to_str().unwrap(), work.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // A process group of its own: the server, both workers and every task die together.
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut cluster, 0);
    let mut cluster = cluster.spawn().unwrap();
    let t = Instant::now();
    while records(&out).len() < 4 {
        if let Some(status) = cluster.try_wait().unwrap() {
            let o = cluster.wait_with_output().unwrap();
            panic!("the cluster ended before 4 results ({status}):\n{}", streams(&o));
        }
        assert!(t.elapsed() < Duration::from_secs(300), "no 4 results in 300 s");
        std::thread::sleep(Duration::from_millis(50));
    }
    // Killed mid-run: no task gets to finish its work or write anything more.
    #[cfg(unix)]
    {
        let pid = rustix::process::Pid::from_child(&cluster);
        rustix::process::kill_process_group(pid, rustix::process::Signal::KILL).unwrap();
    }
    #[cfg(not(unix))]
    cluster.kill().unwrap();
    let o = cluster.wait_with_output().unwrap();
    assert!(!String::from_utf8_lossy(&o.stdout).contains("done"), "killed too late");
    // HyperQueue starts each task in a session of its own: the tasks under way at the
    // kill are orphans now, as on a worker node whose worker died. They end by themselves
    // (recording their variant) before the resume, which would run them a second time.
    wait_for_processes_naming(&m, Duration::from_secs(300));
    let before = records(&out);
    // A task told to stop by its dying worker records its variant as interrupted.
    for r in &before {
        assert!(r["status"] == "ok" || r["status"] == "interrupted", "{r}");
    }
    let done = before.iter().filter(|r| r["status"] == "ok").count();
    assert!(done >= 4 && done < n, "{done} variants done at the kill");

    // --resume runs what the cluster did not finish, and only that.
    let o = smartmesh(
        &["batch", m.to_str().unwrap(), "-o", out.to_str().unwrap(), "--resume", "--jobs", "2"],
        None,
    );
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains(&format!("{n} of {n} variants done ({done} already recorded)")), "{err}");
    assert_eq!(records(&out).len(), before.len() + n - done);
    check_complete(&out, n);
}

/// Waits until no process has `path` on its command line (Linux's /proc; elsewhere, no
/// wait).
fn wait_for_processes_naming(path: &Path, limit: Duration) {
    let needle = path.to_str().unwrap().as_bytes().to_vec();
    let t = Instant::now();
    loop {
        let running = std::fs::read_dir("/proc").into_iter().flatten().flatten().any(|e| {
            std::fs::read(e.path().join("cmdline"))
                .is_ok_and(|c| c.windows(needle.len()).any(|w| w == needle.as_slice()))
        });
        if !running {
            return;
        }
        assert!(t.elapsed() < limit, "tasks still running after {limit:?}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn a_slurm_array_of_shards_runs_the_whole_manifest() {
    let Some(sbatch) = cli::program_quiet("sbatch") else {
        smartmesh_test_support::skip::skip("`sbatch` is not on PATH (tests/engines/slurm-single-node.sh sets up Slurm on one machine)");
        return;
    };
    // Installed is not running: a node must answer (slurmctld and slurmd up).
    let up = Command::new("sinfo").args(["-h", "-o", "%T"]).output().is_ok_and(|o| {
        let states = String::from_utf8_lossy(&o.stdout);
        o.status.success() && ["idle", "mixed", "allocated"].iter().any(|s| states.contains(s))
    });
    if !up {
        smartmesh_test_support::skip::skip("`sbatch` is there but no Slurm node answers `sinfo` (tests/engines/slurm-single-node.sh starts one)");
        return;
    }
    let n = 6;
    let d = tempfile::tempdir().unwrap();
    let m = manifest(d.path(), n);
    let out = d.path().join("out");
    let script = d.path().join("batch.sbatch");
    std::fs::write(
        &script,
        format!(
            "#!/bin/sh\n#SBATCH --array=0-2\n#SBATCH --cpus-per-task=1\n#SBATCH --output={}/slurm-%A_%a.out\n{SMARTMESH} batch {} -o {} --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT\n",
            d.path().display(),
            m.display(),
            out.display()
        ),
    )
    .unwrap();
    let o = Command::new(sbatch).arg("--wait").arg(&script).current_dir(d.path()).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    // Each array task ran its own shard: every variant once.
    assert_eq!(records(&out).len(), n);
    check_complete(&out, n);
}
