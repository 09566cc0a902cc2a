use super::*;
use crate::solution::test_meshes3::{jittered, kuhn, mapped, Mesh3};

/// u = 3 + 2x − y + 0.5z + 1.5x² − 4xy + 0.7y² + 2.5xz − 1.2yz − 0.9z²:
/// H = [[3, −4, 2.5], [−4, 1.4, −1.2], [2.5, −1.2, −1.8]].
fn quadratic(p: Point3) -> f64 {
    let [x, y, z] = p;
    3.0 + 2.0 * x - y + 0.5 * z + 1.5 * x * x - 4.0 * x * y + 0.7 * y * y + 2.5 * x * z
        - 1.2 * y * z
        - 0.9 * z * z
}
const H: Sym3 = Sym3 { xx: 3.0, xy: -4.0, yy: 1.4, xz: 2.5, yz: -1.2, zz: -1.8 };
fn quadratic_gradient(p: Point3) -> [f64; 3] {
    let g = H.mul_vec(p);
    [2.0 + g[0], -1.0 + g[1], 0.5 + g[2]]
}

/// The Frobenius norm of a − b.
fn hessian_error(a: &Sym3, b: &Sym3) -> f64 {
    let (x, y) = (a.rows(), b.rows());
    (0..3).flat_map(|i| (0..3).map(move |j| (x[i][j] - y[i][j]).powi(2))).sum::<f64>().sqrt()
}

fn norm(h: &Sym3) -> f64 {
    hessian_error(h, &Sym3::ZERO)
}

fn derivatives(m: &Mesh3, f: impl Fn(Point3) -> f64, method: Method) -> Derivatives3 {
    let values: Vec<f64> = m.points.iter().map(|&p| f(p)).collect();
    let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
    recover3(&mesh, &values, method).unwrap()
}

#[test]
fn the_quadratic_fit_is_exact_on_a_quadratic_at_every_vertex_of_irregular_tetrahedra() {
    // Away from the origin and not of unit size, so that the scaling matters.
    let meshes = [
        kuhn([4, 5, 3], [10.0, -3.0, 2.0], [0.3, 0.2, 0.25]),
        jittered([6, 5, 7], [10.0, -3.0, 2.0], [0.3, 0.2, 0.25], 0.15, 7),
        jittered([8, 8, 8], [2.0, -1.0, 1.0], [0.05, 0.07, 0.04], 0.15, 11),
    ];
    for (k, m) in meshes.iter().enumerate() {
        let d = derivatives(m, quadratic, Method::QuadraticFit);
        let boundary = m.boundary();
        let (mut inner, mut outer, mut worst) = (0, 0, 0.0f64);
        for (v, &p) in m.points.iter().enumerate() {
            let e = hessian_error(&d.hessian[v], &H) / norm(&H);
            worst = worst.max(e);
            assert!(
                e < 1e-9,
                "mesh {k}, vertex {v} at {p:?} (boundary {}): Hessian error {e}",
                boundary[v]
            );
            let g = quadratic_gradient(p);
            let ge = distance(d.gradient[v], g) / distance(g, [0.0; 3]);
            assert!(ge < 1e-9, "mesh {k}, vertex {v}: gradient error {ge}");
            if boundary[v] {
                outer += 1;
            } else {
                inner += 1;
            }
        }
        eprintln!("mesh {k}: {inner} interior, {outer} boundary vertices, worst relative Hessian error {worst:.1e}");
        assert!(inner > 10 && outer > 10, "{inner} interior, {outer} boundary vertices");
    }
}

/// u = sin(2x) cos(1.5y) e^(z/2) + xyz.
fn smooth(p: Point3) -> f64 {
    let [x, y, z] = p;
    (2.0 * x).sin() * (1.5 * y).cos() * (0.5 * z).exp() + x * y * z
}
fn smooth_hessian(p: Point3) -> Sym3 {
    let [x, y, z] = p;
    let (s, c) = (2.0 * x).sin_cos();
    let (s1, c1) = (1.5 * y).sin_cos();
    let e = (0.5 * z).exp();
    Sym3 {
        xx: -4.0 * s * c1 * e,
        xy: -3.0 * c * s1 * e + z,
        yy: -2.25 * s * c1 * e,
        xz: c * c1 * e + y,
        yz: -0.75 * s * s1 * e + x,
        zz: 0.25 * s * c1 * e,
    }
}

/// The fit's QR solve against nalgebra's SVD least squares on the same patch, the
/// coordinates unscaled: on a field no quadratic fits, every vertex, interior and
/// boundary, agrees to 1e-9 of the Hessian.
#[test]
fn the_fit_agrees_with_a_dense_least_squares_solve_by_nalgebra() {
    let m = jittered([5, 4, 6], [0.5, -1.0, 0.2], [0.2, 0.25, 0.15], 0.15, 3);
    let values: Vec<f64> = m.points.iter().map(|&p| smooth(p)).collect();
    let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
    let d = recover3(&mesh, &values, Method::QuadraticFit).unwrap();
    let mut worst = 0.0f64;
    for v in 0..m.points.len() {
        let patch = fit_patch(&mesh, v).expect("a determined patch");
        let p = m.points[v];
        let a = nalgebra::DMatrix::from_fn(patch.len(), COLS, |i, j| {
            fit_row(sub(m.points[patch[i] as usize], p))[j]
        });
        let b =
            nalgebra::DVector::from_fn(patch.len(), |i, _| values[patch[i] as usize] - values[v]);
        let x = a.svd(true, true).solve(&b, 1e-14).unwrap();
        let h = Sym3 { xx: x[3], xy: x[4], yy: x[5], xz: x[6], yz: x[7], zz: x[8] };
        let e = hessian_error(&d.hessian[v], &h) / norm(&h);
        worst = worst.max(e);
        assert!(e < 1e-9, "vertex {v}: {:?} against nalgebra's {h:?}: {e}", d.hessian[v]);
        let g = [x[0], x[1], x[2]];
        assert!(distance(d.gradient[v], g) < 1e-9 * distance(g, [0.0; 3]), "vertex {v}");
    }
    eprintln!("QR against SVD: worst relative Hessian difference {worst:.1e}");
}

#[test]
fn the_double_projection_is_exact_two_layers_inside_a_kuhn_grid_and_not_at_its_boundary() {
    let n = [7, 6, 6];
    let m = kuhn(n, [-1.0, 2.0, 0.5], [0.25, 0.125, 0.2]);
    let d = derivatives(&m, quadratic, Method::L2Projection);
    let (mut exact, mut worst_boundary) = (0, 0.0f64);
    for (v, &p) in m.points.iter().enumerate() {
        let (i, rest) = (v % (n[0] + 1), v / (n[0] + 1));
        let c = [i, rest % (n[1] + 1), rest / (n[1] + 1)];
        let from_boundary = (0..3).map(|a| c[a].min(n[a] - c[a])).min().unwrap();
        let e = hessian_error(&d.hessian[v], &H) / norm(&H);
        if from_boundary >= 2 {
            assert!(e < 1e-9, "vertex {c:?}: Hessian error {e}");
            let g = quadratic_gradient(p);
            assert!(distance(d.gradient[v], g) < 1e-9 * distance(g, [0.0; 3]), "vertex {c:?}");
            exact += 1;
        } else if from_boundary == 0 {
            worst_boundary = worst_boundary.max(e);
        }
    }
    assert_eq!(exact, (n[0] - 3) * (n[1] - 3) * (n[2] - 3));
    // Honest about the method: at the boundary the one-sided patches miss the Hessian,
    // and so do the irregular patches of a jittered grid.
    assert!(worst_boundary > 0.1, "{worst_boundary}");
    let j = jittered(n, [-1.0, 2.0, 0.5], [0.25, 0.125, 0.2], 0.15, 5);
    let d = derivatives(&j, quadratic, Method::L2Projection);
    let worst = d.hessian.iter().map(|h| hessian_error(h, &H) / norm(&H)).fold(0.0, f64::max);
    assert!(worst > 0.05, "{worst}");
}

/// Volume-weighted RMS and maximum of the Hessian error over the vertices in
/// [0.25, 0.75]³.
fn interior_errors(m: &Mesh3, d: &Derivatives3) -> (f64, f64) {
    let mut w = vec![0.0; m.points.len()];
    for &t in &m.tets {
        let vol = m.volume6(t) / 6.0;
        t.iter().for_each(|&v| w[v as usize] += vol / 4.0);
    }
    let (mut sum, mut weight, mut max) = (0.0, 0.0, 0.0f64);
    for (v, &p) in m.points.iter().enumerate() {
        if p.iter().all(|&x| (0.25..=0.75).contains(&x)) {
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

/// On the unit cube, h halved twice: the quadratic fit converges on jittered grids (first
/// order in the mean; the worst vertex's error falls slowly, 0.29, 0.32, 0.22, since the
/// worst of more random patches is worse), the double projection on smooth images of a
/// grid (both orders printed).
#[test]
fn both_methods_converge_to_the_analytic_hessian_of_a_smooth_field() {
    let fit: Vec<(f64, f64)> = [5, 10, 20]
        .iter()
        .map(|&n| {
            let h = 1.0 / n as f64;
            let m = jittered([n; 3], [0.0; 3], [h; 3], 0.15, 13);
            interior_errors(&m, &derivatives(&m, smooth, Method::QuadraticFit))
        })
        .collect();
    let (rms, max) = (order(&fit, |e| e.0), order(&fit, |e| e.1));
    eprintln!("quadratic fit, jittered grids {fit:?}: orders rms {rms:.2}, max {max:.2}");
    assert!(rms > 0.8 && max > 0.1, "{fit:?}");
    let projection: Vec<(f64, f64)> = [5, 10, 20]
        .iter()
        .map(|&n| {
            let m = mapped(n);
            interior_errors(&m, &derivatives(&m, smooth, Method::L2Projection))
        })
        .collect();
    let (rms, max) = (order(&projection, |e| e.0), order(&projection, |e| e.1));
    eprintln!("double projection, mapped grids {projection:?}: orders rms {rms:.2}, max {max:.2}");
    assert!(rms > 1.5 && max > 1.2, "{projection:?}");
}

#[test]
fn bad_values_and_meshes_are_refused_with_the_vertex() {
    let m = kuhn([2, 2, 2], [0.0; 3], [1.0; 3]);
    let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
    let mut values: Vec<f64> = m.points.iter().map(|&p| quadratic(p)).collect();
    assert_eq!(
        recover3(&mesh, &values[1..], Method::QuadraticFit),
        Err(RecoveryError::Count { values: 26, vertices: 27 })
    );
    values[5] = f64::NAN;
    for method in Method::ALL {
        let e = recover3(&mesh, &values, method).unwrap_err();
        assert!(matches!(e, RecoveryError::NotFinite { vertex: 5, .. }), "{e}");
    }
    // One tetrahedron: four vertices, no quadratic.
    let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let one = P1Mesh3::new(&points, &[[0, 1, 2, 3]]).unwrap();
    let e = recover3(&one, &[1.0, 2.0, 3.0, 4.0], Method::QuadraticFit).unwrap_err();
    assert_eq!(e, RecoveryError::Undetermined { vertex: 0, patch: 3 });
    assert!(e.to_string().contains("vertex 0") && e.to_string().contains("nine in space"), "{e}");
    // The projection needs no patch: a linear field's gradient, a zero Hessian.
    let d = recover3(&one, &[1.0, 2.0, 3.0, 4.0], Method::L2Projection).unwrap();
    assert_eq!(d.gradient, vec![[1.0, 2.0, 3.0]; 4]);
    assert_eq!(d.hessian, vec![Sym3::ZERO; 4]);
    assert_eq!(
        P1Mesh3::new(&points, &[[0, 1, 2, 4]]).unwrap_err(),
        RecoveryError::CornerOutOfRange { cell: 0, vertex: 4, len: 4 }
    );
    let bad = [[0.0, 0.0, f64::INFINITY]];
    assert_eq!(P1Mesh3::new(&bad, &[]).unwrap_err(), RecoveryError::NonFiniteVertex { vertex: 0 });
}

#[test]
fn an_unused_vertex_gets_zero_and_a_linear_field_a_zero_hessian() {
    let mut m = jittered([4, 4, 4], [10.0, -3.0, 2.0], [0.3, 0.2, 0.25], 0.15, 9);
    m.points.push([99.0, 99.0, 99.0]);
    let linear = |p: Point3| 3.0 + 2.0 * p[0] - 7.0 * p[1] + 0.3 * p[2];
    for method in Method::ALL {
        let mut values: Vec<f64> = m.points.iter().map(|&p| linear(p)).collect();
        *values.last_mut().unwrap() = f64::NAN;
        let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
        let d = recover3(&mesh, &values, method).unwrap();
        assert!(d.hessian.iter().all(|h| *h == Sym3::ZERO), "{method:?}");
        assert_eq!(*d.gradient.last().unwrap(), [0.0; 3]);
        let g = d.gradient[0];
        assert!(distance(g, [2.0, -7.0, 0.3]) < 1e-9, "{method:?}: {g:?}");
    }
}
