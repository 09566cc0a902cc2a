use super::*;
use crate::metric::complexity3::expected_vertices3;
use crate::metric::SizeBounds;
use crate::solution::test_meshes3::{jittered, kuhn};
use crate::solution::{recover3, Method, Target};

fn bounds(h_min: f64, h_max: f64, aspect: f64) -> SizeBounds {
    SizeBounds::try_new(h_min, h_max, aspect).unwrap()
}

/// A spherical front: u = tanh(10 (|x − c| − 0.35)).
fn front(p: [f64; 3]) -> f64 {
    let r = ((p[0] - 0.5).powi(2) + (p[1] - 0.45).powi(2) + (p[2] - 0.55).powi(2)).sqrt();
    (10.0 * (r - 0.35)).tanh()
}

/// The count of the normalised field, measured by `metric::complexity3` on its metric
/// tensors (not the normaliser's own sums), is the target to 1e-9 when no bound acts,
/// and to the bisection's 1e-4 when the bounds act.
#[test]
fn the_normalised_complexity_is_the_target() {
    let m = jittered([8, 8, 8], [0.0; 3], [0.125; 3], 0.15, 21);
    let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
    let values: Vec<f64> = m.points.iter().map(|&p| front(p)).collect();
    let h = recover3(&mesh, &values, Method::QuadraticFit).unwrap().hessian;
    let tets: Vec<[usize; 4]> = m.tets.iter().map(|t| t.map(|v| v as usize)).collect();
    for p in [1.0, 2.0, 4.0, f64::INFINITY] {
        for target in [500.0, 20000.0] {
            let o =
                LpOptions { p, target: Target::Vertices(target), bounds: bounds(1e-9, 1e9, 1e9) };
            let r = lp_metric3(&mesh, &h, &o).unwrap();
            let metric: Vec<Sym3> = r.tensors.iter().map(|t| t.to_metric()).collect();
            let measured = expected_vertices3(&m.points, &tets, &metric);
            assert!((measured / target - 1.0).abs() < 1e-9, "p {p}: {measured} for {target}");
            assert!((r.vertices / target - 1.0).abs() < 1e-9, "p {p}: {}", r.vertices);
        }
        // Bounds that act: the count is reached by bisection, every tensor inside them.
        let b = bounds(0.03, 0.3, 5.0);
        let o = LpOptions { p, target: Target::Vertices(3000.0), bounds: b };
        let r = lp_metric3(&mesh, &h, &o).unwrap();
        let metric: Vec<Sym3> = r.tensors.iter().map(|t| t.to_metric()).collect();
        let measured = expected_vertices3(&m.points, &tets, &metric);
        assert!((measured / 3000.0 - 1.0).abs() < 1e-3, "p {p}, bounded: {measured}");
        for t in &r.tensors {
            assert!(t.h_min() >= 0.03 * (1.0 - 1e-12) && t.h_max() <= 0.3 * (1.0 + 1e-12), "{t:?}");
            assert!(t.aspect_ratio() <= 5.0 * (1.0 + 1e-12), "{t:?}");
        }
    }
}

/// A rotation whose axes are none of the coordinate axes: about (1, 2, 3)/√14 by 0.7,
/// its rows the axes.
fn rotation() -> [[f64; 3]; 3] {
    let n = 14f64.sqrt();
    let (x, y, z) = (1.0 / n, 2.0 / n, 3.0 / n);
    let (s, c) = 0.7f64.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y + s * z, t * x * z - s * y],
        [t * x * y - s * z, t * y * y + c, t * y * z + s * x],
        [t * x * z + s * y, t * y * z - s * x, t * z * z + c],
    ]
}

/// A constant Hessian R diag(−8, 2, 0.5) Rᵀ on the unit cube, by hand: det|H| = 8, so
/// ∫ det|H|^(p/(2p+3)) = 8^(p/(2p+3)) =: I; for N vertices C = N · 5.6/(6√2),
/// D = (C/I)^(2/3), and the sizes are (D 8^(−1/(2p+3)) λ)^(−1/2) along R's rows; for an
/// error ε, D = 3 I^(1/p) / (20 ε).
#[test]
fn a_constant_hessian_gives_the_sizes_worked_by_hand() {
    let m = kuhn([3, 3, 3], [0.0; 3], [1.0 / 3.0; 3]);
    let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
    let r = rotation();
    let h = Sym3::from_eigen([-8.0, 2.0, 0.5], r);
    let hessians = vec![h; m.points.len()];
    for p in [1.0, 2.0, 3.5, f64::INFINITY] {
        let e = if p.is_infinite() { 0.0 } else { 1.0 / (2.0 * p + 3.0) };
        let pe = if p.is_infinite() { 1.0 / 2.0 } else { p / (2.0 * p + 3.0) };
        let integral = 8f64.powf(pe);
        let n = 1234.0;
        let c = n * 5.6 / (6.0 * 2f64.sqrt());
        for (target, d) in [
            (Target::Vertices(n), (c / integral).powf(2.0 / 3.0)),
            (
                Target::Error(0.01),
                3.0 * if p.is_infinite() { 1.0 } else { integral.powf(1.0 / p) } / (20.0 * 0.01),
            ),
        ] {
            let o = LpOptions { p, target, bounds: bounds(1e-9, 1e9, 1e9) };
            let out = lp_metric3(&mesh, &hessians, &o).unwrap();
            assert!(
                (out.scale / d - 1.0).abs() < 1e-12,
                "p {p} {target:?}: D {} by hand {d}",
                out.scale
            );
            let g = 8f64.powf(-e);
            let sizes = [8.0, 2.0, 0.5].map(|l: f64| (d * g * l).powf(-0.5));
            for t in &out.tensors {
                for (axis, size) in [(r[0], sizes[0]), (r[1], sizes[1]), (r[2], sizes[2])] {
                    let along = t.size_along(axis);
                    assert!((along / size - 1.0).abs() < 1e-12, "p {p}: {along} for {size}");
                }
            }
            if let Target::Error(eps) = target {
                assert!((out.predicted_error / eps - 1.0).abs() < 1e-12, "{}", out.predicted_error);
            } else {
                assert!((out.vertices / n - 1.0).abs() < 1e-12, "{}", out.vertices);
            }
        }
    }
}

#[test]
fn a_linear_field_gets_the_uniform_metric_and_bad_input_is_refused() {
    let m = kuhn([3, 3, 3], [0.0; 3], [1.0 / 3.0; 3]);
    let mesh = P1Mesh3::new(&m.points, &m.tets).unwrap();
    let zero = vec![Sym3::ZERO; m.points.len()];
    let o = LpOptions { p: 2.0, target: Target::Vertices(800.0), bounds: bounds(1e-9, 1e9, 1e4) };
    let r = lp_metric3(&mesh, &zero, &o).unwrap();
    assert!(r.linear);
    assert!(r.tensors.iter().all(|t| t.aspect_ratio() < 1.0 + 1e-12), "{:?}", r.tensors[0]);
    assert!((r.vertices / 800.0 - 1.0).abs() < 1e-9);
    let bad = |p: f64, target: Target| LpOptions { p, target, bounds: o.bounds };
    assert_eq!(lp_metric3(&mesh, &zero, &bad(0.5, Target::Vertices(1.0))), Err(LpError::P(0.5)));
    assert!(matches!(
        lp_metric3(&mesh, &zero, &bad(2.0, Target::Error(-1.0))),
        Err(LpError::Target { what: "error", .. })
    ));
    assert_eq!(
        lp_metric3(&mesh, &zero[1..], &o),
        Err(LpError::Count { hessians: 63, vertices: 64 })
    );
    let mut nan = zero.clone();
    nan[7].yz = f64::NAN;
    assert_eq!(lp_metric3(&mesh, &nan, &o), Err(LpError::NotFinite(7)));
    let flat = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    let flat_mesh = P1Mesh3::new(&flat, &[[0, 1, 2, 3]]).unwrap();
    let e = lp_metric3(&flat_mesh, &[Sym3::ZERO; 4], &o).unwrap_err();
    assert_eq!(e, LpError::NoVolume);
    assert_eq!(e.to_string(), "the mesh has no tetrahedron of positive volume");
}
