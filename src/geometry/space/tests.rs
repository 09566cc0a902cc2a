//! The triangle kernel against an independent twin on the hard cases: a nested
//! minimisation of the squared distance over the triangle's parameters (exact along one
//! parameter, golden-section search along the other), which evaluates distances
//! directly and shares no formula with the kernel; exact answers where they are known
//! (points on the surface, at vertices, on edges) and the feature where it is clear.

use super::triangle::{orient3d, Feature, Point3, TriangleGeom};
use crate::geometry::test_support::Rng;

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn at(a: Point3, ab: Point3, ac: Point3, v: f64, w: f64) -> Point3 {
    [a[0] + v * ab[0] + w * ac[0], a[1] + v * ab[1] + w * ac[1], a[2] + v * ab[2] + w * ac[2]]
}
fn dist2(p: Point3, q: Point3) -> f64 {
    let d = sub(p, q);
    dot(d, d)
}

/// The twin: `min over v in [0, 1] of min over w in [0, 1 − v]` of `|p − (a + v·ab +
/// w·ac)|²`; the inner minimum is the clamped vertex of a parabola, the outer function is
/// convex (a partial minimum of a convex function), searched by golden sections. Run
/// from each corner in turn (the parameters relative to each vertex), keeping the least.
pub(super) fn twin_distance2(a: Point3, b: Point3, c: Point3, p: Point3) -> f64 {
    let mut best = f64::INFINITY;
    for (a, b, c) in [(a, b, c), (b, c, a), (c, a, b)] {
        best = best.min(twin_from(a, b, c, p));
    }
    best
}

fn twin_from(a: Point3, b: Point3, c: Point3, p: Point3) -> f64 {
    let (ab, ac) = (sub(b, a), sub(c, a));
    let ac2 = dot(ac, ac);
    let g = |v: f64| {
        let base = at(a, ab, ac, v, 0.0);
        let w = if ac2 > 0.0 { (dot(sub(p, base), ac) / ac2).clamp(0.0, 1.0 - v) } else { 0.0 };
        dist2(p, at(a, ab, ac, v, w))
    };
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let mut best = g(0.0).min(g(1.0));
    let (mut x1, mut x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
    let (mut f1, mut f2) = (g(x1), g(x2));
    for _ in 0..120 {
        best = best.min(f1).min(f2);
        if f1 <= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - r * (hi - lo);
            f1 = g(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + r * (hi - lo);
            f2 = g(x2);
        }
    }
    best.min(f1).min(f2)
}

/// Sine of the largest angle of the triangle, computed apart from the kernel.
fn largest_angle_sine(a: Point3, b: Point3, c: Point3) -> f64 {
    let e = [sub(b, a), sub(c, b), sub(a, c)];
    let l = [dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])];
    let k = (0..3).max_by(|&i, &j| l[i].total_cmp(&l[j])).unwrap();
    let (u, w) = (e[(k + 1) % 3], e[(k + 2) % 3]);
    let x = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
    let den = (dot(u, u) * dot(w, w)).sqrt();
    if den > 0.0 {
        dot(x, x).sqrt() / den
    } else {
        0.0
    }
}

/// Checks the kernel's distance against the twin within the accuracy the module doc
/// states: a few `ε (|p − a| + L) / s`, with `s` floored where the kernel switches to
/// the edges (and, there, the sliver's width `L s` as the edges' error).
fn check(a: Point3, b: Point3, c: Point3, p: Point3) -> f64 {
    let g = TriangleGeom::new(a, b, c);
    let r = g.project(p);
    let d = r.distance_squared.sqrt();
    let t = twin_distance2(a, b, c, p).sqrt();
    let l = [dist2(a, b), dist2(b, c), dist2(c, a)].into_iter().fold(0.0, f64::max).sqrt();
    let s = largest_angle_sine(a, b, c);
    let reach = dist2(p, a).sqrt() + l;
    // The twin's points `a + v·ab + w·ac` are rounded to the ulps of the coordinates.
    let ulps = 16.0 * f64::EPSILON * p.iter().chain(&a).fold(0.0f64, |m, x| m.max(x.abs()));
    let tol = 64.0 * f64::EPSILON * reach / s.max(1.0 / 67_108_864.0)
        + ulps
        + if s < 1.0 / 67_108_864.0 { l * s } else { 0.0 };
    assert!(
        (d - t).abs() <= tol + 1e-300,
        "kernel {d:e} twin {t:e} (tol {tol:e}) for {a:?} {b:?} {c:?} p {p:?} feature {:?}",
        r.feature
    );
    // The foot lies on the triangle and as far as said.
    assert!(dist2(p, r.foot).sqrt() - d <= 4.0 * tol + 1e-300);
    assert!(twin_distance2(a, b, c, r.foot).sqrt() <= 4.0 * tol + 1e-300);
    // Relative to the distance and the size, beyond the rounding of the coordinates.
    ((d - t).abs() - ulps).max(0.0) / (t + l)
}

fn random_point(rng: &mut Rng, scale: f64) -> Point3 {
    [
        scale * (2.0 * rng.unit() - 1.0),
        scale * (2.0 * rng.unit() - 1.0),
        scale * (2.0 * rng.unit() - 1.0),
    ]
}

#[test]
fn random_triangles_and_points_agree_with_twin() {
    let mut rng = Rng(7);
    let mut worst: f64 = 0.0;
    for _ in 0..3000 {
        let (a, b, c) =
            (random_point(&mut rng, 1.0), random_point(&mut rng, 1.0), random_point(&mut rng, 1.0));
        let p = random_point(&mut rng, 2.0);
        worst = worst.max(check(a, b, c, p));
    }
    assert!(worst < 1e-13, "worst relative error {worst:e}");
}

#[test]
fn points_on_the_surface_edges_and_vertices() {
    let mut rng = Rng(11);
    for _ in 0..1000 {
        let (a, b, c) =
            (random_point(&mut rng, 1.0), random_point(&mut rng, 1.0), random_point(&mut rng, 1.0));
        let g = TriangleGeom::new(a, b, c);
        let (ab, ac) = (sub(b, a), sub(c, a));
        let (v, w) = (rng.unit(), rng.unit());
        let (v, w) = if v + w > 1.0 { (1.0 - v, 1.0 - w) } else { (v, w) };
        let inside = at(a, ab, ac, v, w);
        assert!(g.project(inside).distance_squared.sqrt() < 1e-14);
        let t = rng.unit();
        let on_edge = at(b, sub(c, b), [0.0; 3], t, 0.0);
        assert!(g.project(on_edge).distance_squared.sqrt() < 1e-14);
        for (k, q) in [a, b, c].into_iter().enumerate() {
            let r = g.project(q);
            assert!(r.distance_squared.sqrt() < 1e-14, "vertex {k}: {:e}", r.distance_squared);
        }
        check(a, b, c, inside);
        check(a, b, c, on_edge);
    }
}

#[test]
fn features_where_they_are_clear() {
    // The unit right triangle in z = 0, normal +z.
    let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let g = TriangleGeom::new(a, b, c);
    assert_eq!(g.unit_normal(), Some([0.0, 0.0, 1.0]));
    let cases: [(Point3, Feature, Point3); 7] = [
        ([0.2, 0.3, 0.7], Feature::Face, [0.2, 0.3, 0.0]),
        ([0.5, -0.4, -0.3], Feature::Edge(0), [0.5, 0.0, 0.0]),
        ([0.8, 0.8, 0.1], Feature::Edge(1), [0.5, 0.5, 0.0]),
        ([-0.3, 0.25, 2.0], Feature::Edge(2), [0.0, 0.25, 0.0]),
        ([-1.0, -2.0, 0.5], Feature::Vertex(0), a),
        ([3.0, -0.5, 0.0], Feature::Vertex(1), b),
        ([-0.1, 4.0, -1.0], Feature::Vertex(2), c),
    ];
    for (p, feature, foot) in cases {
        let r = g.project(p);
        assert_eq!(r.feature, feature, "{p:?}");
        assert!(dist2(r.foot, foot) < 1e-30, "{p:?}: {:?}", r.foot);
        assert!((r.distance_squared - dist2(p, foot)).abs() < 1e-15);
    }
    // The same triangle walked the other way round: the normal flips, features follow.
    let h = TriangleGeom::new(a, c, b);
    assert_eq!(h.unit_normal(), Some([0.0, 0.0, -1.0]));
    assert_eq!(h.project([0.5, -0.4, -0.3]).feature, Feature::Edge(2));
}

#[test]
fn shared_edges_and_vertices_give_identical_distances() {
    let mut rng = Rng(5);
    for _ in 0..500 {
        let (a, b) = (random_point(&mut rng, 1.0), random_point(&mut rng, 1.0));
        let (c, d) = (random_point(&mut rng, 1.0), random_point(&mut rng, 1.0));
        // Two triangles on the edge ab, walked in opposite directions.
        let (s, t) = (TriangleGeom::new(a, b, c), TriangleGeom::new(b, a, d));
        let p = random_point(&mut rng, 2.0);
        let (rs, rt) = (s.project(p), t.project(p));
        if matches!(rs.feature, Feature::Edge(0) | Feature::Vertex(0) | Feature::Vertex(1))
            && matches!(rt.feature, Feature::Edge(0) | Feature::Vertex(0) | Feature::Vertex(1))
        {
            assert_eq!(rs.distance_squared, rt.distance_squared);
            assert_eq!(rs.foot, rt.foot);
        }
    }
}

#[test]
fn degenerate_triangles() {
    let mut rng = Rng(3);
    for _ in 0..500 {
        let (a, b) = (random_point(&mut rng, 1.0), random_point(&mut rng, 1.0));
        let p = random_point(&mut rng, 2.0);
        let t = rng.unit();
        let mid = at(a, sub(b, a), [0.0; 3], t, 0.0);
        // Collinear (zero area), repeated vertex, all three equal.
        for (x, y, z) in [(a, b, mid), (a, mid, b), (a, a, b), (a, b, b), (b, a, a), (a, a, a)] {
            let g = TriangleGeom::new(x, y, z);
            assert!(g.is_degenerate() || largest_angle_sine(x, y, z) > 0.0);
            check(x, y, z, p);
            check(x, y, z, mid);
        }
        assert_eq!(TriangleGeom::new(a, a, a).project(a).distance_squared, 0.0);
        assert_eq!(TriangleGeom::new(a, a, a).project(p).distance_squared, dist2(p, a));
    }
}

#[test]
fn slivers_caps_and_needles() {
    let mut rng = Rng(13);
    for k in 1..=14 {
        let s = 10f64.powi(-k);
        for _ in 0..150 {
            let (a, b) = (random_point(&mut rng, 1.0), random_point(&mut rng, 1.0));
            let ab = sub(b, a);
            let off = random_point(&mut rng, 1.0);
            let len = dot(ab, ab).sqrt();
            let t = rng.unit();
            // A cap: the third vertex at height s·|ab| over a point of ab.
            let cap = [
                a[0] + t * ab[0] + s * len * off[0],
                a[1] + t * ab[1] + s * len * off[1],
                a[2] + t * ab[2] + s * len * off[2],
            ];
            // A needle: two vertices s·|ab| apart, the third far.
            let needle =
                [b[0] + s * len * off[0], b[1] + s * len * off[1], b[2] + s * len * off[2]];
            let p = random_point(&mut rng, 2.0);
            let near = at(a, ab, [0.0; 3], rng.unit(), 0.0);
            for q in [p, near, cap] {
                check(a, b, cap, q);
                check(a, b, needle, q);
            }
        }
    }
}

#[test]
fn far_points_and_tiny_triangles() {
    let mut rng = Rng(17);
    for _ in 0..400 {
        for (size, far) in [(1e-9, 1.0), (1.0, 1e8), (1e-9, 1e8), (1e-9, 1e-8)] {
            let centre = random_point(&mut rng, 3.0);
            let tri: Vec<Point3> = (0..3)
                .map(|_| {
                    let o = random_point(&mut rng, size);
                    [centre[0] + o[0], centre[1] + o[1], centre[2] + o[2]]
                })
                .collect();
            let dir = random_point(&mut rng, far);
            let p = [centre[0] + dir[0], centre[1] + dir[1], centre[2] + dir[2]];
            check(tri[0], tri[1], tri[2], p);
            // In the triangle's plane, far off to the side: the region decision must not
            // send it to the face.
            let (ab, ac) = (sub(tri[1], tri[0]), sub(tri[2], tri[0]));
            let v = -far / size;
            let inplane = at(tri[0], ab, ac, v, 0.3);
            let rel = check(tri[0], tri[1], tri[2], inplane);
            assert!(
                rel < 1e-12,
                "in-plane far point: relative error {rel:e} size {size} far {far}"
            );
        }
    }
}

#[test]
fn orient3d_signs() {
    let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    assert!(orient3d(a, b, c, [0.3, 0.3, 1.0]) > 0.0);
    assert!(orient3d(a, b, c, [0.3, 0.3, -1e-300]) < 0.0);
    assert_eq!(orient3d(a, b, c, [5.0, -7.0, 0.0]), 0.0);
    // Exact where the plain determinant rounds to the wrong sign: the plane through three
    // points near 1 and a fourth a few ulps off it.
    let e = f64::EPSILON;
    let (a, b, c) = ([1.0, 1.0, 1.0], [1.0 + e, 1.0, 1.0 + e], [1.0, 1.0 + e, 1.0 + e]);
    let on = [1.0 + 2.0 * e, 1.0 + 2.0 * e, 1.0 + 4.0 * e];
    assert_eq!(orient3d(a, b, c, on), 0.0);
    let above = [on[0], on[1], on[2] + 2.0 * e];
    let below = [on[0], on[1], on[2] - 2.0 * e];
    assert!(orient3d(a, b, c, above) > 0.0);
    assert!(orient3d(a, b, c, below) < 0.0);
}
