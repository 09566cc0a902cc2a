//! `smartmesh size` end to end on the bundled cylinder and its recipe, and the field it
//! writes used by the real tools: `mmg2d_O3` adapts the mesh to our `.sol`, `gmsh -bgm`
//! meshes the geometry with our `.pos` (BAMG), VTK reads our arrays; in both adapted
//! meshes the refinement is where the recipe asks for it (boundary layer on the
//! cylinder, wake behind it, coarse far away). Interop parts skip when the tools are
//! missing, unless `SMARTMESH_REQUIRE_INTEROP=1` (CI).
#![allow(clippy::print_stdout, clippy::print_stderr)] // What a test measured or skipped is printed for the log.

use smartmesh_test_support::formats as common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::python_with;
use smartmesh::formats::{read_path, CellKind, TaggedMesh};

#[path = "support/cli.rs"]
mod cli;

use cli::{bundled, ok, smartmesh};

fn size_to(out: &Path) -> String {
    ok(&smartmesh(
        &[
            "size",
            &bundled("cylinder.msh"),
            "--recipe",
            &bundled("cylinder.toml"),
            "-o",
            out.to_str().unwrap(),
            "--json",
        ],
        None,
    ))
}

/// Mean edge length of the triangles whose centroid satisfies `inside`, and their count.
fn mean_edge(mesh: &TaggedMesh, inside: impl Fn(f64, f64) -> bool) -> (f64, usize) {
    let (mut sum, mut n) = (0.0, 0usize);
    for (kind, nodes, _, _) in mesh.cells() {
        if kind != CellKind::Triangle {
            continue;
        }
        let p: Vec<[f64; 3]> = nodes.iter().map(|&v| mesh.points[v as usize]).collect();
        let (cx, cy) = ((p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0);
        if inside(cx, cy) {
            n += 1;
            for k in 0..3 {
                sum += ((p[k][0] - p[(k + 1) % 3][0]).powi(2)
                    + (p[k][1] - p[(k + 1) % 3][1]).powi(2))
                .sqrt();
            }
        }
    }
    (sum / (3 * n.max(1)) as f64, n)
}

/// The recipe's intent, checked on an adapted mesh: small elements along the cylinder
/// wall (within 0.03 of the circle), mid-size ones along the wake centre line, coarse far
/// from both (the top and bottom of the channel, away from the cylinder).
fn assert_recipe_followed(what: &str, mesh: &TaggedMesh) {
    let wall = mean_edge(mesh, |x, y| {
        (((x - 1.0).powi(2) + (y - 0.5).powi(2)).sqrt() - 0.15).abs() < 0.03
    });
    let wake = mean_edge(mesh, |x, y| x > 1.6 && x < 2.6 && (y - 0.5).abs() < 0.02);
    let far = mean_edge(mesh, |x, y| x > 2.0 && (y - 0.5).abs() > 0.4);
    eprintln!(
        "{what}: mean edge at the wall {:.4} ({}), wake {:.4} ({}), far {:.4} ({})",
        wall.0, wall.1, wake.0, wake.1, far.0, far.1
    );
    assert!(wall.1 > 0 && wake.1 > 0 && far.1 > 0, "{what}: empty zone");
    assert!(wall.0 < 0.5 * far.0, "{what}: wall {} not finer than far field {}", wall.0, far.0);
    assert!(wake.0 < 0.7 * far.0, "{what}: wake {} not finer than far field {}", wake.0, far.0);
}

#[test]
fn size_writes_every_target_and_a_json_summary() {
    let dir = tempfile::tempdir().unwrap();
    let vtu = dir.path().join("field.vtu");
    let json: serde_json::Value = serde_json::from_str(&size_to(&vtu)).unwrap();
    assert_eq!(json["steps"].as_array().unwrap().len(), 4, "{json}");
    assert!(json["smallest_size"].as_f64().unwrap() >= 0.002);
    assert!(json["largest_size"].as_f64().unwrap() <= 0.15);
    assert!(json["largest_anisotropy"].as_f64().unwrap() <= 40.0 * (1.0 + 1e-9));
    let mesh = read_path(&vtu, None).unwrap();
    for name in ["metric", "size_tensor", "h1", "h2", "anisotropy", "axis1", "axis2"] {
        assert!(mesh.point_data.contains_key(name), "{name} missing from the .vtu");
    }
    for ext in ["sol", "solb", "mesh", "meshb", "msh", "pos", "vtk"] {
        let out = dir.path().join(format!("field.{ext}"));
        size_to(&out);
        assert!(out.exists(), "{ext}");
    }
    assert!(dir.path().join("field.solb").exists());
}

#[test]
fn same_bytes_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let mut outputs = Vec::new();
    for t in ["1", "2", "3"] {
        let out: PathBuf = dir.path().join(format!("field-{t}.sol"));
        ok(&smartmesh(
            &[
                "size",
                &bundled("cylinder.msh"),
                "--recipe",
                &bundled("cylinder.toml"),
                "-o",
                out.to_str().unwrap(),
            ],
            Some(t),
        ));
        outputs.push(std::fs::read(&out).unwrap());
    }
    assert!(outputs.windows(2).all(|w| w[0] == w[1]));
}

#[test]
fn bad_targets_and_recipes_exit_two_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("x.obj");
    let o = smartmesh(
        &[
            "size",
            &bundled("cylinder.msh"),
            "--recipe",
            &bundled("cylinder.toml"),
            "-o",
            obj.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot hold a metric"));
    assert!(!obj.exists());

    let recipe = dir.path().join("bad.toml");
    let text = std::fs::read_to_string(bundled("cylinder.toml"))
        .unwrap()
        .replace("Cylinder = [\"Cylinder\"]", "Cylinder = [\"Cylindre\"]");
    std::fs::write(&recipe, text).unwrap();
    let sol = dir.path().join("x.sol");
    let o = smartmesh(
        &[
            "size",
            &bundled("cylinder.msh"),
            "--recipe",
            recipe.to_str().unwrap(),
            "-o",
            sol.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("Cylindre"), "{err}");
    assert!(!sol.exists());
}

#[test]
fn mmg2d_adapts_the_cylinder_to_our_field() {
    let Some(py) = python_with(&["mmgpy"]) else { return };
    let exe = common::mmg2d(&py);
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("cyl.mesh");
    size_to(&mesh);
    let out = dir.path().join("adapted.mesh");
    let o = Command::new(&exe)
        .arg("-in")
        .arg(&mesh)
        .arg("-sol")
        .arg(mesh.with_extension("sol"))
        .arg("-out")
        .arg(&out)
        .args(["-v", "1"])
        .output()
        .expect("run mmg2d_O3");
    assert!(
        o.status.success(),
        "mmg2d_O3: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let adapted = read_path(&out, None).unwrap();
    assert_recipe_followed("mmg2d_O3", &adapted);
    // The curve references survive: Inlet 1, Outlet 2, Walls 3, Cylinder 4.
    for tag in 1..=4 {
        assert!(adapted.cells().any(|c| c.0 == CellKind::Line && c.2 == tag), "curve {tag} lost");
    }
}

#[test]
fn gmsh_meshes_the_cylinder_with_our_pos_as_background() {
    if python_with(&["gmsh"]).is_none() || cli::program("gmsh").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let pos = dir.path().join("bgm.pos");
    size_to(&pos);
    let geo = bundled("cylinder.geo");
    let out = dir.path().join("bamg.msh");
    let o = Command::new("gmsh")
        .arg(&geo)
        .args([
            "-2",
            "-v",
            "2",
            "-setnumber",
            "Mesh.Algorithm",
            "7",
            "-setnumber",
            "Mesh.MeshSizeExtendFromBoundary",
            "0",
        ])
        .args(["-setnumber", "Mesh.MeshSizeFromPoints", "0", "-bgm"])
        .arg(&pos)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("run gmsh");
    assert!(
        o.status.success(),
        "gmsh: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert_recipe_followed("gmsh -bgm (BAMG)", &read_path(&out, None).unwrap());
}

#[test]
fn appendix_a_recipe_runs_on_the_distributor() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("distributor.sol");
    let o = smartmesh(
        &[
            "size",
            &bundled("distributor.msh"),
            "--recipe",
            &bundled("appendix-a.cfg"),
            "-o",
            out.to_str().unwrap(),
            "--json",
        ],
        None,
    );
    let json: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    let steps: Vec<&str> = json["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["algorithm"].as_str().unwrap())
        .collect();
    assert_eq!(
        steps,
        [
            "UNIFORM",
            "DISTANCE_TO_POINT",
            "DISTANCE_TO_BORDER",
            "DISTANCE_TO_BORDER",
            "DISTANCE_TO_IMAGINARY_POLYLINE"
        ]
    );
    // Every step reaches something; the recipe gives no HMAX, so unreached vertices would
    // get the bounding-box diagonal, with a warning — but UNIFORM on the fluid reaches all.
    assert!(
        json["steps"]
            .as_array()
            .unwrap()
            .iter()
            .all(|s| s["vertices_reached"].as_u64().unwrap() > 0),
        "{json}"
    );
    assert_eq!(json["vertices_reached"], json["vertices"]);
    // The smallest size is the corner function's MINSIZE (0.02), the largest UNIFORM's 2.0.
    assert_eq!(json["smallest_size"].as_f64().unwrap(), 0.02);
    assert_eq!(json["largest_size"].as_f64().unwrap(), 2.0);
    assert!(out.exists());
}
