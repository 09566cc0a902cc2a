//! Neighbour propagation, distance to a 10^4-segment curve, on meshes of 10^4 to 10^6
//! vertices, next to its brute-force twin on the small sizes. Throughput is in vertex
//! evaluations (closest points computed) per second.
//!
//! - `free_curve/N`: jittered structured triangulation of the unit square with N
//!   vertices; the source is a closed wiggly curve of 10^4 segments that crosses cells
//!   (a free polyline), every vertex evaluated (max distance infinite).
//! - `border/N`: an O-mesh of 10^4 × (N / 10^4) vertices around a wavy closed curve
//!   whose 10^4 mesh edges are the source (distance to border).
//! - `brute_force/N`: `closest_point_brute_force` at every vertex of `free_curve/N`.
//!
//! Sequential (`with_parallel(false)`) unless the id says `parallel`: the numbers are
//! per core. Run: `cargo bench -p smartmesh --bench propagation`.
#![allow(clippy::print_stdout, clippy::print_stderr)] // A benchmark prints what it measured.

use std::f64::consts::PI;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use smartmesh::sizing::{closest_point_brute_force, propagate, PropagationOptions, Source};
use smartmesh::MeshGraph;
use smartmesh::Point2;

const SEGMENTS: usize = 10_000;

use smartmesh_test_support::{Generator, SplitMix64 as Rng};

/// Triangulates an `nx × ny` array of points (index `j * nx + i`), each quad split
/// along a random diagonal; `wrap` joins the last column to the first.
fn triangulate(coords: Vec<Point2>, nx: usize, ny: usize, wrap: bool, rng: &mut Rng) -> MeshGraph {
    let cols = if wrap { nx } else { nx - 1 };
    let mut edges = Vec::with_capacity(3 * cols * (ny - 1) + nx);
    let mut cells = Vec::with_capacity(2 * cols * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..cols {
            let i1 = (i + 1) % nx;
            let (a, b, c, d) = (j * nx + i, j * nx + i1, (j + 1) * nx + i1, (j + 1) * nx + i);
            let tris =
                if rng.unit() < 0.5 { [[a, b, c], [a, c, d]] } else { [[a, b, d], [b, c, d]] };
            for t in tris {
                cells.push([t[0], t[1], t[2], usize::MAX]);
                for k in 0..3 {
                    let (p, q) = (t[k], t[(k + 1) % 3]);
                    edges.push([p.min(q), p.max(q)]);
                }
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    MeshGraph::from_edges(coords, &edges, &cells).unwrap()
}

fn jittered_square(n: usize, seed: u64) -> MeshGraph {
    let mut rng = Rng(seed);
    let h = 1.0 / (n - 1) as f64;
    let mut coords = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let mut p = [i as f64 * h, j as f64 * h];
            if i > 0 && i + 1 < n && j > 0 && j + 1 < n {
                p[0] += (2.0 * rng.unit() - 1.0) * 0.3 * h;
                p[1] += (2.0 * rng.unit() - 1.0) * 0.3 * h;
            }
            coords.push(p);
        }
    }
    triangulate(coords, n, n, false, &mut rng)
}

fn wiggly_curve(k: usize, centre: Point2, r: f64) -> Vec<Point2> {
    (0..k)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / k as f64;
            let rr = r * (1.0 + 0.3 * (7.0 * a).cos() + 0.03 * (90.0 * a).sin());
            [centre[0] + rr * a.cos(), centre[1] + rr * a.sin()]
        })
        .collect()
}

/// O-mesh: `SEGMENTS` points around, `layers` rings out from a wavy curve.
fn o_mesh(layers: usize, seed: u64) -> MeshGraph {
    let mut rng = Rng(seed);
    let mut coords = Vec::with_capacity(SEGMENTS * layers);
    for j in 0..layers {
        for i in 0..SEGMENTS {
            let a = 2.0 * PI * i as f64 / SEGMENTS as f64;
            let r = 1.0 + 0.1 * (5.0 * a).cos() + j as f64 * 0.004;
            coords.push([r * a.cos(), r * a.sin()]);
        }
    }
    triangulate(coords, SEGMENTS, layers, true, &mut rng)
}

fn bench(c: &mut Criterion) {
    let seq = PropagationOptions::new().with_parallel(false);
    let mut group = c.benchmark_group("propagation");
    group.sample_size(10);
    for n in [100usize, 317, 1000] {
        let graph = jittered_square(n, 7);
        let curve = wiggly_curve(SEGMENTS, [0.5, 0.5], 0.3);
        let source = Source::builder(&graph).polyline(&curve, true).build().unwrap();
        let reach = propagate(&graph, &source, f64::INFINITY, &seq);
        let r = reach.report();
        eprintln!(
            "free_curve/{}: {} evaluated, {} corrected, {:.1} boxes and {:.1} segments per vertex",
            graph.num_vertices(),
            r.evaluated,
            r.corrected,
            r.boxes_tested as f64 / r.evaluated as f64,
            r.segments_tested as f64 / r.evaluated as f64
        );
        group.throughput(Throughput::Elements(r.evaluated as u64));
        group.bench_function(BenchmarkId::new("free_curve", graph.num_vertices()), |b| {
            b.iter(|| propagate(&graph, &source, f64::INFINITY, &seq))
        });
        if n == 1000 {
            let par = PropagationOptions::new();
            group.bench_function(
                BenchmarkId::new("free_curve_parallel", graph.num_vertices()),
                |b| b.iter(|| propagate(&graph, &source, f64::INFINITY, &par)),
            );
        }
        if n <= 317 {
            group.throughput(Throughput::Elements(graph.num_vertices() as u64));
            group.bench_function(BenchmarkId::new("brute_force", graph.num_vertices()), |b| {
                b.iter(|| {
                    (0..graph.num_vertices())
                        .map(|v| {
                            closest_point_brute_force(&source, graph.point(v)).unwrap().distance
                        })
                        .sum::<f64>()
                })
            });
        }
    }
    for layers in [10usize, 100] {
        let graph = o_mesh(layers, 9);
        let border: Vec<usize> = (0..SEGMENTS).collect();
        let source = Source::builder(&graph).mesh_polyline(&border, true).build().unwrap();
        let reach = propagate(&graph, &source, f64::INFINITY, &seq);
        let r = reach.report();
        eprintln!(
            "border/{}: {} evaluated, {} corrected, {:.1} boxes and {:.1} segments per vertex",
            graph.num_vertices(),
            r.evaluated,
            r.corrected,
            r.boxes_tested as f64 / r.evaluated as f64,
            r.segments_tested as f64 / r.evaluated as f64
        );
        group.throughput(Throughput::Elements(r.evaluated as u64));
        group.bench_function(BenchmarkId::new("border", graph.num_vertices()), |b| {
            b.iter(|| propagate(&graph, &source, f64::INFINITY, &seq))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
