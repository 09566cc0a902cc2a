//! The external programs `adapt` runs (a `--solver`, the `mmg2d_O3` and `gmsh` adapters):
//! no character of a path reaches a shell.
//!
//! The solvers here are `sh` and `awk` scripts on Medit files (`--solver-mesh-format mesh
//! --solution-format sol`), so that no Python is needed.
#![cfg(unix)]

#[path = "support/cli.rs"]
mod cli;

use std::path::{Path, PathBuf};

use cli::{command, streams};

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
