//! The surface index against the brute-force scan, bit for bit (distance, foot, feature
//! and triangle), on hard surfaces: a torus (non-convex), two sheets 10^-9 apart, a
//! regular grid and an octahedron queried where several triangles are equally near,
//! degenerate triangles mixed in, far points; and the parallel queries against the
//! single ones on several thread counts.

use super::surface_index::{closest_brute, triangle_geoms, SurfaceError, SurfaceIndex};
use super::triangle::{Feature, Point3, TriangleGeom};
use crate::geometry::test_support::Rng;

/// A torus of radii `big` and `small` around z, `nu × nv` quads each split in two.
fn torus(nu: usize, nv: usize, big: f64, small: f64) -> (Vec<Point3>, Vec<[u32; 3]>) {
    let tau = std::f64::consts::TAU;
    let mut pts = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (u, v) = (tau * i as f64 / nu as f64, tau * j as f64 / nv as f64);
            let r = big + small * v.cos();
            pts.push([r * u.cos(), r * u.sin(), small * v.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + j % nv) as u32;
    let mut tris = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (pts, tris)
}

/// An `n × n` grid of unit squares at height `z`, each split in two, vertices jittered
/// in the plane by `jitter` (ids offset by `base`).
fn sheet(n: usize, z: f64, jitter: f64, base: u32, rng: &mut Rng) -> (Vec<Point3>, Vec<[u32; 3]>) {
    let mut pts = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let dx = jitter * (rng.unit() - 0.5);
            let dy = jitter * (rng.unit() - 0.5);
            pts.push([i as f64 + dx, j as f64 + dy, z]);
        }
    }
    let id = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (pts, tris)
}

fn random_point(rng: &mut Rng, lo: Point3, hi: Point3) -> Point3 {
    [
        lo[0] + (hi[0] - lo[0]) * rng.unit(),
        lo[1] + (hi[1] - lo[1]) * rng.unit(),
        lo[2] + (hi[2] - lo[2]) * rng.unit(),
    ]
}

/// Every query through the index (from the root, from a few seeds, and in one parallel
/// batch) equals the brute-force scan exactly.
fn agree(pts: &[Point3], tris: &[[u32; 3]], queries: &[Point3]) {
    let idx = SurfaceIndex::new(pts, tris).unwrap();
    let geoms = triangle_geoms(pts, tris).unwrap();
    assert_eq!(idx.len(), tris.len());
    let many = idx.closest_many(queries);
    for (q, m) in queries.iter().zip(&many) {
        let b = closest_brute(&geoms, *q);
        assert_eq!(idx.closest(*q), b, "query {q:?}");
        assert_eq!(*m, b, "query {q:?} in a batch");
        for seed in [0, tris.len() as u32 / 3, tris.len() as u32 - 1, u32::MAX - 1] {
            assert_eq!(idx.closest_from(*q, seed), b, "query {q:?} from {seed}");
        }
    }
}

#[test]
fn torus_inside_outside_and_far() {
    let (pts, tris) = torus(40, 24, 1.0, 0.35);
    let mut rng = Rng(21);
    let mut queries: Vec<Point3> =
        (0..1500).map(|_| random_point(&mut rng, [-1.6, -1.6, -0.6], [1.6, 1.6, 0.6])).collect();
    // The axis (a whole circle of triangles equally near), the vertices, far points.
    queries.extend((0..20).map(|k| [0.0, 0.0, k as f64 * 0.05 - 0.5]));
    queries.extend(pts.iter().step_by(7).copied());
    queries.extend((0..50).map(|_| random_point(&mut rng, [-1e8; 3], [1e8; 3])));
    agree(&pts, &tris, &queries);
}

#[test]
fn two_sheets_a_nanometre_apart() {
    let mut rng = Rng(4);
    let (mut pts, mut tris) = sheet(12, 0.0, 0.3, 0, &mut rng);
    let (p2, t2) = sheet(12, 1e-9, 0.3, pts.len() as u32, &mut rng);
    pts.extend(p2);
    tris.extend(t2);
    let mut queries: Vec<Point3> =
        (0..800).map(|_| random_point(&mut rng, [-0.5, -0.5, -1e-9], [12.5, 12.5, 2e-9])).collect();
    queries.extend((0..200).map(|_| random_point(&mut rng, [-1.0, -1.0, -2.0], [13.0, 13.0, 2.0])));
    // Exactly between the sheets, and on them.
    queries.extend((0..100).map(|_| {
        let p = random_point(&mut rng, [0.0; 3], [12.0, 12.0, 0.0]);
        [p[0], p[1], [0.5e-9, 0.0, 1e-9][rng.unit() as usize * 3 % 3]]
    }));
    agree(&pts, &tris, &queries);
    // Between the sheets the answer is on the nearer one.
    let idx = SurfaceIndex::new(&pts, &tris).unwrap();
    let lower = 2 * 12 * 12;
    for z in [0.2e-9, 0.8e-9] {
        let r = idx.closest([6.3, 5.7, z]).unwrap();
        assert_eq!((r.triangle as usize) < lower, z < 0.5e-9);
        assert_eq!(r.projection.feature, Feature::Face);
        assert!((r.distance() - z.min(1e-9 - z)).abs() < 1e-24);
    }
}

#[test]
fn equidistant_queries_take_the_lowest_triangle() {
    // A regular grid: above a vertex six triangles are equally near (the vertex itself),
    // above an inner edge two are.
    let mut rng = Rng(1);
    let (pts, tris) = sheet(8, 0.0, 0.0, 0, &mut rng);
    let idx = SurfaceIndex::new(&pts, &tris).unwrap();
    let geoms = triangle_geoms(&pts, &tris).unwrap();
    let mut queries = Vec::new();
    for j in 0..=8 {
        for i in 0..=8 {
            queries.push([i as f64, j as f64, 0.75]);
            queries.push([i as f64 + 0.5, j as f64, -0.25]);
            queries.push([i as f64 + 0.5, j as f64 + 0.5, 2.0]);
        }
    }
    agree(&pts, &tris, &queries);
    let r = idx.closest([3.0, 4.0, 0.75]).unwrap();
    let ties: Vec<u32> = (0..tris.len() as u32)
        .filter(|&t| geoms[t as usize].project([3.0, 4.0, 0.75]).distance_squared == 0.5625)
        .collect();
    assert!(ties.len() >= 2, "{ties:?}");
    assert_eq!(r.triangle, ties[0]);
    // The octahedron's centre is equally far from its eight faces.
    let pts = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut tris = Vec::new();
    for (x, y) in [(0, 2), (2, 1), (1, 3), (3, 0)] {
        tris.push([x, y, 4]);
        tris.push([y, x, 5]);
    }
    agree(&pts, &tris, &[[0.0; 3], [1e-17, 0.0, 0.0], [0.0, 0.0, 0.5]]);
    let r = SurfaceIndex::new(&pts, &tris).unwrap().closest([0.0; 3]).unwrap();
    assert_eq!(r.triangle, 0);
}

#[test]
fn degenerate_triangles_and_tiny_ones_mixed_in() {
    let mut rng = Rng(9);
    let (mut pts, mut tris) = torus(12, 8, 1.0, 0.3);
    for _ in 0..300 {
        let c = random_point(&mut rng, [-1.5; 3], [1.5; 3]);
        let base = pts.len() as u32;
        let size = [1e-9, 1e-3, 0.2][(rng.unit() * 3.0) as usize];
        let a = [c[0] + size, c[1], c[2]];
        let b = [c[0] + size * rng.unit(), c[1] + size * rng.unit(), c[2]];
        pts.extend([c, a, b]);
        match (rng.unit() * 4.0) as usize {
            0 => tris.push([base, base + 1, base + 1]),
            1 => tris.push([base, base, base]),
            2 => {
                // Collinear.
                pts.push([c[0] + 0.5 * size, c[1], c[2]]);
                tris.push([base, base + 1, base + 3]);
            }
            _ => tris.push([base, base + 1, base + 2]),
        }
    }
    let queries: Vec<Point3> = (0..1500)
        .map(|_| random_point(&mut rng, [-2.0; 3], [2.0; 3]))
        .chain(pts.iter().copied())
        .collect();
    agree(&pts, &tris, &queries);
}

#[test]
fn batches_are_the_same_on_every_thread_count() {
    let (pts, tris) = torus(60, 30, 1.0, 0.4);
    let idx = SurfaceIndex::new(&pts, &tris).unwrap();
    let mut rng = Rng(33);
    let mut queries: Vec<Point3> =
        (0..5000).map(|_| random_point(&mut rng, [-2.0, -2.0, -1.0], [2.0, 2.0, 1.0])).collect();
    queries.push([f64::NAN, 0.0, 0.0]);
    queries.push([0.0, f64::INFINITY, 0.0]);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| idx.closest_many(&queries))
    };
    let one = run(1);
    assert_eq!(one.len(), queries.len());
    assert_eq!(one[5000], None);
    assert_eq!(one[5001], None);
    for (q, r) in queries.iter().zip(&one) {
        assert_eq!(*r, idx.closest(*q));
    }
    for threads in [2, 3, 8] {
        assert_eq!(run(threads), one, "{threads} threads");
    }
}

#[test]
fn normals_and_directions() {
    let (pts, tris) = torus(16, 12, 1.0, 0.3);
    let idx = SurfaceIndex::new(&pts, &tris).unwrap();
    // Outside the tube on the x axis: the outward normal, and the direction to the point.
    let p = [1.8, 0.0, 0.0];
    let r = idx.closest(p).unwrap();
    let n = idx.normal(r.triangle).unwrap();
    let away = r.away(p).unwrap();
    assert!(n[0] > 0.9, "{n:?}");
    assert!(away[0] > 0.9, "{away:?}");
    assert!((away[0] * away[0] + away[1] * away[1] + away[2] * away[2] - 1.0).abs() < 1e-15);
    assert_eq!(r.away(r.projection.foot), None);
    let flat =
        SurfaceIndex::new(&[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], &[[0, 1, 2]]).unwrap();
    assert_eq!(flat.normal(0), None);
    assert!(flat.triangle(0).is_degenerate());
}

#[test]
fn bad_input_and_empty_surfaces() {
    let pts = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, f64::NAN]];
    assert_eq!(
        SurfaceIndex::new(&pts, &[[0, 1, 3]]).unwrap_err(),
        SurfaceError::VertexOutOfRange { triangle: 0, vertex: 3, count: 3 }
    );
    assert_eq!(
        SurfaceIndex::new(&pts, &[[0, 1, 0], [0, 1, 2]]).unwrap_err(),
        SurfaceError::NonFinite { triangle: 1, vertex: 2 }
    );
    let empty = SurfaceIndex::new(&pts, &[]).unwrap();
    assert!(empty.is_empty());
    assert_eq!(empty.closest([0.0; 3]), None);
    assert_eq!(empty.closest_many(&[[0.0; 3]]), vec![None]);
    let one = SurfaceIndex::new(&pts[..2], &[[0, 1, 1]]).unwrap();
    assert_eq!(one.closest([0.5, 1.0, 0.0]).unwrap().projection.feature, Feature::Edge(0));
    assert_eq!(one.closest([f64::NAN, 0.0, 0.0]), None);
    // The brute force of a single triangle is its kernel.
    let g = TriangleGeom::new(pts[0], pts[1], pts[1]);
    assert_eq!(
        closest_brute(&[g], [0.5, 1.0, 0.0]).unwrap().projection,
        g.project([0.5, 1.0, 0.0])
    );
}

#[test]
fn a_dense_volume_grid_in_a_batch_equals_the_scan_on_every_thread_count() {
    // What the 3D DISTANCE_TO_BORDER asks: every vertex of a volume grid around the
    // surface in one batch (Morton order, each query seeded by the previous answer,
    // the wide tree's search), grid nodes on the axis and in the planes of symmetry
    // where many triangles are equally near.
    let (pts, tris) = torus(36, 20, 1.0, 0.4);
    let geoms = triangle_geoms(&pts, &tris).unwrap();
    let idx = SurfaceIndex::new(&pts, &tris).unwrap();
    let mut rng = Rng(77);
    let mut queries = Vec::new();
    for k in 0..8 {
        for j in 0..20 {
            for i in 0..20 {
                let c = [i as f64 * 0.16 - 1.52, j as f64 * 0.16 - 1.52, k as f64 * 0.2 - 0.7];
                queries.push(c);
                queries.push([c[0] + 0.1 * rng.unit(), c[1] + 0.1 * rng.unit(), c[2]]);
            }
        }
    }
    let brute: Vec<_> = queries.iter().map(|q| closest_brute(&geoms, *q)).collect();
    for threads in [1, 2, 8] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let many = pool.install(|| idx.closest_many(&queries));
        for (i, (m, b)) in many.iter().zip(&brute).enumerate() {
            assert_eq!(m, b, "query {i} {:?} on {threads} threads", queries[i]);
        }
    }
}
