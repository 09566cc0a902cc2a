//! CURVATURE_OF_BORDER in space against its analytic twins: the size tensors of the
//! vertices of a sphere, a cylinder and a torus (and of points off them) against the
//! analytic principal curvatures through the same functions, at several refinements
//! (errors and orders printed, `-- --nocapture`); a coarse sphere; a cube whose edges
//! are ridges (no curvature smeared across them); curves in space (a circle, exact, and
//! a helix, converging).

use super::{CurvatureOfBorder, SpaceBorder, SpaceFoot};
use crate::geometry::space::curvature_tests::{grid, octasphere, Mesh};
use crate::geometry::space::{Point3, SurfaceIndex};
use crate::metric::SizeTensor3;
use crate::sizing::algorithms::EntitySet;
use crate::sizing::functions::{CurvatureToSize, DistanceFunction, SizeProjectionFunction};

fn algorithm() -> CurvatureOfBorder {
    CurvatureOfBorder {
        perpendicular: DistanceFunction::try_new(0.002, 0.5, 1.0, 1.0).unwrap(),
        curvature: CurvatureToSize::try_new(1e-4, 10.0, 1e-3).unwrap(),
        projection: SizeProjectionFunction::try_new(1.0, 1.0, 1.0).unwrap(),
        borders: EntitySet::default(),
    }
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn unit(a: Point3) -> Point3 {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// The relative error of `t`'s size along `dir` against `h`.
fn rel(t: &SizeTensor3, dir: Point3, h: f64) -> f64 {
    (t.size_along(unit(dir)) - h).abs() / h
}

/// The curvature a size stands for: the inverse of the curvature-to-size function (0
/// at its largest size, where it is clamped).
fn k_back(a: &CurvatureOfBorder, h: f64) -> f64 {
    let delta = a.curvature.size_of_error();
    if h >= a.curvature.max_size() {
        0.0
    } else if h > 2.0 * delta {
        // h = 2 √(δ (2R − δ)).
        2.0 / (h * h / (4.0 * delta) + delta)
    } else {
        2.0 / h
    }
}

/// The error of the curvature `t`'s size along `dir` stands for, against `k`.
fn k_err(a: &CurvatureOfBorder, t: &SizeTensor3, dir: Point3, k: f64) -> f64 {
    (k_back(a, t.size_along(unit(dir))) - k).abs()
}

/// The tensor of `p` from its closest point on the surface of `border`.
fn at(border: &SpaceBorder, index: &SurfaceIndex, p: Point3) -> SizeTensor3 {
    let foot = index.closest(p).unwrap();
    border.tensor(&algorithm(), p, 0, &SpaceFoot::Surface(foot)).unwrap()
}

/// Prints the runs with their orders; checks the errors shrink and the last order.
fn report(name: &str, runs: &[(f64, f64)], min_order: f64) {
    for (i, (h, e)) in runs.iter().enumerate() {
        let order = if i == 0 {
            String::new()
        } else {
            format!("  order {:.2}", (runs[i - 1].1 / e).ln() / (runs[i - 1].0 / h).ln())
        };
        println!("{name}: h = {h:.4e}  max error {e:.3e}{order}");
    }
    let n = runs.len();
    let last = (runs[n - 2].1 / runs[n - 1].1).ln() / (runs[n - 2].0 / runs[n - 1].0).ln();
    assert!(runs.windows(2).all(|w| w[1].1 < w[0].1), "{name}: {runs:?}");
    assert!(last >= min_order, "{name}: last order {last} below {min_order}");
}

#[test]
fn sphere_sizes_from_one_over_r() {
    let (a, r, d) = (algorithm(), 1.0, 0.05);
    let h_on = a.curvature.eval(1.0 / r);
    let (mut on_runs, mut off_runs) = (Vec::new(), Vec::new());
    for level in 1..=4 {
        // Jittered but the coarsest (18 vertices, which jitter would fold).
        let mesh = octasphere(level, if level == 1 { 0.0 } else { 0.3 }, 5);
        let border = SpaceBorder::new(&mesh.points, &mesh.triangles, &[]).unwrap();
        let index = SurfaceIndex::new(&mesh.points, &mesh.triangles).unwrap();
        let (mut on, mut off): (f64, f64) = (0.0, 0.0);
        for &p in &mesh.points {
            let t = at(&border, &index, p);
            // The normal size is the perpendicular function's at 0, along the fitted normal.
            assert!(rel(&t, p, a.perpendicular.eval(0.0)) < 0.05, "{t:?}");
            // The tangent sizes (any tangent is principal on a sphere), read on the
            // tensor's own axes: a size along a direction off them mixes in the normal
            // size, 45 times smaller.
            let h = t.sizes();
            on = on.max((h[1] - h_on).abs() / h_on).max((h[2] - h_on).abs() / h_on);
        }
        for tri in &mesh.triangles {
            // Off the surface above each triangle's centroid.
            let c = [0, 1, 2].map(|k| tri.iter().map(|&v| mesh.points[v as usize][k]).sum::<f64>());
            let q = unit(c).map(|x| x * (r + d));
            let foot = index.closest(q).unwrap();
            let (away, dq) = (foot.away(q).unwrap(), foot.distance());
            let t = at(&border, &index, q);
            // Along the way from the foot: the perpendicular function at the distance.
            assert!(rel(&t, away, a.perpendicular.eval(dq)) < 1e-9, "{t:?}");
            let (u, w) = super::plane_basis(away);
            let h_off = a.projection.eval(dq, h_on);
            off = off.max(rel(&t, u, h_off)).max(rel(&t, w, h_off));
        }
        if level == 1 {
            // The coarse sphere (18 vertices): within a factor of two.
            assert!(on < 1.0 && off < 1.0, "{on} {off}");
        }
        on_runs.push((mesh.h(), on));
        off_runs.push((mesh.h(), off));
    }
    report("sphere tangent sizes at the vertices (relative)", &on_runs, 1.5);
    report("sphere tangent sizes 0.05 off the surface (relative)", &off_runs, 1.5);
}

#[test]
fn cylinder_sizes_along_the_circle_and_the_axis() {
    let (a, r) = (algorithm(), 0.5);
    let tau = std::f64::consts::TAU;
    let h_circle = a.curvature.eval(1.0 / r);
    let h_axis = a.curvature.eval(0.0);
    let (mut runs, mut axis_runs) = (Vec::new(), Vec::new());
    for n in [16, 32, 64] {
        let (mesh, params, edge) = grid(n, n / 2, [true, false], 0.3, 11, move |u, v| {
            [r * (tau * u).cos(), r * (tau * u).sin(), 2.0 * v]
        });
        let border = SpaceBorder::new(&mesh.points, &mesh.triangles, &[]).unwrap();
        let index = SurfaceIndex::new(&mesh.points, &mesh.triangles).unwrap();
        let (mut worst, mut worst_axis): (f64, f64) = (0.0, 0.0);
        for v in (0..mesh.points.len()).filter(|&v| !edge[v]) {
            let phi = tau * params[v][0];
            let t = at(&border, &index, mesh.points[v]);
            worst = worst.max(rel(&t, [-phi.sin(), phi.cos(), 0.0], h_circle));
            worst_axis = worst_axis.max(k_err(&a, &t, [0.0, 0.0, 1.0], 0.0));
        }
        runs.push((mesh.h(), worst));
        axis_runs.push((mesh.h(), worst_axis));
    }
    report("cylinder size along the circle (relative)", &runs, 1.5);
    // Along the axis: the curvature the size stands for (its size is h_axis for k = 0).
    report(&format!("cylinder curvature read back along the axis (h(0) = {h_axis})"), &axis_runs, 1.5);
}

#[test]
fn torus_sizes_along_meridians_and_parallels() {
    let (a, big, small) = (algorithm(), 3.0, 1.0);
    let tau = std::f64::consts::TAU;
    let mut runs = Vec::new();
    for n in [12, 24, 48] {
        let (mesh, params, _) = grid(2 * n, n, [true, true], 0.3, 13, |u, v| {
            let (phi, theta) = (tau * u, tau * v);
            let rho = big + small * theta.cos();
            [rho * phi.cos(), rho * phi.sin(), small * theta.sin()]
        });
        let border = SpaceBorder::new(&mesh.points, &mesh.triangles, &[]).unwrap();
        let index = SurfaceIndex::new(&mesh.points, &mesh.triangles).unwrap();
        let mut worst: f64 = 0.0;
        for (v, par) in params.iter().enumerate() {
            let (phi, theta) = (tau * par[0], tau * par[1]);
            let k_parallel = (theta.cos() / (big + small * theta.cos())).abs();
            let t = at(&border, &index, mesh.points[v]);
            let meridian = [-theta.sin() * phi.cos(), -theta.sin() * phi.sin(), theta.cos()];
            let parallel = [-phi.sin(), phi.cos(), 0.0];
            // The curvatures the sizes stand for (the size of a small curvature is too
            // steep a function of it to compare sizes).
            worst = worst
                .max(k_err(&a, &t, meridian, 1.0 / small))
                .max(k_err(&a, &t, parallel, k_parallel));
        }
        runs.push((mesh.h(), worst));
    }
    report("torus curvature read back along meridians and parallels", &runs, 1.4);
}

/// A unit cube, each face an `n` × `n` grid, and its 12 edges.
fn cube(n: i64) -> (Mesh, Vec<[u32; 2]>) {
    let mut points: Vec<Point3> = Vec::new();
    let mut index = std::collections::BTreeMap::new();
    let mut triangles = Vec::new();
    let mut id = |q: [i64; 3], points: &mut Vec<Point3>| {
        *index.entry(q).or_insert_with(|| {
            points.push(q.map(|x| x as f64 / n as f64));
            points.len() as u32 - 1
        })
    };
    for axis in 0..3 {
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: i64, dj: i64| {
                        let mut q = [0; 3];
                        q[axis] = side;
                        q[(axis + 1) % 3] = i + di;
                        q[(axis + 2) % 3] = j + dj;
                        q
                    };
                    let v = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
                        .map(|q| id(q, &mut points));
                    triangles.push([v[0], v[1], v[2]]);
                    triangles.push([v[0], v[2], v[3]]);
                }
            }
        }
    }
    let on_edge = |p: Point3| p.iter().filter(|&&x| x == 0.0 || x == 1.0).count() >= 2;
    let mut edges = Vec::new();
    for t in &triangles {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            let (p, q) = (points[a as usize], points[b as usize]);
            if on_edge(p) && on_edge(q) && (0..3).filter(|&k| p[k] == q[k]).count() == 2 {
                edges.push([a.min(b), a.max(b)]);
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    (Mesh { points, triangles }, edges)
}

#[test]
fn cube_edges_smear_no_curvature() {
    let a = algorithm();
    let (h0, h_max) = (a.perpendicular.eval(0.0), a.curvature.max_size());
    let (mesh, edges) = cube(4);
    let border = SpaceBorder::new(&mesh.points, &mesh.triangles, &edges).unwrap();
    let index = SurfaceIndex::new(&mesh.points, &mesh.triangles).unwrap();
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for &p in &mesh.points {
        let t = at(&border, &index, p);
        let bounds: Vec<usize> = (0..3).filter(|&k| p[k] == 0.0 || p[k] == 1.0).collect();
        for (k, axis) in axes.iter().enumerate() {
            // The normal size along each face's normal, the largest size along the faces
            // and the edges (flat, straight): no size from the dihedral angle.
            let expected = if bounds.contains(&k) { h0 } else { h_max };
            assert!(rel(&t, *axis, expected) < 1e-9, "{p:?} axis {k}: {t:?}");
        }
    }
    // Off the edge x = y = 0 (foot on the ridge, inside an edge): the normal size along
    // the way out, the largest size along the edge and across.
    let d = 0.1;
    let q = [-d / 2f64.sqrt(), -d / 2f64.sqrt(), 0.4];
    let t = at(&border, &index, q);
    assert!(rel(&t, [-1.0, -1.0, 0.0], a.perpendicular.eval(d)) < 1e-9, "{t:?}");
    let h_far = a.projection.eval(d, h_max);
    assert!(rel(&t, [0.0, 0.0, 1.0], h_far) < 1e-9 && rel(&t, [1.0, -1.0, 0.0], h_far) < 1e-9);
    // Without the ridges, the same cube's edges would be read as bent (the twin of
    // "smeared"): a size far below the largest along the faces.
    let smeared = SpaceBorder::new(&mesh.points, &mesh.triangles, &[]).unwrap();
    let edge_vertex = mesh.points.iter().position(|p| *p == [0.5, 0.0, 0.0]).unwrap();
    let t = at(&smeared, &index, mesh.points[edge_vertex]);
    assert!(t.size_along(unit([0.0, 1.0, 1.0])) < 0.1 * h_max, "{t:?}");
}

/// The closest point of `p` on the curve `edges` by a scan.
fn curve_foot(points: &[Point3], edges: &[[u32; 2]], p: Point3) -> SpaceFoot {
    let mut best: Option<(f64, SpaceFoot)> = None;
    for &[x, y] in edges {
        let (a, b) = (points[x as usize], points[y as usize]);
        let ab = sub(b, a);
        let t = (dot(sub(p, a), ab) / dot(ab, ab)).clamp(0.0, 1.0);
        let foot = [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]];
        let distance = dot(sub(p, foot), sub(p, foot)).sqrt();
        if best.as_ref().is_none_or(|b| distance < b.0) {
            best = Some((distance, SpaceFoot::Curve { edge: [x, y], t, distance, foot }));
        }
    }
    best.unwrap().1
}

#[test]
fn curves_in_space_take_their_three_point_curvature() {
    let a = algorithm();
    let tau = std::f64::consts::TAU;
    // A circle of radius 2 in a tilted plane: the circle through three vertices is the
    // circle itself, so the tangent size is h(1/2) to rounding.
    let (e1, e2) = (unit([1.0, 1.0, 0.0]), unit([-1.0, 1.0, 2.0]));
    let n = 40;
    let points: Vec<Point3> = (0..n)
        .map(|i| {
            let (c, s) = ((tau * i as f64 / n as f64).cos(), (tau * i as f64 / n as f64).sin());
            [0, 1, 2].map(|k| 2.0 * (c * e1[k] + s * e2[k]))
        })
        .collect();
    let edges: Vec<[u32; 2]> = (0..n as u32).map(|i| [i, (i + 1) % n as u32]).collect();
    let border = SpaceBorder::new(&points, &[], &edges).unwrap();
    let h_t = a.curvature.eval(0.5);
    for (i, &p) in points.iter().enumerate() {
        let t = border.tensor(&a, p, i, &curve_foot(&points, &edges, p)).unwrap();
        let tangent = sub(points[(i + 1) % n], points[(i + n - 1) % n]);
        assert!(rel(&t, tangent, h_t) < 1e-9, "{i}: {t:?}");
        // Across the curve, both ways: the perpendicular function's size at 0.
        let normal = unit(p);
        let binormal = super::cross3(e1, e2);
        assert!(rel(&t, normal, a.perpendicular.eval(0.0)) < 1e-9);
        assert!(rel(&t, binormal, a.perpendicular.eval(0.0)) < 1e-9);
    }
    // Off the curve, outward from the middle of an edge.
    let mid = [0, 1, 2].map(|k| 0.5 * (points[0][k] + points[1][k]));
    let q = [0, 1, 2].map(|k| mid[k] * 1.05);
    let foot = curve_foot(&points, &edges, q);
    let SpaceFoot::Curve { distance: d, .. } = foot else { unreachable!() };
    let t = border.tensor(&a, q, 0, &foot).unwrap();
    assert!(rel(&t, sub(points[1], points[0]), a.projection.eval(d, h_t)) < 1e-9, "{t:?}");
    assert!(rel(&t, mid, a.perpendicular.eval(d)) < 1e-9, "{t:?}");

    // A helix of radius 1 and pitch 2π·0.5: κ = 1 / (1 + 0.25), converging at O(h²).
    let kappa = 1.0 / 1.25;
    let mut runs = Vec::new();
    for n in [16, 32, 64] {
        let points: Vec<Point3> = (0..=2 * n)
            .map(|i| {
                let s = tau * i as f64 / n as f64;
                [s.cos(), s.sin(), 0.5 * s]
            })
            .collect();
        let edges: Vec<[u32; 2]> = (0..2 * n as u32).map(|i| [i, i + 1]).collect();
        let border = SpaceBorder::new(&points, &[], &edges).unwrap();
        let mut worst: f64 = 0.0;
        for i in 1..2 * n {
            let p = points[i];
            let t = border.tensor(&a, p, i, &curve_foot(&points, &edges, p)).unwrap();
            let s = tau * i as f64 / n as f64;
            let tangent = [-s.sin(), s.cos(), 0.5];
            worst = worst.max(rel(&t, tangent, a.curvature.eval(kappa)));
        }
        let h = dot(sub(points[1], points[0]), sub(points[1], points[0])).sqrt();
        runs.push((h, worst));
    }
    report("helix tangent size (relative)", &runs, 1.8);
}
