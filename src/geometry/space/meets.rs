//! Whether a point, a segment or a triangle meets a tetrahedron, or the convex hull of a
//! cell's corners (closed sets: touching counts), decided by the signs of the exact
//! orientation predicates alone (`orient3d`, and `orient2d` in a coordinate plane for
//! coplanar pieces), so that the answer never depends on rounding: a free source's
//! coarse-mesh rule (`sizing::space`) asks it.
//!
//! Method. A piece (triangle `abc`, a segment as `(a, b, b)`, a point as `(p, p, p)`)
//! meets a tetrahedron T iff a corner of the piece lies in T, or an edge of the piece
//! meets a face of T, or an edge of T meets the piece: the piece ∩ T is a convex set
//! whose boundary points lie on the piece's edges or on T's boundary, and where no
//! corner is inside, one of those crossings exists. A segment `pq` meets a triangle
//! `abc` when p and q are not strictly on one side of its plane and the three
//! orientations of the triangle's edges seen along `pq` do not differ strictly in sign;
//! when all four are coplanar, the question is asked again in the coordinate plane where
//! the triangle's normal is largest (a projection that keeps orientation signs for a
//! triangle of non-zero area). A flat tetrahedron (zero volume) contains no point but
//! its faces: only the crossings decide. A triangle of zero area (a segment piece, a point,
//! a collinear sheet triangle) is its three edges, each met by a segment when the four
//! points are coplanar and their projection onto a coordinate plane that maps their plane
//! (or common line) one to one shows the two segments meeting.
//!
//! A cell of another kind (a surface triangle or quadrilateral, a hexahedron, a prism, a
//! pyramid) is met through its corners' convex hull ([`piece_meets_hull`]): the union of
//! the tetrahedra of every four corners, each decided as above.
//!
//! Hand-written: no crate offers exact segment/triangle–tetrahedron tests (parry3d's
//! intersection tests are in floating point, with tolerances).

use super::triangle::{orient3d, Point3};

type Point2 = [f64; 2];

fn orient2d(a: Point2, b: Point2, c: Point2) -> f64 {
    robust::orient2d(
        robust::Coord { x: a[0], y: a[1] },
        robust::Coord { x: b[0], y: b[1] },
        robust::Coord { x: c[0], y: c[1] },
    )
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// The faces of a tetrahedron, each with the corner opposite it.
const FACES: [([usize; 3], usize); 4] =
    [([1, 2, 3], 0), ([0, 3, 2], 1), ([0, 1, 3], 2), ([0, 2, 1], 3)];
const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// Whether `p` lies in the closed tetrahedron `t` (never for a flat one).
pub(crate) fn point_in_tet(t: &[Point3; 4], p: Point3) -> bool {
    let volume = sign(orient3d(t[0], t[1], t[2], t[3]));
    if volume == 0 {
        return false;
    }
    FACES.iter().all(|&([i, j, k], l)| {
        let own = sign(orient3d(t[i], t[j], t[k], t[l]));
        let s = sign(orient3d(t[i], t[j], t[k], p));
        s == 0 || s == own
    })
}

/// Drops coordinate `k`.
fn drop_axis(p: Point3, k: usize) -> Point2 {
    match k {
        0 => [p[1], p[2]],
        1 => [p[0], p[2]],
        _ => [p[0], p[1]],
    }
}

/// Whether closed segments `pq` and `ab` of the plane meet.
fn segments_meet2(p: Point2, q: Point2, a: Point2, b: Point2) -> bool {
    let (d1, d2) = (sign(orient2d(p, q, a)), sign(orient2d(p, q, b)));
    let (d3, d4) = (sign(orient2d(a, b, p)), sign(orient2d(a, b, q)));
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return true;
    }
    let on = |x: Point2, y: Point2, z: Point2| {
        // z on the closed segment xy, given the three are collinear.
        x[0].min(y[0]) <= z[0]
            && z[0] <= x[0].max(y[0])
            && x[1].min(y[1]) <= z[1]
            && z[1] <= x[1].max(y[1])
    };
    (d1 == 0 && on(p, q, a))
        || (d2 == 0 && on(p, q, b))
        || (d3 == 0 && on(a, b, p))
        || (d4 == 0 && on(a, b, q))
}

/// Whether `p` lies in the closed triangle `abc` of the plane (of non-zero area).
fn point_in_triangle2(p: Point2, a: Point2, b: Point2, c: Point2) -> bool {
    let s = [sign(orient2d(a, b, p)), sign(orient2d(b, c, p)), sign(orient2d(c, a, p))];
    !(s.contains(&1) && s.contains(&-1))
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// The axis of the largest absolute component.
fn largest(v: Point3) -> usize {
    let a = v.map(f64::abs);
    if a[0] >= a[1] && a[0] >= a[2] {
        0
    } else if a[1] >= a[2] {
        1
    } else {
        2
    }
}

/// Whether `a`, `b`, `c` lie on one line (every coordinate projection of zero area).
fn collinear(a: Point3, b: Point3, c: Point3) -> bool {
    (0..3).all(|k| orient2d(drop_axis(a, k), drop_axis(b, k), drop_axis(c, k)) == 0.0)
}

/// Whether closed segments `pq` and `ab` of space meet: coplanar, then in a coordinate
/// plane onto which their plane (or their common line) projects one to one. That plane is
/// chosen from exact signs alone: one where a triple of the four points keeps a non-zero
/// area (its plane is theirs, and the projection keeps it one to one); when every triple
/// is collinear in every projection the four lie on one line, and any coordinate plane
/// where two distinct ones stay distinct maps that line one to one. (Choosing it from the
/// rounded cross product of the directions could take two parallel segments on distinct
/// lines onto one line, or miss a crossing the rounding called parallel.)
fn segments_meet3(p: Point3, q: Point3, a: Point3, b: Point3) -> bool {
    if orient3d(p, q, a, b) != 0.0 {
        return false;
    }
    let points = [p, q, a, b];
    let triples = [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]];
    let spans = |k: usize| {
        triples.iter().any(|t| {
            let [x, y, z] = t.map(|i| drop_axis(points[i], k));
            orient2d(x, y, z) != 0.0
        })
    };
    let axis = (0..3).find(|&k| spans(k)).or_else(|| {
        let v = points.iter().find(|&&x| x != p)?;
        (0..3).find(|&k| drop_axis(p, k) != drop_axis(*v, k))
    });
    match axis {
        Some(k) => {
            segments_meet2(drop_axis(p, k), drop_axis(q, k), drop_axis(a, k), drop_axis(b, k))
        }
        // The four points are one point.
        None => true,
    }
}

/// Whether the closed segment `pq` meets the closed triangle `abc` of non-zero area, all
/// four coplanar: in a coordinate plane where the triangle keeps a non-zero area.
fn coplanar_segment_meets_triangle(p: Point3, q: Point3, a: Point3, b: Point3, c: Point3) -> bool {
    let first = largest(cross(sub(b, a), sub(c, a)));
    for k in [first, (first + 1) % 3, (first + 2) % 3] {
        let (a2, b2, c2) = (drop_axis(a, k), drop_axis(b, k), drop_axis(c, k));
        if orient2d(a2, b2, c2) == 0.0 {
            continue;
        }
        let (p2, q2) = (drop_axis(p, k), drop_axis(q, k));
        return point_in_triangle2(p2, a2, b2, c2)
            || point_in_triangle2(q2, a2, b2, c2)
            || segments_meet2(p2, q2, a2, b2)
            || segments_meet2(p2, q2, b2, c2)
            || segments_meet2(p2, q2, c2, a2);
    }
    false
}

/// Whether the closed segment `pq` meets the closed triangle `abc` (see the module header).
pub(crate) fn segment_meets_triangle(
    p: Point3,
    q: Point3,
    a: Point3,
    b: Point3,
    c: Point3,
) -> bool {
    if collinear(a, b, c) {
        return segments_meet3(p, q, a, b)
            || segments_meet3(p, q, b, c)
            || segments_meet3(p, q, c, a);
    }
    let (op, oq) = (sign(orient3d(a, b, c, p)), sign(orient3d(a, b, c, q)));
    if op * oq > 0 {
        return false;
    }
    if op == 0 && oq == 0 {
        return coplanar_segment_meets_triangle(p, q, a, b, c);
    }
    let s = [sign(orient3d(p, q, a, b)), sign(orient3d(p, q, b, c)), sign(orient3d(p, q, c, a))];
    !(s.contains(&1) && s.contains(&-1))
}

/// Whether the closed triangle (or segment `(a, b, b)`, or point `(p, p, p)`) `piece`
/// meets the closed tetrahedron `t`.
pub(crate) fn piece_meets_tet(piece: &[Point3; 3], t: &[Point3; 4]) -> bool {
    if piece.iter().any(|&p| point_in_tet(t, p)) {
        return true;
    }
    let piece_edges = [[0, 1], [1, 2], [2, 0]];
    for [i, j] in piece_edges {
        for ([a, b, c], _) in FACES {
            if segment_meets_triangle(piece[i], piece[j], t[a], t[b], t[c]) {
                return true;
            }
        }
    }
    // A piece of zero area is its edges, tested above against every face.
    !collinear(piece[0], piece[1], piece[2])
        && EDGES
            .iter()
            .any(|&[i, j]| segment_meets_triangle(t[i], t[j], piece[0], piece[1], piece[2]))
}

/// Whether the closed piece (as [`piece_meets_tet`]) meets the convex hull of `corners`
/// (a cell's corners: one to eight points; none meets nothing). The hull is the union of
/// the tetrahedra of every four of the corners (Carathéodory), some of them flat: a
/// triangle `abc` is the flat tetrahedron `abcc`, a segment `abbb`, four corners their
/// one tetrahedron, flat or not. Every answer is the exact one of [`piece_meets_tet`].
pub(crate) fn piece_meets_hull(piece: &[Point3; 3], corners: &[Point3]) -> bool {
    match *corners {
        [] => false,
        [a] => piece_meets_tet(piece, &[a, a, a, a]),
        [a, b] => piece_meets_tet(piece, &[a, b, b, b]),
        [a, b, c] => piece_meets_tet(piece, &[a, b, c, c]),
        [a, b, c, d] => piece_meets_tet(piece, &[a, b, c, d]),
        _ => {
            let n = corners.len();
            for i in 0..n {
                for j in i + 1..n {
                    for k in j + 1..n {
                        for l in k + 1..n {
                            let t = [corners[i], corners[j], corners[k], corners[l]];
                            if piece_meets_tet(piece, &t) {
                                return true;
                            }
                        }
                    }
                }
            }
            false
        }
    }
}
