//! `smartmesh remesh` on meshes in space, through MMG: a Gmsh-made tetrahedral box with
//! named physical surfaces and volume adapted by `mmg3d_O3` to an analytic anisotropic
//! metric, and the public box-cylinder surface adapted by `mmgs_O3`. Each result is
//! checked apart from the library: positive tetrahedra (orientation computed here), the
//! same tags and names, boundary vertices on their surfaces, and the metric lengths of
//! the edges (integrated here from the analytic metric) near 1. The metric goes to
//! smartmesh as a `.sol` this file writes by hand, in the Medit order m11 m12 m22 m13
//! m23 m33. The refusals (a planar remesher given a mesh in space, a 2D metric, the
//! loop in space asked for what only the planar loop does) need no tool.
//!
//! Needs `mmg3d_O3`/`mmgs_O3` on PATH and Python's `gmsh` (skipped with a message
//! without them, mandatory under CI), and the public fixtures for the surface case.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use smartmesh::formats::{read_path, CellKind, TaggedMesh};
use smartmesh_test_support::formats::public_fixture;
use smartmesh_test_support::require_public_fixtures;
use smartmesh_test_support::space::{
    edge_lengths, edges, gmsh_and_mmg3d, median, metric_length, positive_volume, remesh_as_given,
    write_gmsh_cube,
};

#[path = "support/cli.rs"]
mod support;
use support::{program, run, streams, BIN};

/// A rotation whose axes are none of the coordinate axes: about (1, 2, 3)/√14 by 0.7.
fn rotation() -> [[f64; 3]; 3] {
    let n = 14f64.sqrt();
    let (x, y, z) = (1.0 / n, 2.0 / n, 3.0 / n);
    let (s, c) = 0.7f64.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

/// The analytic metric R diag(1/h1², 1/h2², 1/h3²) Rᵀ, as a full 3×3 matrix, with
/// sizes `sizes(p)` along R's columns.
fn metric_at(p: [f64; 3], sizes: impl Fn([f64; 3]) -> [f64; 3]) -> [[f64; 3]; 3] {
    let r = rotation();
    let h = sizes(p);
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| r[i][k] * r[j][k] / (h[k] * h[k])).sum();
        }
    }
    m
}

/// The sizes of the box case: fine across one oblique direction near x = 0.
fn box_sizes(p: [f64; 3]) -> [f64; 3] {
    [0.05 + 0.15 * p[0], 0.15, 0.2]
}

/// The sizes of the surface case.
fn surface_sizes(p: [f64; 3]) -> [f64; 3] {
    [0.04 + 0.04 * p[0], 0.1, 0.12]
}

/// A Medit `.sol` of `sizes`'s metric at `mesh`'s vertices, written here (m11 m12 m22
/// m13 m23 m33: the lower triangle row by row).
fn write_sol(path: &Path, mesh: &TaggedMesh, sizes: impl Fn([f64; 3]) -> [f64; 3] + Copy) {
    let mut s =
        format!("MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n{}\n1 3\n", mesh.points.len());
    for p in &mesh.points {
        let m = metric_at(*p, sizes);
        s += &format!(
            "{:.17e} {:.17e} {:.17e} {:.17e} {:.17e} {:.17e}\n",
            m[0][0], m[1][0], m[1][1], m[2][0], m[2][1], m[2][2]
        );
    }
    s += "End\n";
    std::fs::write(path, s).unwrap();
}

/// The median and the share in [1/√2, √2] of the metric lengths of `edges`.
fn lengths(
    mesh: &TaggedMesh,
    edges: &BTreeSet<(u32, u32)>,
    sizes: impl Fn([f64; 3]) -> [f64; 3] + Copy,
) -> (f64, f64) {
    let l = edge_lengths(mesh, edges, |a, b| metric_length(a, b, |p| metric_at(p, sizes)));
    let inside = l.iter().filter(|&&x| (0.5f64.sqrt()..=2f64.sqrt()).contains(&x)).count();
    (median(&l), inside as f64 / l.len() as f64)
}

/// Cells per (dimension, physical tag).
fn tag_counts(mesh: &TaggedMesh) -> BTreeMap<(u8, i32), usize> {
    let mut out = BTreeMap::new();
    for (k, _, p, _) in mesh.cells() {
        *out.entry((k.dim(), p)).or_default() += 1;
    }
    out
}

#[test]
fn mmg3d_adapts_a_gmsh_box_to_an_oblique_metric_keeping_names_and_tags() {
    let Some(py) = gmsh_and_mmg3d() else { return };
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("box.msh");
    write_gmsh_cube(&py, &input, 0.25);
    let start = read_path(&input, None).unwrap();
    assert!(start.num_cells_of(CellKind::Tetra) > 50);
    let sol = dir.path().join("box.sol");
    write_sol(&sol, &start, box_sizes);
    let out = dir.path().join("adapted.msh");
    let o = remesh_as_given(BIN, input.to_str().unwrap(), &sol, &out, &["--json"]);
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["adapter"], "mmg3d");
    let mesh = read_path(&out, None).unwrap();
    assert_eq!(json["output"]["tetrahedra"], mesh.num_cells_of(CellKind::Tetra));

    // The same physical tags, each with cells, and the same names; the point where it
    // was, the rim's edges on the face's rim.
    let (before, after) = (tag_counts(&start), tag_counts(&mesh));
    let tags =
        |m: &BTreeMap<(u8, i32), usize>| -> BTreeSet<(u8, i32)> { m.keys().copied().collect() };
    assert_eq!(tags(&before), tags(&after), "{after:?}");
    let names = [
        ((0, 30), "Origin"),
        ((1, 20), "Rim"),
        ((2, 1), "Left"),
        ((2, 2), "Right"),
        ((2, 3), "Walls"),
        ((3, 10), "Solid"),
    ];
    for (k, name) in names {
        assert_eq!(mesh.tag_names.get(&k).map(String::as_str), Some(name), "{k:?}");
    }
    assert!(after[&(1, 20)] > before[&(1, 20)], "the rim was not refined: {after:?}");
    for (k, n, _, _) in mesh.cells() {
        let q = |i: usize| mesh.points[n[i] as usize];
        match k {
            CellKind::Vertex => assert_eq!(q(0), [0.0, 0.0, 0.0]),
            CellKind::Line => {
                for q in [q(0), q(1)] {
                    let on_rim = q[0] == 0.0
                        && q[1..].iter().any(|&c| c.abs() < 1e-12 || (c - 1.0).abs() < 1e-12);
                    assert!(on_rim, "rim vertex {q:?}");
                }
            }
            _ => {}
        }
    }
    // Every tetrahedron positive, the volume the cube's.
    let volume = positive_volume(&mesh, 1e-12);
    assert!((volume - 1.0).abs() < 1e-9, "volume {volume}");
    // Each boundary triangle on the face its tag says.
    for (k, n, p, _) in mesh.cells() {
        if k == CellKind::Triangle {
            for &v in n {
                let q = mesh.points[v as usize];
                let on = match p {
                    1 => q[0].abs() < 1e-12,
                    2 => (q[0] - 1.0).abs() < 1e-12,
                    _ => q[1..].iter().any(|&c| c.abs() < 1e-12 || (c - 1.0).abs() < 1e-12),
                };
                assert!(on, "triangle of tag {p} has vertex {q:?} off its face");
            }
        }
    }
    // The metric lengths, integrated here from the analytic metric.
    let (median, share) = lengths(&mesh, &edges(&mesh, CellKind::Tetra), box_sizes);
    let (median0, share0) = lengths(&start, &edges(&start, CellKind::Tetra), box_sizes);
    eprintln!(
        "mmg3d box: {} -> {} tets, median metric length {median0:.3} -> {median:.3}, in [1/√2, √2] {share0:.3} -> {share:.3}",
        start.num_cells_of(CellKind::Tetra),
        mesh.num_cells_of(CellKind::Tetra)
    );
    assert!((0.8..=1.2).contains(&median), "median metric length {median}");
    assert!(share > 0.8 && share > share0, "share {share} (start {share0})");
}

#[test]
fn mmgs_adapts_the_box_cylinder_surface_keeping_its_references() {
    require_public_fixtures!();
    if program("mmgs_O3").is_none() {
        return;
    }
    let input = public_fixture("3d/box_cyl_surf_input.mesh");
    let start = read_path(&input, None).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let sol = dir.path().join("surf.sol");
    write_sol(&sol, &start, surface_sizes);
    let out = dir.path().join("surf.vtu");
    let o = run(&[
        "remesh",
        input.to_str().unwrap(),
        "--adapter",
        "mmgs",
        "--metric",
        sol.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--hausd",
        "0.01",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["adapter"], "mmgs");
    let mesh = read_path(&out, None).unwrap();
    assert_eq!(mesh.num_cells_of(CellKind::Tetra), 0);
    let (before, after) = (tag_counts(&start), tag_counts(&mesh));
    assert_eq!(before.keys().collect::<Vec<_>>(), after.keys().collect::<Vec<_>>(), "{after:?}");
    // Every vertex on the box's faces or on the cylinder (r = 0.2 about x = 0.6, y = 0.5):
    // between the input's facets, which span up to 54° of the circle (r down to 0.2 cos 27°
    // = 0.178), and MMG's smooth surface through the input's vertices.
    for q in &mesh.points {
        let on_box = [(q[0], 2.0), (q[1], 1.0), (q[2], 1.0)]
            .iter()
            .any(|&(c, hi)| c.abs() < 1e-9 || (c - hi).abs() < 1e-9);
        let r = (q[0] - 0.6).hypot(q[1] - 0.5);
        let chord = 0.2 * 27f64.to_radians().cos();
        assert!(on_box || (chord..0.21).contains(&r), "vertex {q:?} off the surface (r = {r})");
    }
    let (median, share) = lengths(&mesh, &edges(&mesh, CellKind::Triangle), surface_sizes);
    let (median0, share0) = lengths(&start, &edges(&start, CellKind::Triangle), surface_sizes);
    eprintln!(
        "mmgs surface: {} -> {} triangles, median metric length {median0:.3} -> {median:.3}, in [1/√2, √2] {share0:.3} -> {share:.3}",
        start.num_cells_of(CellKind::Triangle),
        mesh.num_cells_of(CellKind::Triangle)
    );
    assert!((0.8..=1.2).contains(&median), "median metric length {median}");
    assert!(share > 0.8 && share > share0, "share {share} (start {share0})");
}

#[test]
fn a_mesh_in_space_is_refused_by_the_planar_paths_naming_mmg3d() {
    require_public_fixtures!();
    let input = public_fixture("3d/box_cyl.v41_ascii.msh");
    let sol = public_fixture("3d/box_cyl_input.sol");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.msh");
    let (i, s, o) = (input.to_str().unwrap(), sol.to_str().unwrap(), out.to_str().unwrap());
    // The native remesher: bad input, naming the tools that take it.
    let r = run(&["remesh", i, "--metric", s, "-o", o, "--adapter", "native"]);
    assert_eq!(r.status.code(), Some(2), "{}", streams(&r));
    assert!(String::from_utf8_lossy(&r.stderr).contains("--adapter mmg3d"), "{}", streams(&r));
    // A 2D metric on a mesh in space.
    let flat = dir.path().join("flat.sol");
    let mut text = "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n634\n1 3\n".to_string();
    text += &"1 0 1\n".repeat(634);
    text += "End\n";
    std::fs::write(&flat, text).unwrap();
    let r = run(&["remesh", i, "--metric", flat.to_str().unwrap(), "-o", o]);
    assert_eq!(r.status.code(), Some(2), "{}", streams(&r));
    assert!(String::from_utf8_lossy(&r.stderr).contains("a 3D metric has"), "{}", streams(&r));
    // A planar-only option.
    let r = run(&["remesh", i, "--metric", s, "-o", o, "--split-quads"]);
    assert_eq!(r.status.code(), Some(2), "{}", streams(&r));
    // The loop in space: a planar remesher, or what only the planar loop does, is
    // refused before any work.
    let recipe = dir.path().join("r.toml");
    std::fs::write(&recipe, "[global]\nhmin = 0.01\nhmax = 0.5\n").unwrap();
    let r = run(&["adapt", i, "--recipe", recipe.to_str().unwrap(), "-o", o, "--adapter", "mmg2d"]);
    assert_eq!(r.status.code(), Some(2), "{}", streams(&r));
    assert!(String::from_utf8_lossy(&r.stderr).contains("goes to mmg3d"), "{}", streams(&r));
    let r = run(&["adapt", i, "--recipe", recipe.to_str().unwrap(), "-o", o, "--split-quads"]);
    assert_eq!(r.status.code(), Some(2), "{}", streams(&r));
    assert!(String::from_utf8_lossy(&r.stderr).contains("planar meshes only"), "{}", streams(&r));
    assert!(!out.exists());
    // The library: the planar adapters refuse adapt_space, naming mmg3d and mmgs.
    let mesh = read_path(&input, None).unwrap();
    let metric =
        smartmesh::MetricField::<smartmesh::metric::Sym3>::read_field(&sol, None, &mesh, &input)
            .unwrap()
            .into_tensors();
    let native = smartmesh::adapter(smartmesh::AdapterKind::Native, Default::default()).unwrap();
    let e = native.adapt_space(&mesh, &metric).unwrap_err().to_string();
    assert!(e.contains("mmg3d") && e.contains("mmgs"), "{e}");
}
