//! Every command that computes in the plane refuses a mesh that does not lie in one plane
//! z = const (exit 2, saying so, nothing written) instead of flattening it onto z = 0,
//! while `size`, `adapt` and `recipe check` take it as a surface in space (a 3D field,
//! the loop through `mmgs_O3`: `tests/size3d_cli.rs`, `tests/adapt_space_cli.rs`); a
//! mesh in a plane z = c comes back in that plane; `info` describes a surface in space
//! with its lengths and areas measured in space and says that it is not planar.

use std::path::{Path, PathBuf};

use smartmesh::formats::{read_path, write_path, CellKind, TaggedMesh, WriteOptions};
use smartmesh_test_support::grid::unit_square;

#[path = "support/cli.rs"]
mod cli;
use cli::{bad, ok, run, stderr};

/// A uniform size on the unit square's face (tag 1).
const RECIPE: &str = "[global]\nhmin = 0.01\nhmax = 0.5\n[regions]\nAll = [1]\n\
    [[algorithms]]\ntype = \"uniform\"\nsize = 0.2\nregions = [\"All\"]\n";

fn write(dir: &Path, name: &str, mesh: &TaggedMesh) -> String {
    let p = dir.join(name);
    write_path(&p, mesh, None, &WriteOptions::default()).unwrap();
    p.display().to_string()
}

fn recipe(dir: &Path) -> String {
    let p = dir.join("recipe.toml");
    std::fs::write(&p, RECIPE).unwrap();
    p.display().to_string()
}

/// The unit square, 4 cells a side, with each point moved by `f`.
fn square_moved(f: impl Fn([f64; 3]) -> [f64; 3]) -> TaggedMesh {
    let mut m = unit_square(4);
    for p in &mut m.points {
        *p = f(*p);
    }
    m
}

/// Each 2D command on `input`, writing `OUT` under `dir`.
fn commands(dir: &Path, input: &str, recipe: &str) -> Vec<(&'static str, Vec<String>, PathBuf)> {
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let out = |name: &str| dir.join(name);
    let o = |name: &str| out(name).display().to_string();
    vec![
        ("size", s(&["size", input, "--recipe", recipe, "-o", &o("f.vtu")]), out("f.vtu")),
        ("remesh", s(&["remesh", input, "-o", &o("r.msh")]), out("r.msh")),
        ("adapt", s(&["adapt", input, "--recipe", recipe, "-o", &o("a.msh")]), out("a.msh")),
        (
            "layer",
            s(&[
                "layer",
                input,
                "--curves",
                "11",
                "--first-height",
                "0.01",
                "--ratio",
                "1.2",
                "--layers",
                "3",
                "-o",
                &o("l.msh"),
            ]),
            out("l.msh"),
        ),
        ("report", s(&["report", input, "-o", &o("p.svg")]), out("p.svg")),
        ("recipe check", s(&["recipe", "check", recipe, input]), out("none")),
        ("mesh", s(&["mesh", input, "-o", &o("m.msh")]), out("m.msh")),
    ]
}

#[test]
fn every_2d_command_refuses_a_surface_in_space() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let recipe = recipe(d);
    // A square in the xz-plane (its shadow on z = 0 has no area) and a tilted one.
    let xz = write(d, "xz.msh", &square_moved(|p| [p[0], 0.0, p[1]]));
    let tilted = write(d, "tilted.msh", &square_moved(|p| [p[0], p[1], 0.5 * p[0]]));
    for input in [&xz, &tilted] {
        for (what, args, out) in commands(d, input, &recipe) {
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            if matches!(what, "size" | "adapt" | "recipe check") {
                continue; // A surface in space: sized and adapted in space.
            }
            let e = bad(&run(&args));
            assert!(e.contains("not planar") && e.contains(input.as_str()), "{what} {input}: {e}");
            assert!(e.contains("z = const"), "{what}: {e}");
            assert!(!out.exists(), "{what} wrote {}", out.display());
        }
        // `size` gives the tilted or upright square a field in space: 3×3 tensors.
        let field = d.join("space.vtu");
        ok(&run(&["size", input, "--recipe", &recipe, "-o", field.to_str().unwrap()]));
        let m = read_path(&field, None).unwrap();
        assert_eq!(m.point_data["metric"].components, 9, "{input}");
    }
}

fn all_z(path: &Path) -> Vec<f64> {
    let m = read_path(path, None).unwrap();
    let mut z: Vec<f64> = m.points.iter().map(|p| p[2]).collect();
    z.dedup();
    z
}

#[test]
fn a_square_at_z_5_comes_back_at_z_5() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let recipe = recipe(d);
    let at5 = square_moved(|p| [p[0], p[1], 5.0]);
    let input = write(d, "at5.msh", &at5);
    let mut lines_only = at5.clone();
    lines_only.blocks.retain(|b| b.kind == CellKind::Line);
    let outline = write(d, "outline.msh", &lines_only);
    for (what, args, out) in commands(d, &input, &recipe) {
        if what == "remesh" || what == "report" || what == "recipe check" || what == "mesh" {
            continue;
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        ok(&run(&args));
        assert_eq!(all_z(&out), vec![5.0], "{what}");
    }
    // The field written by `size` is on the square at z = 5: remeshed to it, in place.
    let field = d.join("f.vtu");
    let r = d.join("r.msh");
    ok(&run(&["remesh", field.to_str().unwrap(), "-o", r.to_str().unwrap()]));
    assert_eq!(all_z(&r), vec![5.0], "remesh");
    let m = d.join("m.msh");
    ok(&run(&["mesh", &outline, "-o", m.to_str().unwrap()]));
    assert_eq!(all_z(&m), vec![5.0], "mesh");
    assert!(read_path(&m, None).unwrap().num_cells_of(CellKind::Triangle) > 0);
    ok(&run(&["recipe", "check", &recipe, &input]));
    let svg = d.join("p.svg");
    ok(&run(&["report", &input, "-o", svg.to_str().unwrap()]));
}

#[test]
fn info_measures_a_surface_in_space_in_space() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let xz = write(d, "xz.msh", &square_moved(|p| [p[0], 0.0, p[1]]));
    let o = run(&["info", "--json", &xz]);
    let text = ok(&o);
    assert!(stderr(&o).contains("not planar"), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(j["planar"], false);
    let area: f64 = j["topology"]["faces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["area"].as_f64().unwrap())
        .sum();
    assert!((area - 1.0).abs() < 1e-12, "area {area} (its shadow on z = 0 has none)");
    let length: f64 = j["topology"]["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["length"].as_f64().unwrap())
        .sum();
    assert!((length - 4.0).abs() < 1e-12, "perimeter {length}");

    let flat = write(d, "flat.msh", &unit_square(4));
    let o = run(&["info", "--json", &flat]);
    let j: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    assert_eq!(j["planar"], true);
    assert!(!stderr(&o).contains("not planar"));
}
