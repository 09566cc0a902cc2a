//! Twins of the distance-based algorithms in space: every vertex's tensor against a
//! brute-force scan over every source piece (triangle, segment, point) and a tensor
//! written here from its definition, on hard cases — jittered vertices, a concave corner
//! of two walls (a sharp ridge seen from inside), two sheets close together, a coarse
//! mesh — and the same field on one thread and on several.

use smartmesh_formats::TaggedMesh;
use smartmesh_test_support::grid::kuhn_box;

use super::tests::{face, plan, run};
use super::*;
use crate::geometry::space::{closest_brute, TriangleGeom};
use crate::sizing::algorithms::{Algorithm, DistanceToPoint, EntitySet};
use crate::sizing::functions::DistanceFunction;
use crate::sizing::space::SpaceSourceBuilder;

/// A Kuhn box with every interior vertex moved by up to `amount` of a cell in each
/// direction (a fixed LCG): queries off the grid's symmetry, ties broken.
pub(super) fn jittered_box(n: usize, size: [f64; 3], amount: f64, seed: u64) -> TaggedMesh {
    let mut mesh = kuhn_box(n, size);
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for p in mesh.points.iter_mut() {
        let interior = (0..3).all(|k| p[k] > 0.0 && p[k] < size[k]);
        for k in 0..3 {
            let d = next() * 2.0 * amount * size[k] / n as f64;
            if interior {
                p[k] += d;
            }
        }
    }
    mesh
}

/// The relative distance between two metrics (Frobenius).
pub(super) fn metric_gap(a: &Sym3, b: &Sym3) -> f64 {
    let (x, y) = (a.to_row_major(), b.to_row_major());
    let d: f64 = x.iter().zip(&y).map(|(p, q)| (p - q) * (p - q)).sum();
    let n: f64 = y.iter().map(|q| q * q).sum();
    (d / n).sqrt()
}

/// The field on one thread equals the field on three.
pub(super) fn same_on_any_thread_count(mesh: &TaggedMesh, p: &SizingPlan) {
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| run(mesh, p).unwrap())
    };
    assert_eq!(on(1), on(3));
}

/// For every vertex of `mesh`, the source's indexed closest point is the brute-force
/// scan's bit for bit (distance, foot, piece), and the scan agrees with `geoms` scanned
/// here in the order the pieces were given.
pub(super) fn index_is_its_scan(mesh: &TaggedMesh, source: &SpaceSource, geoms: &[TriangleGeom]) {
    let mut seed = u32::MAX;
    for p in &mesh.points {
        let a = source.closest_from(*p, seed).unwrap();
        seed = a.piece;
        let b = source.closest_brute(*p).unwrap();
        assert_eq!(a, b, "{p:?}");
        let c = closest_brute(geoms, *p).unwrap();
        assert_eq!(a.distance_squared.to_bits(), c.projection.distance_squared.to_bits());
        assert_eq!(a.piece, c.triangle);
    }
}

/// DISTANCE_TO_POINT from the vertices of two box edges (two curves of the box's
/// boundary) on a jittered box: each vertex within reach gets f(d), d the distance to
/// the nearest of those vertices computed here, the others the default; on a coarse box
/// too; the same on any thread count.
#[test]
fn distance_to_point_in_space_is_its_twin() {
    for (n, amount) in [(6, 0.3), (2, 0.0), (5, 0.45)] {
        let mesh = jittered_box(n, [1.0, 0.7, 1.3], amount, n as u64);
        let topology = Topology::from_mesh(&mesh);
        let curves: Vec<usize> = (0..topology.curves.len().min(2)).collect();
        let f = DistanceFunction::try_new(0.01, 0.3, 0.6, 1.3).unwrap();
        let sources = EntitySet { curves: curves.clone(), ..EntitySet::default() };
        let p = plan(
            vec![Algorithm::DistanceToPoint(DistanceToPoint { function: f, sources })],
            Some(1.0),
        );
        let field = run(&mesh, &p).unwrap();
        // The points, scanned here.
        let mut points: Vec<[f64; 3]> = Vec::new();
        let mut b = SpaceSourceBuilder::new(&mesh.points);
        for &c in &curves {
            for pl in &topology.curves[c].polylines {
                for &v in &pl.vertices {
                    points.push(mesh.points[v]);
                    b.vertex(v).unwrap();
                }
            }
        }
        let geoms: Vec<TriangleGeom> = points.iter().map(|&x| TriangleGeom::new(x, x, x)).collect();
        index_is_its_scan(&mesh, &b.build().unwrap(), &geoms);
        let mut reached = 0;
        for (v, x) in mesh.points.iter().enumerate() {
            let d2 = points
                .iter()
                .map(|q| {
                    let e = [x[0] - q[0], x[1] - q[1], x[2] - q[2]];
                    e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
                })
                .fold(f64::INFINITY, f64::min);
            let h = if d2 <= 0.6 * 0.6 { f.eval(d2.sqrt()) } else { 1.0 };
            reached += usize::from(d2 <= 0.6 * 0.6);
            let want = SizeTensor3::isotropic(h).to_metric();
            assert!(metric_gap(&field.tensors[v].to_metric(), &want) < 1e-12, "{v}: {x:?}");
        }
        assert_eq!(field.steps[0].vertices_reached, reached);
        assert!(reached > 0 && reached < mesh.points.len(), "{reached}");
        same_on_any_thread_count(&mesh, &p);
    }
    let _ = face;
}
