//! The sizing engine on DISTANCE_TO_BORDER: `compute_size_field` with one step, on
//! O-meshes around a wavy closed border curve, every vertex within reach, next to its
//! brute-force twin (closest point by scanning every segment, then the same tensor) on
//! the smaller sizes. Throughput is in vertex evaluations (a closest point and a size
//! tensor per vertex) per second.
//!
//! - `distance_to_border/N`: N = around × layers vertices, the border the innermost
//!   ring (`around` mesh edges, a topological curve); one rayon thread, so per core.
//! - `distance_to_border_2_threads/N`: the same on two threads.
//! - `brute_force/N`: the twin, one thread.
//!
//! Meshes: (around, layers) = (2000, 5), (10^4, 10), (10^4, 100). Each vertex is
//! r(a) = 1 + 0.1 cos 5a + 0.004 j at angle a = 2π i / around (ring j); quads split along
//! a seeded random diagonal. `SMARTMESH_BENCH_DUMP=dir` writes each mesh's points and
//! border segments as little-endian f64 files for `benches/compare_ckdtree.py`.
//!
//! Run: `cargo bench -p smartmesh --bench sizing`.

use std::f64::consts::PI;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use smartmesh::formats::{CellBlock, CellKind, TaggedMesh};
use smartmesh::sizing::{closest_point_brute_force, compute_size_field, Algorithm, DistanceFunction, EntitySet, SizingPlan, Source, Step};
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

struct Case {
    mesh: TaggedMesh,
    topology: Topology,
    graph: MeshGraph,
    border: usize,
}

fn o_mesh(around: usize, layers: usize) -> Case {
    let mut mesh = TaggedMesh::new();
    for j in 0..layers {
        for i in 0..around {
            let a = 2.0 * PI * i as f64 / around as f64;
            let r = 1.0 + 0.1 * (5.0 * a).cos() + j as f64 * 0.004;
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
    for i in 0..around {
        lines.push(&[i, (i + 1) % around], 1, 1);
    }
    mesh.blocks = vec![lines, tris];
    let topology = Topology::from_mesh(&mesh);
    let graph = MeshGraph::from_topology(&topology, &mesh).unwrap();
    let border = topology.curves.iter().position(|c| c.tag == Some(1)).unwrap();
    Case { mesh, topology, graph, border }
}

fn functions() -> (DistanceFunction, DistanceFunction) {
    (DistanceFunction::try_new(0.001, 0.1, 1.0, 1.5).unwrap(), DistanceFunction::try_new(0.01, 0.2, 1.0, 1.0).unwrap())
}

fn plan(case: &Case) -> SizingPlan {
    let (perpendicular, parallel) = functions();
    SizingPlan {
        h_max: Some(1.0),
        steps: vec![Step {
            label: "border".into(),
            algorithm: Algorithm::DistanceToBorder { perpendicular, parallel, borders: EntitySet { curves: vec![case.border], ..EntitySet::default() } },
        }],
        ..SizingPlan::default()
    }
}

/// The brute-force twin: scan every segment, then the tensor.
fn brute_force(case: &Case, source: &Source) -> Vec<SizeTensor> {
    let (perp, par) = functions();
    (0..case.graph.num_vertices())
        .map(|v| {
            let p = case.graph.point(v);
            let c = closest_point_brute_force(source, p).unwrap();
            let s = source.segments()[c.segment as usize];
            let n = if c.distance > 0.0 { [p[0] - c.foot[0], p[1] - c.foot[1]] } else { [s.a[1] - s.b[1], s.b[0] - s.a[0]] };
            SizeTensor::new(n, perp.eval(c.distance), par.eval(c.distance))
        })
        .collect()
}

fn dump(case: &Case, around: usize, layers: usize) {
    let Ok(dir) = std::env::var("SMARTMESH_BENCH_DUMP") else { return };
    let bytes = |v: &mut dyn Iterator<Item = f64>| v.flat_map(f64::to_le_bytes).collect::<Vec<u8>>();
    let pts = bytes(&mut case.mesh.points.iter().flat_map(|p| [p[0], p[1]]));
    let segs = bytes(&mut (0..around).flat_map(|i| {
        let (a, b) = (case.mesh.points[i], case.mesh.points[(i + 1) % around]);
        [a[0], a[1], b[0], b[1]]
    }));
    let base = format!("{dir}/o_mesh_{around}x{layers}");
    std::fs::write(format!("{base}.points.f64"), pts).unwrap();
    std::fs::write(format!("{base}.segments.f64"), segs).unwrap();
}

fn bench(c: &mut Criterion) {
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let mut group = c.benchmark_group("sizing");
    group.sample_size(10);
    for (around, layers) in [(2000usize, 5usize), (10_000, 10), (10_000, 100)] {
        let case = o_mesh(around, layers);
        dump(&case, around, layers);
        let n = case.graph.num_vertices();
        let p = plan(&case);
        let field = compute_size_field(&case.graph, &case.topology, &p, &mut |_| {}).unwrap();
        assert_eq!(field.steps[0].vertices_reached, n, "every vertex within reach");
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::new("distance_to_border", n), |b| {
            b.iter(|| one.install(|| compute_size_field(&case.graph, &case.topology, &p, &mut |_| {}).unwrap()))
        });
        group.bench_function(BenchmarkId::new("distance_to_border_2_threads", n), |b| {
            b.iter(|| two.install(|| compute_size_field(&case.graph, &case.topology, &p, &mut |_| {}).unwrap()))
        });
        if n <= 100_000 {
            let source = Source::builder(&case.graph).topology_curve(&case.topology, case.border).build().unwrap();
            group.bench_function(BenchmarkId::new("brute_force", n), |b| b.iter(|| brute_force(&case, &source)));
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
