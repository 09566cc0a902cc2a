//! `smartmesh batch` where many processes share one output directory, and what one
//! variant, one record or one manifest must not do to the rest: one owner per variant (a
//! lock), variants' processes that die with the batch, records that stay whole after a
//! short write, outputs that never replace the batch's own inputs, and the checks made
//! before any run.

#[path = "support/cli.rs"]
mod cli;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use cli::{bad, bundled, command, smartmesh, streams};
use serde_json::Value;

const SMARTMESH: &str = env!("CARGO_BIN_EXE_smartmesh");

/// A manifest line: the bundled cylinder with `options`.
fn line(name: &str, input: &str, options: &str) -> String {
    format!(
        r#"{{"name":"{name}","input":"{input}","recipe":"{}","options":{options}}}"#,
        bundled("cylinder.toml")
    )
}

fn cylinder(name: &str, options: &str) -> String {
    line(name, &bundled("cylinder.msh"), options)
}

fn write_manifest(dir: &Path, lines: &[String]) -> PathBuf {
    let m = dir.join("variants.jsonl");
    std::fs::write(&m, lines.join("\n") + "\n").unwrap();
    m
}

/// The records of `DIR/results.jsonl`; every line must be one.
fn records(dir: &Path) -> Vec<Value> {
    std::fs::read_to_string(dir.join("results.jsonl"))
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect()
}

fn names(records: &[Value]) -> Vec<String> {
    let mut n: Vec<String> = records.iter().map(|r| r["name"].as_str().unwrap().into()).collect();
    n.sort();
    n
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn two_batches_on_one_directory_run_each_variant_once() {
    let d = tempfile::tempdir().unwrap();
    let lines: Vec<String> =
        (0..4).map(|k| cylinder(&format!("cyl-{k}"), r#"{"max_iterations":1}"#)).collect();
    let m = write_manifest(d.path(), &lines);
    let out = d.path().join("out");
    let start = || {
        Command::new(SMARTMESH)
            .args(["batch", s(&m), "-o", s(&out)])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (start(), start());
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    assert_eq!(a.status.code(), Some(0), "{}", streams(&a));
    assert_eq!(b.status.code(), Some(0), "{}", streams(&b));
    let r = records(&out);
    assert_eq!(names(&r), ["cyl-0", "cyl-1", "cyl-2", "cyl-3"], "one record per variant");
    assert!(r.iter().all(|r| r["status"] == "ok"), "{r:?}");
}

#[test]
fn a_variant_whose_lock_is_held_is_left_to_its_owner() {
    if Command::new("flock").arg("--version").output().is_err() {
        eprintln!("skipped: flock(1) is not installed");
        return;
    }
    let d = tempfile::tempdir().unwrap();
    let m = write_manifest(
        d.path(),
        &[cylinder("held", r#"{"max_iterations":1}"#), line("free", "missing.msh", "{}")],
    );
    let out = d.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let lock = out.join(".held.lock");
    // Another owner (any process on any host sharing the directory) holds it.
    let mut owner = Command::new("flock").arg(&lock).args(["sleep", "60"]).spawn().unwrap();
    let t = Instant::now();
    while Command::new("flock").arg("-n").arg(&lock).arg("true").status().unwrap().success() {
        assert!(t.elapsed() < Duration::from_secs(20), "flock never took the lock");
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = smartmesh(&["batch", s(&m), "-o", s(&out)], None);
    owner.kill().unwrap();
    owner.wait().unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("1 left to another batch sharing"), "{err}");
    assert!(err.contains("(held: locked or recorded meanwhile)"), "{err}");
    assert_eq!(names(&records(&out)), ["free"]);
    assert!(!out.join("held.msh").exists());
}

/// The pids of the processes whose parent is `parent` (Linux `/proc`).
fn children(parent: u32) -> Vec<u32> {
    let mut found = Vec::new();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<u32>() else { continue };
        let Ok(stat) = std::fs::read_to_string(e.path().join("stat")) else { continue };
        // pid (comm) state ppid …: comm may hold spaces, so read after the last `)`.
        let Some(rest) = stat.rsplit_once(')').map(|r| r.1) else { continue };
        let fields: Vec<&str> = rest.split_whitespace().collect();
        if fields.get(1).and_then(|p| p.parse::<u32>().ok()) == Some(parent) {
            found.push(pid);
        }
    }
    found
}

/// Whether the process `pid` has not ended yet: some thread of it has not finished
/// exiting. Its main thread's state alone does not say so: the main thread of a
/// multi-threaded process (`adapt` has rayon's workers) shows as a zombie once it has
/// exited itself, while other threads may still be exiting, and they share the open
/// files (the variant's lock among them) until the last one is done. The kernel closes a
/// thread's files before it leaves `/proc/PID/task`, so a zombie whose task list holds
/// only itself has closed them all (and released their `flock`s).
fn alive(pid: u32) -> bool {
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else { return false };
    let zombie = stat.rsplit_once(')').is_some_and(|r| r.1.trim_start().starts_with('Z'));
    !zombie
        || std::fs::read_dir(format!("/proc/{pid}/task")).is_ok_and(|threads| {
            threads.flatten().any(|t| t.file_name() != pid.to_string().as_str())
        })
}

/// Whether `pid`'s main thread still runs (a zombie does not).
fn running(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .is_ok_and(|s| s.rsplit_once(')').is_some_and(|r| !r.1.trim_start().starts_with('Z')))
}

#[cfg(target_os = "linux")]
#[test]
fn a_variants_process_dies_with_the_batch_and_resume_runs_it_alone() {
    let d = tempfile::tempdir().unwrap();
    // Never converges: runs its 40 iterations unless stopped.
    let m = write_manifest(
        d.path(),
        &[cylinder(
            "long",
            r#"{"max_iterations":40,"tol_vertices":0,"tol_conformity":1,"max_growth":1.02}"#,
        )],
    );
    let out = d.path().join("out");
    let mut batch = Command::new(SMARTMESH)
        .args(["batch", s(&m), "-o", s(&out)])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t = Instant::now();
    let adapt = loop {
        if let Some(&c) = children(batch.id()).first() {
            break c;
        }
        assert!(t.elapsed() < Duration::from_secs(30), "no variant process started");
        std::thread::sleep(Duration::from_millis(20));
    };
    // Let the child become `adapt` (and its guard start) before the batch dies.
    std::thread::sleep(Duration::from_millis(500));
    assert!(running(adapt));
    batch.kill().unwrap();
    batch.wait().unwrap();
    let t = Instant::now();
    while alive(adapt) {
        assert!(t.elapsed() < Duration::from_secs(5), "the variant's process outlived the batch");
        std::thread::sleep(Duration::from_millis(50));
    }
    // Nobody owns it any more: the next batch may take it at once (the batch and the
    // variant's process were its only holders; what the variant starts gets another stdin).
    let lock = out.join(".long.lock");
    assert!(lock.exists());
    if Command::new("flock").arg("--version").output().is_ok() {
        assert!(
            Command::new("flock").arg("-n").arg(&lock).arg("true").status().unwrap().success(),
            "the lock outlived the variant's process"
        );
    }
}

#[test]
fn a_short_write_of_a_record_is_rolled_back() {
    let d = tempfile::tempdir().unwrap();
    let m = write_manifest(d.path(), &[cylinder("cyl", r#"{"max_iterations":1}"#)]);
    let out = d.path().join("out");
    std::fs::create_dir(&out).unwrap();
    // One whole record (padded inside its object) leaving 40 bytes under a 1 KiB limit.
    let mut first = r#"{"name":"old","line":1,"status":"ok","converged":true,"iterations":1,"vertices":1,"triangles":1,"conformity":1.0,"mean_quality":1.0,"min_quality":1.0,"seconds":1.0,"output":"old.msh","history":"old.history.json","log":"old.log","error":null,"hash":"x""#.to_string();
    first.push_str(&" ".repeat(1024 - 40 - first.len() - 2));
    first.push_str("}\n");
    assert_eq!(first.len(), 984);
    std::fs::write(out.join("results.jsonl"), &first).unwrap();
    // A full disk, as a file size limit whose signal is ignored: write() comes short
    // (the variant's own mesh cannot be written either: it fails, and its record is cut).
    let o = Command::new("/bin/sh")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 2; exec \"$0\" batch \"$1\" -o \"$2\"")
        .args([SMARTMESH, s(&m), s(&out)])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    assert!(String::from_utf8_lossy(&o.stderr).contains("appending to"), "{}", streams(&o));
    assert_eq!(std::fs::read_to_string(out.join("results.jsonl")).unwrap(), first);
    // The next run's record is whole, and so is the one before it.
    let o = smartmesh(&["batch", s(&m), "-o", s(&out)], None);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    assert_eq!(names(&records(&out)), ["cyl", "old"]);
}

#[test]
fn resume_reads_past_torn_and_non_utf8_lines() {
    let d = tempfile::tempdir().unwrap();
    let m = write_manifest(d.path(), &[cylinder("cyl", r#"{"max_iterations":1}"#)]);
    let out = d.path().join("out");
    let o = smartmesh(&["batch", s(&m), "-o", s(&out)], None);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let results = out.join("results.jsonl");
    let mut bytes = std::fs::read(&results).unwrap();
    bytes.extend_from_slice(b"\xff\xfe not text\n{\"name\":\"cyl\",\"sta");
    std::fs::write(&results, &bytes).unwrap();
    let o = smartmesh(&["batch", s(&m), "-o", s(&out), "--resume"], None);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("(1 already recorded)"), "{err}");
    assert!(err.contains("results.jsonl:2: not a result record, ignored: not UTF-8 text"), "{err}");
}

#[test]
fn outputs_that_would_replace_the_batchs_inputs_are_refused_before_any_run() {
    let d = tempfile::tempdir().unwrap();
    let fam = d.path().join("fam");
    let o = smartmesh(
        &[
            "variants",
            "naca",
            "--thickness",
            "0.1:0.12:2",
            "--recipe",
            &bundled("cylinder.toml"),
            "--options",
            r#"{"format":"node","max_iterations":1}"#,
            "-o",
            s(&fam),
        ],
        None,
    );
    assert!(o.status.success(), "{}", streams(&o));
    let polys = |dir: &Path| {
        let mut p: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "poly"))
            .map(|p| (p.display().to_string(), std::fs::read(&p).unwrap()))
            .collect();
        p.sort();
        p
    };
    let before = polys(&fam);
    assert_eq!(before.len(), 2);
    let o = smartmesh(&["batch", s(&fam.join("manifest.jsonl")), "-o", s(&fam)], None);
    let err = bad(&o);
    assert!(err.contains("the batch would replace its own inputs"), "{err}");
    assert!(err.contains(".poly, which is the input of"), "{err}");
    assert_eq!(polys(&fam), before);
    assert!(!fam.join("results.jsonl").exists(), "nothing runs");
}

#[test]
fn what_is_wrong_with_one_variant_is_its_record_and_the_others_run() {
    let d = tempfile::tempdir().unwrap();
    let m = write_manifest(
        d.path(),
        &[
            cylinder("ok", r#"{"max_iterations":1}"#),
            cylinder("logdir", r#"{"max_iterations":1}"#),
            line("missing", "nowhere.msh", "{}"),
            // One argument longer than the kernel takes (E2BIG).
            cylinder("toolong", &format!(r#"{{"adapter_args":["{}"]}}"#, "x".repeat(200_000))),
        ],
    );
    let out = d.path().join("out");
    std::fs::create_dir_all(out.join("logdir.log")).unwrap();
    let o = smartmesh(&["batch", s(&m), "-o", s(&out)], None);
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    let r = records(&out);
    assert_eq!(names(&r), ["logdir", "missing", "ok", "toolong"]);
    let of = |n: &str| r.iter().find(|x| x["name"] == n).unwrap().clone();
    assert_eq!(of("ok")["status"], "ok");
    assert_eq!(of("logdir")["status"], "failed");
    assert!(of("logdir")["error"].as_str().unwrap().contains("logdir.log"), "{r:?}");
    assert_eq!(of("missing")["status"], "failed");
    assert_eq!(of("missing")["line"], 3);
    assert!(of("missing")["error"].as_str().unwrap().contains("nowhere.msh does not exist"));
    assert_eq!(of("toolong")["status"], "failed");
    assert!(of("toolong")["error"].as_str().unwrap().starts_with("starting "), "{r:?}");
}

#[test]
fn unwritable_results_are_found_before_any_run() {
    let d = tempfile::tempdir().unwrap();
    let m = write_manifest(d.path(), &[cylinder("cyl", r#"{"max_iterations":1}"#)]);
    let out = d.path().join("out");
    std::fs::create_dir_all(out.join("results.jsonl")).unwrap();
    let o = smartmesh(&["batch", s(&m), "-o", s(&out)], None);
    let err = bad(&o);
    assert!(err.contains("results.jsonl cannot be written"), "{err}");
    assert!(!out.join("cyl.log").exists() && !out.join("cyl.msh").exists(), "a variant ran");
}

#[test]
fn a_manifest_is_a_bounded_regular_file_and_hq_entry_is_text() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("out");
    let o = smartmesh(&["batch", "/dev/zero", "-o", s(&out)], None);
    assert!(bad(&o).contains("is not a regular file"));
    let fifo = d.path().join("fifo");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let mut child = command(&["batch", s(&fifo), "-o", s(&out)])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t.elapsed() > Duration::from_secs(20) {
            child.kill().unwrap();
            panic!("batch blocked on a FIFO");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = child.wait_with_output().unwrap();
    assert!(bad(&o).contains("is not a regular file"));

    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        let m = write_manifest(d.path(), &[cylinder("cyl", r#"{"max_iterations":1}"#)]);
        let o = command(&["batch", s(&m), "-o", s(&out)])
            .env("HQ_ENTRY", std::ffi::OsStr::from_bytes(b"{\"name\":\"\xff\"}"))
            .output()
            .unwrap();
        assert!(bad(&o).contains("HQ_ENTRY holds bytes that are not UTF-8"));
    }
    assert!(!out.exists());
}

#[test]
fn manifest_messages_say_what_is_wrong_and_stay_plain_text() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("out");
    let run = |text: &str| {
        let m = d.path().join("m.jsonl");
        std::fs::write(&m, text).unwrap();
        smartmesh(&["batch", s(&m), "-o", s(&out)], None)
    };
    // A byte order mark is not part of the first line.
    let o = run(&format!("\u{feff}{}\n", line("gone", "missing.msh", "{}")));
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    assert_eq!(names(&records(&out)), ["gone"]);
    // A negative size is a value, refused as one.
    let err = bad(&run(&format!("{}\n", cylinder("neg", r#"{"hmin":-1}"#))));
    assert!(err.contains("-1 is not a size"), "{err}");
    assert!(!err.contains("unexpected argument"), "{err}");
    // A key given twice.
    let err = bad(&run(&format!("{}\n", cylinder("dup", r#"{"hmin":0.1,"hmin":0.2}"#))));
    assert!(err.contains("m.jsonl:1: ") && err.contains("the key `hmin` is given twice"), "{err}");
    // Control characters of the line reach the terminal escaped.
    for text in [
        "{\"name\":\"a\\u001b]0;pwned\\u0007\",\"input\":\"x\",\"recipe\":\"y\"}\n",
        "{\"na\\u001b[2Jme\":1}\n",
        "{\"name\":\"a\",\"input\":\"x\",\"recipe\":\"y\",\"options\":{\"\\u001b[31m\":1}}\n",
    ] {
        let o = run(text);
        assert_eq!(o.status.code(), Some(2), "{}", streams(&o));
        assert!(!o.stderr.iter().any(|&b| b == 0x1b || b == 0x07), "{}", streams(&o));
        assert!(String::from_utf8_lossy(&o.stderr).contains("\\u{1b}"), "{}", streams(&o));
    }
}

#[test]
fn options_are_checked_once_per_set_not_once_per_variant() {
    let d = tempfile::tempdir().unwrap();
    let mut lines: Vec<String> =
        (0..20_000).map(|k| cylinder(&format!("v{k}"), r#"{"max_iterations":2}"#)).collect();
    lines.push(cylinder("bad", r#"{"adapter":"zz"}"#));
    let m = write_manifest(d.path(), &lines);
    let t = Instant::now();
    let o = smartmesh(&["batch", s(&m), "-o", s(&d.path().join("out"))], None);
    assert!(bad(&o).contains(":20001: the options of `bad`"));
    // Once per variant took 53 s here (a debug build); once per set, under a second.
    assert!(t.elapsed() < Duration::from_secs(15), "{:?}", t.elapsed());
}
