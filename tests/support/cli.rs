//! Running the `smartmesh` binary from integration tests: the helpers of
//! `smartmesh_test_support::cli` with the binary Cargo builds for this package's tests.

use std::process::{Command, Output};

#[allow(unused_imports)] // each test file uses some of them
pub use smartmesh_test_support::cli::{bad, bundled, ok, program, streams};

/// The binary under test.
const BIN: &str = env!("CARGO_BIN_EXE_smartmesh");

/// Runs `smartmesh ARGS`, with `RAYON_NUM_THREADS` set when `threads` is given.
#[allow(dead_code)]
pub fn smartmesh(args: &[&str], threads: Option<&str>) -> Output {
    smartmesh_test_support::cli::run(BIN, args, threads)
}

/// A `smartmesh` command to finish by hand (environment, stdin, spawn).
#[allow(dead_code)]
pub fn command(args: &[&str]) -> Command {
    smartmesh_test_support::cli::command(BIN, args)
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
