//! The mesher on a NACA 0012 airfoil (256 points per side, closed trailing edge) in the
//! far-field box [-2, 3] x [-2, 2], minimum angle 30°, area bounds 2e-3, 2e-4 and 2e-5
//! (about 20 000, 160 000 and 1.57 million triangles): Triangle's `-pq30Aa<area>a` on the
//! same graph is the baseline, timed by `benches/compare_triangle.py` on the `.poly` this
//! bench writes to `target/bench-meshes/mesher-naca256.poly`.
//!
//! - `mesher/triangulate/AREA`: `smartmesh::mesher::triangulate`, the whole job (graph
//!   checks, spade's bulk load and refinement, domain flood fills, the area pass,
//!   segment walks, corners, the output mesh);
//! - `mesher/spade_refine/AREA`: spade alone on the same graph and parameters (bulk load
//!   and `refine` with outer faces excluded), what the rest is measured against.
//!
//! - `mesher/square_hole_triangulate/1e-6` and `mesher/square_hole_spade_refine/1e-6`:
//!   the same on `fixtures/square_hole.poly` (two regions with an interface and a hole,
//!   about 1.5 million triangles), where spade's exclusion of outer faces cannot be used
//!   and both refine the hole too; Triangle's baseline is `-pq30Aa0.000001a`.
//!
//! Before timing, each case prints its triangle count, smallest angle and mean quality.
//!
//! Run: `cargo bench -p smartmesh --bench mesher`, then
//! `python3 benches/compare_triangle.py target/bench-meshes/mesher-naca256.poly` and
//! `python3 benches/compare_triangle.py fixtures/square_hole.poly 0.000001`.
#![allow(clippy::print_stdout, clippy::print_stderr)] // A benchmark prints what it measured.

use std::path::Path;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use smartmesh::formats::{read_path, write_path, CellKind, TaggedMesh, WriteOptions};
use smartmesh::mesher::{triangulate, MeshOptions};
use smartmesh_test_support::measure::{min_angle_deg, quality as triangle_quality};
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

const AREAS: [f64; 3] = [2e-3, 2e-4, 2e-5];
const MIN_ANGLE: f64 = 30.0;
/// Area bound on `fixtures/square_hole.poly` (about 1.5 million triangles).
const SQUARE_AREA: f64 = 1e-6;

/// Half thickness of the NACA 0012 with a closed trailing edge (as fixtures/make_poly.py).
fn naca0012(x: f64) -> f64 {
    0.6 * (0.2969 * x.sqrt() - 0.1260 * x - 0.3516 * x.powi(2) + 0.2843 * x.powi(3)
        - 0.1036 * x.powi(4))
}

/// The graph of `fixtures/make_poly.py`'s `airfoil_poly(n)`, same points in the same order.
fn airfoil(n: usize) -> TaggedMesh {
    let (x0, x1, y0, y1) = (-2.0, 3.0, -2.0, 2.0);
    let mut pts = vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    let mut segs = vec![(0, 1, 3), (1, 2, 2), (2, 3, 3), (3, 0, 1)];
    let xs: Vec<f64> =
        (0..=n).map(|i| 0.5 * (1.0 - (std::f64::consts::PI * i as f64 / n as f64).cos())).collect();
    let mut foil = vec![[1.0, 0.0]];
    foil.extend(xs[1..n].iter().rev().map(|&x| [x, naca0012(x)]));
    foil.push([0.0, 0.0]);
    foil.extend(xs[1..n].iter().map(|&x| [x, -naca0012(x)]));
    let base = pts.len();
    let m = foil.len();
    pts.extend(foil);
    segs.extend((0..m).map(|i| (base + i, base + (i + 1) % m, 4)));
    let mut mesh = TaggedMesh::new();
    mesh.points = pts.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let b = mesh.block_mut(CellKind::Line);
    for (a, c, t) in segs {
        b.push(&[a, c], t, t);
    }
    mesh.holes.push([0.5, 0.0]);
    mesh.regions.push(smartmesh::formats::RegionSeed {
        point: [x0 + 0.5, 0.0],
        attribute: 1.0,
        max_area: -1.0,
    });
    mesh
}

fn spade_only(pslg: &TaggedMesh, area: f64, exclude: bool) -> usize {
    let pts: Vec<Point2<f64>> = pslg.points.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let edges: Vec<[usize; 2]> = pslg
        .cells()
        .filter(|c| c.0 == CellKind::Line)
        .map(|c| [c.1[0] as usize, c.1[1] as usize])
        .collect();
    let mut cdt =
        ConstrainedDelaunayTriangulation::<Point2<f64>>::bulk_load_cdt(pts, edges).unwrap();
    let r = cdt.refine(
        RefinementParameters::<f64>::new()
            .with_angle_limit(AngleLimit::from_deg(MIN_ANGLE))
            .with_max_allowed_area(area)
            .exclude_outer_faces(exclude)
            .with_max_additional_vertices(usize::MAX / 4),
    );
    cdt.num_inner_faces() - r.excluded_faces.len()
}

/// Prints count, smallest angle and mean quality of one mesh, and returns the count.
fn report(label: &str, pslg: &TaggedMesh, opts: &MeshOptions, spade_alone: usize) -> usize {
    let out = triangulate(pslg, opts).unwrap();
    let p = |v: u32| [out.points[v as usize][0], out.points[v as usize][1]];
    let (mut n, mut amin, mut q) = (0usize, f64::INFINITY, 0.0);
    for (kind, t, _, _) in out.cells() {
        if kind == CellKind::Triangle {
            n += 1;
            amin = amin.min(min_angle_deg(p(t[0]), p(t[1]), p(t[2])));
            q += triangle_quality(p(t[0]), p(t[1]), p(t[2]));
        }
    }
    eprintln!("{label}: {n} triangles, smallest angle {amin:.3}, mean quality {:.4}, {} points; spade alone {spade_alone} triangles", q / n as f64, out.points.len());
    n
}

fn bench(c: &mut Criterion) {
    let pslg = airfoil(256);
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench-meshes");
    std::fs::create_dir_all(&dir).unwrap();
    write_path(&dir.join("mesher-naca256.poly"), &pslg, None, &WriteOptions::default()).unwrap();
    let mut g = c.benchmark_group("mesher");
    g.sample_size(10);

    // A graph with an interface between two regions: spade's exclusion of outer faces
    // does not apply, holes are refined and carved (see the mesher's refine module).
    let square =
        read_path(&Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/square_hole.poly"), None)
            .unwrap();
    let opts = MeshOptions {
        min_angle_deg: MIN_ANGLE,
        max_area: Some(SQUARE_AREA),
        ..MeshOptions::default()
    };
    let n = report(
        &format!("square_hole, area {SQUARE_AREA:e}"),
        &square,
        &opts,
        spade_only(&square, SQUARE_AREA, false),
    );
    g.throughput(Throughput::Elements(n as u64));
    g.bench_with_input(
        BenchmarkId::new("square_hole_triangulate", SQUARE_AREA),
        &SQUARE_AREA,
        |b, _| b.iter(|| triangulate(&square, &opts).unwrap()),
    );
    g.bench_with_input(
        BenchmarkId::new("square_hole_spade_refine", SQUARE_AREA),
        &SQUARE_AREA,
        |b, &a| b.iter(|| spade_only(&square, a, false)),
    );

    for area in AREAS {
        let opts = MeshOptions {
            min_angle_deg: MIN_ANGLE,
            max_area: Some(area),
            ..MeshOptions::default()
        };
        let n =
            report(&format!("naca256, area {area:e}"), &pslg, &opts, spade_only(&pslg, area, true));
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("triangulate", area), &area, |b, _| {
            b.iter(|| triangulate(&pslg, &opts).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("spade_refine", area), &area, |b, &a| {
            b.iter(|| spade_only(&pslg, a, true))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
