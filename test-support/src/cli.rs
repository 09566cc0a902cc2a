//! Running a command-line binary from integration tests: the command, the bundled
//! fixtures, the exit-status checks that print both streams when they fail, and the
//! lookup of external programs that skips a test (or fails it under
//! `SMARTMESH_REQUIRE_INTEROP=1`).
//!
//! The binary is named by its caller (`env!("CARGO_BIN_EXE_smartmesh")` exists only in
//! the integration tests of the package that builds it): `tests/support/cli.rs` binds
//! it and re-exports the rest.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `bin ARGS`, with `RAYON_NUM_THREADS` set when `threads` is given.
pub fn run(bin: &str, args: &[&str], threads: Option<&str>) -> Output {
    let mut c = command(bin, args);
    if let Some(t) = threads {
        c.env("RAYON_NUM_THREADS", t);
    }
    c.output().unwrap_or_else(|e| panic!("run {bin}: {e}"))
}

/// `bin ARGS` as a command to finish by hand (environment, stdin, spawn).
pub fn command(bin: &str, args: &[&str]) -> Command {
    let mut c = Command::new(bin);
    c.args(args);
    c
}

/// The path of a bundled fixture of the workspace (`fixtures/NAME`).
pub fn bundled(name: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("the workspace root");
    root.join("fixtures").join(name).display().to_string()
}

/// Asserts exit status 0 and returns stdout.
pub fn ok(o: &Output) -> String {
    assert_eq!(
        o.status.code(),
        Some(0),
        "stdout:\n{}\nstderr:\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Asserts exit status 2 (bad usage or input) and returns stderr.
pub fn bad(o: &Output) -> String {
    assert_eq!(
        o.status.code(),
        Some(2),
        "stdout:\n{}\nstderr:\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Both streams, for assertion messages.
pub fn streams(o: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// The executable `name` found on `PATH`, or `None` after saying on stderr that the test
/// skips; with `SMARTMESH_REQUIRE_INTEROP=1` (CI) a missing program fails the test
/// instead. A Python module being importable is not enough: the command a test runs is
/// looked up on `PATH`.
pub fn program(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let found = std::env::split_paths(&path)
        .filter(|d| !d.as_os_str().is_empty())
        .map(|d| d.join(name))
        .find(|p| p.is_file());
    if found.is_none() {
        if std::env::var("SMARTMESH_REQUIRE_INTEROP").as_deref() == Ok("1") {
            panic!("`{name}` is needed on PATH (SMARTMESH_REQUIRE_INTEROP=1)");
        }
        eprintln!("skipping: `{name}` is not on PATH");
    }
    found
}
