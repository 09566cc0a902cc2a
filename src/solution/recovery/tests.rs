use super::*;
use crate::solution::test_meshes::{grid, mapped_grid, scattered, Mesh};

/// u = 3 + 2x − y + 1.5x² − 4xy + 0.7y²: H = [[3, −4], [−4, 1.4]].
fn quadratic(p: Point2) -> f64 {
    let [x, y] = p;
    3.0 + 2.0 * x - y + 1.5 * x * x - 4.0 * x * y + 0.7 * y * y
}
const H: Sym2 = Sym2::new(3.0, -4.0, 1.4);
fn quadratic_gradient(p: Point2) -> [f64; 2] {
    let [x, y] = p;
    [2.0 + 3.0 * x - 4.0 * y, -1.0 - 4.0 * x + 1.4 * y]
}

fn hessian_error(a: &Sym2, b: &Sym2) -> f64 {
    ((a.a - b.a).powi(2) + 2.0 * (a.b - b.b).powi(2) + (a.c - b.c).powi(2)).sqrt()
}

fn norm(h: &Sym2) -> f64 {
    hessian_error(h, &Sym2::new(0.0, 0.0, 0.0))
}

fn derivatives(m: &Mesh, f: impl Fn(Point2) -> f64, method: Method) -> Derivatives {
    let values: Vec<f64> = m.points.iter().map(|&p| f(p)).collect();
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    recover(&mesh, &values, method).unwrap()
}

#[test]
fn the_quadratic_fit_is_exact_on_a_quadratic_at_every_vertex_of_any_mesh() {
    // Away from the origin and not of unit size, so that scaling matters.
    for m in [grid(7, 5, [10.0, -3.0], [0.3, 0.2]), scattered(150, 7, [10.0, -3.0], 0.5)] {
        let d = derivatives(&m, quadratic, Method::QuadraticFit);
        let boundary = m.boundary();
        let (mut inner, mut outer) = (0, 0);
        for (v, &p) in m.points.iter().enumerate() {
            let e = hessian_error(&d.hessian[v], &H) / norm(&H);
            assert!(e < 1e-9, "vertex {v} at {p:?} (boundary: {}): Hessian error {e}", boundary[v]);
            let g = quadratic_gradient(p);
            let ge = (d.gradient[v][0] - g[0]).hypot(d.gradient[v][1] - g[1]) / g[0].hypot(g[1]);
            assert!(ge < 1e-9, "vertex {v}: gradient error {ge}");
            if boundary[v] {
                outer += 1;
            } else {
                inner += 1;
            }
        }
        assert!(inner > 10 && outer > 10, "{inner} interior, {outer} boundary vertices");
    }
}

#[test]
fn the_double_projection_is_exact_two_rings_inside_a_structured_mesh_and_not_at_its_boundary() {
    let (nx, ny) = (9, 8);
    let m = grid(nx, ny, [-1.0, 2.0], [0.25, 0.125]);
    let d = derivatives(&m, quadratic, Method::L2Projection);
    let mut exact = 0;
    let mut worst_boundary: f64 = 0.0;
    for j in 0..=ny {
        for i in 0..=nx {
            let v = j * (nx + 1) + i;
            let e = hessian_error(&d.hessian[v], &H) / norm(&H);
            let from_boundary = i.min(j).min(nx - i).min(ny - j);
            if from_boundary >= 2 {
                assert!(e < 1e-9, "vertex ({i}, {j}): Hessian error {e}");
                let g = quadratic_gradient(m.points[v]);
                let ge = (d.gradient[v][0] - g[0]).hypot(d.gradient[v][1] - g[1]);
                assert!(ge < 1e-9 * g[0].hypot(g[1]), "vertex ({i}, {j}): gradient error {ge}");
                exact += 1;
            } else if from_boundary == 0 {
                worst_boundary = worst_boundary.max(e);
            }
        }
    }
    assert_eq!(exact, (nx - 3) * (ny - 3));
    // Honest about the method: at the boundary the one-sided patches miss the Hessian.
    assert!(worst_boundary > 0.1, "{worst_boundary}");
}

/// u = sin(3x) cos(2y) + x²y on the unit square.
fn smooth(p: Point2) -> f64 {
    let [x, y] = p;
    (3.0 * x).sin() * (2.0 * y).cos() + x * x * y
}
fn smooth_hessian(p: Point2) -> Sym2 {
    let [x, y] = p;
    let (s, c) = ((3.0 * x).sin(), (3.0 * x).cos());
    let (s2, c2) = ((2.0 * y).sin(), (2.0 * y).cos());
    Sym2::new(-9.0 * s * c2 + 2.0 * y, -6.0 * c * s2 + 2.0 * x, -4.0 * s * c2)
}

/// Area-weighted RMS and maximum of the Hessian error over the vertices at least 0.2
/// from the boundary of the unit square.
fn interior_errors(m: &Mesh, d: &Derivatives) -> (f64, f64) {
    let n = m.points.len();
    let mut w = vec![0.0; n];
    for t in &m.triangles {
        let [a, b, c] = t.map(|v| m.points[v as usize]);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
        for v in t {
            w[*v as usize] += area / 3.0;
        }
    }
    let (mut sum, mut weight, mut max) = (0.0, 0.0, 0.0f64);
    for (v, &p) in m.points.iter().enumerate() {
        if p.iter().all(|&x| (0.2..=0.8).contains(&x)) {
            let e = hessian_error(&d.hessian[v], &smooth_hessian(p));
            sum += w[v] * e * e;
            weight += w[v];
            max = max.max(e);
        }
    }
    ((sum / weight).sqrt(), max)
}

fn order(e: &[(f64, f64)], pick: fn(&(f64, f64)) -> f64) -> f64 {
    (pick(&e[0]) / pick(&e[2])).log2() / 2.0
}

/// The quadratic fit on Delaunay meshes of scattered points, h halved twice (4x the
/// points each time): first order in the mean, a little less at the worst vertex (the
/// most irregular patch).
#[test]
fn on_unstructured_meshes_the_quadratic_fit_converges_to_the_analytic_hessian() {
    let errors: Vec<(f64, f64)> = [400, 1600, 6400]
        .iter()
        .map(|&n| {
            let m = scattered(n, 11, [0.0, 0.0], 1.0);
            interior_errors(&m, &derivatives(&m, smooth, Method::QuadraticFit))
        })
        .collect();
    let (rms, max) = (order(&errors, |e| e.0), order(&errors, |e| e.1));
    eprintln!("quadratic fit {errors:?}: orders rms {rms:.2}, max {max:.2}");
    assert!(rms > 0.8 && max > 0.4, "{errors:?}");
}

/// The double projection converges (at second order) on irregular meshes that are
/// smooth images of a grid; on Delaunay meshes of scattered points it does not
/// converge at all: its error stays of the order of the Hessian (the averaged gradients
/// of irregular patches are consistent only to O(h), which the second derivative
/// divides by h). The quadratic fit is the method for such meshes.
#[test]
fn the_double_projection_converges_on_mildly_structured_meshes_only() {
    let mapped: Vec<(f64, f64)> = [16, 32, 64]
        .iter()
        .map(|&n| {
            let m = mapped_grid(n);
            interior_errors(&m, &derivatives(&m, smooth, Method::L2Projection))
        })
        .collect();
    let (rms, max) = (order(&mapped, |e| e.0), order(&mapped, |e| e.1));
    eprintln!("double projection, mapped grids {mapped:?}: orders rms {rms:.2}, max {max:.2}");
    assert!(rms > 1.5 && max > 1.5, "{mapped:?}");
    let scattered: Vec<(f64, f64)> = [400, 1600, 6400]
        .iter()
        .map(|&n| {
            let m = scattered(n, 11, [0.0, 0.0], 1.0);
            interior_errors(&m, &derivatives(&m, smooth, Method::L2Projection))
        })
        .collect();
    let rms = order(&scattered, |e| e.0);
    eprintln!("double projection, scattered points {scattered:?}: order rms {rms:.2}");
    assert!(rms.abs() < 0.3, "{scattered:?}");
    assert!(scattered.iter().all(|e| e.0 < 3.0), "{scattered:?}");
}

#[test]
fn bad_values_and_meshes_are_refused_with_the_vertex() {
    let m = grid(3, 3, [0.0, 0.0], [1.0, 1.0]);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let mut values: Vec<f64> = m.points.iter().map(|&p| quadratic(p)).collect();
    assert_eq!(
        recover(&mesh, &values[1..], Method::QuadraticFit),
        Err(RecoveryError::Count { values: 15, vertices: 16 })
    );
    values[5] = f64::NAN;
    for method in Method::ALL {
        let e = recover(&mesh, &values, method).unwrap_err();
        assert!(matches!(e, RecoveryError::NotFinite { vertex: 5, .. }), "{e}");
    }
    // One triangle: three vertices, no quadratic.
    let points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let one = P1Mesh::from_triangles(&points, &[[0, 1, 2]]).unwrap();
    let e = recover(&one, &[1.0, 2.0, 3.0], Method::QuadraticFit).unwrap_err();
    assert_eq!(e, RecoveryError::Undetermined { vertex: 0, patch: 2 });
    assert!(e.to_string().contains("vertex 0"), "{e}");
    // The projection needs no patch: a linear field's gradient, a zero Hessian.
    let d = recover(&one, &[1.0, 2.0, 3.0], Method::L2Projection).unwrap();
    assert_eq!(d.gradient, vec![[1.0, 2.0]; 3]);
    assert_eq!(
        P1Mesh::from_triangles(&points, &[[0, 1, 3]]).unwrap_err(),
        RecoveryError::CornerOutOfRange { cell: 0, vertex: 3, len: 3 }
    );
}

#[test]
fn a_vertex_no_cell_uses_gets_zero_and_may_hold_anything() {
    let points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [9.0, 9.0]];
    let mesh = P1Mesh::from_triangles(&points, &[[0, 1, 2]]).unwrap();
    let d = recover(&mesh, &[0.0, 1.0, 1.0, f64::NAN], Method::L2Projection).unwrap();
    assert_eq!(d.gradient[3], [0.0, 0.0]);
    assert_eq!(d.hessian[3], Sym2::new(0.0, 0.0, 0.0));
}

#[test]
fn quadrangles_are_split_and_their_sides_kept_as_edges() {
    // A 4 x 4 grid of unit quads: the fit is exact on a quadratic everywhere.
    let mut points = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            points.push([i as f64, j as f64]);
        }
    }
    let mut cells = Vec::new();
    for j in 0..4u32 {
        for i in 0..4u32 {
            let v = j * 5 + i;
            cells.push([v, v + 1, v + 6, v + 5]);
        }
    }
    let mesh = P1Mesh::new(&points, &cells).unwrap();
    assert_eq!(mesh.triangles().len(), 32);
    assert_eq!(mesh.neighbours(6), &[1, 5, 7, 11]);
    let values: Vec<f64> = points.iter().map(|&p| quadratic(p)).collect();
    let d = recover(&mesh, &values, Method::QuadraticFit).unwrap();
    for h in &d.hessian {
        assert!(hessian_error(h, &H) < 1e-9 * norm(&H), "{h:?}");
    }
}

/// A linear field's recovered Hessian is round-off (up to 1e-13 and more on an offset,
/// scaled mesh), which the Lp metric turned into sizes with an anisotropy of 167: it is
/// zero at every vertex, by both methods, on grids and scattered points, offset and
/// scaled, and the Lp metric is then the uniform one; a quadratic keeps its Hessian, and
/// one of curvature 1e-4 against values of 1e3 is still seen.
#[test]
fn a_linear_fields_roundoff_hessian_is_zero_and_asks_for_nothing() {
    let linear = |p: Point2| 3.0 + 2.0 * p[0] - 7.0 * p[1];
    let meshes = [
        grid(9, 7, [10.0, -3.0], [0.3, 0.2]),
        scattered(300, 7, [10.0, -3.0], 0.5),
        scattered(300, 11, [1e3, 2e3], 1e-3),
        mapped_grid(12),
    ];
    for (k, m) in meshes.iter().enumerate() {
        for method in [Method::QuadraticFit, Method::L2Projection] {
            let d = derivatives(m, linear, method);
            let worst = d.hessian.iter().map(norm).fold(0.0, f64::max);
            assert_eq!(worst, 0.0, "mesh {k}, {method:?}");
        }
        let values: Vec<f64> = m.points.iter().map(|&p| linear(p)).collect();
        let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
        let d = recover(&mesh, &values, Method::QuadraticFit).unwrap();
        let options = crate::solution::LpOptions {
            p: 2.0,
            target: crate::solution::Target::Vertices(500.0),
            bounds: crate::metric::SizeBounds::try_new(1e-9, 1e9, 1e4).unwrap(),
        };
        let metric = crate::solution::lp_metric(&mesh, &d.hessian, &options).unwrap();
        assert!(metric.linear, "mesh {k}");
        let aniso = metric.tensors.iter().map(|t| t.aspect_ratio()).fold(0.0, f64::max);
        assert!(aniso < 1.0 + 1e-9, "mesh {k}: anisotropy {aniso}");
    }
    let m = scattered(300, 7, [10.0, -3.0], 0.5);
    let d = derivatives(&m, quadratic, Method::QuadraticFit);
    assert!(d.hessian.iter().all(|h| (hessian_error(h, &H) / norm(&H)) < 1e-9));
    let faint = |p: Point2| 1e3 + p[0] + 1e-4 * p[1] * p[1];
    let d = derivatives(&m, faint, Method::QuadraticFit);
    let seen = d.hessian.iter().filter(|h| (h.c - 2e-4).abs() < 2e-5).count();
    assert!(seen > m.points.len() / 2, "{seen} of {}", m.points.len());
}
