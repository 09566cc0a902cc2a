//! The six sizing algorithms, each as a one-step plan run by `compute_size_field`, on
//! O-meshes of 10^4 to 4·10^6 vertices around a wavy closed border, next to the
//! brute-force twin of their closest-point search. Throughput is in vertex
//! evaluations (a closest point and a size tensor per reached vertex) per second.
//!
//! Single-thread runs are timed in CPU time of the process (`/proc/self/task/*/schedstat`,
//! summed over its threads; wall time where there is no such file): on a machine that
//! other processes share, wall time also counts the time they held the core.
//!
//! - `<algorithm>/N`: one rayon thread (per core), N vertices, every algorithm with the
//!   same reach on every mesh (ten rings from a border, 0.2 from the point; UNIFORM
//!   covers the face): the vertices reached stay near 10^5 while N grows 400-fold.
//! - `brute_force_<algorithm>/10000`: the twin on one thread: every source segment
//!   scanned for every vertex (`closest_point_brute_force`), then the tensor of
//!   DISTANCE_TO_BORDER (for DISTANCE_TO_POINT the exact isotropic size); for
//!   DISTANCE_BETWEEN_TWO_BORDERS both borders are scanned. UNIFORM searches nothing,
//!   so it has no twin.
//! - `distance_to_border_full_reach[_2_threads|_cpu_time]/N`, N up to 10^6: every
//!   vertex reached, in wall time on one thread and on two, and in CPU time on one;
//!   `brute_force_distance_to_border_full_reach/N` up to 10^5.
//!   The bench prints the index's work per vertex for these runs.
//!
//! Meshes: (around, layers) = (2000, 5), (10^4, 10), (10^4, 100), (10^4, 400): ring j
//! at r(a) = 1 + 0.1 cos 5a + 0.004 j, angle a = 2π i / around, quads split along a
//! seeded random diagonal. Tags: the inner ring is curve 1 (the border, `around`
//! segments), ring 8 (or the outer ring of a thinner mesh) curve 2, the triangles face 1, and a vertex half-way out
//! at angle 0 is topological point 5. The imaginary polyline is a radial wake at angle
//! π/3 across every ring but the first and the last, 1000 points.
//!
//! `SMARTMESH_BENCH_MAX_VERTICES=n` skips the meshes above n vertices (default 4·10^6).
//! `SMARTMESH_BENCH_DUMP=dir` writes each mesh's points and border segments as
//! little-endian f64 files for `benches/compare_ckdtree.py` (scipy on the same bytes).
//!
//! Run: `cargo bench -p smartmesh --bench sizing`.
#![allow(clippy::print_stdout, clippy::print_stderr)] // A benchmark prints what it measured.

use std::f64::consts::PI;
use std::time::Duration;

use criterion::{
    criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode, Throughput,
};
use smartmesh::formats::{CellBlock, CellKind, TaggedMesh};
use smartmesh::sizing::{
    closest_point_brute_force, compute_size_field, propagate, Algorithm, CurvatureOfBorder,
    CurvatureToSize, DistanceBetweenTwoBorders, DistanceFunction, DistanceToBorder,
    DistanceToImaginaryPolyline, DistanceToPoint, EntitySet, PolylinePoints, PropagationOptions,
    SizeProjectionFunction, SizingPlan, Source, Step, Uniform,
};
use smartmesh::{MeshGraph, SizeTensor, Topology};

use smartmesh_test_support::{Generator, SplitMix64 as Rng};

const SPACING: f64 = 0.004;

struct Case {
    mesh: TaggedMesh,
    topology: Topology,
    graph: MeshGraph,
    around: usize,
    layers: usize,
}

impl Case {
    fn curve(&self, tag: i32) -> usize {
        self.topology.curves.iter().position(|c| c.tag == Some(tag)).expect("tagged curve")
    }
    fn point(&self, tag: i32) -> usize {
        self.topology.points.iter().position(|p| p.tag == Some(tag)).expect("tagged point")
    }
    fn face(&self, tag: i32) -> usize {
        self.topology.faces.iter().position(|f| f.tag == tag).expect("tagged face")
    }
    fn curves(&self, tag: i32) -> EntitySet {
        EntitySet { curves: vec![self.curve(tag)], ..EntitySet::default() }
    }
    /// Outer radius of the mesh, an upper bound on every distance in it.
    fn extent(&self) -> f64 {
        2.0 * (1.1 + SPACING * self.layers as f64)
    }
    fn wake(&self) -> Vec<[f64; 2]> {
        // At a = π/3 the inner ring is at r = 1 + 0.1 cos(5π/3) = 1.05: the wake runs
        // from half a ring spacing out to half a spacing inside the outer ring.
        let a = PI / 3.0;
        let (r0, r1) = (1.05 + 0.5 * SPACING, 1.05 + SPACING * (self.layers as f64 - 1.5));
        (0..1000)
            .map(|k| r0 + (r1 - r0) * k as f64 / 999.0)
            .map(|r| [r * a.cos(), r * a.sin()])
            .collect()
    }
}

fn o_mesh(around: usize, layers: usize) -> Case {
    let mut mesh = TaggedMesh::new();
    mesh.points.reserve(around * layers);
    for j in 0..layers {
        for i in 0..around {
            let a = 2.0 * PI * i as f64 / around as f64;
            let r = 1.0 + 0.1 * (5.0 * a).cos() + j as f64 * SPACING;
            mesh.points.push([r * a.cos(), r * a.sin(), 0.0]);
        }
    }
    let mut rng = Rng(9);
    let mut tris = CellBlock::new(CellKind::Triangle);
    for j in 0..layers - 1 {
        for i in 0..around {
            let i1 = (i + 1) % around;
            let (a, b, c, d) =
                (j * around + i, j * around + i1, (j + 1) * around + i1, (j + 1) * around + i);
            if rng.bit() {
                tris.push(&[a, b, c], 1, 1);
                tris.push(&[a, c, d], 1, 1);
            } else {
                tris.push(&[a, b, d], 1, 1);
                tris.push(&[b, c, d], 1, 1);
            }
        }
    }
    let mut lines = CellBlock::new(CellKind::Line);
    // Curve 2, the second wall of DISTANCE_BETWEEN_TWO_BORDERS: ring 8 (0.032 out,
    // inside the reach of the table's runs), or the outer ring of a thinner mesh.
    let second = (layers - 1).min(8) * around;
    for i in 0..around {
        lines.push(&[i, (i + 1) % around], 1, 1);
    }
    for i in 0..around {
        lines.push(&[second + i, second + (i + 1) % around], 2, 2);
    }
    let mut point = CellBlock::new(CellKind::Vertex);
    point.push(&[(layers / 2) * around], 5, 5);
    mesh.blocks = vec![point, lines, tris];
    let topology = Topology::from_mesh(&mesh);
    let graph = MeshGraph::from_topology(&topology, &mesh).unwrap();
    Case { mesh, topology, graph, around, layers }
}

fn df(s0: f64, s1: f64, dmax: f64, e: f64) -> DistanceFunction {
    DistanceFunction::try_new(s0, s1, dmax, e).unwrap()
}

/// The border functions (perpendicular, parallel) of DISTANCE_TO_BORDER and its twin,
/// reaching `d` from the border.
fn border_functions(d: f64) -> (DistanceFunction, DistanceFunction) {
    (df(0.001, 0.1, d, 1.5), df(0.01, 0.2, d, 1.0))
}

/// How far the sources of the six-algorithm table reach: ten rings from a border
/// (about 64 border segments of the 10^4-segment border), 0.2 from the point. The same
/// reach on every mesh, so that the vertices reached stay near 10^5 while the mesh
/// grows to 4·10^6: the cost must follow the vertices reached, not the mesh.
const REACH: f64 = 10.0 * SPACING;
const POINT_REACH: f64 = 0.2;

/// The six algorithms as `(name, algorithm)`, each reaching `reach` from its sources.
fn algorithms(case: &Case, reach: f64) -> Vec<(&'static str, Algorithm)> {
    let d = reach;
    let (perpendicular, parallel) = border_functions(d);
    let projection = SizeProjectionFunction::try_new(0.2, d, 1.0).unwrap();
    vec![
        (
            "uniform",
            Algorithm::Uniform(Uniform {
                size: 0.05,
                on: EntitySet { faces: vec![case.face(1)], ..EntitySet::default() },
            }),
        ),
        (
            "distance_to_point",
            Algorithm::DistanceToPoint(DistanceToPoint {
                function: df(0.001, 0.1, POINT_REACH.max(reach), 1.0),
                sources: EntitySet { points: vec![case.point(5)], ..EntitySet::default() },
            }),
        ),
        (
            "distance_to_border",
            Algorithm::DistanceToBorder(DistanceToBorder {
                perpendicular,
                parallel,
                borders: case.curves(1),
            }),
        ),
        (
            "curvature_of_border",
            Algorithm::CurvatureOfBorder(CurvatureOfBorder {
                perpendicular,
                curvature: CurvatureToSize::try_new(0.001, 0.2, 0.001).unwrap(),
                projection,
                borders: case.curves(1),
            }),
        ),
        (
            "distance_between_two_borders",
            Algorithm::DistanceBetweenTwoBorders(DistanceBetweenTwoBorders {
                perpendicular,
                parallel,
                first: case.curves(1),
                second: case.curves(2),
            }),
        ),
        (
            "distance_to_imaginary_polyline",
            Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
                perpendicular: df(0.002, 0.1, d, 1.0),
                polyline_distance: df(0.01, 0.1, d, 1.0),
                projection,
                polyline: PolylinePoints::Plane(case.wake()),
                within: EntitySet::default(),
            }),
        ),
    ]
}

fn plan(algorithm: Algorithm) -> SizingPlan {
    SizingPlan {
        h_max: Some(1.0),
        steps: vec![Step { label: "bench".into(), algorithm, names: Vec::new() }],
        ..SizingPlan::default()
    }
}

/// The brute-force twin's sources: the closest-point search of each algorithm made by
/// scanning every segment (`None`: UNIFORM, which searches nothing).
fn twin_sources(case: &Case, name: &str) -> Option<Vec<Source>> {
    let curve = |tag| {
        Source::builder(&case.graph)
            .topology_curve(&case.topology, case.curve(tag))
            .build()
            .unwrap()
    };
    match name {
        "uniform" => None,
        "distance_to_point" => Some(vec![Source::builder(&case.graph)
            .topology_point(&case.topology, case.point(5))
            .build()
            .unwrap()]),
        "distance_to_border" | "curvature_of_border" => Some(vec![curve(1)]),
        "distance_between_two_borders" => Some(vec![curve(1), curve(2)]),
        _ => {
            Some(vec![Source::builder(&case.graph).polyline(&case.wake(), false).build().unwrap()])
        }
    }
}

/// The twin: for every vertex, every segment of every source scanned, then the
/// tensor of DISTANCE_TO_BORDER at the nearest one.
fn brute_force(case: &Case, sources: &[Source], reach: f64) -> Vec<SizeTensor> {
    let (perp, par) = border_functions(reach);
    (0..case.graph.num_vertices())
        .map(|v| {
            let p = case.graph.point(v);
            let mut best = None;
            for s in sources {
                let c = closest_point_brute_force(s, p).unwrap();
                let d = c.distance;
                if best.as_ref().map_or(true, |(b, _): &(f64, [f64; 2])| d < *b) {
                    best = Some((d, c.foot));
                }
            }
            let (d, foot) = best.unwrap();
            let n = if d > 0.0 { [p[0] - foot[0], p[1] - foot[1]] } else { [1.0, 0.0] };
            SizeTensor::new(n, perp.eval(d), par.eval(d))
        })
        .collect()
}

/// CPU time of the whole process, every thread summed, from
/// `/proc/self/task/*/schedstat` (nanoseconds spent on a CPU; `None` where there is no
/// such file). On a shared, loaded machine wall time also counts the time other
/// processes held the core; CPU time is what "per core" means.
fn process_cpu_time() -> Option<Duration> {
    let mut total = 0u64;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let stat = std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok()?;
        total += stat.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(Duration::from_nanos(total))
}

/// Benchmarks `f` in process CPU time where `/proc` gives it (wall time otherwise):
/// the figures of a single-thread run are then per core even on a loaded machine.
fn bench_cpu<M: criterion::measurement::Measurement<Value = Duration>, R>(
    g: &mut criterion::BenchmarkGroup<'_, M>,
    id: BenchmarkId,
    mut f: impl FnMut() -> R,
) {
    if process_cpu_time().is_none() {
        g.bench_function(id, |b| b.iter(&mut f));
        return;
    }
    g.bench_function(id, |b| {
        b.iter_custom(|iters| {
            let t0 = process_cpu_time().unwrap_or_default();
            for _ in 0..iters {
                std::hint::black_box(f());
            }
            process_cpu_time().unwrap_or_default().saturating_sub(t0)
        })
    });
}

fn dump(case: &Case) {
    let Ok(dir) = std::env::var("SMARTMESH_BENCH_DUMP") else { return };
    let around = case.around;
    let bytes =
        |v: &mut dyn Iterator<Item = f64>| v.flat_map(f64::to_le_bytes).collect::<Vec<u8>>();
    let pts = bytes(&mut case.mesh.points.iter().flat_map(|p| [p[0], p[1]]));
    let segs = bytes(&mut (0..around).flat_map(|i| {
        let (a, b) = (case.mesh.points[i], case.mesh.points[(i + 1) % around]);
        [a[0], a[1], b[0], b[1]]
    }));
    let base = format!("{dir}/o_mesh_{around}x{}", case.layers);
    let written = std::fs::create_dir_all(&dir)
        .and_then(|()| std::fs::write(format!("{base}.points.f64"), pts))
        .and_then(|()| std::fs::write(format!("{base}.segments.f64"), segs));
    if let Err(e) = written {
        panic!("SMARTMESH_BENCH_DUMP: cannot write {base}.*.f64: {e}");
    }
}

fn bench(c: &mut Criterion) {
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let max_vertices: usize = std::env::var("SMARTMESH_BENCH_MAX_VERTICES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4_000_000);
    let mut group = c.benchmark_group("sizing");
    // Flat sampling: each sample the same number of runs, so that the slow runs take
    // 10 iterations rather than criterion's 55.
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    let run = |pool: &rayon::ThreadPool, case: &Case, p: &SizingPlan| {
        pool.install(|| compute_size_field(&case.graph, &case.topology, p, &mut |_| {}).unwrap())
    };
    for (around, layers) in [(2000usize, 5usize), (10_000, 10), (10_000, 100), (10_000, 400)] {
        if around * layers > max_vertices {
            continue;
        }
        let case = o_mesh(around, layers);
        dump(&case);
        let n = case.graph.num_vertices();

        // The six algorithms, the same reach on every mesh.
        for (name, algorithm) in algorithms(&case, REACH) {
            let p = plan(algorithm);
            let reached = run(&one, &case, &p).steps[0].vertices_reached;
            let segments = twin_sources(&case, name)
                .map_or(0, |s| s.iter().map(|s| s.segments().len()).sum::<usize>());
            eprintln!("{name}/{n}: {reached} vertices reached, {segments} source segments");
            group.throughput(Throughput::Elements(reached as u64));
            bench_cpu(&mut group, BenchmarkId::new(name, n), || run(&one, &case, &p));
            // The twin costs vertices × segments: on the 10^4-vertex mesh only.
            if let Some(sources) = twin_sources(&case, name).filter(|_| n <= 10_000) {
                group.throughput(Throughput::Elements(n as u64));
                bench_cpu(&mut group, BenchmarkId::new(format!("brute_force_{name}"), n), || {
                    brute_force(&case, &sources, REACH)
                });
            }
        }

        // DISTANCE_TO_BORDER reaching every vertex, on up to 10^6 vertices (the target
        // case: a 10^6-vertex mesh, a 10^4-segment border): wall time on one and two
        // threads, CPU time on one, the twin up to 10^5 vertices.
        if n > 1_000_000 {
            continue;
        }
        let full = case.extent();
        let (perpendicular, parallel) = border_functions(full);
        let p = plan(Algorithm::DistanceToBorder(DistanceToBorder {
            perpendicular,
            parallel,
            borders: case.curves(1),
        }));
        let source = Source::builder(&case.graph)
            .topology_curve(&case.topology, case.curve(1))
            .build()
            .unwrap();
        let reach =
            propagate(&case.graph, &source, full, &PropagationOptions::new().with_parallel(false));
        assert_eq!(reach.len(), n, "every vertex within reach");
        let r = reach.report();
        eprintln!(
            "distance_to_border_full_reach/{n}: {} segments, farthest vertex {:.0} segment lengths out, {} of {} vertices certified by a clearance, {:.1} boxes and {:.1} segments tested per vertex, {} corrected by the index",
            source.segments().len(),
            reach.closest_points().map(|c| c.distance).fold(0.0, f64::max) / (2.0 * PI / around as f64),
            r.certified_locally,
            r.evaluated,
            r.boxes_tested as f64 / r.evaluated as f64,
            r.segments_tested as f64 / r.evaluated as f64,
            r.corrected
        );
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::new("distance_to_border_full_reach", n), |b| {
            b.iter(|| run(&one, &case, &p))
        });
        group.bench_function(BenchmarkId::new("distance_to_border_full_reach_2_threads", n), |b| {
            b.iter(|| run(&two, &case, &p))
        });
        bench_cpu(
            &mut group,
            BenchmarkId::new("distance_to_border_full_reach_cpu_time", n),
            || run(&one, &case, &p),
        );
        if n <= 100_000 {
            let sources = [source];
            bench_cpu(
                &mut group,
                BenchmarkId::new("brute_force_distance_to_border_full_reach", n),
                || brute_force(&case, &sources, full),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
