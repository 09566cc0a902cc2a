//! Running the `smartmesh` binary from integration tests: the helpers of
//! `smartmesh_test_support::cli` with the binary Cargo builds for this package's tests.

use std::process::{Command, Output};

#[allow(unused_imports)] // each test file uses some of them
pub(crate) use smartmesh_test_support::cli::{
    bad, bundled, cpp_or_skip, fixture, ok, program, program_quiet, stderr, stdout, streams,
};

/// The binary under test.
pub(crate) const BIN: &str = env!("CARGO_BIN_EXE_smartmesh");

/// Runs `smartmesh ARGS`, with `RAYON_NUM_THREADS` set when `threads` is given.
#[allow(dead_code)]
pub(crate) fn smartmesh(args: &[&str], threads: Option<&str>) -> Output {
    smartmesh_test_support::cli::run(BIN, args, threads)
}

/// Runs `smartmesh ARGS` with the default thread count.
#[allow(dead_code)]
pub(crate) fn run(args: &[&str]) -> Output {
    smartmesh(args, None)
}

/// A `smartmesh` command to finish by hand (environment, stdin, spawn).
#[allow(dead_code)]
pub(crate) fn command(args: &[&str]) -> Command {
    smartmesh_test_support::cli::command(BIN, args)
}
