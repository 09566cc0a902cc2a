//! The external programs `adapt` runs (a `--solver`, the `mmg2d_O3` and `gmsh` adapters):
//! no character of a path reaches a shell, their output costs a bounded buffer, a Ctrl-C
//! stops them (their whole process group, their temporary directory removed) and exits
//! with 130, and a failing solver is a failure (exit 1) at every iteration.
//!
//! The solvers here are `sh` and `awk` scripts on Medit files (`--solver-mesh-format mesh
//! --solution-format sol`), so that no Python is needed.
#![cfg(unix)]

#[path = "support/cli.rs"]
mod cli;

use std::path::{Path, PathBuf};
use std::process::{Child, Output, Stdio};
use std::time::{Duration, Instant};

use cli::{bundled, command, streams};

/// A solver: u = x³ + 3y³ at the vertices of the Medit mesh `$1`, written to `$2` as a
/// `.sol`; from the iteration named in `$3` on (the K of `mesh-K.mesh`; none when absent)
/// it does what `$4` says: `fail` (exit 3), `hang` (writes its pid to `$5`, then sleeps).
const SOLVER: &str = r#"#!/bin/sh
mesh=$1 solution=$2 at=${3:-none} mode=$4
k=${mesh##*mesh-}; k=${k%%.*}
if [ "$k" = "$at" ] || { [ "$at" != none ] && [ "$k" -gt "$at" ]; }; then
  case $mode in
    fail) echo "solver: the linear system did not converge" >&2; exit 3 ;;
    hang) echo $$ > "$5"; sleep 1000; echo never ;;
  esac
fi
awk 'BEGIN{s=0} /^ *Vertices/{s=1; next}
  s==1{n=$1; print "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n" n "\n1 1" > out; s=2; next}
  s==2{ if (c<n) {print ($1*$1*$1 + 3*$2*$2*$2) > out; c++} else s=3}
  END{print "End" > out}' out="$solution" "$mesh"
"#;

/// An executable script at `path`.
fn script(path: &Path, body: &str) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::write(path, body).unwrap();
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
}

/// `dir/solve.sh` and `dir/square.poly`.
fn setup(dir: &Path) -> (PathBuf, PathBuf) {
    let solver = dir.join("solve.sh");
    script(&solver, SOLVER);
    let poly = dir.join("square.poly");
    std::fs::write(
        &poly,
        "4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n4 1\n1 1 2 1\n2 2 3 2\n3 3 4 3\n4 4 1 4\n0\n",
    )
    .unwrap();
    (solver, poly)
}

/// `smartmesh adapt POLY --solver COMMAND … ARGS` in `dir` (at most 8 iterations, as
/// by default, unless ARGS say).
fn adapt(dir: &Path, solver: &str, args: &[&str]) -> std::process::Command {
    let mut all = vec![
        "adapt",
        "square.poly",
        "--solver",
        solver,
        "--solver-mesh-format",
        "mesh",
        "--solution-format",
        "sol",
        "--complexity-start",
        "150",
        "--complexity",
        "400",
    ];
    all.extend_from_slice(args);
    let mut c = command(&all);
    c.current_dir(dir);
    c
}

fn history(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Every file and directory under `dir`, relative.
fn tree(dir: &Path) -> Vec<String> {
    let mut all = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            all.push(p.strip_prefix(dir).unwrap().display().to_string());
            if p.is_dir() {
                stack.push(p);
            }
        }
    }
    all.sort();
    all
}

/// Every shell metacharacter, quotes of both kinds, a newline and both placeholders.
const NASTY: &str = "a {solution}'\"$(touch PWNED1)`touch PWNED2`;touch PWNED3 & | < > * ? [x] # ~ = % ! \\ \t\n{mesh}${HOME}";

#[test]
fn no_character_of_a_path_reaches_the_shell() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    // Both placeholders in every kind of quoting, in the solver's directory and in the
    // output's name (which names the default solver directory).
    let solvers = ["./solve.sh {mesh} {solution}", "./solve.sh \"{mesh}\" '{solution}'"];
    let outputs = [
        ("sd".to_string() + NASTY, format!("out/{NASTY}.vtu")),
        (String::new(), format!("out2/x{NASTY}.vtu")),
    ];
    for solver in solvers {
        for (solver_dir, out) in &outputs {
            let parent = dir.path().join(Path::new(out).parent().unwrap());
            std::fs::create_dir_all(&parent).unwrap();
            let mut args = vec!["-o", out.as_str(), "--max-iterations", "1"];
            if !solver_dir.is_empty() {
                args.extend(["--solver-dir", solver_dir.as_str()]);
            }
            let o = adapt(dir.path(), solver, &args).output().unwrap();
            assert_eq!(o.status.code(), Some(0), "{solver} {out}: {}", streams(&o));
            let files = tree(dir.path());
            for pwned in ["PWNED1", "PWNED2", "PWNED3"] {
                assert!(!dir.path().join(pwned).exists(), "a path was run by the shell: {files:?}");
            }
            // The solver read and wrote the files at the paths given.
            let solver_dir = if solver_dir.is_empty() {
                let stem = Path::new(out).file_stem().unwrap().to_string_lossy().into_owned();
                parent.join(format!("{stem}.solver"))
            } else {
                dir.path().join(solver_dir)
            };
            for f in ["mesh-0.mesh", "solution-0.sol", "solution-1.sol"] {
                assert!(
                    solver_dir.join(f).is_file(),
                    "no {f} in {}: {files:?}",
                    solver_dir.display()
                );
            }
            assert!(dir.path().join(out).is_file());
            std::fs::remove_dir_all(&solver_dir).unwrap();
        }
    }
}

/// Runs `c` under an address-space limit of about 1.5 GB, which holding 2 GB of a
/// solver's output would pass.
fn limited(c: std::process::Command) -> Output {
    let program = c.get_program().to_owned();
    let mut sh = std::process::Command::new("/bin/sh");
    sh.arg("-c").arg("ulimit -v 1500000 && exec \"$@\"").arg("sh").arg(program);
    sh.args(c.get_args());
    if let Some(d) = c.get_current_dir() {
        sh.current_dir(d);
    }
    sh.output().unwrap()
}

#[test]
fn a_solver_printing_gigabytes_costs_a_tail_and_fails_as_one() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    // 2.1 GB of stdout, then a message on stderr, then a failure.
    let solver = "head -c 2100M /dev/zero; echo 'solver: diverged' >&2; exit 3 # {mesh} {solution}";
    let o = limited(adapt(dir.path(), solver, &["-o", "x.vtu"]));
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    // A solver failing on the starting mesh is a failure, not bad input.
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    assert!(err.contains("exit status 3") && err.contains("solver: diverged"), "{err}");
    assert!(err.contains("2202009600 bytes in all"), "{err}");
    assert!(err.len() < 4000, "the message quotes {} bytes", err.len());

    // The same output from a solver that then solves: the loop goes on.
    let solver = "head -c 2100M /dev/zero; ./solve.sh {mesh} {solution}";
    let o = limited(adapt(dir.path(), solver, &["-o", "y.vtu", "--max-iterations", "1"]));
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    assert_eq!(
        history(&dir.path().join("y.history.json"))["iterations"].as_array().unwrap().len(),
        2
    );
}

#[test]
fn a_failing_solver_exits_one_at_the_first_iteration_and_later() {
    for at in ["0", "1"] {
        let dir = tempfile::tempdir().unwrap();
        setup(dir.path());
        let solver = format!("./solve.sh {{mesh}} {{solution}} {at} fail");
        let o = adapt(dir.path(), &solver, &["-o", "x.vtu"]).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(1), "at {at}: {}", streams(&o));
        assert!(err.contains("exit status 3") && err.contains("did not converge"), "{err}");
    }
}

/// The process group of the running process `pid` (field 5 of /proc/PID/stat).
fn group_of(pid: &str) -> String {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
    stat.rsplit_once(')').unwrap().1.split_whitespace().nth(2).unwrap().to_string()
}

/// The processes of group `pgid` still alive 5 s from now at most (a process killed is
/// gone a moment after the signal; zombies left to an init that does not reap count as
/// gone).
fn alive_in_group(pgid: &str) -> Vec<String> {
    let t = Instant::now();
    loop {
        let alive = alive_now(pgid);
        if alive.is_empty() || t.elapsed() > Duration::from_secs(5) {
            return alive;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The processes of group `pgid` alive now, zombies left out.
fn alive_now(pgid: &str) -> Vec<String> {
    let mut alive = Vec::new();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(stat) = std::fs::read_to_string(e.path().join("stat")) else { continue };
        let Some((_, rest)) = stat.rsplit_once(')') else { continue };
        let f: Vec<&str> = rest.split_whitespace().collect();
        if f.len() > 2 && f[2] == pgid && f[0] != "Z" {
            alive.push(e.file_name().to_string_lossy().into_owned());
        }
    }
    alive
}

/// Waits until `file` holds a line (a pid the child wrote).
fn wait_for_pid(file: &Path, child: &mut Child) -> String {
    let t = Instant::now();
    loop {
        if let Ok(s) = std::fs::read_to_string(file) {
            if s.ends_with('\n') {
                return s.trim().to_string();
            }
        }
        if let Ok(Some(status)) = child.try_wait() {
            panic!("smartmesh ended ({status}) before its child started");
        }
        assert!(t.elapsed() < Duration::from_secs(120), "the child did not start");
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(pid: u32, name: &str) {
    let ok = std::process::Command::new("kill")
        .args([&format!("-{name}"), &pid.to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill -{name} {pid}");
}

/// Waits for `child` to exit, at most `limit`.
fn finish(mut child: Child, limit: Duration) -> Output {
    let t = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t.elapsed() > limit {
            let _ = child.kill();
            panic!("smartmesh still runs {limit:?} after the signal");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[cfg(target_os = "linux")]
#[test]
fn a_hanging_solver_is_stopped_by_the_first_signal() {
    for sig in ["INT", "TERM"] {
        let dir = tempfile::tempdir().unwrap();
        setup(dir.path());
        let pid_file = dir.path().join("solver.pid");
        let solver = format!("./solve.sh {{mesh}} {{solution}} 1 hang {}", pid_file.display());
        let child = adapt(dir.path(), &solver, &["-o", "x.vtu"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut child = child;
        let pid = wait_for_pid(&pid_file, &mut child);
        let pgid = group_of(&pid);
        assert_ne!(pgid, group_of(&child.id().to_string()), "the solver runs in smartmesh's group");
        signal(child.id(), sig);
        let o = finish(child, Duration::from_secs(20));
        assert_eq!(o.status.code(), Some(130), "{sig}: {}", streams(&o));
        let h = history(&dir.path().join("x.history.json"));
        assert_eq!(h["stopped"], "interrupted", "{sig}: {h}");
        assert_eq!(h["iterations"].as_array().unwrap().len(), 1, "{sig}: {h}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("interrupted") && !err.contains("failed"), "{sig}: {err}");
        assert!(alive_in_group(&pgid).is_empty(), "{sig}: the solver's group lives on");
    }
}

#[cfg(target_os = "linux")]
#[test]
fn a_solver_hanging_on_the_starting_mesh_is_interrupted_not_failed() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let pid_file = dir.path().join("solver.pid");
    let solver = format!("./solve.sh {{mesh}} {{solution}} 0 hang {}", pid_file.display());
    let mut child = adapt(dir.path(), &solver, &["-o", "x.vtu"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pgid = group_of(&wait_for_pid(&pid_file, &mut child));
    signal(child.id(), "INT");
    let o = finish(child, Duration::from_secs(20));
    assert_eq!(o.status.code(), Some(130), "{}", streams(&o));
    assert!(String::from_utf8_lossy(&o.stderr).contains("interrupted"), "{}", streams(&o));
    assert!(alive_in_group(&pgid).is_empty(), "the solver's group lives on");
}

/// A fake `mmg2d_O3` that writes its pid and working directory to `info`, then hangs;
/// with `stubborn` it ignores SIGTERM (and so do the `sleep`s it starts).
fn hanging_adapter(dir: &Path, info: &Path, stubborn: bool) -> PathBuf {
    let fake = dir.join("mmg2d_O3");
    let trap = if stubborn { "trap '' TERM\n" } else { "" };
    script(
        &fake,
        &format!(
            "#!/bin/sh\n{trap}pwd > '{0}.dir'\necho $$ > '{0}'\nwhile :; do sleep 1; done\n",
            info.display()
        ),
    );
    fake
}

/// `adapt` of the bundled cylinder with a hanging adapter, its temporary files in
/// `dir/tmp`; returns the child, the adapter's process group and its directory.
fn adapt_hanging(dir: &Path, stubborn: bool) -> (Child, String, PathBuf) {
    let info = dir.join("adapter.pid");
    let fake = hanging_adapter(dir, &info, stubborn);
    let tmp = dir.join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let out = dir.join("o.msh");
    let mut child = command(&[
        "adapt",
        &bundled("cylinder.msh"),
        "-r",
        &bundled("cylinder.toml"),
        "-o",
        out.to_str().unwrap(),
        "--adapter",
        "mmg2d",
        "--adapter-program",
        fake.to_str().unwrap(),
    ])
    .env("TMPDIR", &tmp)
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .unwrap();
    let pid = wait_for_pid(&info, &mut child);
    let pgid = group_of(&pid);
    let work =
        PathBuf::from(std::fs::read_to_string(info.with_extension("pid.dir")).unwrap().trim());
    assert!(work.starts_with(&tmp) && work.is_dir(), "{}", work.display());
    (child, pgid, work)
}

#[cfg(target_os = "linux")]
#[test]
fn a_hanging_adapter_is_stopped_by_the_first_signal_and_its_directory_removed() {
    let dir = tempfile::tempdir().unwrap();
    let (child, pgid, work) = adapt_hanging(dir.path(), false);
    signal(child.id(), "INT");
    let o = finish(child, Duration::from_secs(20));
    assert_eq!(o.status.code(), Some(130), "{}", streams(&o));
    let h = history(&dir.path().join("o.history.json"));
    assert_eq!(h["stopped"], "interrupted", "{h}");
    assert!(alive_in_group(&pgid).is_empty(), "the adapter's group lives on");
    assert!(!work.exists(), "{} is left behind", work.display());
    assert!(tree(&dir.path().join("tmp")).is_empty(), "{:?}", tree(&dir.path().join("tmp")));
}

#[cfg(target_os = "linux")]
#[test]
fn an_adapter_deaf_to_sigterm_is_killed_after_its_grace_or_at_the_second_signal() {
    for twice in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        let (child, pgid, work) = adapt_hanging(dir.path(), true);
        signal(child.id(), "INT");
        if twice {
            std::thread::sleep(Duration::from_millis(300));
            signal(child.id(), "INT");
        }
        let o = finish(child, Duration::from_secs(20));
        assert_eq!(o.status.code(), Some(130), "twice {twice}: {}", streams(&o));
        assert!(alive_in_group(&pgid).is_empty(), "twice {twice}: the adapter's group lives on");
        assert!(!work.exists(), "twice {twice}: {} is left behind", work.display());
    }
}
