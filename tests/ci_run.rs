//! What `.ci/run` promises: its closing line counts passed, failed and skipped tests
//! honestly (`.ci/count-tests`), and it installs the Python packages from the one file
//! README.md tells a fresh machine to install.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn count(log: &str) -> String {
    let mut child = Command::new("bash")
        .arg(root().join(".ci/count-tests"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(log.as_bytes()).unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success());
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn the_closing_line_counts_each_skipped_test_once_and_not_as_passed() {
    let log = "\
     Running tests/cli.rs (target/debug/deps/cli-0123abcd)
skipped: lossy (cli): the public sample meshes are not at /x (set SMARTMESH_PUBLIC_FIXTURES)
test lossy ... ok
test result: ok. 12 passed; 0 failed; 1 ignored; 0 measured; 0 filtered out; finished in 2.54s
skipped: mod::a (gmsh): `gmsh` is not on PATH
skipped: mod::a (gmsh): `meshio` is not on PATH
skipped: lossy (other): no: colons: here
test result: FAILED. 30 passed; 2 failed; 0 ignored; 0 measured; 0 filtered out; finished in 5.13s
   Doc-tests smartmesh
test result: ok. 0 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; finished in 0.00s
";
    assert_eq!(count(log), "39 passed, 2 failed, 3 skipped\n");
    assert_eq!(count("error: could not compile\n"), "0 passed, 0 failed, 0 skipped\n");
}

#[test]
fn ci_and_the_readme_install_the_same_requirements() {
    let run = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let line = "python3 -m pip install -r requirements-interop.txt";
    assert!(readme.contains(line), "README.md must say `{line}`");
    assert!(run.contains("-r requirements-interop.txt"), ".ci/run must install that file");
    let reqs = std::fs::read_to_string(root().join("requirements-interop.txt")).unwrap();
    for module in ["gmsh", "vtk", "mmgpy", "meshio", "triangle", "scikit-fem", "hyperqueue"] {
        assert!(
            reqs.lines().any(|l| l.trim_start().starts_with(module)),
            "requirements-interop.txt lacks {module}"
        );
    }
    assert!(run.contains("--no-fail-fast") && run.contains(".ci/count-tests"));
}

/// Runs `.ci/import-graph` with `args`; None (the test skips) where Python is missing.
fn import_graph(args: &[&str]) -> Option<(bool, String)> {
    let out = Command::new("python3").arg(root().join(".ci/import-graph")).args(args).output();
    match out {
        Ok(o) => Some((o.status.success(), String::from_utf8(o.stdout).unwrap())),
        Err(e) => {
            smartmesh_test_support::skip::missing_tool(&format!("python3: {e}"));
            None
        }
    }
}

/// A made-up crate whose counts are known: `a.rs` and `b/mod.rs` import each other (one
/// import must run back up, and the cycle crosses folders), `c.rs` is named only in a
/// comment, a doc comment, a string and a test module, which are no imports.
#[test]
fn the_import_graph_counts_a_made_up_crate_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir_all(src.join("b")).unwrap();
    let files = [
        ("lib.rs", "//! Uses crate::c::C in its doc only.\nmod a;\nmod b;\nmod c;\n"),
        (
            "a.rs",
            "use crate::b::B;\n/// Not crate::c::C.\npub struct A(B);\n\
             fn f() -> &'static str { \"crate::c::C\" }\n\
             #[cfg(test)]\nmod tests {\n    use crate::c::C;\n}\n",
        ),
        ("b/mod.rs", "pub struct B;\npub fn g(_: crate::a::A) {}\n"),
        ("c.rs", "pub struct C; // crate::a::A\n"),
    ];
    for (name, text) in files {
        std::fs::write(src.join(name), text).unwrap();
    }
    let root = dir.path().to_str().unwrap();
    let Some((ok, out)) = import_graph(&["--root", root]) else { return };
    assert!(ok, "{out}");
    assert!(
        out.ends_with(
            "4 files in 3 modules, 2 imports, 1 running back up between modules, \
             1 cycles of files (1 across folders)\n"
        ),
        "{out}"
    );
    assert!(out.contains("cycle (ACROSS FOLDERS): src/a.rs, src/b/mod.rs"), "{out}");
    let Some((ok, _)) = import_graph(&["--root", root, "--max-up", "3"]) else { return };
    assert!(!ok, "a cycle across folders fails the check");
    let Some((_, modules)) = import_graph(&["--root", root, "--modules"]) else { return };
    assert_eq!(modules, "a: b\nb: a\nc:\n");
}

/// The rule ARCHITECTURE.md states: at most 3 imports run back up between the modules,
/// and no cycle of files crosses folders.
#[test]
fn the_house_keeps_its_imports_pointing_down() {
    let Some((ok, out)) = import_graph(&["--max-up", "3"]) else { return };
    assert!(ok, "{out}");
}
