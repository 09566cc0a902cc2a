//! Metrics from a solution on tetrahedra:
//!
//! - `size MESH --field u --complexity N` on a tetrahedral box writes the 3D Lp metric to
//!   every metric target, each read back to the same tensors, with the vertex count the
//!   complexity asks (as `info --metric` measures it independently);
//! - a recipe's SOLUTION_HESSIAN step sizes it as `size --field` does (the same file);
//! - `mmg3d_O3` adapts the box to the metric of a Gaussian bump: the median metric
//!   length of its edges (in the metric it carries to its vertices) is near 1;
//! - Gmsh's unstructured tetrahedra of a cube and a ball: both recovery methods (the
//!   quadratic fit and the l2-projection) recover a quadratic's Hessian at every vertex,
//!   interior and boundary, to 1e-9.
//!
//! The external tools skip with a message when absent, unless interop is required (CI).
#![allow(clippy::print_stdout, clippy::print_stderr)] // What a test measured is printed for the log.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::path::Path;
use std::process::Command;

use smartmesh::formats::{read_path, write_path, CellKind, DataArray, TaggedMesh, WriteOptions};
use smartmesh::metric::length3::metric_edge_length3;
use smartmesh::metric::Sym3;
use smartmesh::sizing::solution::{recover3, Method, P1Mesh3};
use smartmesh::MetricField;
use smartmesh_test_support::formats::{python_with, run_python};
use smartmesh_test_support::grid::kuhn_box;
use support::{bad, ok, program, run};

/// u = exp(−|x − c|²/σ), a bump in the unit cube.
fn bump(p: [f64; 3]) -> f64 {
    let r2 = (p[0] - 0.5).powi(2) + (p[1] - 0.45).powi(2) + (p[2] - 0.55).powi(2);
    (-r2 / 0.03).exp()
}

/// The Kuhn box of `n` cubes a side with the point data `u` = [`bump`] (and `v`).
fn box_with_field(n: usize) -> TaggedMesh {
    let mut mesh = kuhn_box(n, [1.0; 3]);
    let u: Vec<f64> = mesh.points.iter().map(|&p| bump(p)).collect();
    let v: Vec<f64> = mesh.points.iter().map(|p| p[0] * p[1]).collect();
    mesh.point_data.insert("u".into(), DataArray::new(1, u));
    mesh.point_data.insert("v".into(), DataArray::new(1, v));
    mesh
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn size_writes_the_3d_solution_metric_to_every_target() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = box_with_field(8);
    let input = dir.path().join("box.vtu");
    write_path(&input, &mesh, None, &WriteOptions::default()).unwrap();
    let mut first: Option<Vec<Sym3>> = None;
    for ext in ["sol", "solb", "mesh", "meshb", "msh", "pos", "vtu", "vtk"] {
        let out = dir.path().join(format!("metric.{ext}"));
        let o = run(&[
            "size",
            s(&input),
            "--field",
            "u",
            "--complexity",
            "4000",
            "-o",
            s(&out),
            "--json",
        ]);
        let json: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
        let expected = json["solution"]["expected_vertices"].as_f64().unwrap();
        assert!((expected / 4000.0 - 1.0).abs() < 1e-3, "{ext}: {expected}");
        // The metric read back: from the file itself, or the .sol beside a Medit mesh.
        let metric_file = match ext {
            "mesh" => dir.path().join("metric.sol"),
            "meshb" => dir.path().join("metric.solb"),
            _ => out.clone(),
        };
        let field = MetricField::<Sym3>::read_field(&metric_file, None, &mesh, &input)
            .unwrap_or_else(|e| panic!("{ext}: {e}"));
        let tensors = field.into_tensors();
        assert_eq!(tensors.len(), mesh.points.len());
        match &first {
            None => {
                // The count `info --metric` measures on the written field, independently.
                let o = run(&["info", s(&input), "--metric", s(&out), "--json"]);
                let info: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
                let measured = info["metric"]["expected_vertices"].as_f64().unwrap();
                assert!((measured / 4000.0 - 1.0).abs() < 1e-3, "info --metric: {measured}");
                first = Some(tensors);
            }
            Some(f) => {
                for (a, b) in f.iter().zip(&tensors) {
                    let (ra, rb) = (a.rows(), b.rows());
                    let scale = a.trace().abs();
                    for i in 0..3 {
                        for j in 0..3 {
                            assert!(
                                (ra[i][j] - rb[i][j]).abs() <= 1e-6 * scale,
                                "{ext}: {a:?} against {b:?}"
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn size_in_space_refuses_what_it_cannot_do_with_exit_two() {
    // Several fields, a missing field, no target.
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("box.vtu");
    write_path(&input, &box_with_field(3), None, &WriteOptions::default()).unwrap();
    let out = dir.path().join("m.sol");
    let e = bad(&run(&["size", s(&input), "--field", "u,v", "--complexity", "100", "-o", s(&out)]));
    assert!(e.contains("one field in space"), "{e}");
    let e = bad(&run(&["size", s(&input), "--field", "w", "--complexity", "100", "-o", s(&out)]));
    assert!(e.contains("`w`") && e.contains("u, v"), "{e}");
    let e = bad(&run(&["size", s(&input), "--field", "u", "-o", s(&out)]));
    assert!(e.contains("--complexity"), "{e}");
    assert!(!out.exists(), "no output on failure");
}

/// A recipe with a SOLUTION_HESSIAN step (its bounds left to the mesh, as `--field`
/// leaves them) sizes a tetrahedral mesh as `size --field` does: the same `.sol`, byte
/// for byte; with a UNIFORM step before it the two are intersected (no size above the
/// uniform one).
#[test]
fn a_recipe_with_solution_hessian_sizes_a_tetra_mesh_as_the_solution_command() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("box.vtu");
    let mesh = box_with_field(6);
    write_path(&input, &mesh, None, &WriteOptions::default()).unwrap();
    let (by_recipe, by_field) = (dir.path().join("r.sol"), dir.path().join("f.sol"));
    let recipe = dir.path().join("r.toml");
    let step =
        "[[algorithms]]\ntype = \"solution_hessian\"\nfield = \"u\"\ncomplexity = 2500\np = 3\n";
    std::fs::write(&recipe, step).unwrap();
    ok(&run(&["size", s(&input), "-r", s(&recipe), "-o", s(&by_recipe)]));
    let args = ["--field", "u", "--complexity", "2500", "--p", "3", "-o", s(&by_field)];
    ok(&run(&[&["size", s(&input)][..], &args[..]].concat()));
    let (a, b) = (std::fs::read(&by_recipe).unwrap(), std::fs::read(&by_field).unwrap());
    assert!(a.len() > 1000 && a == b, "the recipe's .sol differs from --field's");
    // With UNIFORM 0.05 on the volume first: every size at most 0.05.
    let both = format!("[regions]\nAll = [1]\n[[algorithms]]\ntype = \"uniform\"\nsize = 0.05\nregions = [\"All\"]\n{step}");
    std::fs::write(&recipe, both).unwrap();
    ok(&run(&["size", s(&input), "-r", s(&recipe), "-o", s(&by_recipe)]));
    let tensors =
        MetricField::<Sym3>::read_field(&by_recipe, None, &mesh, &input).unwrap().into_tensors();
    let fine =
        MetricField::<Sym3>::read_field(&by_field, None, &mesh, &input).unwrap().into_tensors();
    let mut finer = 0;
    for (t, f) in tensors.iter().zip(&fine) {
        // The largest size is 1/sqrt of the smallest eigenvalue.
        let smallest = t.eigen().values[2];
        assert!(smallest >= 1.0 / (0.05f64 * 0.05) * (1.0 - 1e-9), "{t:?}");
        finer += usize::from(t.trace() > f.trace() * (1.0 + 1e-9));
    }
    assert!(finer > mesh.points.len() / 2, "the uniform step acts at {finer} vertices");
}

/// The median of the UGAWG metric lengths of the edges of the tetrahedra of `mesh` in
/// the metric `metric` at its vertices.
fn median_length(mesh: &TaggedMesh, metric: &[Sym3]) -> (f64, usize) {
    let mut edges = std::collections::BTreeSet::new();
    for (k, n, _, _) in mesh.cells() {
        if k == CellKind::Tetra {
            for i in 0..4 {
                for j in i + 1..4 {
                    edges.insert((n[i].min(n[j]), n[i].max(n[j])));
                }
            }
        }
    }
    let mut lengths: Vec<f64> = edges
        .iter()
        .map(|&(a, b)| {
            let (a, b) = (a as usize, b as usize);
            metric_edge_length3(mesh.points[a], mesh.points[b], &metric[a], &metric[b])
        })
        .collect();
    lengths.sort_by(f64::total_cmp);
    (lengths[lengths.len() / 2], lengths.len())
}

#[test]
fn mmg3d_adapts_a_cube_to_the_metric_of_a_bump() {
    if program("mmg3d_O3").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mesh = box_with_field(10);
    let input = dir.path().join("box.mesh");
    write_path(&input, &mesh, None, &WriteOptions::default()).unwrap();
    let field = dir.path().join("box.vtu");
    write_path(&field, &mesh, None, &WriteOptions::default()).unwrap();
    let sol = dir.path().join("box.sol");
    let args = ["size", s(&input), "--solution-file", s(&field), "--field", "u"];
    ok(&run(&[&args[..], &["--complexity", "3000", "-o", s(&sol)]].concat()));
    let out = dir.path().join("adapted.mesh");
    let o = Command::new("mmg3d_O3")
        .args(["-in", s(&input), "-sol", s(&sol), "-out", s(&out), "-hgrad", "-1", "-v", "-1"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let adapted = read_path(&out, None).unwrap();
    // mmg3d carries the metric to its vertices in the .sol beside its output.
    let metric =
        MetricField::<Sym3>::read_field(&dir.path().join("adapted.sol"), None, &adapted, &out)
            .unwrap()
            .into_tensors();
    let (median, edges) = median_length(&adapted, &metric);
    eprintln!(
        "mmg3d_O3: {} vertices, {} tetrahedra, {edges} edges, median metric length {median:.3}",
        adapted.points.len(),
        adapted.num_cells_of(CellKind::Tetra)
    );
    assert!((0.7..=1.3).contains(&median), "median metric length {median}");
    // Refined at the bump, as the Hessian asks: the smallest edge is near the centre.
    assert!(adapted.points.len() > 2 * mesh.points.len(), "{} vertices", adapted.points.len());
}

/// Gmsh's tetrahedra of the unit cube and of a ball, written to `dir`.
const GMSH_SCRIPT: &str = r#"
import gmsh, sys
out, shape = sys.argv[1], sys.argv[2]
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
if shape == "cube":
    gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
else:
    gmsh.model.occ.addSphere(0.2, -0.1, 0.3, 0.8)
gmsh.model.occ.synchronize()
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.2)
gmsh.model.mesh.generate(3)
gmsh.write(out)
gmsh.finalize()
"#;

#[test]
fn both_recoveries_are_exact_at_every_vertex_of_gmsh_tetrahedra() {
    let Some(py) = python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let h = Sym3 { xx: 3.0, xy: -4.0, yy: 1.4, xz: 2.5, yz: -1.2, zz: -1.8 };
    let u = |p: [f64; 3]| 1.0 + 2.0 * p[0] - p[2] + 0.5 * h.quadratic_form(p);
    for shape in ["cube", "ball"] {
        let path = dir.path().join(format!("{shape}.msh"));
        run_python(&py, GMSH_SCRIPT, &[s(&path), shape]);
        let mesh = read_path(&path, None).unwrap();
        let tets: Vec<[u32; 4]> = mesh
            .cells()
            .filter(|c| c.0 == CellKind::Tetra)
            .map(|(_, n, _, _)| [n[0], n[1], n[2], n[3]])
            .collect();
        let values: Vec<f64> = mesh.points.iter().map(|&p| u(p)).collect();
        let p1 = P1Mesh3::new(&mesh.points, &tets).unwrap();
        for method in Method::ALL {
            let d = recover3(&p1, &values, method).unwrap();
            let norm = h.rows().iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
            let mut worst = 0.0f64;
            let mut used = 0;
            for v in (0..mesh.points.len()).filter(|&v| p1.is_used(v)) {
                let (a, b) = (d.hessian[v].rows(), h.rows());
                let e = (0..3)
                    .flat_map(|i| (0..3).map(move |j| (a[i][j] - b[i][j]).powi(2)))
                    .sum::<f64>()
                    .sqrt()
                    / norm;
                worst = worst.max(e);
                used += 1;
            }
            eprintln!(
                "{shape}, {}: {used} vertices, {} tetrahedra, worst relative Hessian error {worst:.1e}",
                method.name(),
                tets.len()
            );
            assert!(used > 100 && worst < 1e-9, "{shape}, {method:?}: {worst}");
        }
    }
}
