//! What a reader could not keep reaches `--json` as `read_notes`, not only stderr
//! (which `-q` silences): a partitioned Gmsh file merged into one mesh.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;

use cli::{fixture, ok, smartmesh};

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

/// `convert --json -q` and `info --json -q` of a partitioned MSH 4.1 file: its physical
/// groups are there, and the merged partitions are listed in `read_notes`.
#[test]
fn a_partitioned_file_says_in_json_that_its_partitions_were_merged() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixture("partitioned_t21.msh");
    let out = dir.path().join("p.vtu");
    let o = smartmesh(
        &["convert", input.to_str().unwrap(), out.to_str().unwrap(), "--json", "-q"],
        None,
    );
    let j = json(&ok(&o));
    assert!(o.stderr.is_empty(), "{}", String::from_utf8_lossy(&o.stderr));
    let notes = j["read_notes"].as_array().unwrap();
    assert_eq!(notes.len(), 1, "{j}");
    assert!(notes[0].as_str().unwrap().contains("3 partitions read as one mesh"), "{j}");

    let j = json(&ok(&smartmesh(&["info", "--json", "-q", input.to_str().unwrap()], None)));
    assert_eq!(j["read_notes"], serde_json::json!(notes), "{j}");
    let named: Vec<(&str, u64)> = j["tags"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| (t["name"].as_str().unwrap_or(""), t["cells"].as_u64().unwrap()))
        .collect();
    assert_eq!(named, vec![("Bottom", 5), ("Left", 66), ("Right", 66)], "{j}");
}

/// A unit square of two triangles, in Medit's ASCII format.
const SQUARE_MESH: &str = "MeshVersionFormatted 2\nDimension 2\nVertices\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\nTriangles\n2\n1 2 3 5\n1 3 4 5\nEdges\n4\n1 2 1\n2 3 1\n3 4 1\n4 1 1\nEnd\n";

/// Its metric, 100·I at each vertex, followed by a solver's own keywords as in MMG's
/// `naca-multiSols.sol` (`Time` and `Iterations` are libMeshb's, the others are not).
const SOL_WITH_SOLVER_KEYWORDS: &str = "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n4\n1 3\n100 0 100\n100 0 100\n100 0 100\n100 0 100\n Time\n  0.000000000000000E+000\n Iterations\n           0\n CFL\n  1.947954677045874E-004\n Model\n       11001\n Nvar\n           4\n NvarPhys\n           9\n Residu\n        0.0000001700       23.7755237546       32.9919322005\n \nEnd\n";

/// The `.sol` reads (mmg2d_O3 reads it too, where it is installed), its metric kept,
/// the keywords skipped said in a note on stderr and in `--json`.
#[test]
fn solver_keywords_after_a_solution_are_skipped_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("sq.mesh");
    std::fs::write(&mesh, SQUARE_MESH).unwrap();
    std::fs::write(dir.path().join("sq.sol"), SOL_WITH_SOLVER_KEYWORDS).unwrap();
    let mesh = mesh.to_str().unwrap();
    let o = smartmesh(&["info", "--json", mesh], None);
    let j = json(&ok(&o));
    let point_data: Vec<&str> =
        j["point_data"].as_array().unwrap().iter().map(|f| f["name"].as_str().unwrap()).collect();
    assert_eq!(point_data, vec!["metric"], "{j}");
    let notes = j["read_notes"].as_array().unwrap();
    assert_eq!(notes.len(), 1, "{j}");
    let note = notes[0].as_str().unwrap();
    assert!(
        note.contains("sq.sol: ")
            && note.contains("from line 14")
            && note.ends_with("CFL, Model, Nvar, NvarPhys, Residu"),
        "{note}"
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains(note), "{o:?}");

    let Some(py) = smartmesh_test_support::formats::python_with(&["mmgpy"]) else { return };
    let mmg = smartmesh_test_support::formats::mmg2d(&py);
    let out = dir.path().join("out.mesh");
    let run = std::process::Command::new(mmg)
        .args([
            mesh,
            "-sol",
            dir.path().join("sq.sol").to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-v",
            "-1",
        ])
        .output()
        .unwrap();
    assert!(run.status.success() && out.exists(), "mmg2d_O3: {run:?}");
}

/// A `.sol` that cannot be read makes its mesh unreadable (exit 2, naming the `.sol`);
/// `--no-solution` reads the mesh without it.
#[test]
fn no_solution_reads_a_mesh_without_its_sol() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("sq.mesh");
    std::fs::write(&mesh, SQUARE_MESH).unwrap();
    // Three solutions for four vertices.
    std::fs::write(
        dir.path().join("sq.sol"),
        "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n3\n1 1\n0.1\n0.1\n0.1\nEnd\n",
    )
    .unwrap();
    let mesh = mesh.to_str().unwrap();
    let o = smartmesh(&["info", mesh], None);
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    assert!(String::from_utf8_lossy(&o.stderr).contains("sq.sol"), "{o:?}");
    let j = json(&ok(&smartmesh(&["info", "--json", "--no-solution", mesh], None)));
    assert_eq!(j["points"], 4, "{j}");
    assert_eq!(j["point_data"], serde_json::json!([]), "{j}");
    let out = dir.path().join("sq.vtu");
    ok(&smartmesh(&["convert", "--no-solution", mesh, out.to_str().unwrap()], None));
    assert_eq!(smartmesh::formats::read_path(&out, None).unwrap().num_cells(), 6);
}

/// Three triangles with a Gmsh `$ElementData` view that covers one of them.
const PARTIAL_VIEW_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n$EndNodes\n$Elements\n3\n1 2 2 1 1 1 2 3\n2 2 2 1 1 1 3 4\n3 2 2 1 1 2 5 3\n$EndElements\n$ElementData\n1\n\"err\"\n1\n0\n3\n0\n1\n1\n2 0.25\n$EndElementData\n";

/// A view covering part of the cells: `convert` keeps the others as NaN and says so
/// (`read_notes`); VTK and meshio read the `.vtu` and `.vtk` written (NaN where the
/// view gave nothing), and so do `info` and `convert` (which refused them before).
#[test]
fn a_partial_view_is_kept_as_nan_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let msh = dir.path().join("partial.msh");
    std::fs::write(&msh, PARTIAL_VIEW_MSH).unwrap();
    let mut outs = Vec::new();
    for (name, extra) in [
        ("p.vtu", "--vtu-encoding=ascii"),
        ("p.vtk", "--vtk-version=4.2"),
        ("pb.vtu", "--vtu-encoding=binary"),
    ] {
        let out = dir.path().join(name).display().to_string();
        let j = json(&ok(&smartmesh(
            &["convert", msh.to_str().unwrap(), &out, extra, "--json", "-q"],
            None,
        )));
        assert_eq!(
            j["read_notes"],
            serde_json::json!(["view `err` gives values for 1 of 3 elements; the others are NaN"]),
            "{j}"
        );
        let info = ok(&smartmesh(&["info", &out], None));
        assert!(
            info.contains("cell data   err (1 component) in [0.25, 0.25], 2 items NaN"),
            "{info}"
        );
        outs.push(out);
    }
    let Some(py) = smartmesh_test_support::formats::python_with(&["vtk", "meshio"]) else { return };
    let script = r#"
import sys, math, meshio, vtk
from vtk.util.numpy_support import vtk_to_numpy
for f in sys.argv[1:]:
    r = vtk.vtkXMLUnstructuredGridReader() if f.endswith(".vtu") else vtk.vtkUnstructuredGridReader()
    r.SetFileName(f)
    r.Update()
    a = [float(x) for x in vtk_to_numpy(r.GetOutput().GetCellData().GetArray("err"))]
    m = [float(x) for x in meshio.read(f).cell_data["err"][0]]
    print(" ".join("nan" if math.isnan(x) else repr(x) for x in a + m))
"#;
    let args: Vec<&str> = outs.iter().map(String::as_str).collect();
    let out = smartmesh_test_support::formats::run_python(&py, script, &args);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines, vec!["nan 0.25 nan nan 0.25 nan"; 3], "{out}");
}

/// A unit square of two 6-node triangles, its sides 3-node lines, in Gmsh's MSH 2.2
/// (as `gmsh -2 -order 2` writes it), with a physical point `Corner` for a recipe.
const SECOND_ORDER_MSH: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n0 3 \"Corner\"\n1 2 \"Wall\"\n2 1 \"Fluid\"\n$EndPhysicalNames\n$Nodes\n9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0 0\n6 1 0.5 0\n7 0.5 1 0\n8 0 0.5 0\n9 0.5 0.5 0\n$EndNodes\n$Elements\n7\n1 15 2 3 1 1\n2 8 2 2 1 1 2 5\n3 8 2 2 2 2 3 6\n4 8 2 2 3 3 4 7\n5 8 2 2 4 4 1 8\n6 9 2 1 1 1 2 3 5 6 9\n7 9 2 1 1 1 3 4 9 7 8\n$EndElements\n";

/// Sizes near the corner `Corner`, coarse elsewhere.
const CORNER_RECIPE: &str = "[global]\nhmin = 0.05\nhmax = 0.3\n\n[regions]\nCorner = [\"Corner\"]\n\n[functions.F]\nkind = \"distance\"\nsize_at_source = 0.1\nsize_at_max_distance = 0.3\nmax_distance = 0.5\nexponent = 1.0\n\n[[algorithms]]\ntype = \"distance_to_point\"\nfunction = \"F\"\nregions = [\"Corner\"]\n";

/// The second-order square and its recipe written in `dir`: (mesh, recipe).
fn second_order_square(dir: &std::path::Path) -> (String, String) {
    let mesh = dir.join("p2.msh");
    std::fs::write(&mesh, SECOND_ORDER_MSH).unwrap();
    let recipe = dir.join("r.toml");
    std::fs::write(&recipe, CORNER_RECIPE).unwrap();
    (mesh.display().to_string(), recipe.display().to_string())
}

/// The `read_notes` of a `--json -q` run on the second-order square: nothing on stderr,
/// and the one note says its cells were made linear.
fn linearised_note(args: &[&str]) -> serde_json::Value {
    let o = smartmesh(args, None);
    let j = json(&ok(&o));
    assert!(o.stderr.is_empty(), "{}", String::from_utf8_lossy(&o.stderr));
    let notes = j["read_notes"].as_array().unwrap_or_else(|| panic!("no read_notes: {j}"));
    assert_eq!(notes.len(), 1, "{j}");
    let note = notes[0].as_str().unwrap();
    assert!(
        note.contains("second-order cells made linear")
            && note.contains("2 6-node triangles as 3-node")
            && note.contains("4 3-node lines as 2-node"),
        "{note}"
    );
    j
}

/// `size --json -q` of a second-order mesh lists in `read_notes` that it was made linear.
#[test]
fn size_json_says_second_order_cells_were_made_linear() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, recipe) = second_order_square(dir.path());
    let field = dir.path().join("f.vtu").display().to_string();
    let j = linearised_note(&["size", &mesh, "-r", &recipe, "-o", &field, "--json", "-q"]);
    assert_eq!(j["vertices"], 4, "{j}");
}

/// `remesh --json -q` (and `remesh --measure --json -q`) of a second-order mesh list in
/// `read_notes` that it was made linear.
#[test]
fn remesh_json_says_second_order_cells_were_made_linear() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, recipe) = second_order_square(dir.path());
    let field = dir.path().join("f.vtu").display().to_string();
    ok(&smartmesh(&["size", &mesh, "-r", &recipe, "-o", &field, "-q"], None));
    let out = dir.path().join("o.vtu").display().to_string();
    linearised_note(&["remesh", &mesh, "--metric", &field, "-o", &out, "--json", "-q"]);
    let j = linearised_note(&["remesh", &mesh, "--metric", &field, "--measure", "--json", "-q"]);
    assert_eq!(j["triangles"], 2, "{j}");
}

/// `adapt --json -q` of a second-order mesh lists in `read_notes` that the starting mesh
/// was made linear.
#[test]
fn adapt_json_says_second_order_cells_were_made_linear() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, recipe) = second_order_square(dir.path());
    let out = dir.path().join("a.msh").display().to_string();
    let j = linearised_note(&[
        "adapt",
        &mesh,
        "-r",
        &recipe,
        "-o",
        &out,
        "--max-iterations",
        "1",
        "--json",
        "-q",
    ]);
    assert_eq!(j["input"], mesh.as_str(), "{j}");
}
