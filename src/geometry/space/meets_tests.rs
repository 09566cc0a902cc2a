//! Twins of the exact piece–hull test (`meets::piece_meets_hull`): a floating-point
//! separating-axis test on random cells of every corner count (surface triangles,
//! warped quadrilaterals, pyramids, prisms, hexahedra) against random points, segments and
//! triangles, wherever the float test is clear of a tie; a dense sampling of warped
//! hexahedra (every point of the trilinear cell lies in the hull); and touching and
//! parallel cases built exactly.

use super::meets::piece_meets_hull;
use super::Point3;

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Every direction between two of `points`, and the normal of every three of them.
fn directions(points: &[Point3]) -> (Vec<Point3>, Vec<Point3>) {
    let (mut edges, mut normals) = (Vec::new(), Vec::new());
    for (i, a) in points.iter().enumerate() {
        for (j, b) in points.iter().enumerate().skip(i + 1) {
            edges.push(sub(*b, *a));
            for c in &points[j + 1..] {
                normals.push(cross(sub(*b, *a), sub(*c, *a)));
            }
        }
    }
    (edges, normals)
}

/// A float separating-axis test of the convex hulls of `a` and `b`, over a superset of
/// the axes the theorem needs (every normal of three points of either set, every edge of
/// one crossed with every edge of the other, and for flat sets the in-plane normals
/// `normal × edge`): an extra axis never separates wrongly. Returns whether they meet and
/// the smallest separation or overlap found (near zero: too close to call in float).
fn sat(a: &[Point3], b: &[Point3]) -> (bool, f64) {
    let (ea, na) = directions(a);
    let (eb, nb) = directions(b);
    let mut axes: Vec<Point3> = na.iter().chain(&nb).copied().collect();
    for x in &ea {
        for y in &eb {
            axes.push(cross(*x, *y));
        }
    }
    for (normals, edges) in [(&na, &ea), (&nb, &eb)] {
        for n in normals {
            for e in edges {
                axes.push(cross(*n, *e));
            }
        }
    }
    let mut best = f64::INFINITY;
    for axis in axes {
        let l = dot(axis, axis).sqrt();
        if l < 1e-12 {
            continue;
        }
        let axis = axis.map(|x| x / l);
        let range = |ps: &[Point3]| {
            ps.iter()
                .map(|p| dot(*p, axis))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
        };
        let ((al, ah), (bl, bh)) = (range(a), range(b));
        let gap = (bl - ah).max(al - bh);
        if gap > 0.0 {
            return (false, gap);
        }
        best = best.min(-gap);
    }
    (true, best)
}

struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn point(&mut self, lo: f64, hi: f64) -> Point3 {
        std::array::from_fn(|_| lo + (hi - lo) * self.next())
    }
}

/// A hexahedron: the unit cube's corners (Gmsh order) moved by up to `warp` each.
fn warped_hex(r: &mut Random, warp: f64) -> [Point3; 8] {
    let cube =
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]];
    cube.map(|c| std::array::from_fn(|k| c[k] as f64 + warp * (r.next() - 0.5)))
}

/// The cells of the random cases: a triangle, a warped quadrilateral, a pyramid and a
/// prism from a warped hexahedron's corners, the hexahedron itself.
fn cell(r: &mut Random, case: usize) -> Vec<Point3> {
    let h = warped_hex(r, 0.6);
    match case % 5 {
        0 => vec![h[0], h[1], h[2]],
        1 => vec![h[0], h[1], h[2], h[3]],
        2 => vec![h[0], h[1], h[2], h[3], [0.5 + 0.3 * r.next(), 0.5, 1.0 + 0.3 * r.next()]],
        3 => vec![h[0], h[1], h[2], h[4], h[5], h[6]],
        _ => h.to_vec(),
    }
}

#[test]
fn the_exact_piece_hull_test_is_its_separating_axis_twin() {
    let mut r = Random(19);
    let mut counts = [[0usize; 2]; 5];
    for case in 0..6000 {
        let corners = cell(&mut r, case);
        let mut piece: [Point3; 3] = std::array::from_fn(|_| r.point(-0.6, 1.6));
        match (case / 5) % 3 {
            0 => piece[2] = piece[1],
            1 => piece = [piece[0]; 3],
            _ => {}
        }
        let mut distinct: Vec<Point3> = piece.to_vec();
        distinct.dedup();
        let (float, margin) = sat(&distinct, &corners);
        if margin.abs() < 1e-9 {
            continue;
        }
        assert_eq!(piece_meets_hull(&piece, &corners), float, "case {case}: {piece:?} {corners:?}");
        counts[case % 5][usize::from(float)] += 1;
    }
    // Every kind of cell was met and missed many times (points rarely meet a triangle).
    for (kind, [apart, met]) in counts.iter().enumerate() {
        assert!(*apart > 300 && (*met > 150 || kind == 0 && *met > 50), "{kind}: {counts:?}");
    }
}

/// Every point of a warped hexahedron (its trilinear map) is met by the test of its
/// corners' hull: a dense sampling of the cell's inside, as points; every corner too.
#[test]
fn every_point_of_a_warped_hexahedron_meets_its_hull() {
    let mut r = Random(3);
    for _ in 0..40 {
        let h = warped_hex(&mut r, 0.8);
        // Inside the cell (on its boundary, rounding may put the sample a hair out).
        for i in 1..6 {
            for j in 1..6 {
                for k in 1..6 {
                    let (u, v, w) = (i as f64 / 6.0, j as f64 / 6.0, k as f64 / 6.0);
                    let weights = [
                        (1.0 - u) * (1.0 - v) * (1.0 - w),
                        u * (1.0 - v) * (1.0 - w),
                        u * v * (1.0 - w),
                        (1.0 - u) * v * (1.0 - w),
                        (1.0 - u) * (1.0 - v) * w,
                        u * (1.0 - v) * w,
                        u * v * w,
                        (1.0 - u) * v * w,
                    ];
                    let p: Point3 = std::array::from_fn(|d| {
                        weights.iter().zip(&h).map(|(wt, c)| wt * c[d]).sum::<f64>()
                    });
                    assert!(piece_meets_hull(&[p; 3], &h), "{p:?} in {h:?}");
                }
            }
        }
        assert!(h.iter().all(|&c| piece_meets_hull(&[c; 3], &h)));
    }
}

/// Touching cases built exactly meet, the same a hair away do not; two parallel segments
/// on distinct lines of one coordinate plane never meet (a projection could merge them).
#[test]
fn touching_and_parallel_cases_are_exact() {
    let cube: Vec<Point3> =
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]
            .iter()
            .map(|c| c.map(f64::from))
            .collect();
    let above = 1.0 + f64::EPSILON;
    assert!(piece_meets_hull(&[[0.5, 0.5, 1.0]; 3], &cube));
    assert!(!piece_meets_hull(&[[0.5, 0.5, above]; 3], &cube));
    assert!(piece_meets_hull(&[[2.0, 2.0, 2.0], [1.0, 1.0, 1.0], [1.0, 1.0, 1.0]], &cube));
    assert!(piece_meets_hull(&[[-1.0, 0.5, 1.0], [2.0, 0.5, 1.0], [0.5, 3.0, 1.0]], &cube));
    assert!(!piece_meets_hull(&[[-1.0, 0.5, above], [2.0, 0.5, above], [0.5, 3.0, above]], &cube));
    let line = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    assert!(!piece_meets_hull(&[[0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 0.0]], &line));
    assert!(!piece_meets_hull(&[[0.2, 1e-300, 0.0]; 3], &line));
    assert!(piece_meets_hull(&[[1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 0.0, 0.0]], &line));
    let triangle = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert!(piece_meets_hull(&[[0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [0.5, 0.5, 1.0]], &triangle));
    let off = 0.5 + f64::EPSILON / 2.0;
    assert!(!piece_meets_hull(&[[off, 0.5, -1.0], [off, 0.5, 1.0], [off, 0.5, 1.0]], &triangle));
    // A sheet triangle crossing the triangle's plane along a line through its interior.
    assert!(piece_meets_hull(&[[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [3.0, 3.0, 0.5]], &triangle));
    assert!(!piece_meets_hull(&[[0.6, 0.6, -1.0], [0.6, 0.6, 1.0], [3.0, 3.0, 0.5]], &triangle));
}
