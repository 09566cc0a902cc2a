//! One output directory shared by processes whose PIDs mean different things: the nodes
//! of a cluster on one file system, the containers of one machine. A temporary left by a
//! process killed mid-write is removed only by a later writer of the same host and PID
//! namespace; another namespace's writer never removes it, since the PID in its name may
//! belong to a process alive there.
//!
//! The second namespace is made with `unshare --user --pid --fork` (util-linux); the test
//! skips, saying so, where the kernel or the system does not allow it.

#[path = "support/cli.rs"]
mod cli;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use cli::{bundled, streams};

const SMARTMESH: &str = env!("CARGO_BIN_EXE_smartmesh");

/// The temporaries (`.NAME.smartmesh-….tmp`) in `dir`.
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    let mut t: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy().into_owned();
            n.starts_with('.') && n.contains(".smartmesh-") && n.ends_with(".tmp")
        })
        .collect();
    t.sort();
    t
}

/// Whether `unshare` can start a process in a PID namespace of its own here.
fn unshare_works() -> bool {
    Command::new("unshare")
        .args(["--user", "--map-root-user", "--pid", "--fork", "true"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// `smartmesh convert cylinder.msh OUT`, in a PID namespace of its own.
fn convert_elsewhere(out: &Path) -> std::process::Output {
    Command::new("unshare")
        .args(["--user", "--map-root-user", "--pid", "--fork", SMARTMESH, "convert"])
        .arg(bundled("cylinder.msh"))
        .arg(out)
        .output()
        .unwrap()
}

fn convert_here(out: &Path) -> std::process::Output {
    Command::new(SMARTMESH).arg("convert").arg(bundled("cylinder.msh")).arg(out).output().unwrap()
}

#[cfg(unix)]
#[test]
fn a_live_temporary_of_another_pid_namespace_is_never_removed() {
    if !unshare_works() {
        eprintln!("skipped: `unshare --user --pid --fork` is not available here");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // A write killed by its file size limit (SIGXFSZ) leaves its temporary: the name a
    // writer of this namespace gives it.
    let killed = Command::new("/bin/sh")
        .arg("-c")
        .arg("ulimit -f 1; exec \"$0\" convert \"$1\" \"$2\"")
        .arg(SMARTMESH)
        .arg(bundled("cylinder.msh"))
        .arg(dir.path().join("a.msh"))
        .spawn()
        .unwrap();
    let dead = killed.id();
    let o = killed.wait_with_output().unwrap();
    assert!(!o.status.success(), "{}", streams(&o));
    let left = temporaries(dir.path());
    assert_eq!(left.len(), 1, "{left:?}");

    // Its writer is now alive (a process of ours that still runs): the same name with a
    // live PID of this namespace, which the other namespace does not have.
    let mut alive = Command::new("sleep").arg("60").spawn().unwrap();
    let name = left[0].file_name().unwrap().to_string_lossy().into_owned();
    let at = name.rfind(&format!("-{dead}.")).expect("the temporary names its PID");
    let live_name =
        format!("{}-{}.{}", &name[..at], alive.id(), &name[at + format!("-{dead}.").len()..]);
    let live = dir.path().join(&live_name);
    std::fs::rename(&left[0], &live).unwrap();

    // A writer of another PID namespace sharing the directory leaves it alone.
    let o = convert_elsewhere(&dir.path().join("b.msh"));
    assert!(o.status.success(), "{}", streams(&o));
    assert!(live.exists(), "another namespace's writer removed a live temporary");
    // So does a writer of this namespace, while its writer runs.
    let o = convert_here(&dir.path().join("c.msh"));
    assert!(o.status.success(), "{}", streams(&o));
    assert!(live.exists(), "a live temporary was removed");

    // Once its writer is gone, a writer of the other namespace still leaves it (its PID
    // says nothing there); one of this namespace removes it.
    alive.kill().unwrap();
    alive.wait().unwrap();
    let o = convert_elsewhere(&dir.path().join("d.msh"));
    assert!(o.status.success(), "{}", streams(&o));
    assert!(live.exists(), "another namespace's writer judged our PID");
    let o = convert_here(&dir.path().join("e.msh"));
    assert!(o.status.success(), "{}", streams(&o));
    assert_eq!(temporaries(dir.path()), Vec::<PathBuf>::new(), "the stale temporary stays");
}
