//! Exact closest points on a surface in space (`geometry::space::SurfaceIndex`, what
//! the 3D DISTANCE_TO_BORDER asks for every mesh vertex) against parry3d's `TriMesh`
//! projection (crate `parry3d-f64`, its BVH and its triangle projection) on the same
//! data in the same run.
//!
//! - Surface: a bumpy torus (radii 1 and 0.4, the tube's radius varied by 10 %) of
//!   250 × 200 quads split in two: 10^5 triangles.
//! - Queries: the vertices of a volume mesh around it, a jittered grid filling the box
//!   [-1.6, 1.6]² × [-0.8, 0.8] (inside and outside the tube), in grid order, given alike
//!   to both: 10^5 by default, `SURFACE_BENCH_QUERIES=1000000` for the full 10^6.
//!   Why the whole box and not a thin shell: DISTANCE_TO_BORDER asks for every vertex
//!   of the volume mesh, and the far ones (on the tube's axis, in the torus' hole,
//!   where many triangles are nearly equally far) are the costly queries.
//! - `smartmesh/1thread`: `closest_many` (Morton order, seeded queries) in a rayon pool
//!   of one thread; `parry/1thread`: `project_local_point_and_get_location` (the
//!   triangle and feature, as ours gives) in a plain loop. Both per core. The `2threads`
//!   ids run each on a pool of two.
//!
//! First `SURFACE_BENCH_ROUNDS` (default 3) timed passes of each on one thread,
//! alternating, whose medians give the summary line. Every query is checked: the
//! distances agree within 1e-12 and ours equal the brute-force scan bit for bit on a
//! sample. Then criterion's runs. Run:
//! `cargo bench -p smartmesh --bench surface_distance` (add the variable for 10^6).
//!
//! The index's files are compiled here on their own (`#[path]`): the library keeps its
//! geometry private, and these files import nothing else of it.
#![allow(clippy::print_stdout, clippy::print_stderr)] // A benchmark prints what it measured.

#[allow(dead_code, unreachable_pub)]
#[path = "../src/geometry/space/triangle.rs"]
mod triangle;

#[allow(dead_code, unreachable_pub)]
#[path = "../src/geometry/space/surface_index.rs"]
mod surface_index;

use std::f64::consts::TAU;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use parry3d_f64::math::Vector;
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::TriMesh;
use rayon::prelude::*;
use smartmesh_test_support::{Generator, SplitMix64};

use surface_index::{closest_brute, triangle_geoms, SurfaceIndex};
use triangle::Point3;

/// The bumpy torus: `nu × nv` quads, each split in two.
fn bumpy_torus(nu: usize, nv: usize) -> (Vec<Point3>, Vec<[u32; 3]>) {
    let mut pts = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (u, v) = (TAU * i as f64 / nu as f64, TAU * j as f64 / nv as f64);
            let small = 0.4 * (1.0 + 0.1 * (7.0 * u).sin() * (5.0 * v).cos());
            let r = 1.0 + small * v.cos();
            pts.push([r * u.cos(), r * u.sin(), small * v.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + j % nv) as u32;
    let mut tris = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (pts, tris)
}

/// About `n` points of a jittered grid in the box around the torus, in grid order.
fn volume_points(n: usize) -> Vec<Point3> {
    let (lo, hi) = ([-1.6, -1.6, -0.8], [1.6, 1.6, 0.8]);
    // Cells of equal sides: nx = ny = 2 nz.
    let nz = ((n as f64 / 4.0).cbrt().round() as usize).max(1);
    let (nx, ny) = (2 * nz, 2 * nz);
    let h = [(hi[0] - lo[0]) / nx as f64, (hi[1] - lo[1]) / ny as f64, (hi[2] - lo[2]) / nz as f64];
    let mut rng = SplitMix64(42);
    let mut pts = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let c = [i, j, k];
                pts.push(std::array::from_fn(|a| {
                    lo[a] + h[a] * (c[a] as f64 + 0.2 + 0.6 * rng.unit())
                }));
            }
        }
    }
    pts
}

fn parry_mesh(pts: &[Point3], tris: &[[u32; 3]]) -> TriMesh {
    let verts: Vec<Vector> = pts.iter().map(|p| Vector::new(p[0], p[1], p[2])).collect();
    TriMesh::new(verts, tris.to_vec()).expect("a valid torus")
}

fn parry_distances(mesh: &TriMesh, queries: &[Point3]) -> Vec<(f64, u32)> {
    queries
        .iter()
        .map(|q| {
            let p = Vector::new(q[0], q[1], q[2]);
            let (proj, (tri, _)) = mesh.project_local_point_and_get_location(p, false);
            ((proj.point - p).length(), tri)
        })
        .collect()
}

/// The median of `times` (the upper one of an even count).
fn median(times: &mut [f64]) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool")
}

fn bench(c: &mut Criterion) {
    let n: usize =
        std::env::var("SURFACE_BENCH_QUERIES").ok().and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let (pts, tris) = bumpy_torus(250, 200);
    let queries = volume_points(n);
    let n = queries.len();

    let t = Instant::now();
    let index = SurfaceIndex::new(&pts, &tris).expect("a valid torus");
    let build_ours = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let mesh = parry_mesh(&pts, &tris);
    let build_parry = t.elapsed().as_secs_f64();

    // Timed passes on one thread, ours and parry's alternating (the machine's load
    // changes from second to second: alternating gives both the same share of it), the
    // medians reported; then the checks.
    let rounds: usize =
        std::env::var("SURFACE_BENCH_ROUNDS").ok().and_then(|s| s.parse().ok()).unwrap_or(3);
    let one = pool(1);
    let (mut times_ours, mut times_parry) = (Vec::new(), Vec::new());
    let (mut ours, mut theirs) = (Vec::new(), Vec::new());
    for _ in 0..rounds.max(1) {
        let t = Instant::now();
        ours = one.install(|| index.closest_many(&queries));
        times_ours.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        theirs = parry_distances(&mesh, &queries);
        times_parry.push(t.elapsed().as_secs_f64());
    }
    let (t_ours, t_parry) = (median(&mut times_ours), median(&mut times_parry));
    let mut worst: f64 = 0.0;
    let mut other_triangle = 0usize;
    for (o, (d, tri)) in ours.iter().zip(&theirs) {
        let o = o.expect("finite queries have an answer");
        worst = worst.max((o.distance() - d).abs());
        other_triangle += usize::from(o.triangle != *tri);
    }
    assert!(worst < 1e-12, "distances differ from parry's by {worst:e}");
    let geoms = triangle_geoms(&pts, &tris).expect("a valid torus");
    for i in (0..n).step_by((n / 200).max(1)) {
        assert_eq!(ours[i], closest_brute(&geoms, queries[i]), "query {i}");
    }
    let (q_ours, q_parry) = (n as f64 / t_ours, n as f64 / t_parry);
    println!(
        "surface_distance: {} triangles, {n} queries; build {:.3} s (parry {:.3} s); one thread, \
         median of {rounds} alternating passes: smartmesh {:.3e} queries/s, parry {:.3e} \
         queries/s, ratio {:.2}; \
         largest |distance difference| {worst:.1e}, {other_triangle} queries on another \
         triangle of equal distance; 200 sampled queries equal to the brute-force scan",
        tris.len(),
        build_ours,
        build_parry,
        q_ours,
        q_parry,
        q_ours / q_parry
    );

    let mut group = c.benchmark_group("surface_distance");
    group.sample_size(10);
    group.throughput(Throughput::Elements(n as u64));
    for threads in [1, 2] {
        let p = pool(threads);
        group.bench_function(BenchmarkId::new("smartmesh", format!("{threads}thread")), |b| {
            b.iter(|| p.install(|| index.closest_many(&queries)))
        });
        group.bench_function(BenchmarkId::new("parry", format!("{threads}thread")), |b| {
            b.iter(|| {
                p.install(|| {
                    queries
                        .par_chunks(1024)
                        .flat_map_iter(|ch| parry_distances(&mesh, ch))
                        .collect::<Vec<_>>()
                })
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
