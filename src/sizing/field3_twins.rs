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
}

/// The pieces of a border written here from the topology: each surface cell's triangle
/// (0, 1, 2) — the boxes have no quads — then each curve edge as (a, b, b), then each
/// point as (p, p, p); with each piece's mesh vertices.
pub(super) fn border_pieces(
    mesh: &TaggedMesh,
    topology: &Topology,
    set: &EntitySet,
) -> (Vec<TriangleGeom>, Vec<[usize; 3]>) {
    let x = |v: usize| mesh.points[v];
    let (mut geoms, mut corners) = (Vec::new(), Vec::new());
    for &f in &set.faces {
        for &c in &topology.faces[f].cells {
            let v = topology.surface_cells[c].vertices();
            assert_eq!(v.len(), 3);
            geoms.push(TriangleGeom::new(x(v[0]), x(v[1]), x(v[2])));
            corners.push([v[0], v[1], v[2]]);
        }
    }
    for &c in &set.curves {
        for pl in &topology.curves[c].polylines {
            for [a, b] in pl.edges() {
                geoms.push(TriangleGeom::new(x(a), x(b), x(b)));
                corners.push([a, b, b]);
            }
        }
    }
    for &p in &set.points {
        let v = topology.points[p].vertex;
        geoms.push(TriangleGeom::new(x(v), x(v), x(v)));
        corners.push([v; 3]);
    }
    (geoms, corners)
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

/// The metric of sizes `h_along` along unit `n` and `h_across` across it, from its
/// definition: n nᵀ / h_along² + (I − n nᵀ) / h_across².
pub(super) fn axial_metric(n: [f64; 3], h_along: f64, h_across: f64) -> Sym3 {
    let m = |i: usize, j: usize| {
        let nn = n[i] * n[j];
        nn / (h_along * h_along) + (f64::from(u8::from(i == j)) - nn) / (h_across * h_across)
    };
    Sym3 { xx: m(0, 0), xy: m(0, 1), yy: m(1, 1), xz: m(0, 2), yz: m(1, 2), zz: m(2, 2) }
}

/// The wall-aligned metric at `x` written from its definition (see
/// `algorithms::frame3`), with the brute-force closest point over `geoms`.
pub(super) fn wall_metric_brute(
    mesh: &TaggedMesh,
    geoms: &[TriangleGeom],
    corners: &[[usize; 3]],
    x: [f64; 3],
    h: impl Fn(f64) -> (f64, f64),
) -> (f64, Sym3) {
    let c = closest_brute(geoms, x).unwrap();
    let d = c.projection.distance_squared.sqrt();
    let (hn, ht) = h(d);
    let k = corners[c.triangle as usize];
    let p = |v: usize| mesh.points[v];
    let longest = (0..3).map(|i| {
        let e = sub3(p(k[i]), p(k[(i + 1) % 3]));
        (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt()
    });
    let longest = longest.fold(0.0, f64::max);
    if d > 1e-12 * longest {
        return (d, axial_metric(unit(sub3(x, c.projection.foot)), hn, ht));
    }
    let small = hn.min(ht);
    if k[0] == k[1] {
        return (d, axial_metric([1.0, 0.0, 0.0], small, small));
    }
    if k[1] == k[2] {
        return (d, axial_metric(unit(sub3(p(k[1]), p(k[0]))), ht, small));
    }
    // On the surface, at one of its vertices: the area-weighted normal of the source's
    // triangles around it, turned as the first of them.
    let v = (0..mesh.points.len()).find(|&v| mesh.points[v] == x).unwrap();
    let raw = |k: [usize; 3]| {
        let (a, b) = (sub3(p(k[1]), p(k[0])), sub3(p(k[2]), p(k[0])));
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    };
    let first = raw(k);
    let mut sum = [0.0; 3];
    for t in corners.iter().filter(|t| t[1] != t[2] && t.contains(&v)) {
        let n = raw(*t);
        let s = if n[0] * first[0] + n[1] * first[1] + n[2] * first[2] < 0.0 { -1.0 } else { 1.0 };
        for i in 0..3 {
            sum[i] += s * n[i];
        }
    }
    (d, axial_metric(unit(sum), hn, ht))
}

/// DISTANCE_TO_BORDER in space against its twin on hard cases: the bottom and the side
/// x = 0 of a jittered box (a concave right-angle ridge seen from inside), the top and
/// bottom of a thin box (two sheets 0.06 apart), a coarse box (2 cells a side) with a box
/// edge and a point as well. Distances bit for bit, tensors to 1e-12.
#[test]
fn distance_to_border_in_space_is_its_twin() {
    use crate::sizing::algorithms::DistanceToBorder;
    let perp = DistanceFunction::try_new(0.004, 0.2, 0.5, 1.4).unwrap();
    let par = DistanceFunction::try_new(0.03, 0.25, 0.7, 1.0).unwrap();
    let cases: Vec<(TaggedMesh, Vec<i32>, bool)> = vec![
        (jittered_box(6, [1.0, 0.8, 0.9], 0.3, 7), vec![15, 11], false),
        (jittered_box(5, [1.0, 1.0, 0.06], 0.3, 8), vec![15, 16], false),
        (kuhn_box(2, [1.0, 1.0, 1.0]), vec![16], true),
    ];
    for (mesh, tags, more) in cases {
        let topology = Topology::from_mesh(&mesh);
        let mut set = EntitySet {
            faces: tags.iter().map(|&t| face(&mesh, t)).collect(),
            ..EntitySet::default()
        };
        if more {
            set.curves = vec![0];
            set.points = if topology.points.is_empty() { vec![] } else { vec![0] };
        }
        let algorithm =
            DistanceToBorder { perpendicular: perp, parallel: par, borders: set.clone() };
        let p = plan(vec![Algorithm::DistanceToBorder(algorithm)], Some(1.0));
        let field = run(&mesh, &p).unwrap();
        let (geoms, corners) = border_pieces(&mesh, &topology, &set);
        let space = SpaceMesh::new(&mesh, &topology).unwrap();
        let source =
            crate::sizing::algorithms::space_border_source(&space, &topology, &set, true).unwrap();
        index_is_its_scan(&mesh, &source, &geoms);
        let mut on_surface = 0;
        for (v, x) in mesh.points.iter().enumerate() {
            let (d, want) =
                wall_metric_brute(&mesh, &geoms, &corners, *x, |d| (perp.eval(d), par.eval(d)));
            on_surface += usize::from(d == 0.0);
            let want = if d <= 0.7 { want } else { SizeTensor3::isotropic(1.0).to_metric() };
            let gap = metric_gap(&field.tensors[v].to_metric(), &want);
            assert!(gap < 1e-12, "{v} at {x:?} (d = {d}): {gap:e} {:?}", field.tensors[v]);
        }
        assert!(on_surface > 0);
        same_on_any_thread_count(&mesh, &p);
    }
}

/// DISTANCE_BETWEEN_TWO_BORDERS in space against its twin: the two sheets of a thin box
/// (0.08 apart), the two walls of a concave right-angle ridge, a coarse box's top and a
/// box edge. The thickness d1 + d2 and the normal of Fig. 4.6 written here from the
/// brute-force closest points; tensors to 1e-12.
#[test]
fn distance_between_two_borders_in_space_is_its_twin() {
    use crate::sizing::algorithms::DistanceBetweenTwoBorders;
    let perp = DistanceFunction::try_new(0.01, 0.1, 0.4, 1.0).unwrap();
    let par = DistanceFunction::try_new(0.05, 0.2, 0.3, 2.0).unwrap();
    let reach: f64 = 0.4;
    let cases: Vec<(TaggedMesh, EntitySet, EntitySet)> = {
        let thin = jittered_box(5, [1.0, 1.0, 0.08], 0.3, 3);
        let corner = jittered_box(6, [1.0, 1.0, 1.0], 0.35, 4);
        let coarse = kuhn_box(2, [0.5, 0.5, 0.3]);
        let faces =
            |m: &TaggedMesh, t: i32| EntitySet { faces: vec![face(m, t)], ..EntitySet::default() };
        let curve0 = EntitySet { curves: vec![0], ..EntitySet::default() };
        vec![
            (thin.clone(), faces(&thin, 15), faces(&thin, 16)),
            (corner.clone(), faces(&corner, 15), faces(&corner, 11)),
            (coarse.clone(), faces(&coarse, 16), curve0),
        ]
    };
    for (mesh, first, second) in cases {
        let topology = Topology::from_mesh(&mesh);
        let algorithm = DistanceBetweenTwoBorders {
            perpendicular: perp,
            parallel: par,
            first: first.clone(),
            second: second.clone(),
        };
        let p = plan(vec![Algorithm::DistanceBetweenTwoBorders(algorithm)], Some(1.0));
        let field = run(&mesh, &p).unwrap();
        let (g1, k1) = border_pieces(&mesh, &topology, &first);
        let (g2, k2) = border_pieces(&mesh, &topology, &second);
        let mut reached = 0;
        for (v, x) in mesh.points.iter().enumerate() {
            let (a, b) = (closest_brute(&g1, *x).unwrap(), closest_brute(&g2, *x).unwrap());
            let (d1s, d2s) = (a.projection.distance_squared, b.projection.distance_squared);
            let (d1, d2) = (d1s.sqrt(), d2s.sqrt());
            let t = d1 + d2;
            let want = if d1s > reach * reach || d2s > reach * reach || t > reach {
                SizeTensor3::isotropic(1.0).to_metric()
            } else {
                reached += 1;
                let h = |_: f64| (perp.eval(t), par.eval(t));
                let on = |k: &[[usize; 3]], c: &crate::geometry::space::SurfacePoint| {
                    let corners = k[c.triangle as usize].map(|i| mesh.points[i]);
                    let longest = (0..3)
                        .map(|i| {
                            let e = sub3(corners[i], corners[(i + 1) % 3]);
                            (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt()
                        })
                        .fold(0.0, f64::max);
                    c.projection.distance_squared.sqrt() <= 1e-12 * longest
                };
                if on(&k1, &a) {
                    wall_metric_brute(&mesh, &g1, &k1, *x, h).1
                } else if on(&k2, &b) {
                    wall_metric_brute(&mesh, &g2, &k2, *x, h).1
                } else {
                    let u1 = unit(sub3(a.projection.foot, *x));
                    let u2 = unit(sub3(b.projection.foot, *x));
                    let w = [0, 1, 2].map(|k| d2 * u1[k] - d1 * u2[k]);
                    let wn = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                    let n = if wn > 1e-9 * t {
                        unit(w)
                    } else if d1 <= d2 {
                        u1
                    } else {
                        u2
                    };
                    axial_metric(n, perp.eval(t), par.eval(t))
                }
            };
            let gap = metric_gap(&field.tensors[v].to_metric(), &want);
            assert!(gap < 1e-12, "{v} at {x:?} (d1 {d1}, d2 {d2}): {gap:e}");
        }
        assert_eq!(field.steps[0].vertices_reached, reached);
        assert!(reached > 0);
        same_on_any_thread_count(&mesh, &p);
    }
}
