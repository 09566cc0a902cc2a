//! The Fluent meshes `smartmesh convert` writes (the bundled cylinder, its skin of quads,
//! the examples' meshes, the public 3D fixtures), read by other tools: OpenFOAM's
//! `fluentMeshToFoam` (with `-2D` for a 2D mesh) converts them and `checkMesh` then says
//! "Mesh OK." with our zone names as patches and our cell counts; meshio's `ansys`
//! reader finds our nodes and faces. Skips, saying so, when the tools or the public
//! fixtures are missing, unless `SMARTMESH_REQUIRE_INTEROP=1` (CI, where `.ci/run`
//! installs Debian's `openfoam` and meshio).

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::path::Path;
use std::process::Command;

use smartmesh_test_support::formats::{public_fixture, python_with, run_python};
use smartmesh_test_support::require_public_fixtures;
use support::{bundled, ok, program, run, stderr};

/// An OpenFOAM command in `case`, with Debian's `WM_PROJECT_DIR` unless the user's is
/// set; returns its stdout, asserting success.
fn foam(program: &Path, case: &Path, args: &[&str]) -> String {
    let mut c = Command::new(program);
    c.args(args).current_dir(case);
    if std::env::var_os("WM_PROJECT_DIR").is_none() {
        c.env("WM_PROJECT_DIR", "/usr/share/openfoam");
    }
    let out = c.output().expect("run an OpenFOAM tool");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{} {args:?}:\n{text}\n{}",
        program.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// Converts `mesh` to `NAME.fluent.msh`, runs `fluentMeshToFoam [ARGS] FILE` in a fresh
/// case and `checkMesh`; asserts "Mesh OK.", every patch and every `(label, count)`.
fn check(mesh: &str, extra: &[&str], patches: &[&str], counts: &[(&str, usize)]) {
    let (Some(convert), Some(check)) = (program("fluentMeshToFoam"), program("checkMesh")) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("mesh.fluent.msh");
    let out = run(&["convert", mesh, file.to_str().unwrap()]);
    ok(&out);
    let case = dir.path().join("case");
    std::fs::create_dir_all(case.join("system")).unwrap();
    for (name, bytes) in smartmesh::formats::openfoam::missing_system_files(&case.join("system")) {
        std::fs::write(case.join("system").join(name), bytes).unwrap();
    }
    let mut args: Vec<&str> = extra.to_vec();
    args.push(file.to_str().unwrap());
    let log = foam(&convert, &case, &args);
    let text = foam(&check, &case, &[]);
    assert!(text.contains("\nMesh OK.") && !text.contains("Failed "), "{mesh}:\n{log}\n{text}");
    for patch in patches {
        assert!(text.contains(&format!("    {patch} ")), "{patch}: {text}\n{}", stderr(&out));
    }
    for (label, n) in counts {
        let line = text.lines().find(|l| l.trim_start().starts_with(label)).unwrap_or("");
        assert_eq!(line.rsplit(' ').next(), Some(n.to_string().as_str()), "{label}: {text}");
    }
}

#[test]
fn fluent_mesh_to_foam_and_check_mesh_accept_the_2d_cylinder() {
    check(
        &bundled("cylinder.msh"),
        &["-2D", "0.1"],
        &["Inlet", "Outlet", "Walls", "Cylinder", "frontAndBackPlanes"],
        &[("prisms:", 2134), ("cells:", 2134)],
    );
}

#[test]
fn fluent_mesh_to_foam_and_check_mesh_accept_a_skin_of_quads_and_the_examples() {
    // Quads beside triangles: one mixed cell zone, its cell types listed.
    let dir = tempfile::tempdir().unwrap();
    let skin = dir.path().join("skin.msh");
    let layer = [
        "layer",
        &bundled("cylinder.msh"),
        "--curves",
        "Cylinder",
        "--first-height",
        "0.002",
        "--ratio",
        "1.2",
        "--layers",
        "8",
        "-o",
        skin.to_str().unwrap(),
    ];
    ok(&run(&layer));
    check(
        skin.to_str().unwrap(),
        &["-2D", "0.1"],
        &["Cylinder"],
        &[("hexahedra:", 288), ("prisms:", 2018)],
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for example in ["naca0012-agard01", "gamm-a7-viscous", "distributor/1-narrow"] {
        let input = root.join("examples").join(example).join("start.msh");
        check(input.to_str().unwrap(), &["-2D", "0.1"], &[], &[]);
    }
}

#[test]
fn fluent_mesh_to_foam_and_check_mesh_accept_the_3d_fixtures() {
    require_public_fixtures!();
    let box_cyl = public_fixture("3d/box_cyl.v41_ascii.msh");
    check(
        box_cyl.to_str().unwrap(),
        &[],
        &["Inlet", "Outlet", "Walls", "Cylinder"],
        &[("tetrahedra:", 2187)],
    );
    let mixed = public_fixture("3d/hex_prism_pyr.v41_ascii.msh");
    check(
        mixed.to_str().unwrap(),
        &[],
        &["Bottom", "Top", "Sides"],
        &[("hexahedra:", 27), ("prisms:", 54), ("pyramids:", 9), ("tetrahedra:", 152)],
    );
}

#[test]
fn meshio_reads_our_nodes_and_faces() {
    let Some(py) = python_with(&["meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cyl.fluent.msh");
    ok(&run(&["convert", &bundled("cylinder.msh"), file.to_str().unwrap()]));
    let script = r#"
import sys, meshio
m = meshio.read(sys.argv[1], file_format="ansys")
print(len(m.points), m.points.shape[1], " ".join(f"{c.type}:{len(c.data)}" for c in m.cells))
"#;
    let out = run_python(&py, script, &[file.to_str().unwrap()]);
    // 1148 nodes in 2D; the face zones in order: inner edges, Inlet, Outlet, Walls,
    // Cylinder (meshio skips the cell zones, whose Fluent sections hold no nodes).
    assert_eq!(out.trim(), "1148 2 line:3120 line:13 line:13 line:100 line:36", "{out}");
}

/// OpenFOAM's `foamMeshToFluent` writes a Fluent file of a case (ours, of the mixed 3D
/// fixture); smartmesh reads it back (a plain `.msh`, told Fluent by its first byte)
/// with `checkMesh`'s counts: points, cells per kind, boundary faces, patch names.
#[test]
fn foam_mesh_to_fluent_files_read_back_with_check_mesh_counts() {
    require_public_fixtures!();
    let (Some(to_fluent), Some(check)) = (program("foamMeshToFluent"), program("checkMesh")) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case.foam");
    let mixed = public_fixture("3d/hex_prism_pyr.v41_ascii.msh");
    ok(&run(&["convert", mixed.to_str().unwrap(), case.to_str().unwrap()]));
    foam(&to_fluent, &case, &[]);
    let text = foam(&check, &case, &[]);
    let count = |label: &str| -> usize {
        let line = text.lines().find(|l| l.trim_start().starts_with(label));
        line.and_then(|l| l.rsplit(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{label}: {text}"))
    };
    let file = case.join("fluentInterface/case.foam.msh");
    let mesh = smartmesh::formats::read_path(&file, None).unwrap_or_else(|e| panic!("{e}"));
    use smartmesh::formats::CellKind as K;
    assert_eq!(mesh.points.len(), count("points:"));
    assert_eq!(mesh.num_cells_of(K::Hexa), count("hexahedra:"));
    assert_eq!(mesh.num_cells_of(K::Wedge), count("prisms:"));
    assert_eq!(mesh.num_cells_of(K::Pyramid), count("pyramids:"));
    assert_eq!(mesh.num_cells_of(K::Tetra), count("tetrahedra:"));
    let boundary = mesh.num_cells_of(K::Triangle) + mesh.num_cells_of(K::Quad);
    assert_eq!(boundary, count("faces:") - count("internal faces:"));
    let names: Vec<&str> =
        mesh.tag_names.iter().filter(|(k, _)| k.0 == 2).map(|(_, n)| n.as_str()).collect();
    for patch in ["Bottom", "Top", "Sides"] {
        assert!(names.contains(&patch), "{patch}: {names:?}");
    }
}
