//! Running the `smartmesh` binary from integration tests: the command, the bundled
//! fixtures, and the exit-status checks that print both streams when they fail.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `smartmesh ARGS`, with `RAYON_NUM_THREADS` set when `threads` is given.
pub fn smartmesh(args: &[&str], threads: Option<&str>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_smartmesh"));
    c.args(args);
    if let Some(t) = threads {
        c.env("RAYON_NUM_THREADS", t);
    }
    c.output().expect("run smartmesh")
}

/// The path of a bundled fixture (`fixtures/NAME`).
pub fn bundled(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures").join(name).display().to_string()
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
#[allow(dead_code)] // not every test file checks refusals
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

/// A `smartmesh` command to finish by hand (environment, stdin, spawn).
#[allow(dead_code)] // not every test file needs more than `smartmesh`
pub fn command(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_smartmesh"));
    c.args(args);
    c
}

/// Both streams, for assertion messages.
#[allow(dead_code)]
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
#[allow(dead_code)]
pub fn program(name: &str) -> Option<std::path::PathBuf> {
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

/// The executable `name` found on `PATH`, if any (no message: for engines a test may
/// well not find, and says so itself).
#[allow(dead_code)]
pub fn program_quiet(name: &str) -> Option<std::path::PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .filter(|d| !d.as_os_str().is_empty())
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}
