//! The solver formats (SU2, OpenFOAM cases) reached by extension from every command that
//! reads or writes a mesh: `info`, `size -o`, `adapt -o` and `batch` (`convert`, `mesh`,
//! `remesh` and `layer` have their own tests). Where a combination cannot make sense
//! (a metric in a mesh-only format, a case directory on stdout), exit 2 with the reason.
//! The case `adapt` writes is checked by OpenFOAM's `checkMesh` where it is on PATH.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::path::Path;
use std::process::Command;

use support::{bad, bundled, ok, program, run, stderr};

fn repo(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path).display().to_string()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn info_reads_su2_files_and_openfoam_cases_by_extension() {
    let d = tempfile::tempdir().unwrap();
    let su2 = d.path().join("cyl.su2");
    let case = d.path().join("cyl.foam");
    ok(&run(&["convert", &bundled("cylinder.msh"), s(&su2)]));
    ok(&run(&["convert", &bundled("cylinder.msh"), s(&case)]));
    for (path, name) in [(&su2, "Cylinder"), (&case, "Cylinder")] {
        let out = ok(&run(&["info", s(path)]));
        assert!(out.contains("1148"), "{}: {out}", path.display());
        assert!(out.contains(name), "{}: {out}", path.display());
    }
}

#[test]
fn size_refuses_a_solver_mesh_as_metric_output_with_the_reason() {
    let d = tempfile::tempdir().unwrap();
    for out in ["m.su2", "m.foam"] {
        let path = d.path().join(out);
        let err = bad(&run(&[
            "size",
            &bundled("cylinder.msh"),
            "--recipe",
            &repo("fixtures/cylinder.toml"),
            "-o",
            s(&path),
        ]));
        assert!(err.contains("cannot hold a metric") && err.contains(".sol"), "{out}: {err}");
        assert!(!path.exists(), "{out}: nothing written");
    }
}

#[test]
fn adapt_writes_its_best_mesh_as_su2() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("a.su2");
    let o = run(&[
        "adapt",
        &bundled("cylinder.msh"),
        "--recipe",
        &repo("fixtures/cylinder.toml"),
        "--max-iterations",
        "2",
        "-o",
        s(&out),
    ]);
    ok(&o);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("NDIME= 2") && text.contains("MARKER_TAG= Cylinder"), "{text:.300}");
    assert!(d.path().join("a.history.json").is_file());
    ok(&run(&["info", s(&out)]));
}

/// Runs `checkMesh -case DIR` (skipping, saying so, where it is absent) and asserts it
/// passes every check.
fn check_mesh(case: &Path) {
    let Some(check) = program("checkMesh") else { return };
    let mut c = Command::new(check);
    c.arg("-case").arg(case);
    if std::env::var_os("WM_PROJECT_DIR").is_none() {
        c.env("WM_PROJECT_DIR", "/usr/share/openfoam");
    }
    let out = c.output().expect("run checkMesh");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.contains("\nMesh OK.") && !text.contains("Failed "),
        "checkMesh on {}:\n{text}\n{}",
        case.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn adapt_writes_its_best_mesh_as_an_openfoam_case_with_the_case_options() {
    let d = tempfile::tempdir().unwrap();
    let case = d.path().join("a.foam");
    let o = run(&[
        "adapt",
        &bundled("cylinder.msh"),
        "--recipe",
        &repo("fixtures/cylinder.toml"),
        "--max-iterations",
        "2",
        "--extrude",
        "0.05",
        "--patch-type",
        "Walls=symmetry",
        "-o",
        s(&case),
    ]);
    ok(&o);
    let poly = case.join("constant/polyMesh");
    for f in ["points", "faces", "owner", "neighbour", "boundary"] {
        assert!(poly.join(f).is_file(), "{f}: {}", stderr(&o));
    }
    assert!(case.join("system/controlDict").is_file());
    let boundary = std::fs::read_to_string(poly.join("boundary")).unwrap();
    let walls = &boundary[boundary.find("Walls").unwrap()..];
    assert!(walls[..walls.find('}').unwrap()].contains("type            symmetry;"), "{boundary}");
    // The history names the case's files, as it names any mesh's.
    let history = std::fs::read_to_string(d.path().join("a.history.json")).unwrap();
    assert!(history.contains("\"points\""), "{history}");
    // Read back: the best iteration's mesh, one cell layer 0.05 thick.
    let info = ok(&run(&["info", s(&case)]));
    assert!(info.contains("Cylinder"), "{info}");
    let points = std::fs::read_to_string(poly.join("points")).unwrap();
    assert!(points.contains(" 0.05)"), "{points:.400}");
    check_mesh(&case);

    // A case cannot go to stdout: refused before any work.
    let err = bad(&run(&[
        "adapt",
        &bundled("cylinder.msh"),
        "--recipe",
        &repo("fixtures/cylinder.toml"),
        "-o",
        "-",
        "--to",
        "openfoam",
        "--history",
        s(&d.path().join("h.json")),
    ]));
    assert!(err.contains("directory"), "{err}");
    assert!(!d.path().join("h.json").exists());
    // Nor over a file.
    let file = d.path().join("file.foam");
    std::fs::write(&file, "x").unwrap();
    let err = bad(&run(&[
        "adapt",
        &bundled("cylinder.msh"),
        "--recipe",
        &repo("fixtures/cylinder.toml"),
        "-o",
        s(&file),
    ]));
    // Refused before any work: the remesher never ran.
    assert!(err.contains("name a directory such as case.foam"), "{err}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "x");
    assert!(!d.path().join("file.history.json").exists());
}

#[test]
fn batch_writes_su2_and_openfoam_outputs_named_in_the_manifest() {
    let d = tempfile::tempdir().unwrap();
    let lines = [
        format!(
            r#"{{"name":"cyl-su2","input":"{}","recipe":"{}","options":{{"format":"su2","max_iterations":1}}}}"#,
            bundled("cylinder.msh"),
            repo("fixtures/cylinder.toml")
        ),
        format!(
            r#"{{"name":"cyl-case","input":"{}","recipe":"{}","options":{{"format":"foam","max_iterations":1,"extrude":0.05,"patch_type":["Walls=symmetry"]}}}}"#,
            bundled("cylinder.msh"),
            repo("fixtures/cylinder.toml")
        ),
    ];
    let m = d.path().join("variants.jsonl");
    std::fs::write(&m, lines.join("\n") + "\n").unwrap();
    let out = d.path().join("out");
    ok(&run(&["batch", s(&m), "-o", s(&out), "--jobs", "1"]));
    let su2 = std::fs::read_to_string(out.join("cyl-su2.su2")).unwrap();
    assert!(su2.contains("MARKER_TAG= Cylinder"));
    let boundary =
        std::fs::read_to_string(out.join("cyl-case.foam/constant/polyMesh/boundary")).unwrap();
    assert!(boundary.contains("type            symmetry;"), "{boundary}");
    let results = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    assert_eq!(results.lines().count(), 2, "{results}");
    // Run again with --resume: both are recorded, nothing reruns.
    ok(&run(&["batch", s(&m), "-o", s(&out), "--resume"]));
}
