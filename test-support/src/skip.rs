//! Skipping a test that needs something this machine lacks (an interop program, a Python
//! module, the public sample meshes, a font), so that it says so whatever the capture.
//!
//! libtest captures what `print!`/`eprint!` write and shows it only for failed tests or
//! under `--nocapture`, so a test that returns early would show as `ok` with no trace of
//! the skip. [`skip`] writes straight to the process's standard error through the
//! `std::io::stderr()` handle, which the capture does not touch: the line shows in every
//! run. Each line names the test (libtest runs each test on a thread named after it) and
//! its binary, so that `.ci/run` counts each skipped test once however many lines it
//! writes.

use std::io::Write;

/// The prefix of every skip line; `.ci/run` counts the lines that start with it.
pub const PREFIX: &str = "skipped: ";

/// The line [`skip`] writes for `reason` in the test `test` of the binary `binary`.
pub fn line(test: &str, binary: &str, reason: &str) -> String {
    format!("{PREFIX}{test} ({binary}): {reason}\n")
}

/// The test binary's name without Cargo's hash (`cli` for `cli-0123abcd`).
fn binary() -> String {
    let exe = std::env::args_os().next().unwrap_or_default();
    let stem = std::path::Path::new(&exe).file_stem().unwrap_or_default().to_string_lossy();
    without_hash(&stem).to_string()
}

/// `stem` without the `-HASH` Cargo appends to a test binary's name.
fn without_hash(stem: &str) -> &str {
    match stem.rsplit_once('-') {
        Some((name, hash)) if !hash.is_empty() && hash.chars().all(|c| c.is_ascii_hexdigit()) => {
            name
        }
        _ => stem,
    }
}

/// Says on the process's standard error, bypassing libtest's capture, that the current
/// test skips and why. The caller then returns from the test.
pub fn skip(reason: &str) {
    let thread = std::thread::current();
    let test = thread.name().unwrap_or("?");
    // One write of one line: lines of tests running in parallel do not interleave.
    let _ = std::io::stderr().lock().write_all(line(test, &binary(), reason).as_bytes());
}

/// Whether the interop tools must be there (CI sets `SMARTMESH_REQUIRE_INTEROP=1`).
pub fn interop_required() -> bool {
    std::env::var("SMARTMESH_REQUIRE_INTEROP").as_deref() == Ok("1")
}

/// A missing interop tool: fails the test when interop is required (CI), else says that
/// the test skips ([`skip`]).
pub fn missing_tool(what: &str) {
    if interop_required() {
        panic!("{what} (needed: SMARTMESH_REQUIRE_INTEROP=1)");
    }
    skip(what);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_names_the_test_its_binary_and_the_reason() {
        assert_eq!(line("a::b", "cli", "no gmsh"), "skipped: a::b (cli): no gmsh\n");
    }

    #[test]
    fn the_binary_name_loses_only_cargo_s_hash() {
        assert_eq!(without_hash("cli-0123abcdef"), "cli");
        assert_eq!(without_hash("batch_engines-0123abcdef"), "batch_engines");
        assert_eq!(without_hash("smartmesh-test-support"), "smartmesh-test-support");
        assert_eq!(without_hash("cli"), "cli");
    }

    /// The skip line shows in a plain run, without `--nocapture`: the test runs itself
    /// as a child, where [`child_that_skips`] skips, and reads the child's stderr.
    #[test]
    fn a_skip_shows_without_nocapture() {
        let o = std::process::Command::new(std::env::current_exe().unwrap())
            .args(["--exact", "skip::tests::child_that_skips", "--test-threads", "1"])
            .env("SMARTMESH_SKIP_CHILD", "1")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        assert!(
            err.contains("skipped: skip::tests::child_that_skips (smartmesh_test_support): the child's reason"),
            "stderr of the child: {err}\nstdout: {}",
            String::from_utf8_lossy(&o.stdout)
        );
    }

    /// Skips when run as the child of [`a_skip_shows_without_nocapture`], else does nothing.
    #[test]
    fn child_that_skips() {
        if std::env::var_os("SMARTMESH_SKIP_CHILD").is_some() {
            skip("the child's reason");
        }
    }
}
