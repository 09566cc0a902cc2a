use super::*;
use crate::solution::test_meshes::{grid, jittered_grid, mapped_grid, scattered, Mesh};

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
fn both_methods_are_exact_on_a_quadratic_at_every_vertex_of_any_mesh() {
    // Away from the origin and not of unit size, so that scaling matters.
    let meshes = [
        grid(7, 5, [10.0, -3.0], [0.3, 0.2]),
        jittered_grid([9, 8], [10.0, -3.0], [0.3, 0.2], 0.25, 5),
        scattered(150, 7, [10.0, -3.0], 0.5),
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
                    "{method:?}, mesh {k}, vertex {v} at {p:?} (boundary: {on}): Hessian error {e}"
                );
                let g = quadratic_gradient(p);
                let ge =
                    (d.gradient[v][0] - g[0]).hypot(d.gradient[v][1] - g[1]) / g[0].hypot(g[1]);
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

/// The lumped projection of the P1 gradient alone (the first half of the method before
/// the edge fit), applied once for the gradient and once more for the Hessian.
fn projection_alone(m: &Mesh, values: &[f64]) -> (Vec<[f64; 2]>, Vec<Sym2>) {
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let scalar: Vec<[f64; 1]> = values.iter().map(|&v| [v]).collect();
    let gradient: Vec<[f64; 2]> =
        project_gradients(&mesh, &scalar).into_iter().map(|g| g[0]).collect();
    let hessian = project_gradients(&mesh, &gradient)
        .into_iter()
        .map(|[gx, gy]| Sym2::new(gx[0], 0.5 * (gx[1] + gy[0]), gy[1]))
        .collect();
    (gradient, hessian)
}

/// What the edge fit buys: at every boundary vertex of a grid, and at every vertex of a
/// jittered one, the lumped projection of the P1 gradient misses a quadratic's gradient
/// (and the projection applied twice its Hessian, by 0.3 or more of it), where the method
/// is exact. Without the fit, or with patches that cannot grow past a boundary vertex's
/// one-sided star (whose fit is singular), this fails.
#[test]
fn the_edge_fit_makes_the_projection_exact_where_the_plain_projection_is_not() {
    let meshes = [
        grid(9, 8, [-1.0, 2.0], [0.25, 0.125]),
        jittered_grid([9, 8], [-1.0, 2.0], [0.25, 0.125], 0.25, 3),
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
            let scale = g[0].hypot(g[1]);
            let miss = |r: [f64; 2]| (r[0] - g[0]).hypot(r[1] - g[1]) / scale;
            plain_g = plain_g.max(miss(plain_gradient[v]));
            plain_h = plain_h.max(hessian_error(&plain_hessian[v], &H) / norm(&H));
            fitted = fitted.max(miss(d.gradient[v]));
            fitted = fitted.max(hessian_error(&d.hessian[v], &H) / norm(&H));
        }
        eprintln!("mesh {k}: plain projection gradient error {plain_g:.2e}, Hessian {plain_h:.2e}; with the edge fit {fitted:.1e}");
        assert!(plain_g > 1e-3 && plain_h > 0.3, "mesh {k}: {plain_g}, {plain_h}");
        assert!(fitted < 1e-9, "mesh {k}: {fitted}");
    }
}

/// The edge fit is solved in each patch's own frame, so a mesh stretched 100:1 at an
/// angle (an adapted mesh's anisotropy) is as exact as an isotropic one; in the patch
/// radius's scaling every vertex fell back to the plain projection (errors of 100x the
/// Hessian).
#[test]
fn the_l2_projection_is_exact_on_a_stretched_rotated_mesh() {
    let mut m = jittered_grid([16, 16], [0.0, 0.0], [1.0 / 16.0; 2], 0.25, 9);
    let (c, s) = (0.5f64.cos(), 0.5f64.sin());
    for p in &mut m.points {
        let [x, y] = [p[0], 0.01 * p[1]];
        *p = [c * x - s * y, s * x + c * y];
    }
    let d = derivatives(&m, quadratic, Method::L2Projection);
    let worst = d.hessian.iter().map(|h| hessian_error(h, &H) / norm(&H)).fold(0.0, f64::max);
    eprintln!("stretched 100:1: worst relative Hessian error {worst:.1e}");
    assert!(worst < 1e-9, "{worst}");
}

/// The same mesh and values give the same bits on one thread and on three.
#[test]
fn both_methods_give_the_same_bits_on_any_thread_count() {
    let m = scattered(2000, 5, [0.0, 0.0], 1.0);
    let values: Vec<f64> = m.points.iter().map(|&p| smooth(p)).collect();
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    for method in Method::ALL {
        let runs: Vec<Derivatives> = [1, 3]
            .iter()
            .map(|&threads| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                pool.install(|| recover(&mesh, &values, method).unwrap())
            })
            .collect();
        let bits = |d: &Derivatives| -> Vec<u64> {
            d.gradient
                .iter()
                .flatten()
                .chain(d.hessian.iter().flat_map(|h| [&h.a, &h.b, &h.c]))
                .map(|x| x.to_bits())
                .collect()
        };
        assert_eq!(bits(&runs[0]), bits(&runs[1]), "{method:?}");
    }
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

/// Area-weighted RMS and maximum of the Hessian error over the vertices at least
/// `margin` from the boundary of the unit square (every vertex for 0).
fn errors(m: &Mesh, hessian: &[Sym2], margin: f64) -> (f64, f64) {
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
        if p.iter().all(|&x| (margin..=1.0 - margin).contains(&x)) {
            let e = hessian_error(&hessian[v], &smooth_hessian(p));
            sum += w[v] * e * e;
            weight += w[v];
            max = max.max(e);
        }
    }
    ((sum / weight).sqrt(), max)
}

fn interior_errors(m: &Mesh, d: &Derivatives) -> (f64, f64) {
    errors(m, &d.hessian, 0.2)
}

fn order(e: &[(f64, f64)], pick: fn(&(f64, f64)) -> f64) -> f64 {
    (pick(&e[0]) / pick(&e[2])).log2() / 2.0
}

/// The quadratic fit on Delaunay meshes of scattered points, h halved twice (4x the
/// points each time): first order in the mean, a little less at the worst vertex (the
/// most irregular patch).
#[test]
fn on_unstructured_meshes_the_quadratic_fit_converges_to_the_analytic_hessian() {
    let (mut inner, mut all) = (vec![], vec![]);
    for n in [400, 1600, 6400] {
        let m = scattered(n, 11, [0.0, 0.0], 1.0);
        let d = derivatives(&m, smooth, Method::QuadraticFit);
        inner.push(interior_errors(&m, &d));
        all.push(errors(&m, &d.hessian, 0.0));
    }
    let errors = inner;
    let (rms, max) = (order(&errors, |e| e.0), order(&errors, |e| e.1));
    eprintln!("quadratic fit, scattered points: inside {errors:.3?}: orders rms {rms:.2}, max {max:.2}; every vertex {all:.3?}");
    assert!(rms > 0.8 && max > 0.4, "{errors:?}");
}

/// The Hessian errors of the `l2-projection` method and of the plain double projection
/// ([`projection_alone`], the method before the edge fit) on three meshes of a family,
/// h halved twice: (inside [0.2, 0.8]², every vertex) for each.
type Errors = Vec<((f64, f64), (f64, f64))>;
fn both_projections(meshes: &[Mesh]) -> (Errors, Errors) {
    let mut fitted = Vec::new();
    let mut plain = Vec::new();
    for m in meshes {
        let d = derivatives(m, smooth, Method::L2Projection);
        fitted.push((errors(m, &d.hessian, 0.2), errors(m, &d.hessian, 0.0)));
        let values: Vec<f64> = m.points.iter().map(|&p| smooth(p)).collect();
        let (_, h) = projection_alone(m, &values);
        plain.push((errors(m, &h, 0.2), errors(m, &h, 0.0)));
    }
    (fitted, plain)
}

/// The `l2-projection` method converges on every family, at the boundary too: at second
/// order inside smooth images of a grid (as the plain double projection did, with
/// smaller errors), at first order on jittered grids and Delaunay meshes of scattered
/// points (where the plain projection's error stayed of the order of the Hessian, its
/// averaged gradients consistent to O(h) only), and the worst vertex, on the boundary,
/// at first order everywhere (the plain projection's stayed at 4.4).
#[test]
fn the_l2_projection_converges_on_every_mesh_and_at_the_boundary() {
    let families: [(&str, Vec<Mesh>); 3] = [
        ("mapped grids", [16, 32, 64].map(mapped_grid).into()),
        (
            "jittered grids",
            [16, 32, 64]
                .map(|n| jittered_grid([n, n], [0.0, 0.0], [1.0 / n as f64; 2], 0.25, 17))
                .into(),
        ),
        ("scattered points", [400, 1600, 6400].map(|n| scattered(n, 11, [0.0, 0.0], 1.0)).into()),
    ];
    for (name, meshes) in &families {
        let (fitted, plain) = both_projections(meshes);
        let inner: Vec<(f64, f64)> = fitted.iter().map(|e| e.0).collect();
        let all: Vec<(f64, f64)> = fitted.iter().map(|e| e.1).collect();
        let plain_inner: Vec<(f64, f64)> = plain.iter().map(|e| e.0).collect();
        let (rms, max) = (order(&inner, |e| e.0), order(&inner, |e| e.1));
        let (all_rms, all_max) = (order(&all, |e| e.0), order(&all, |e| e.1));
        eprintln!("l2-projection, {name}: inside (rms, max) {inner:.3?}, orders {rms:.2}, {max:.2}; every vertex {all:.3?}, orders {all_rms:.2}, {all_max:.2}");
        eprintln!(
            "plain double projection, {name}: inside {plain_inner:.3?}; every vertex {:.3?}",
            plain.iter().map(|e| e.1).collect::<Vec<_>>()
        );
        assert!(rms > 0.8 && all_rms > 0.8 && all_max > 0.8, "{name}: {fitted:?}");
        if *name == "mapped grids" {
            assert!(rms > 1.5 && max > 1.5, "{name}: {inner:?}");
            for (f, p) in inner.iter().zip(&plain_inner) {
                assert!(f.0 <= p.0 && f.1 <= p.1, "{name}: {inner:?} against {plain_inner:?}");
            }
        } else {
            assert!(max > 0.4, "{name}: {inner:?}");
            let plain_rms = order(&plain_inner, |e| e.0);
            assert!(plain_rms.abs() < 0.3, "{name}: {plain_inner:?}");
        }
    }
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
    // The projection needs no patch: where no patch determines its edge fit (here, no
    // vertex) it keeps the lumped projection: a linear field's gradient, a zero Hessian.
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
