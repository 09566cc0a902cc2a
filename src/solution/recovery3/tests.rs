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
fn both_methods_are_exact_on_a_quadratic_at_every_vertex_of_irregular_tetrahedra() {
    // Away from the origin and not of unit size, so that the scaling matters.
    let meshes = [
        kuhn([4, 5, 3], [10.0, -3.0, 2.0], [0.3, 0.2, 0.25]),
        jittered([6, 5, 7], [10.0, -3.0, 2.0], [0.3, 0.2, 0.25], 0.15, 7),
        jittered([8, 8, 8], [2.0, -1.0, 1.0], [0.05, 0.07, 0.04], 0.15, 11),
    ];
    for method in Method::ALL {
        for (k, m) in meshes.iter().enumerate() {
            let d = derivatives(m, quadratic, method);
            let boundary = m.boundary();
            let (mut inner, mut outer, mut worst) = (0, 0, 0.0f64);
            for (v, &p) in m.points.iter().enumerate() {
                let e = hessian_error(&d.hessian[v], &H) / norm(&H);
                worst = worst.max(e);
                let on = boundary[v];
                assert!(
                    e < 1e-9,
                    "{method:?}, mesh {k}, vertex {v} at {p:?} (boundary {on}): Hessian error {e}"
                );
                let g = quadratic_gradient(p);
                let ge = distance(d.gradient[v], g) / distance(g, [0.0; 3]);
                assert!(ge < 1e-9, "{method:?}, mesh {k}, vertex {v}: gradient error {ge}");
                if on {
                    outer += 1;
                } else {
                    inner += 1;
                }
            }
            eprintln!("{method:?}, mesh {k}: {inner} interior, {outer} boundary vertices, worst relative Hessian error {worst:.1e}");
            assert!(inner > 10 && outer > 10, "{inner} interior, {outer} boundary vertices");
        }
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

/// The lumped projection of the P1 gradient alone (the first half of the method before
/// the edge fit), applied once for the gradient and once more for the Hessian.
fn projection_alone(m: &Mesh3, values: &[f64]) -> (Vec<[f64; 3]>, Vec<Sym3>) {
    let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
    let scalar: Vec<[f64; 1]> = values.iter().map(|&v| [v]).collect();
    let gradient: Vec<[f64; 3]> =
        project_gradients(&mesh, &scalar).into_iter().map(|g| g[0]).collect();
    let hessian = project_gradients(&mesh, &gradient)
        .into_iter()
        .map(|s| Sym3 {
            xx: s[0][0],
            xy: 0.5 * (s[0][1] + s[1][0]),
            yy: s[1][1],
            xz: 0.5 * (s[0][2] + s[2][0]),
            yz: 0.5 * (s[1][2] + s[2][1]),
            zz: s[2][2],
        })
        .collect();
    (gradient, hessian)
}

/// What the edge fit buys: at every boundary vertex of a Kuhn grid, and at every vertex
/// of a jittered one, the lumped projection of the P1 gradient misses a quadratic's
/// gradient (and the projection applied twice its Hessian, by 0.3 or more of it), where
/// the method is exact. Without the fit, or with patches that cannot grow past a
/// boundary vertex's one-sided star (whose fit is singular on a flat side), this fails.
#[test]
fn the_edge_fit_makes_the_projection_exact_where_the_plain_projection_is_not() {
    let n = [7, 6, 6];
    let meshes = [
        kuhn(n, [-1.0, 2.0, 0.5], [0.25, 0.125, 0.2]),
        jittered(n, [-1.0, 2.0, 0.5], [0.25, 0.125, 0.2], 0.15, 5),
    ];
    for (k, m) in meshes.iter().enumerate() {
        let values: Vec<f64> = m.points.iter().map(|&p| quadratic(p)).collect();
        let (plain_gradient, plain_hessian) = projection_alone(m, &values);
        let d = derivatives(m, quadratic, Method::L2Projection);
        let boundary = m.boundary();
        let (mut plain_g, mut plain_h, mut fitted) = (0.0f64, 0.0f64, 0.0f64);
        for (v, &p) in m.points.iter().enumerate() {
            if k == 0 && !boundary[v] {
                continue;
            }
            let g = quadratic_gradient(p);
            let scale = distance(g, [0.0; 3]);
            plain_g = plain_g.max(distance(plain_gradient[v], g) / scale);
            plain_h = plain_h.max(hessian_error(&plain_hessian[v], &H) / norm(&H));
            fitted = fitted.max(distance(d.gradient[v], g) / scale);
            fitted = fitted.max(hessian_error(&d.hessian[v], &H) / norm(&H));
        }
        eprintln!("mesh {k}: plain projection gradient error {plain_g:.2e}, Hessian {plain_h:.2e}; with the edge fit {fitted:.1e}");
        assert!(plain_g > 1e-3 && plain_h > 0.3, "mesh {k}: {plain_g}, {plain_h}");
        assert!(fitted < 1e-9, "mesh {k}: {fitted}");
    }
}

/// The edge fit is solved in each patch's own frame, so a mesh stretched 100:5:1 and
/// turned about a skew axis (an adapted mesh's anisotropy) is as exact as an isotropic
/// one; in the patch radius's scaling every vertex fell back to the plain projection.
#[test]
fn the_l2_projection_is_exact_on_a_stretched_rotated_mesh() {
    let mut m = jittered([6, 6, 6], [0.0; 3], [1.0 / 6.0; 3], 0.15, 4);
    // A rotation by 0.7 about (1, 2, 3)/√14 (Rodrigues).
    let axis = [1.0, 2.0, 3.0].map(|x: f64| x / 14f64.sqrt());
    let (s, c) = 0.7f64.sin_cos();
    for p in &mut m.points {
        let q = [p[0], 0.01 * p[1], 0.2 * p[2]];
        let dot = axis[0] * q[0] + axis[1] * q[1] + axis[2] * q[2];
        let k = cross(axis, q);
        *p = std::array::from_fn(|i| q[i] * c + k[i] * s + axis[i] * dot * (1.0 - c));
    }
    let d = derivatives(&m, quadratic, Method::L2Projection);
    let worst = d.hessian.iter().map(|h| hessian_error(h, &H) / norm(&H)).fold(0.0, f64::max);
    eprintln!("stretched 100:5:1: worst relative Hessian error {worst:.1e}");
    assert!(worst < 1e-9, "{worst}");
}

/// The same mesh and values give the same bits on one thread and on three.
#[test]
fn both_methods_give_the_same_bits_on_any_thread_count() {
    let m = jittered([9, 8, 7], [0.0; 3], [0.11, 0.12, 0.13], 0.15, 21);
    let values: Vec<f64> = m.points.iter().map(|&p| smooth(p)).collect();
    let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
    for method in Method::ALL {
        let runs: Vec<Derivatives3> = [1, 3]
            .iter()
            .map(|&threads| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                pool.install(|| recover3(&mesh, &values, method).unwrap())
            })
            .collect();
        let bits = |d: &Derivatives3| -> Vec<u64> {
            let mut out: Vec<u64> = d.gradient.iter().flatten().map(|x| x.to_bits()).collect();
            for h in &d.hessian {
                out.extend(h.rows().iter().flatten().map(|x| x.to_bits()));
            }
            out
        };
        assert_eq!(bits(&runs[0]), bits(&runs[1]), "{method:?}");
    }
}

/// Volume-weighted RMS and maximum of the Hessian error over the vertices at least
/// `margin` from the boundary of the unit cube (every vertex for 0).
fn errors(m: &Mesh3, hessian: &[Sym3], margin: f64) -> (f64, f64) {
    let mut w = vec![0.0; m.points.len()];
    for &t in &m.tets {
        let vol = m.volume6(t) / 6.0;
        t.iter().for_each(|&v| w[v as usize] += vol / 4.0);
    }
    let (mut sum, mut weight, mut max) = (0.0, 0.0, 0.0f64);
    for (v, &p) in m.points.iter().enumerate() {
        if p.iter().all(|&x| (margin..=1.0 - margin).contains(&x)) {
            let e = hessian_error(&hessian[v], &smooth_hessian(p));
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

/// The quadratic fit converges on jittered grids of the unit cube, h halved twice (first
/// order in the mean inside [0.25, 0.75]³; the worst vertex's error falls slowly, 0.29,
/// 0.32, 0.22, since the worst of more random patches is worse), and over every vertex,
/// boundary included: RMS 0.92, 0.36, 0.14, worst 3.5, 1.7, 1.7 (the field's Hessian
/// being about 5). Fitting each vertex's first determined patch gave 18.9, 18.7, 6.5
/// and 243, 535, 483: a face vertex's ten one-sided neighbours determine the nine
/// unknowns with a condition number up to 8e4, which the field's cubic part went through.
#[test]
fn the_quadratic_fit_converges_to_the_analytic_hessian_of_a_smooth_field() {
    let (mut fit, mut all) = (vec![], vec![]);
    for n in [5, 10, 20] {
        let h = 1.0 / n as f64;
        let m = jittered([n; 3], [0.0; 3], [h; 3], 0.15, 13);
        let d = derivatives(&m, smooth, Method::QuadraticFit);
        fit.push(errors(&m, &d.hessian, 0.25));
        all.push(errors(&m, &d.hessian, 0.0));
    }
    let (rms, max) = (order(&fit, |e| e.0), order(&fit, |e| e.1));
    eprintln!("quadratic fit, jittered grids: inside {fit:.3?}: orders rms {rms:.2}, max {max:.2}; every vertex {all:.3?}");
    assert!(rms > 0.8 && max > 0.1, "{fit:?}");
    let all_rms = order(&all, |e| e.0);
    assert!(all_rms > 1.0 && all.iter().all(|e| e.1 < 4.0) && all[2].1 < 2.0, "{all:?}");
}

/// The `l2-projection` method on the unit cube, h halved twice, against the plain double
/// projection ([`projection_alone`], the method before the edge fit): inside
/// [0.25, 0.75]³ second order on smooth images of a Kuhn grid (as the plain projection,
/// with smaller errors once n ≥ 10) and faster than first on jittered grids (where the
/// plain projection's error stalls), and at every vertex, boundary included, first order
/// in the worst (the plain projection's stays near 4, the field's Hessian being about 5).
#[test]
fn the_l2_projection_converges_on_every_mesh_and_at_the_boundary() {
    let families: [(&str, Vec<Mesh3>); 2] = [
        ("mapped grids", [5, 10, 20].map(mapped).into()),
        (
            "jittered grids",
            [5, 10, 20].map(|n| jittered([n; 3], [0.0; 3], [1.0 / n as f64; 3], 0.15, 13)).into(),
        ),
    ];
    for (name, meshes) in &families {
        let (mut inner, mut all, mut plain_inner, mut plain_all) = (vec![], vec![], vec![], vec![]);
        for m in meshes {
            let d = derivatives(m, smooth, Method::L2Projection);
            inner.push(errors(m, &d.hessian, 0.25));
            all.push(errors(m, &d.hessian, 0.0));
            let values: Vec<f64> = m.points.iter().map(|&p| smooth(p)).collect();
            let (_, h) = projection_alone(m, &values);
            plain_inner.push(errors(m, &h, 0.25));
            plain_all.push(errors(m, &h, 0.0));
        }
        let (rms, max) = (order(&inner, |e| e.0), order(&inner, |e| e.1));
        let (all_rms, all_max) = (order(&all, |e| e.0), order(&all, |e| e.1));
        eprintln!("l2-projection, {name}: inside (rms, max) {inner:.3?}, orders {rms:.2}, {max:.2}; every vertex {all:.3?}, orders {all_rms:.2}, {all_max:.2}");
        eprintln!("plain double projection, {name}: inside {plain_inner:.3?}; every vertex {plain_all:.3?}");
        assert!(rms > 1.2 && all_rms > 1.2 && all_max > 0.8, "{name}: {inner:?}, {all:?}");
        for (f, p) in inner.iter().zip(&plain_inner).skip(1) {
            assert!(f.0 <= p.0 && f.1 <= p.1, "{name}: {inner:?} against {plain_inner:?}");
        }
        if *name == "mapped grids" {
            assert!(rms > 1.5 && max > 1.2, "{name}: {inner:?}");
        }
    }
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
    // The projection needs no patch: where no patch determines its edge fit (here, no
    // vertex) it keeps the lumped projection: a linear field's gradient, a zero Hessian.
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
