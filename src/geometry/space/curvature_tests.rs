//! The curvature estimator against its analytic twins: surfaces whose principal
//! curvatures and directions are known in closed form (sphere, cylinder, torus,
//! ellipsoid, the saddle z = x² − y², planes), meshed parametrically here at several
//! refinements, regular and with jittered vertices (still on the surface). Each test
//! prints the largest error per refinement and the observed convergence order
//! (`cargo test curvature_tests -- --nocapture`), and asserts the errors shrink at the
//! order the cubic fit promises (O(h²), see the module header) within a margin; planes
//! exactly. Ridges: a cube's faces stay flat at its edges and corners, a capped cylinder's
//! rim sees the cylinder and the cap apart.

use super::curvature::{surface_curvature, three_point_curvature, CurvatureSide, Fit};
use super::triangle::Point3;
use crate::geometry::test_support::Rng;
use std::collections::BTreeMap;

/// A triangulated surface.
pub(crate) struct Mesh {
    pub(crate) points: Vec<Point3>,
    pub(crate) triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// The mean edge length (each edge counted once per triangle).
    pub(crate) fn h(&self) -> f64 {
        let mut sum = 0.0;
        for t in &self.triangles {
            for i in 0..3 {
                sum += norm(sub(self.points[t[i] as usize], self.points[t[(i + 1) % 3] as usize]));
            }
        }
        sum / (3 * self.triangles.len()) as f64
    }
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: Point3) -> f64 {
    dot(a, a).sqrt()
}
fn normalize(a: Point3) -> Point3 {
    let l = norm(a);
    [a[0] / l, a[1] / l, a[2] / l]
}

/// The unit sphere from an octahedron, each triangle split in four `level` times, new
/// points pushed onto the sphere; with vertices at the six poles ±x, ±y, ±z (valence 4),
/// outward triangles. `jitter` (a fraction of the edge) moves every vertex but the six
/// poles tangentially at random, then back onto the sphere.
pub(crate) fn octasphere(level: u32, jitter: f64, seed: u64) -> Mesh {
    let mut points: Vec<Point3> = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for &x in &[0u32, 1] {
        for &y in &[2u32, 3] {
            for &z in &[4u32, 5] {
                // Outward: (x, y, z) counter-clockwise seen from outside when the signs'
                // product is positive.
                let positive = (x == 0) ^ (y == 3) ^ (z == 5);
                triangles.push(if positive { [x, y, z] } else { [x, z, y] });
            }
        }
    }
    for _ in 0..level {
        let mut mid: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        let mut next = Vec::with_capacity(4 * triangles.len());
        for t in &triangles {
            let mut m = [0u32; 3];
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                m[i] = *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let (p, q) = (points[a as usize], points[b as usize]);
                    points.push(normalize([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                    points.len() as u32 - 1
                });
            }
            next.push([t[0], m[0], m[2]]);
            next.push([m[0], t[1], m[1]]);
            next.push([m[2], m[1], t[2]]);
            next.push([m[0], m[1], m[2]]);
        }
        triangles = next;
    }
    let mut mesh = Mesh { points, triangles };
    if jitter > 0.0 {
        let h = mesh.h();
        let mut rng = Rng(seed);
        for p in mesh.points.iter_mut().skip(6) {
            let q = [
                p[0] + jitter * h * (rng.unit() - 0.5),
                p[1] + jitter * h * (rng.unit() - 0.5),
                p[2] + jitter * h * (rng.unit() - 0.5),
            ];
            *p = normalize(q);
        }
    }
    mesh
}

/// A grid over the parameters (u, v) ∈ [0, 1]², `nu` × `nv` cells, periodic in u and/or
/// v as asked, one diagonal per cell, mapped by `f`; `jitter` (a fraction of a cell)
/// moves the parameters of every vertex off the grid's open edges at random. Returns the
/// mesh and each vertex's parameters and whether it is on an open edge.
pub(crate) fn grid(
    nu: usize,
    nv: usize,
    wrap: [bool; 2],
    jitter: f64,
    seed: u64,
    f: impl Fn(f64, f64) -> Point3,
) -> (Mesh, Vec<[f64; 2]>, Vec<bool>) {
    let cols = if wrap[0] { nu } else { nu + 1 };
    let rows = if wrap[1] { nv } else { nv + 1 };
    let mut rng = Rng(seed);
    let mut params = Vec::with_capacity(cols * rows);
    let mut edge = Vec::with_capacity(cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            let on_edge = (!wrap[0] && (i == 0 || i == nu)) || (!wrap[1] && (j == 0 || j == nv));
            let (du, dv) = if on_edge || jitter == 0.0 {
                (0.0, 0.0)
            } else {
                (jitter * (rng.unit() - 0.5), jitter * (rng.unit() - 0.5))
            };
            params.push([(i as f64 + du) / nu as f64, (j as f64 + dv) / nv as f64]);
            edge.push(on_edge);
        }
    }
    let id = |i: usize, j: usize| ((j % rows) * cols + i % cols) as u32;
    let mut triangles = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    let points = params.iter().map(|p| f(p[0], p[1])).collect();
    (Mesh { points, triangles }, params, edge)
}

/// The one side of a vertex of a smooth surface, its signs made relative to `outward`.
fn oriented(sides: &[CurvatureSide], outward: Point3) -> CurvatureSide {
    assert_eq!(sides.len(), 1);
    let mut s = sides[0];
    if dot(s.normal, outward) < 0.0 {
        s.normal = [-s.normal[0], -s.normal[1], -s.normal[2]];
        s.k = [-s.k[0], -s.k[1]];
    }
    s
}

/// The observed orders between successive (h, error) pairs.
fn orders(runs: &[(f64, f64)]) -> Vec<f64> {
    runs.windows(2).map(|w| (w[0].1 / w[1].1).ln() / (w[0].0 / w[1].0).ln()).collect()
}

/// Prints the runs and their orders; checks the errors shrink and the last order is at
/// least `min_order`.
fn report(name: &str, runs: &[(f64, f64)], min_order: f64) {
    let o = orders(runs);
    for (i, (h, e)) in runs.iter().enumerate() {
        let order = if i == 0 { String::new() } else { format!("  order {:.2}", o[i - 1]) };
        println!("{name}: h = {h:.4e}  max error {e:.3e}{order}");
    }
    assert!(runs.windows(2).all(|w| w[1].1 < w[0].1), "{name}: errors do not shrink: {runs:?}");
    assert!(*o.last().unwrap() >= min_order, "{name}: order {o:?} below {min_order}");
}

/// The angle (radians) between two lines.
fn line_angle(a: Point3, b: Point3) -> f64 {
    (dot(a, b).abs() / (norm(a) * norm(b))).clamp(0.0, 1.0).acos()
}

#[test]
fn sphere_both_curvatures_are_one_over_r() {
    let r = 2.0;
    for (jitter, min_order) in [(0.0, 1.8), (0.3, 1.5)] {
        let (mut runs, mut normal_runs) = (Vec::new(), Vec::new());
        for level in 1..=5 {
            let mut mesh = octasphere(level, jitter, 7 + level as u64);
            for p in &mut mesh.points {
                *p = [r * p[0], r * p[1], r * p[2]];
            }
            let c = surface_curvature(&mesh.points, &mesh.triangles, &[]).unwrap();
            let (mut worst, mut worst_normal): (f64, f64) = (0.0, 0.0);
            for (v, p) in mesh.points.iter().enumerate() {
                let s = oriented(c.sides(v), *p);
                if level >= 2 {
                    assert_eq!(s.fit, Fit::Cubic, "vertex {v} level {level}");
                }
                // Outward normal: the sphere bends away, k = −1/R.
                worst = worst.max((s.k[0] + 1.0 / r).abs()).max((s.k[1] + 1.0 / r).abs());
                worst_normal = worst_normal.max(line_angle(s.normal, *p));
            }
            runs.push((mesh.h(), worst));
            normal_runs.push((mesh.h(), worst_normal));
        }
        report(&format!("sphere jitter {jitter}"), &runs, min_order);
        report(&format!("sphere normals (rad) jitter {jitter}"), &normal_runs, min_order);
        // The finest (4098 vertices) within 1 %.
        assert!(runs[4].1 < 0.01 / r, "{runs:?}");
    }
}

/// A cylinder of radius `r` and height 2 along z.
fn cylinder(n: usize, jitter: f64, r: f64) -> (Mesh, Vec<[f64; 2]>, Vec<bool>) {
    let tau = std::f64::consts::TAU;
    grid(n, n / 2, [true, false], jitter, 11, move |u, v| {
        [r * (tau * u).cos(), r * (tau * u).sin(), 2.0 * v]
    })
}

#[test]
fn cylinder_curvatures_and_directions() {
    let r = 0.5;
    let tau = std::f64::consts::TAU;
    for (jitter, min_order) in [(0.0, 1.8), (0.3, 1.5)] {
        let (mut runs, mut dir_runs) = (Vec::new(), Vec::new());
        for n in [16, 32, 64] {
            let (mesh, params, edge) = cylinder(n, jitter, r);
            let c = surface_curvature(&mesh.points, &mesh.triangles, &[]).unwrap();
            let (mut worst, mut worst_dir): (f64, f64) = (0.0, 0.0);
            for v in (0..mesh.points.len()).filter(|&v| !edge[v]) {
                let phi = tau * params[v][0];
                let s = oriented(c.sides(v), [phi.cos(), phi.sin(), 0.0]);
                worst = worst.max((s.k[0] + 1.0 / r).abs()).max(s.k[1].abs());
                let along_circle = [-phi.sin(), phi.cos(), 0.0];
                worst_dir = worst_dir
                    .max(line_angle(s.directions[0], along_circle))
                    .max(line_angle(s.directions[1], [0.0, 0.0, 1.0]));
            }
            runs.push((mesh.h(), worst));
            dir_runs.push((mesh.h(), worst_dir));
        }
        report(&format!("cylinder jitter {jitter}"), &runs, min_order);
        report(&format!("cylinder directions (rad) jitter {jitter}"), &dir_runs, min_order - 0.5);
    }
}

#[test]
fn torus_curvatures_and_directions() {
    let (big, small) = (3.0, 1.0);
    let tau = std::f64::consts::TAU;
    for (jitter, min_order) in [(0.0, 1.8), (0.3, 1.5)] {
        let (mut runs, mut dir_runs) = (Vec::new(), Vec::new());
        for n in [12, 24, 48] {
            // u: around the axis (φ), v: around the tube (θ).
            let (mesh, params, _) = grid(2 * n, n, [true, true], jitter, 13, |u, v| {
                let (phi, theta) = (tau * u, tau * v);
                let rho = big + small * theta.cos();
                [rho * phi.cos(), rho * phi.sin(), small * theta.sin()]
            });
            let c = surface_curvature(&mesh.points, &mesh.triangles, &[]).unwrap();
            let (mut worst, mut worst_dir): (f64, f64) = (0.0, 0.0);
            for (v, par) in params.iter().enumerate() {
                let (phi, theta) = (tau * par[0], tau * par[1]);
                let outward = [theta.cos() * phi.cos(), theta.cos() * phi.sin(), theta.sin()];
                let s = oriented(c.sides(v), outward);
                // Both bend away from the outward normal where cos θ > 0.
                let k_tube = -1.0 / small;
                let k_parallel = -theta.cos() / (big + small * theta.cos());
                worst = worst.max((s.k[0] - k_tube).abs()).max((s.k[1] - k_parallel).abs());
                let meridian = [-theta.sin() * phi.cos(), -theta.sin() * phi.sin(), theta.cos()];
                let parallel = [-phi.sin(), phi.cos(), 0.0];
                worst_dir = worst_dir
                    .max(line_angle(s.directions[0], meridian))
                    .max(line_angle(s.directions[1], parallel));
            }
            runs.push((mesh.h(), worst));
            dir_runs.push((mesh.h(), worst_dir));
        }
        report(&format!("torus jitter {jitter}"), &runs, min_order);
        report(&format!("torus directions (rad) jitter {jitter}"), &dir_runs, min_order - 0.5);
    }
}

#[test]
fn ellipsoid_gaussian_and_mean_curvature() {
    let (a, b, c) = (3.0, 2.0, 1.0);
    for (jitter, min_order) in [(0.0, 1.8), (0.3, 1.4)] {
        let (mut runs, mut pole_runs, mut axis_runs) = (Vec::new(), Vec::new(), Vec::new());
        for level in 2..=5 {
            let mut mesh = octasphere(level, jitter, 17 + level as u64);
            for p in &mut mesh.points {
                *p = [a * p[0], b * p[1], c * p[2]];
            }
            let curv = surface_curvature(&mesh.points, &mesh.triangles, &[]).unwrap();
            let (mut worst, mut worst_pole, mut worst_axis): (f64, f64, f64) = (0.0, 0.0, 0.0);
            for (v, &[x, y, z]) in mesh.points.iter().enumerate() {
                let g = [x / (a * a), y / (b * b), z / (c * c)];
                let s = oriented(curv.sides(v), g);
                let q = dot(g, g);
                let gauss = 1.0 / ((a * b * c).powi(2) * q * q);
                // Mean curvature, negative with the outward normal.
                let mean = (x * x + y * y + z * z - a * a - b * b - c * c)
                    / (2.0 * (a * b * c).powi(2) * q.powf(1.5));
                let (k_gauss, k_mean) = (s.k[0] * s.k[1], 0.5 * (s.k[0] + s.k[1]));
                worst =
                    worst.max((k_gauss - gauss).abs() / gauss).max((k_mean - mean).abs() / -mean);
                // Poles (0, 0, ±c) and the equator's vertices (±a, 0, 0), (0, ±b, 0):
                // the principal curvatures and their axes.
                let expected: Option<([f64; 2], [Point3; 2])> = if v >= 6 {
                    None
                } else if z != 0.0 {
                    Some(([c / (b * b), c / (a * a)], [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]))
                } else if x != 0.0 {
                    Some(([a / (c * c), a / (b * b)], [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]]))
                } else {
                    Some(([b / (c * c), b / (a * a)], [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))
                };
                if let Some((k, d)) = expected {
                    for i in 0..2 {
                        worst_pole = worst_pole.max((s.k[i] + k[i]).abs() / k[i]);
                        let angle = line_angle(s.directions[i], d[i]);
                        // Exact on the regular mesh, whose stars there are symmetric.
                        assert!(jitter > 0.0 || angle < 1e-9, "{v}: {s:?}");
                        worst_axis = worst_axis.max(angle);
                    }
                }
            }
            runs.push((mesh.h(), worst));
            pole_runs.push((mesh.h(), worst_pole));
            axis_runs.push((mesh.h(), worst_axis));
        }
        if jitter > 0.0 {
            // Six vertices, each with its own jittered star at each level: a noisy order.
            report(
                &format!("ellipsoid poles and equator directions (rad) jitter {jitter}"),
                &axis_runs,
                0.5,
            );
        }
        report(&format!("ellipsoid K and H (relative) jitter {jitter}"), &runs, min_order);
        report(
            &format!("ellipsoid poles and equator (relative) jitter {jitter}"),
            &pole_runs,
            min_order,
        );
    }
}

#[test]
fn saddle_exact_at_the_origin_and_converging_elsewhere() {
    let mut runs = Vec::new();
    for n in [8, 16, 32, 64] {
        let (mesh, params, edge) = grid(n, n, [false, false], 0.0, 0, |u, v| {
            let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
            [x, y, x * x - y * y]
        });
        let c = surface_curvature(&mesh.points, &mesh.triangles, &[]).unwrap();
        let mut worst: f64 = 0.0;
        for v in 0..mesh.points.len() {
            let [x, y, _] = mesh.points[v];
            let s = oriented(c.sides(v), [0.0, 0.0, 1.0]);
            let w2 = 1.0 + 4.0 * x * x + 4.0 * y * y;
            let gauss = -4.0 / (w2 * w2);
            let mean = 4.0 * (y * y - x * x) / w2.powf(1.5);
            if x == 0.0 && y == 0.0 {
                // The vertex's star is point-symmetric: the normal guess is exact, and
                // the surface is a polynomial of the fitted degree over it.
                assert!((s.k[0].abs() - 2.0).abs() < 1e-12 && (s.k[1].abs() - 2.0).abs() < 1e-12);
                assert!((s.k[0] + s.k[1]).abs() < 1e-12, "{s:?}");
                let d = if s.k[0] > 0.0 { s.directions[0] } else { s.directions[1] };
                assert!(line_angle(d, [1.0, 0.0, 0.0]) < 1e-12, "{s:?}");
                assert_eq!(s.fit, Fit::Cubic);
            }
            if edge[v] || params[v][0] < 1.5 / n as f64 || params[v][0] > 1.0 - 1.5 / n as f64 {
                continue;
            }
            let (k_gauss, k_mean) = (s.k[0] * s.k[1], 0.5 * (s.k[0] + s.k[1]));
            worst = worst.max((k_gauss - gauss).abs()).max((k_mean - mean).abs());
        }
        runs.push((mesh.h(), worst));
    }
    report("saddle K and H", &runs, 1.8);
}

#[test]
fn planes_have_no_curvature() {
    // The plane z = 1: jittered vertices, heights exactly zero, curvature exactly zero.
    let (mesh, _, _) = grid(10, 7, [false, false], 0.8, 3, |u, v| [3.0 * u, 2.0 * v, 1.0]);
    let c = surface_curvature(&mesh.points, &mesh.triangles, &[]).unwrap();
    for v in 0..mesh.points.len() {
        let s = c.sides(v)[0];
        assert_eq!(s.k, [0.0, 0.0], "{v}");
        assert_eq!(s.normal.map(f64::abs), [0.0, 0.0, 1.0]);
    }
    // A tilted plane: zero to rounding.
    let (mesh, _, _) = grid(10, 7, [false, false], 0.8, 4, |u, v| {
        [3.0 * u + 0.3 * v, 2.0 * v - 0.5 * u, 0.7 * u + 1.1 * v]
    });
    let c = surface_curvature(&mesh.points, &mesh.triangles, &[]).unwrap();
    for v in 0..mesh.points.len() {
        let s = c.sides(v)[0];
        assert!(s.k[0].abs() < 1e-12 / mesh.h(), "{v}: {s:?}");
    }
}

#[test]
fn cube_edges_and_corners_see_flat_faces() {
    // A unit cube, each face a 4×4 grid, vertices shared; its 12 edges are ridges.
    let n = 4;
    let mut points: Vec<Point3> = Vec::new();
    let mut index: BTreeMap<[i64; 3], u32> = BTreeMap::new();
    let mut triangles = Vec::new();
    let mut at = |q: [i64; 3], points: &mut Vec<Point3>| {
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
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                    let v = q.map(|q| at(q, &mut points));
                    triangles.push([v[0], v[1], v[2]]);
                    triangles.push([v[0], v[2], v[3]]);
                }
            }
        }
    }
    let ridges: Vec<[u32; 2]> = {
        let mut edges = Vec::new();
        for t in &triangles {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                let (p, q) = (points[a as usize], points[b as usize]);
                let on = |p: Point3| p.iter().filter(|&&x| x == 0.0 || x == 1.0).count() >= 2;
                if on(p) && on(q) && (0..3).filter(|&k| p[k] == q[k]).count() == 2 {
                    edges.push([a.min(b), a.max(b)]);
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        edges
    };
    assert_eq!(ridges.len(), 12 * n as usize);
    let c = surface_curvature(&points, &triangles, &ridges).unwrap();
    for (v, p) in points.iter().enumerate() {
        let bounds = p.iter().filter(|&&x| x == 0.0 || x == 1.0).count();
        assert_eq!(c.sides(v).len(), bounds, "{v} {p:?}");
        assert_eq!(c.on_ridge(v), bounds >= 2);
        for s in c.sides(v) {
            assert_eq!(s.k, [0.0, 0.0], "{v} {p:?} {s:?}");
            assert_eq!(s.normal.iter().filter(|x| x.abs() == 1.0).count(), 1, "{s:?}");
        }
    }
    // Without the ridges the edges' vertices see one bent surface.
    let smeared = surface_curvature(&points, &triangles, &[]).unwrap();
    let edge_vertex = points.iter().position(|p| *p == [0.5, 0.0, 0.0]).unwrap();
    assert_eq!(smeared.sides(edge_vertex).len(), 1);
    assert!(smeared.sides(edge_vertex)[0].k[0].abs() > 1.0);
}

#[test]
fn capped_cylinder_rim_sees_each_side() {
    // A cylinder of radius 1 between z = 0 and z = 2 closed by two flat caps: the rims
    // are ridges; a rim vertex has the cylinder's 1/R on one side and 0 on the cap.
    let (mut mesh, params, edge) = cylinder(32, 0.0, 1.0);
    let ring: Vec<u32> = (0..32).collect();
    let mut ridges = Vec::new();
    for (cap_z, offset) in [(0.0, 0u32), (2.0, 16 * 32)] {
        let centre = mesh.points.len() as u32;
        mesh.points.push([0.0, 0.0, cap_z]);
        for &i in &ring {
            let (a, b) = (offset + i, offset + (i + 1) % 32);
            mesh.triangles.push(if cap_z == 0.0 { [centre, b, a] } else { [centre, a, b] });
            ridges.push([a, b]);
        }
    }
    let c = surface_curvature(&mesh.points, &mesh.triangles, &ridges).unwrap();
    for v in (0..params.len()).filter(|&v| edge[v]) {
        let sides = c.sides(v);
        assert_eq!(sides.len(), 2, "{v}");
        assert!(c.on_ridge(v));
        let (wall, cap) = if sides[0].normal[2].abs() < 0.5 {
            (sides[0], sides[1])
        } else {
            (sides[1], sides[0])
        };
        assert!((wall.k[0].abs() - 1.0).abs() < 0.05 && wall.k[1].abs() < 0.05, "{v}: {wall:?}");
        assert_eq!(cap.k, [0.0, 0.0], "{v}: {cap:?}");
    }
}

#[test]
fn coarse_and_degenerate_neighbourhoods() {
    // The octahedron: every vertex has 4 neighbours at 90° on two lines (the paraboloid
    // is singular), one antipode left out.
    let mesh = octasphere(0, 0.0, 0);
    let c = surface_curvature(&mesh.points, &mesh.triangles, &[]).unwrap();
    for (v, p) in mesh.points.iter().enumerate() {
        let s = oriented(c.sides(v), *p);
        assert_eq!(s.fit, Fit::Umbilic);
        // The paraboloid through the 4 neighbours at height −1, distance 1: k = −2.
        assert!((s.k[0] + 2.0).abs() < 1e-12 && (s.k[1] + 2.0).abs() < 1e-12, "{s:?}");
    }
    // One triangle: two neighbours, a flat umbilic fit.
    let c = surface_curvature(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[[0, 1, 2]], &[])
        .unwrap();
    assert_eq!((c.sides(0)[0].fit, c.sides(0)[0].k), (Fit::Umbilic, [0.0, 0.0]));
    assert_eq!(c.sides(0)[0].normal, [0.0, 0.0, 1.0]);
    // A degenerate triangle: its vertex sees no plane, no side.
    // A vertex of no triangle, a degenerate triangle, a NaN point: no side, no panic.
    let c = surface_curvature(
        &[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [f64::NAN; 3]],
        &[[0, 1, 2]],
        &[],
    )
    .unwrap();
    assert!(c.sides(0).is_empty() && c.sides(3).is_empty());
    assert!(surface_curvature(&[[0.0; 3]], &[[0, 0, 1]], &[]).is_err());
    assert!(surface_curvature(&[[0.0; 3]], &[], &[[0, 4]]).is_err());
}

#[test]
fn three_points_in_space() {
    // A circle of radius 2 in a tilted plane, sampled at three points: 1/2 exactly to
    // rounding, whatever the spacing.
    let (e1, e2) = (normalize([1.0, 1.0, 0.0]), normalize([-1.0, 1.0, 2.0]));
    let at = |t: f64| {
        let (c, s) = (2.0 * t.cos(), 2.0 * t.sin());
        [c * e1[0] + s * e2[0], c * e1[1] + s * e2[1], c * e1[2] + s * e2[2]]
    };
    for (a, b, c) in [(0.0, 0.1, 0.3), (1.0, 2.0, 4.0), (0.0, 1e-4, 2e-4)] {
        assert!((three_point_curvature(at(a), at(b), at(c)) - 0.5).abs() < 1e-6);
    }
    assert_eq!(three_point_curvature([0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]), 0.0);
    assert_eq!(three_point_curvature([0.0; 3], [0.0; 3], [2.0, 2.0, 2.0]), 0.0);
}
