//! The six sizing algorithms, each as a one-step plan run by `compute_size_field`, on
//! O-meshes of 10^4 to 4·10^6 vertices around a wavy closed border, next to the
//! brute-force twin of their closest-point search. Throughput is in vertex
//! evaluations (a closest point and a size tensor per reached vertex) per second;
//! every function reaches as far as the mesh goes, so every algorithm reaches every
//! vertex (the bench checks it and prints the counts).
//!
//! - `<algorithm>/N`: one rayon thread (per core), N vertices.
//! - `distance_to_border_2_threads/N`: DISTANCE_TO_BORDER on two threads.
//! - `brute_force_<algorithm>/N`: the twin on one thread, on the smaller meshes: every
//!   source segment scanned for every vertex (`closest_point_brute_force`), then the
//!   tensor of DISTANCE_TO_BORDER (for DISTANCE_TO_POINT the exact isotropic size);
//!   for DISTANCE_BETWEEN_TWO_BORDERS both borders are scanned. UNIFORM searches
//!   nothing, so it has no twin.
//!
//! Meshes: (around, layers) = (2000, 5), (10^4, 10), (10^4, 100), (10^4, 400): ring j
//! at r(a) = 1 + 0.1 cos 5a + 0.004 j, angle a = 2π i / around, quads split along a
//! seeded random diagonal. Tags: the inner ring is curve 1 (the border, `around`
//! segments), the outer ring curve 2, the triangles face 1, and a vertex half-way out
//! at angle 0 is topological point 5. The imaginary polyline is a radial wake at angle
//! π/3 across every ring but the first and the last, 1000 points.
//!
//! `SMARTMESH_BENCH_MAX_VERTICES=n` skips the meshes above n vertices (default 4·10^6).
//! `SMARTMESH_BENCH_DUMP=dir` writes each mesh's points and border segments as
//! little-endian f64 files for `benches/compare_ckdtree.py` (scipy on the same bytes).
//!
//! Run: `cargo bench -p smartmesh --bench sizing`.

use std::f64::consts::PI;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode, Throughput};
use smartmesh::formats::{CellBlock, CellKind, TaggedMesh};
use smartmesh::sizing::{
    closest_point_brute_force, compute_size_field, Algorithm, CurvatureToSize, DistanceFunction, EntitySet, SizeProjectionFunction, SizingPlan,
    Source, Step,
};
use smartmesh::{MeshGraph, SizeTensor, Topology};

/// splitmix64, as in the tests.
struct Rng(u64);

impl Rng {
    fn bit(&mut self) -> bool {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) & 1 == 0
    }
}

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
        (0..1000).map(|k| r0 + (r1 - r0) * k as f64 / 999.0).map(|r| [r * a.cos(), r * a.sin()]).collect()
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
            let (a, b, c, d) = (j * around + i, j * around + i1, (j + 1) * around + i1, (j + 1) * around + i);
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
    let outer = (layers - 1) * around;
    for i in 0..around {
        lines.push(&[i, (i + 1) % around], 1, 1);
    }
    for i in 0..around {
        lines.push(&[outer + i, outer + (i + 1) % around], 2, 2);
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

/// The border functions (perpendicular, parallel) of DISTANCE_TO_BORDER and its twin.
fn border_functions(case: &Case) -> (DistanceFunction, DistanceFunction) {
    let d = case.extent();
    (df(0.001, 0.1, d, 1.5), df(0.01, 0.2, d, 1.0))
}

/// The six algorithms as `(name, algorithm)`, every one reaching the whole mesh.
fn algorithms(case: &Case) -> Vec<(&'static str, Algorithm)> {
    let d = case.extent();
    let (perpendicular, parallel) = border_functions(case);
    let projection = SizeProjectionFunction::try_new(0.2, d, 1.0).unwrap();
    vec![
        ("uniform", Algorithm::Uniform { size: 0.05, on: EntitySet { faces: vec![case.face(1)], ..EntitySet::default() } }),
        (
            "distance_to_point",
            Algorithm::DistanceToPoint { function: df(0.001, 0.1, d, 1.0), sources: EntitySet { points: vec![case.point(5)], ..EntitySet::default() } },
        ),
        ("distance_to_border", Algorithm::DistanceToBorder { perpendicular, parallel, borders: case.curves(1) }),
        (
            "curvature_of_border",
            Algorithm::CurvatureOfBorder { perpendicular, curvature: CurvatureToSize::try_new(0.001, 0.2, 0.001).unwrap(), projection, borders: case.curves(1) },
        ),
        ("distance_between_two_borders", Algorithm::DistanceBetweenTwoBorders { perpendicular, parallel, first: case.curves(1), second: case.curves(2) }),
        (
            "distance_to_imaginary_polyline",
            Algorithm::DistanceToImaginaryPolyline {
                perpendicular: df(0.002, 0.1, d, 1.0),
                polyline_distance: df(0.01, 0.1, d, 1.0),
                projection,
                polyline: case.wake(),
                within: EntitySet::default(),
            },
        ),
    ]
}

fn plan(algorithm: Algorithm) -> SizingPlan {
    SizingPlan { h_max: Some(1.0), steps: vec![Step { label: "bench".into(), algorithm }], ..SizingPlan::default() }
}

/// The brute-force twin's sources: the closest-point search of each algorithm made by
/// scanning every segment (`None`: UNIFORM, which searches nothing).
fn twin_sources(case: &Case, name: &str) -> Option<Vec<Source>> {
    let curve = |tag| Source::builder(&case.graph).topology_curve(&case.topology, case.curve(tag)).build().unwrap();
    match name {
        "uniform" => None,
        "distance_to_point" => Some(vec![Source::builder(&case.graph).topology_point(&case.topology, case.point(5)).build().unwrap()]),
        "distance_to_border" | "curvature_of_border" => Some(vec![curve(1)]),
        "distance_between_two_borders" => Some(vec![curve(1), curve(2)]),
        _ => Some(vec![Source::builder(&case.graph).polyline(&case.wake(), false).build().unwrap()]),
    }
}

/// The twin: for every vertex, every segment of every source scanned, then the
/// tensor of DISTANCE_TO_BORDER at the nearest one.
fn brute_force(case: &Case, sources: &[Source]) -> Vec<SizeTensor> {
    let (perp, par) = border_functions(case);
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

fn dump(case: &Case) {
    let Ok(dir) = std::env::var("SMARTMESH_BENCH_DUMP") else { return };
    let around = case.around;
    let bytes = |v: &mut dyn Iterator<Item = f64>| v.flat_map(f64::to_le_bytes).collect::<Vec<u8>>();
    let pts = bytes(&mut case.mesh.points.iter().flat_map(|p| [p[0], p[1]]));
    let segs = bytes(&mut (0..around).flat_map(|i| {
        let (a, b) = (case.mesh.points[i], case.mesh.points[(i + 1) % around]);
        [a[0], a[1], b[0], b[1]]
    }));
    let base = format!("{dir}/o_mesh_{around}x{}", case.layers);
    std::fs::write(format!("{base}.points.f64"), pts).unwrap();
    std::fs::write(format!("{base}.segments.f64"), segs).unwrap();
}

fn bench(c: &mut Criterion) {
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let max_vertices: usize = std::env::var("SMARTMESH_BENCH_MAX_VERTICES").ok().and_then(|s| s.parse().ok()).unwrap_or(4_000_000);
    let mut group = c.benchmark_group("sizing");
    // Flat sampling: each sample the same number of runs, so that the 4·10^6-vertex
    // runs take 10 iterations rather than criterion's 55.
    group.sample_size(10).sampling_mode(SamplingMode::Flat).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    for (around, layers) in [(2000usize, 5usize), (10_000, 10), (10_000, 100), (10_000, 400)] {
        if around * layers > max_vertices {
            continue;
        }
        let case = o_mesh(around, layers);
        dump(&case);
        let n = case.graph.num_vertices();
        for (name, algorithm) in algorithms(&case) {
            let p = plan(algorithm);
            let field = compute_size_field(&case.graph, &case.topology, &p, &mut |_| {}).unwrap();
            let reached = field.steps[0].vertices_reached;
            eprintln!("{name}/{n}: {reached} vertices reached, {} source segments (border {around})", twin_sources(&case, name).map_or(0, |s| s.iter().map(|s| s.segments().len()).sum::<usize>()));
            assert_eq!(reached, n, "{name}: every vertex within reach");
            group.throughput(Throughput::Elements(reached as u64));
            group.bench_function(BenchmarkId::new(name, n), |b| b.iter(|| one.install(|| compute_size_field(&case.graph, &case.topology, &p, &mut |_| {}).unwrap())));
            if name == "distance_to_border" {
                group.bench_function(BenchmarkId::new("distance_to_border_2_threads", n), |b| {
                    b.iter(|| two.install(|| compute_size_field(&case.graph, &case.topology, &p, &mut |_| {}).unwrap()))
                });
            }
            // The twin costs vertices × segments: 10^4 vertices for every algorithm,
            // 10^5 for DISTANCE_TO_BORDER.
            let twin_limit = if name == "distance_to_border" { 100_000 } else { 10_000 };
            if let Some(sources) = twin_sources(&case, name).filter(|_| n <= twin_limit) {
                group.bench_function(BenchmarkId::new(format!("brute_force_{name}"), n), |b| b.iter(|| brute_force(&case, &sources)));
            }
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
