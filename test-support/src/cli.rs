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
pub fn fixture(name: &str) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("the workspace root");
    root.join("fixtures").join(name)
}

/// [`fixture`] as a string, for a command's arguments.
pub fn bundled(name: &str) -> String {
    fixture(name).display().to_string()
}

/// stdout, lossily decoded.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// stderr, lossily decoded.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
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

pub use crate::skip::{interop_required, skip};

/// The executable `name` found on `PATH`, if any, saying nothing (for engines a test may
/// well not find, and says so itself).
pub fn program_quiet(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .filter(|d| !d.as_os_str().is_empty())
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// Whether the C preprocessor runs (a recipe with `#define` needs it, as the thesis'
/// appendix A.1.6). Where it does not, the test skips, saying so for `what`; on CI (`CI`
/// set) a missing `cpp` fails it instead.
pub fn cpp_or_skip(what: &str) -> bool {
    let ok = Command::new("cpp").arg("--version").output().is_ok_and(|o| o.status.success());
    assert!(ok || std::env::var_os("CI").is_none(), "CI must have cpp for {what}");
    if !ok {
        skip(&format!("no cpp on this machine for {what}"));
    }
    ok
}

/// The executable `name` found on `PATH`, or `None` after saying on stderr that the test
/// skips; with `SMARTMESH_REQUIRE_INTEROP=1` (CI) a missing program fails the test
/// instead. A Python module being importable is not enough: the command a test runs is
/// looked up on `PATH`.
pub fn program(name: &str) -> Option<PathBuf> {
    let found = program_quiet(name);
    if found.is_none() {
        crate::skip::missing_tool(&format!("`{name}` is not on PATH"));
    }
    found
}
