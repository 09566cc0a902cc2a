//! The adaptation loop on meshes in space through the library
//! ([`smartmesh::adapt::space::run_space`]) with the real remeshers: a tetrahedral box
//! through `mmg3d_O3` to the UGAWG's linear metric (its layer thickened to h0 = 0.02 so
//! that the mesh stays at a few thousand tetrahedra), a triangulated surface through
//! `mmgs_O3`. The field is analytic, given as a function, and every check is made here
//! apart from the library: each tetrahedron's orientation, the volume, the tags and names
//! in the file written, the history on disk (one row per iteration, naming the mesh on
//! disk), and the metric lengths of the best mesh's edges integrated from the analytic
//! metric.
//!
//! Needs `mmg3d_O3`/`mmgs_O3` on PATH (skipped with a message without them, mandatory
//! under CI) and the public fixtures for the surface case.

use std::collections::BTreeSet;

use smartmesh::adapt::files::ResultFiles;
use smartmesh::adapt::space::{run_space, SpaceField, SpaceSizingError};
use smartmesh::formats::{read_path, CellKind, TaggedMesh};
use smartmesh::metric::Sym3;
use smartmesh::{adapter, AdaptOptions, AdapterKind, AdapterOptions, History};
use smartmesh_test_support::formats::public_fixture;
use smartmesh_test_support::grid::kuhn_box;
use smartmesh_test_support::require_public_fixtures;
use smartmesh_test_support::space::positive_volume;

#[path = "support/cli.rs"]
mod support;
use support::program;

/// The UGAWG linear sizes (benches/ugawg3d.py) with h0 = 0.02: h_x = h_y = 0.1,
/// h_z = h0 + 2 (0.1 − h0) |z − 0.5|.
fn linear_sizes(p: [f64; 3]) -> [f64; 3] {
    [0.1, 0.1, 0.02 + 2.0 * (0.1 - 0.02) * (p[2] - 0.5).abs()]
}

/// Sizes along the axes for the surface: fine across x near x = 0.
fn surface_sizes(p: [f64; 3]) -> [f64; 3] {
    [0.04 + 0.04 * p[0], 0.1, 0.12]
}

/// diag(h⁻²) of `sizes` at every vertex.
fn field(
    sizes: fn([f64; 3]) -> [f64; 3],
) -> impl Fn(&TaggedMesh) -> Result<SpaceField, SpaceSizingError> {
    move |mesh: &TaggedMesh| {
        let metric = mesh
            .points
            .iter()
            .map(|&p| {
                let h = sizes(p);
                Sym3 { xx: h[0].powi(-2), yy: h[1].powi(-2), zz: h[2].powi(-2), ..Sym3::ZERO }
            })
            .collect();
        Ok(SpaceField { metric, warnings: Vec::new() })
    }
}

/// The metric length of a–b under diag(sizes⁻²), midpoint rule on 16 pieces.
fn metric_length(a: [f64; 3], b: [f64; 3], sizes: fn([f64; 3]) -> [f64; 3]) -> f64 {
    let e = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    (0..16)
        .map(|k| {
            let t = (k as f64 + 0.5) / 16.0;
            let h = sizes([a[0] + t * e[0], a[1] + t * e[1], a[2] + t * e[2]]);
            (0..3).map(|i| (e[i] / h[i]).powi(2)).sum::<f64>().sqrt() / 16.0
        })
        .sum()
}

/// The median metric length of the edges of `kind`'s cells.
fn median_length(mesh: &TaggedMesh, kind: CellKind, sizes: fn([f64; 3]) -> [f64; 3]) -> f64 {
    let k = kind.nodes_per_cell();
    let mut edges = BTreeSet::new();
    for (c, n, _, _) in mesh.cells() {
        if c == kind {
            for i in 0..k {
                for j in i + 1..k {
                    edges.insert((n[i].min(n[j]), n[i].max(n[j])));
                }
            }
        }
    }
    let mut l: Vec<f64> = edges
        .iter()
        .map(|&(a, b)| metric_length(mesh.points[a as usize], mesh.points[b as usize], sizes))
        .collect();
    l.sort_by(f64::total_cmp);
    l[l.len() / 2]
}

/// The physical tags of each dimension's cells.
fn tags(mesh: &TaggedMesh) -> BTreeSet<(u8, i32)> {
    mesh.cells().map(|(k, _, p, _)| (k.dim(), p)).collect()
}

#[test]
fn mmg3d_adapts_a_box_to_the_linear_metric_keeping_tags_names_and_the_best_mesh() {
    if program("mmg3d_O3").is_none() {
        return;
    }
    let mut start = kuhn_box(3, [1.0; 3]);
    for (side, name) in ["Left", "Right", "Front", "Back", "Bottom", "Top"].iter().enumerate() {
        start.tag_names.insert((2, 11 + side as i32), name.to_string());
    }
    start.tag_names.insert((3, 1), "Solid".into());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("box.msh");
    let mut files = ResultFiles::new(&out, None, Default::default());
    let mmg3d = adapter(AdapterKind::Mmg3d, AdapterOptions::default()).unwrap();
    let options = AdaptOptions { max_iterations: 6, ..AdaptOptions::default() };
    let sizing = field(linear_sizes);
    let outcome =
        run_space(start.clone(), &sizing, mmg3d.as_ref(), &options, "box", "linear", &mut files)
            .unwrap();
    assert!(outcome.failure.is_none(), "{:?}", outcome.failure);
    let h = &outcome.history;
    // The history on disk: a row per iteration, naming the mesh on disk.
    let text = std::fs::read_to_string(dir.path().join("box.history.json")).unwrap();
    let disk = History::from_json(&text).unwrap();
    assert_eq!(&disk.iterations, &h.iterations);
    assert_eq!(disk.mismatch(&out), None);
    assert!(h.iterations.len() >= 3, "{}", h.stopped);
    for r in &h.iterations {
        let s = r.space.as_ref().unwrap();
        assert_eq!(s.cell, "tetrahedron");
        eprintln!(
            "iteration {}: {} vertices, {} tets, {:.1}% conforming, mean ratio {:.3} (min {:.3}), {:.3} s sizing+measure, {:.3} s remeshing",
            r.iteration,
            r.vertices,
            s.cells,
            100.0 * r.conforming_share,
            r.mean_quality,
            r.min_quality,
            r.seconds.size + r.seconds.measure,
            r.seconds.remesh
        );
    }
    let best = &h.iterations[h.best_iteration];
    assert!(h.iterations.iter().all(|r| r.conforming_share <= best.conforming_share));
    assert!(best.conforming_share > 0.6, "{best:?}");
    // The mesh written: every tetrahedron positive, the cube's volume, every tag and name.
    let mesh = read_path(&out, None).unwrap();
    assert_eq!(mesh.points.len(), best.vertices);
    let volume = positive_volume(&mesh, 0.0);
    assert!((volume - 1.0).abs() < 1e-9, "volume {volume}");
    assert_eq!(tags(&mesh), tags(&start));
    assert_eq!(mesh.tag_names, start.tag_names);
    let median = median_length(&mesh, CellKind::Tetra, linear_sizes);
    let median0 = median_length(&start, CellKind::Tetra, linear_sizes);
    eprintln!("median metric length {median0:.3} -> {median:.3}");
    assert!((0.7..=1.3).contains(&median), "median metric length {median}");
    // The field it was measured against is in the file.
    assert_eq!(mesh.point_data["metric"].components, 9);
}

#[test]
fn mmgs_adapts_a_surface_in_space_keeping_its_references() {
    require_public_fixtures!();
    if program("mmgs_O3").is_none() {
        return;
    }
    let start = read_path(&public_fixture("3d/box_cyl_surf_input.mesh"), None).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("surf.vtu");
    let mut files = ResultFiles::new(&out, None, Default::default());
    let options = AdapterOptions { hausd: Some(0.01), ..AdapterOptions::default() };
    let mmgs = adapter(AdapterKind::Mmgs, options).unwrap();
    let o = AdaptOptions { max_iterations: 3, ..AdaptOptions::default() };
    let sizing = field(surface_sizes);
    let outcome =
        run_space(start.clone(), &sizing, mmgs.as_ref(), &o, "surf", "axes", &mut files).unwrap();
    assert!(outcome.failure.is_none(), "{:?}", outcome.failure);
    let h = &outcome.history;
    let s0 = h.iterations[0].conforming_share;
    let best = &h.iterations[h.best_iteration];
    assert_eq!(best.space.as_ref().unwrap().cell, "triangle");
    assert!(best.conforming_share > s0 && best.conforming_share > 0.6, "{s0} -> {best:?}");
    let mesh = read_path(&out, None).unwrap();
    assert_eq!(mesh.num_cells_of(CellKind::Tetra), 0);
    assert_eq!(tags(&mesh), tags(&start));
    let median = median_length(&mesh, CellKind::Triangle, surface_sizes);
    assert!((0.7..=1.3).contains(&median), "median metric length {median}");
    // No complexity on a surface: no growth limit, and nothing refused.
    assert!(h.iterations[1].remeshing.as_ref().unwrap().growth_limited_to.is_none());
}
