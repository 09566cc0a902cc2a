//! Every `.msh` smartmesh writes in normal use — `convert`, `mesh`, `size`, `remesh`,
//! `adapt` with the native remesher and with Gmsh — read whole by meshio and saved again
//! by Gmsh without losing an element, on Triangle's own samples without regional
//! attributes (their faces have no tag while their segments have markers); and a
//! second-order Gmsh mesh kept by `info` and `convert` (Gmsh reads the same element
//! types back) and made linear, with a note, by `adapt`. Skips when
//! gmsh or meshio is missing for `python3`, unless `SMARTMESH_REQUIRE_INTEROP=1` (CI).

use smartmesh_test_support::formats as common;

use smartmesh::formats::read_path;

#[path = "support/cli.rs"]
#[allow(dead_code)] // `bundled` is not needed here
mod cli;

use cli::{ok, smartmesh};

/// A recipe for Triangle's `A.poly`: finer around its point 1.
const RECIPE: &str = r#"
[global]
hmin = 0.01
hmax = 0.1

[regions]
Corner = [1]

[functions.F]
kind = "distance"
size_at_source = 0.02
size_at_max_distance = 0.08
max_distance = 0.3
exponent = 1.0

[[algorithms]]
type = "distance_to_point"
function = "F"
regions = ["Corner"]
"#;

#[test]
fn meshio_and_gmsh_read_every_msh_smartmesh_writes_whole() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["gmsh", "meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    let sample =
        |name: &str| common::public_fixture(&format!("triangle/{name}")).display().to_string();
    let recipe = out("a.toml");
    std::fs::write(&recipe, RECIPE).unwrap();
    let runs: Vec<(String, Vec<String>)> = vec![
        ("convert".into(), vec!["convert".into(), sample("A.1.ele"), out("convert.msh")]),
        ("mesh".into(), vec!["mesh".into(), sample("A.poly"), "-o".into(), out("mesh.msh")]),
        (
            "mesh double_hex".into(),
            vec!["mesh".into(), sample("double_hex.poly"), "-o".into(), out("hex.msh")],
        ),
        (
            "mesh square_circle_hole".into(),
            vec!["mesh".into(), sample("square_circle_hole.poly"), "-o".into(), out("hole.msh")],
        ),
        (
            "size".into(),
            vec![
                "size".into(),
                out("mesh.msh"),
                "--recipe".into(),
                recipe.clone(),
                "-o".into(),
                out("size.msh"),
            ],
        ),
        ("remesh".into(), vec!["remesh".into(), out("size.msh"), "-o".into(), out("remesh.msh")]),
        (
            "adapt".into(),
            vec![
                "adapt".into(),
                sample("A.poly"),
                "--recipe".into(),
                recipe.clone(),
                "-o".into(),
                out("adapt.msh"),
                "--max-iterations".into(),
                "2".into(),
            ],
        ),
        (
            "adapt --adapter gmsh".into(),
            vec![
                "adapt".into(),
                sample("A.poly"),
                "--recipe".into(),
                recipe.clone(),
                "-o".into(),
                out("gmsh.msh"),
                "--max-iterations".into(),
                "1".into(),
                "--adapter".into(),
                "gmsh".into(),
            ],
        ),
    ];
    let mut files = Vec::new();
    for (what, args) in &runs {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = smartmesh(&args, None);
        ok(&o);
        let stderr = String::from_utf8_lossy(&o.stderr);
        // The faces without a tag are said to go to a group of their own.
        assert!(
            stderr.contains("without a physical tag written as physical group"),
            "{what}: {stderr}"
        );
        let path = args.iter().position(|&a| a == "-o").map_or(args[2], |i| args[i + 1]);
        let cells = read_path(path.as_ref(), None).unwrap().num_cells();
        files.push((what.clone(), path.to_string(), cells));
    }
    let paths: Vec<&str> = files.iter().map(|f| f.1.as_str()).collect();
    let text = common::run_python(&py, common::READ_AND_RESAVE, &paths);
    let summaries: Vec<serde_json::Value> = serde_json::from_str(text.lines().last().unwrap_or(""))
        .unwrap_or_else(|e| panic!("{e}: {text}"));
    for ((what, _, cells), s) in files.iter().zip(&summaries) {
        assert_eq!(s["meshio"], *cells, "{what}: meshio");
        let total: u64 = s["before"].as_object().unwrap().values().filter_map(|v| v.as_u64()).sum();
        assert_eq!(total as usize, *cells, "{what}: Gmsh reads {}", s["before"]);
        assert_eq!(s["after"], s["before"], "{what}: Gmsh saved it again");
    }
}

/// A Gmsh that saves a mesh without triangles (as it does when the triangles belong to
/// no physical group of a model that has some): the failure says why that may be.
#[cfg(unix)]
#[test]
fn a_gmsh_output_without_triangles_names_the_likely_cause() {
    smartmesh_test_support::require_public_fixtures!();
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let fake = dir.path().join("gmsh");
    let lines_only = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n$Elements\n1\n1 1 2 1 1 1 2\n$EndElements\n";
    std::fs::write(
        &fake,
        format!("#!/bin/sh\nprintf '{}' > out.msh\n", lines_only.replace('\n', "\\n")),
    )
    .unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let recipe = dir.path().join("a.toml");
    std::fs::write(&recipe, RECIPE).unwrap();
    let poly = common::public_fixture("triangle/A.poly").display().to_string();
    let out = dir.path().join("o.msh").display().to_string();
    let o = smartmesh(
        &[
            "adapt",
            &poly,
            "--recipe",
            recipe.to_str().unwrap(),
            "-o",
            &out,
            "--adapter",
            "gmsh",
            "--adapter-program",
            fake.to_str().unwrap(),
        ],
        None,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("has no triangle (Gmsh saves only the elements of physical groups"),
        "{err}"
    );
}

/// A second-order mesh from `gmsh -2 -order 2`: `info` and `convert` keep its cells as
/// they are (Gmsh reads the same element types and nodes from what `convert` wrote, in
/// 4.1 and 2.2), and `adapt`, which remeshes linear cells, makes them linear with a note.
#[test]
fn a_second_order_gmsh_mesh_is_kept_and_made_linear_only_to_adapt() {
    let Some(py) = common::python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let p2 = dir.path().join("p2.msh").display().to_string();
    let make = r#"
import sys, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
gmsh.model.occ.synchronize()
gmsh.model.addPhysicalGroup(2, [1], 1, "Fluid")
gmsh.model.addPhysicalGroup(1, [1, 2, 3, 4], 2, "Wall")
gmsh.model.addPhysicalGroup(0, [1], 3, "Corner")
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.2)
gmsh.model.mesh.generate(2)
gmsh.model.mesh.setOrder(2)
gmsh.write(sys.argv[1])
corners, used, triangles, lines = set(), set(), 0, 0
for ty, nodes in zip(*gmsh.model.mesh.getElements()[::2]):
    k = gmsh.model.mesh.getElementProperties(ty)[3]
    c = {15: 1, 8: 2, 9: 3}[ty]
    corners.update(n for i, n in enumerate(nodes) if i % k < c)
    used.update(nodes)
    triangles += len(nodes) // k if ty == 9 else 0
    lines += len(nodes) // k if ty == 8 else 0
print(len(used), triangles, lines, len(used - corners))
gmsh.finalize()
"#;
    let out = common::run_python(&py, make, &[&p2]);
    let counts: Vec<usize> =
        out.lines().last().unwrap().split(' ').map(|v| v.parse().unwrap()).collect();
    let o = smartmesh(&["info", &p2], None);
    let info = ok(&o);
    assert!(!info.contains("used by no cell"), "{info}");
    assert!(info.contains(&format!("points      {},", counts[0])), "{info}");
    assert!(
        info.contains(&format!("{} line3", counts[2]))
            && info.contains(&format!("{} triangle6", counts[1])),
        "{info}"
    );
    // Nothing was changed: no note.
    assert!(!String::from_utf8_lossy(&o.stderr).contains("note:"), "{o:?}");

    // What Gmsh reads from what `convert` wrote: element types, counts and nodes.
    let types = r#"
import sys, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
for f in sys.argv[1:]:
    gmsh.open(f)
    t, e, n = gmsh.model.mesh.getElements()
    print(f.rsplit("/", 1)[-1], sorted((int(a), len(b)) for a, b in zip(t, e)), len(gmsh.model.mesh.getNodes()[0]))
gmsh.finalize()
"#;
    let mut files = vec![p2.clone()];
    for version in ["4.1", "2.2"] {
        let out = dir.path().join(format!("back{version}.msh")).display().to_string();
        ok(&smartmesh(&["convert", &p2, &out, "--gmsh-version", version], None));
        files.push(out);
    }
    let args: Vec<&str> = files.iter().map(String::as_str).collect();
    let seen = common::run_python(&py, types, &args);
    let lines: Vec<&str> = seen.lines().collect();
    assert_eq!(lines.len(), 3, "{seen}");
    let what = |l: &str| l.split_once(' ').unwrap().1.to_string();
    assert!(lines[0].contains("(9, ") && lines[0].contains("(8, "), "{seen}");
    assert_eq!(what(lines[1]), what(lines[0]), "{seen}");
    assert_eq!(what(lines[2]), what(lines[0]), "{seen}");

    // `adapt` says what it made linear, and nothing under -q.
    let recipe = dir.path().join("r.toml");
    std::fs::write(&recipe, RECIPE.replace("[1]", "[\"Corner\"]")).unwrap();
    let adapted = dir.path().join("a.msh").display().to_string();
    let adapt = |quiet: bool| {
        let mut args = vec![
            "adapt",
            &p2,
            "--recipe",
            recipe.to_str().unwrap(),
            "-o",
            &adapted,
            "--max-iterations",
            "1",
        ];
        if quiet {
            args.push("-q");
        }
        smartmesh(&args, None)
    };
    let o = adapt(false);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("note: ")
            && err.contains("second-order cells made linear")
            && err.contains(&format!("{} 6-node triangles as 3-node", counts[1]))
            && err.contains(&format!("{} 3-node lines as 2-node", counts[2]))
            && err.contains(&format!("; {} mid-edge nodes dropped", counts[3])),
        "{err}"
    );
    let quiet = adapt(true);
    ok(&quiet);
    assert!(!String::from_utf8_lossy(&quiet.stderr).contains("note:"), "{quiet:?}");
}
