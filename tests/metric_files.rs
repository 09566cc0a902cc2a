//! A metric given as a file of its own, wherever a metric is read (`remesh --metric`,
//! `info --metric`, `report --metric`, `remesh --measure --background`): a `.vtu`, a
//! `.msh` with its `$NodeData`, a Medit `.sol`/`.solb` alone (as `mmg2d_O3 MESH -sol X.sol`
//! takes it) and a Gmsh `.pos` view (as `gmsh -bgm` takes it) all give the same field,
//! so `size -o X.sol` then `remesh --metric X.sol` gives the bytes `--metric X.vtu` gives;
//! a file for another mesh is refused with exit 2, naming both files and both counts.
//! Gmsh's data-only `.msh` (views without a mesh, written here by the gmsh Python API)
//! is a metric too, on the vertices of the mesh it goes with.

use smartmesh_test_support::formats as common;

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

#[path = "support/cli.rs"]
mod cli;

use cli::{bad, bundled, ok, smartmesh};

/// Every kind of metric file, as `size -o` writes it.
const KINDS: [&str; 5] = ["vtu", "msh", "sol", "solb", "pos"];

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The cylinder's recipe field written as `dir/field.EXT`.
fn field(dir: &Path, ext: &str) -> PathBuf {
    let f = dir.join(format!("field.{ext}"));
    ok(&smartmesh(
        &["size", &bundled("cylinder.msh"), "--recipe", &bundled("cylinder.toml"), "-o", s(&f)],
        None,
    ));
    f
}

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&ok(&smartmesh(args, None))).unwrap()
}

#[test]
fn remesh_gives_the_same_bytes_from_every_kind_of_metric_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut outputs = Vec::new();
    for ext in KINDS {
        let f = field(dir.path(), ext);
        let out = dir.path().join(format!("out_{ext}.mesh"));
        ok(&smartmesh(
            &["remesh", &bundled("cylinder.msh"), "--metric", s(&f), "-o", s(&out)],
            None,
        ));
        let bytes =
            (std::fs::read(&out).unwrap(), std::fs::read(out.with_extension("sol")).unwrap());
        outputs.push((ext, bytes));
    }
    for (ext, bytes) in &outputs[1..] {
        assert!(*bytes == outputs[0].1, "--metric field.{ext} remeshes otherwise than field.vtu");
    }
}

#[test]
fn info_and_report_measure_the_same_from_every_kind_of_metric_file() {
    let dir = tempfile::tempdir().unwrap();
    let cyl = bundled("cylinder.msh");
    let mut seen: Vec<(&str, Value, Value)> = Vec::new();
    for ext in KINDS {
        let f = field(dir.path(), ext);
        let info = json(&["info", "--json", &cyl, "--metric", s(&f)]);
        assert!(info["metric"]["source"].as_str().unwrap().contains(s(&f)), "{info}");
        let svg = dir.path().join(format!("r_{ext}.svg"));
        let report = json(&["report", &cyl, "--metric", s(&f), "-o", s(&svg), "--json"]);
        assert!(svg.exists());
        seen.push((
            ext,
            info["metric"]["conformity"].clone(),
            report["report"]["conformity"].clone(),
        ));
    }
    assert!(seen[0].1.is_object() && seen[0].2.is_object(), "{:?}", seen[0]);
    for (ext, info, report) in &seen[1..] {
        assert_eq!(*info, seen[0].1, "info --metric field.{ext}");
        assert_eq!(*report, seen[0].2, "report --metric field.{ext}");
    }
}

#[test]
fn measure_background_takes_a_view_and_a_solution_beside_its_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let vtu = field(d, "vtu");
    let out = d.join("out.vtu");
    ok(&smartmesh(&["remesh", &bundled("cylinder.msh"), "--metric", s(&vtu), "-o", s(&out)], None));
    let measure = |background: &Path| {
        json(&["remesh", s(&out), "--measure", "--background", s(background), "--json"])
    };
    let want = measure(&vtu);
    // The same mesh and field as a .msh: the same triangles, the same numbers.
    assert_eq!(measure(&field(d, "msh")), want, "--background field.msh");
    // A `.sol` beside the `.mesh` it belongs to, and a `.solb` beside its `.meshb`.
    for (mesh, sol) in [("g.mesh", "g.sol"), ("h.meshb", "h.solb")] {
        ok(&smartmesh(
            &[
                "size",
                &bundled("cylinder.msh"),
                "--recipe",
                &bundled("cylinder.toml"),
                "-o",
                s(&d.join(mesh)),
            ],
            None,
        ));
        assert_eq!(measure(&d.join(sol)), want, "--background {sol}");
    }
    // A view: its records are the background triangles, located the same way.
    let pos = field(d, "pos");
    let got = measure(&pos);
    for k in
        ["edges", "triangles", "conforming_share", "edge_length_histogram", "quality_histogram"]
    {
        assert_eq!(got[k], want[k], "--background field.pos: {k}");
    }
    for k in ["mean_edge_length", "mean_quality", "min_quality"] {
        let (a, b) = (got[k].as_f64().unwrap(), want[k].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * b.abs(), "--background field.pos: {k} {a} vs {b}");
    }
    // A solution alone holds no positions: said, exit 2.
    let alone = field(d, "sol");
    let err = bad(&smartmesh(&["remesh", s(&out), "--measure", "--background", s(&alone)], None));
    assert!(err.contains("field.sol") && err.contains("field.mesh"), "{err}");
}

#[test]
fn a_solution_for_another_mesh_is_refused_by_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The remeshed cylinder has other vertices than the field's 1148.
    let vtu = field(d, "vtu");
    let other = d.join("other.vtu");
    ok(&smartmesh(
        &["remesh", &bundled("cylinder.msh"), "--metric", s(&vtu), "-o", s(&other)],
        None,
    ));
    let n = smartmesh::formats::read_path(&other, None).unwrap().points.len();
    assert_ne!(n, 1148);
    for ext in ["sol", "solb"] {
        let f = field(d, ext);
        let x = d.join("x.vtu");
        let svg = d.join("x.svg");
        let runs: [Vec<&str>; 3] = [
            vec!["remesh", s(&other), "--metric", s(&f), "-o", s(&x)],
            vec!["info", s(&other), "--metric", s(&f)],
            vec!["report", s(&other), "--metric", s(&f), "-o", s(&svg)],
        ];
        for args in runs {
            let err = bad(&smartmesh(&args, None));
            for want in [s(&f), s(&other), "1148 items", &format!("{n} vertices")] {
                assert!(err.contains(want), "{args:?}: `{err}` lacks `{want}`");
            }
            assert!(!x.exists() && !svg.exists());
        }
    }
    // A mesh file of the same count whose vertices moved: every command checks the
    // positions (`remesh` alone did before the readers were one).
    let mut moved = smartmesh::formats::read_path(&vtu, None).unwrap();
    moved.points[3][0] += 0.25;
    let moved_path = d.join("moved.vtu");
    smartmesh::formats::write_path(&moved_path, &moved, None, &Default::default()).unwrap();
    let cyl = bundled("cylinder.msh");
    let svg = d.join("m.svg");
    for args in [
        vec!["info", cyl.as_str(), "--metric", s(&moved_path)],
        vec!["report", cyl.as_str(), "--metric", s(&moved_path), "-o", s(&svg)],
    ] {
        let err = bad(&smartmesh(&args, None));
        assert!(err.contains("moved.vtu") && err.contains("vertex 3"), "{args:?}: {err}");
    }
    // A view with no tensor record, and a solution with no metric, are no metric.
    let scalar = d.join("s.pos");
    std::fs::write(&scalar, "View \"h\" {\nST(0,0,0,1,0,0,0,1,0){1,1,1};\n};\n").unwrap();
    let err = bad(&smartmesh(&["info", &bundled("cylinder.msh"), "--metric", s(&scalar)], None));
    assert!(err.contains("s.pos:1") && err.contains("TT, TQ"), "{err}");
    let sizes = d.join("s.sol");
    std::fs::write(&sizes, "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n1148\n1 1\n")
        .unwrap();
    std::fs::OpenOptions::new()
        .append(true)
        .open(&sizes)
        .and_then(|mut f| std::io::Write::write_all(&mut f, "0.1\n".repeat(1148).as_bytes()))
        .unwrap();
    let err = bad(&smartmesh(
        &["remesh", &bundled("cylinder.msh"), "--metric", s(&sizes), "-o", s(&d.join("y.vtu"))],
        None,
    ));
    assert!(err.contains("s.sol") && err.contains("no point data `metric`"), "{err}");
}

/// `gmsh.view.write` of the last view of `src` with `PostProcessing.SaveMesh = 0`: the
/// views alone, no `$Nodes` nor `$Elements` (binary when `binary`).
const DATA_ONLY: &str = r#"
import sys, gmsh
src, out, binary = sys.argv[1], sys.argv[2], int(sys.argv[3])
gmsh.initialize(["-v", "0"])
gmsh.merge(src)
view = gmsh.view.getTags()[-1]
gmsh.option.setNumber("PostProcessing.SaveMesh", 0)
gmsh.option.setNumber("Mesh.Binary", binary)
gmsh.view.write(view, out)
gmsh.finalize()
"#;

#[test]
fn a_gmsh_data_only_file_is_a_metric_wherever_one_is_read() {
    let Some(py) = common::python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let msh = field(d, "msh");
    let data_only = |name: &str, binary: bool| {
        let out = d.join(name);
        let o = Command::new(&py)
            .args(["-c", DATA_ONLY, s(&msh), s(&out), if binary { "1" } else { "0" }])
            .output()
            .unwrap();
        assert!(o.status.success(), "gmsh: {}", String::from_utf8_lossy(&o.stderr));
        let bytes = std::fs::read(&out).unwrap();
        let has = |section: &[u8]| bytes.windows(section.len()).any(|w| w == section);
        assert!(has(b"$NodeData") && !has(b"$Nodes\n") && !has(b"$Elements"), "{name}");
        out
    };
    let (binary, ascii) = (data_only("b.msh", true), data_only("a.msh", false));
    let cyl = bundled("cylinder.msh");

    // remesh --metric: the binary view carries the exact tensors, so the bytes of
    // `--metric field.msh`; the ASCII one (16 digits) is accepted.
    let remesh = |metric: &Path, out: &str| {
        let out = d.join(out);
        ok(&smartmesh(&["remesh", &cyl, "--metric", s(metric), "-o", s(&out)], None));
        std::fs::read(out).unwrap()
    };
    assert!(remesh(&binary, "b.vtu") == remesh(&msh, "m.vtu"), "--metric b.msh");
    remesh(&ascii, "a.vtu");

    // info, report and --measure --background measure what the mesh file's view gives.
    for (args, key) in [
        (vec!["info", "--json", cyl.as_str(), "--metric"], "metric"),
        (vec!["report", cyl.as_str(), "--json", "-o", s(&d.join("r.svg")), "--metric"], "report"),
    ] {
        let with = |m: &Path| {
            let mut a = args.clone();
            a.push(s(m));
            json(&a)[key]["conformity"].clone()
        };
        let want = with(&msh);
        assert!(want.is_object(), "{args:?}: {want}");
        assert_eq!(with(&binary), want, "{args:?} b.msh");
    }
    let measure =
        |args: &[&str]| json(&[&["remesh", cyl.as_str(), "--measure", "--json"], args].concat());
    assert_eq!(measure(&["--background", s(&binary)]), measure(&["--metric", s(&msh)]));

    // Another mesh's vertex count: exit 2 naming both files and both counts, nothing
    // written.
    let other = d.join("other.vtu");
    ok(&smartmesh(&["remesh", &cyl, "--metric", s(&msh), "-o", s(&other)], None));
    let n = smartmesh::formats::read_path(&other, None).unwrap().points.len();
    assert_ne!(n, 1148);
    let (x, svg) = (d.join("x.vtu"), d.join("x.svg"));
    for args in [
        vec!["remesh", s(&other), "--metric", s(&binary), "-o", s(&x)],
        vec!["info", s(&other), "--metric", s(&binary)],
        vec!["report", s(&other), "--metric", s(&binary), "-o", s(&svg)],
        vec!["remesh", s(&other), "--measure", "--background", s(&binary)],
    ] {
        let err = bad(&smartmesh(&args, None));
        for want in [s(&binary), s(&other), "1148 items", &format!("{n} vertices")] {
            assert!(err.contains(want), "{args:?}: `{err}` lacks `{want}`");
        }
        assert!(!x.exists() && !svg.exists());
    }
    // As a mesh, a data-only file is refused, saying what it is.
    let err = bad(&smartmesh(&["convert", s(&ascii), s(&d.join("c.vtu"))], None));
    assert!(err.contains("a.msh") && err.contains("data-only"), "{err}");
}
