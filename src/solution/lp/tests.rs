use super::*;
use crate::solution::test_meshes::{brute_force_vertices, grid, scattered};
use crate::solution::{recover, Method};

fn bounds(h_min: f64, h_max: f64, aspect: f64) -> SizeBounds {
    SizeBounds::try_new(h_min, h_max, aspect).unwrap()
}

fn options(p: f64, target: Target) -> LpOptions {
    LpOptions { p, target, bounds: bounds(1e-9, 1e9, 1e9) }
}

/// A front: u = tanh(20 (x − 0.5 − 0.1 sin 2πy)).
fn front(p: [f64; 2]) -> f64 {
    (20.0 * (p[0] - 0.5 - 0.1 * (2.0 * std::f64::consts::PI * p[1]).sin())).tanh()
}

#[test]
fn normalisation_hits_the_target_vertex_count_by_an_independent_integral() {
    let m = scattered(1500, 3, [0.0, 0.0], 1.0);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let values: Vec<f64> = m.points.iter().map(|&p| front(p)).collect();
    let h = recover(&mesh, &values, Method::QuadraticFit).unwrap().hessian;
    for (target, b) in [
        (300.0, bounds(1e-9, 1e9, 1e9)),
        (3000.0, bounds(1e-9, 1e9, 1e9)),
        // Bounds that act: h_max coarsens the flat parts, aspect ratio 5 caps the front.
        (1000.0, bounds(1e-3, 0.1, 5.0)),
        (1000.0, bounds(0.02, 0.2, 100.0)),
    ] {
        for p in [1.0, 2.0, f64::INFINITY] {
            let o = LpOptions { p, target: Target::Vertices(target), bounds: b };
            let r = lp_metric(&mesh, &h, &o).unwrap();
            let brute = brute_force_vertices(&m, &r.tensors, 6);
            assert!((r.vertices / target - 1.0).abs() < 1e-3, "p {p}, {b:?}: {}", r.vertices);
            assert!((brute / target - 1.0).abs() < 0.1, "p {p}, {b:?}: brute force {brute}");
            for t in &r.tensors {
                let [h1, h2] = t.sizes();
                assert!(h1.min(h2) >= b.h_min() && h1.max(h2) <= b.h_max(), "{t:?}");
                assert!(t.aspect_ratio() <= b.max_aspect_ratio() * (1.0 + 1e-12), "{t:?}");
            }
        }
    }
}

#[test]
fn a_target_the_bounds_forbid_gives_the_nearest_field_they_allow() {
    let m = grid(10, 10, [0.0, 0.0], [0.1, 0.1]);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let h = vec![Sym2::new(2.0, 0.0, 2.0); m.points.len()];
    // h_min = 0.1 on the unit square: at most 2/√3 / 0.01 ≈ 115 vertices.
    let o = LpOptions { p: 2.0, target: Target::Vertices(1e6), bounds: bounds(0.1, 1.0, 10.0) };
    let r = lp_metric(&mesh, &h, &o).unwrap();
    assert!(r.tensors.iter().all(|t| t.sizes() == [0.1, 0.1]), "{:?}", r.tensors[0]);
    assert!((r.vertices - 2.0 / 3f64.sqrt() / 0.01).abs() < 1e-6, "{}", r.vertices);
}

/// u = x² + 100 y², turned by `angle`: |H| = R diag(2, 200) Rᵀ.
fn turned(angle: f64) -> (Sym2, [f64; 2]) {
    let (s, c) = angle.sin_cos();
    (Sym2::from_eigen([200.0, 2.0], [-s, c]), [c, s])
}

#[test]
fn a_constant_anisotropic_hessian_gives_the_known_sizes() {
    let m = grid(8, 8, [0.0, 0.0], [0.125, 0.125]);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    for angle in [0.0, 0.5] {
        let (h, x_axis) = turned(angle);
        let hessians = vec![h; m.points.len()];
        for p in [1.0, 2.0, 4.0, f64::INFINITY] {
            let r = lp_metric(&mesh, &hessians, &options(p, Target::Vertices(500.0))).unwrap();
            for t in &r.tensors {
                // The ratio of sizes is √(200/2) = 10, x across the weak direction.
                let (hx, hy) = (t.size_along(x_axis), t.size_along([-x_axis[1], x_axis[0]]));
                assert!((hx / hy - 10.0).abs() < 1e-9, "p {p}: {hx} / {hy}");
                // A constant metric on the unit square: 2/√3 / (hx hy) vertices.
                let v = 2.0 / 3f64.sqrt() / (hx * hy);
                assert!((v / 500.0 - 1.0).abs() < 1e-9, "p {p}: {v}");
            }
        }
    }
}

/// The mean of u − Πu over triangle `t` for the quadratic u of SPD Hessian `h`: the
/// mean of λᵢλⱼ is 1/12, so (1/24) Σ eᵀ H e over its edges.
fn mean_quadratic_error(points: &[[f64; 2]], t: [usize; 3], h: &Sym2) -> f64 {
    (0..3)
        .map(|i| {
            let (a, b) = (points[t[i]], points[t[(i + 1) % 3]]);
            h.quadratic_form([b[0] - a[0], b[1] - a[1]])
        })
        .sum::<f64>()
        / 24.0
}

#[test]
fn an_error_target_gives_a_mesh_of_that_error_when_the_mesh_conforms() {
    // On the unit square the optimal metric of a constant Hessian is constant; a mesh of
    // unit triangles in it (the equilateral lattice mapped by M^(-1/2)) has the same mean
    // error on every triangle, which must be the target spread over the area.
    let m = grid(4, 4, [0.0, 0.0], [0.25, 0.25]);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    for angle in [0.0, 0.7] {
        let (h, _) = turned(angle);
        for (p, eps) in [(1.0, 1e-3), (2.0, 1e-4), (f64::INFINITY, 1e-2)] {
            let r = lp_metric(&mesh, &vec![h; 25], &options(p, Target::Error(eps))).unwrap();
            assert!((r.predicted_error / eps - 1.0).abs() < 1e-12, "{}", r.predicted_error);
            let t = r.tensors[0];
            let to_physical = |xi: [f64; 2]| {
                let (e, f) = (t.axis(), t.second_axis());
                let [h1, h2] = t.sizes();
                let (u, v) = (xi[0] * e[0] + xi[1] * e[1], xi[0] * f[0] + xi[1] * f[1]);
                [h1 * (u * e[0]) + h2 * (v * f[0]), h1 * (u * e[1]) + h2 * (v * f[1])]
            };
            let unit = [[0.0, 0.0], [1.0, 0.0], [0.5, 0.75f64.sqrt()]].map(to_physical);
            let mean = mean_quadratic_error(&unit, [0, 1, 2], &h);
            // |e| constant over a domain of area 1: its Lp norm is that constant.
            assert!((mean / eps - 1.0).abs() < 1e-9, "p {p}, angle {angle}: {mean} vs {eps}");
        }
    }
}

#[test]
fn a_degenerate_hessian_is_capped_by_the_aspect_ratio_and_a_linear_field_is_uniform() {
    let m = scattered(300, 5, [0.0, 0.0], 1.0);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let n = m.points.len();
    // u = x²: no curvature along y.
    let o = LpOptions { p: 2.0, target: Target::Vertices(400.0), bounds: bounds(1e-6, 10.0, 50.0) };
    let r = lp_metric(&mesh, &vec![Sym2::new(2.0, 0.0, 0.0); n], &o).unwrap();
    for t in &r.tensors {
        assert!((t.size_along([0.0, 1.0]) / t.size_along([1.0, 0.0]) - 50.0).abs() < 1e-9);
    }
    assert!(!r.linear);
    let r = lp_metric(&mesh, &vec![Sym2::new(0.0, 0.0, 0.0); n], &o).unwrap();
    assert!(r.linear);
    let first = r.tensors[0];
    assert!((first.h1() - first.h2()).abs() < 1e-12 * first.h1());
    assert!(r.tensors.iter().all(|t| t.sizes() == first.sizes()));
    assert!((r.vertices / 400.0 - 1.0).abs() < 1e-3, "{}", r.vertices);
}

#[test]
fn intersection_keeps_the_smaller_size_in_every_direction() {
    let mut state = 7u64;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut fields = vec![Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..200 {
        for f in &mut fields {
            let h1 = 10f64.powf(-3.0 + 3.0 * next());
            let h2 = h1 * 10f64.powf(2.0 * next());
            f.push(SizeTensor::from_angle(6.3 * next(), h1, h2).unwrap());
        }
    }
    let both = intersect_all(&fields).unwrap();
    for (v, t) in both.iter().enumerate() {
        let mut touches = 0;
        for k in 0..90 {
            let a = k as f64 * std::f64::consts::PI / 90.0;
            let d = [a.cos(), a.sin()];
            let smallest = fields.iter().map(|f| f[v].size_along(d)).fold(f64::INFINITY, f64::min);
            assert!(t.size_along(d) <= smallest * (1.0 + 1e-9), "vertex {v}, direction {a}");
            if t.size_along(d) > 0.5 * smallest {
                touches += 1;
            }
        }
        // Not a degenerate answer: as large as the smallest input somewhere.
        assert!(touches > 0, "vertex {v}");
    }
    assert_eq!(intersect_all(&[]), None);
    assert_eq!(intersect_all(&[both.clone(), both[1..].to_vec()]), None);
}

#[test]
fn bad_options_are_refused() {
    let m = grid(2, 2, [0.0, 0.0], [1.0, 1.0]);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let h = vec![Sym2::IDENTITY; 9];
    let go = |p, target, h: &[Sym2]| lp_metric(&mesh, h, &options(p, target)).unwrap_err();
    assert_eq!(go(0.5, Target::Vertices(10.0), &h), LpError::P(0.5));
    assert!(matches!(go(f64::NAN, Target::Vertices(10.0), &h), LpError::P(_)));
    assert!(matches!(go(2.0, Target::Vertices(0.0), &h), LpError::Target { .. }));
    assert!(matches!(go(2.0, Target::Error(f64::INFINITY), &h), LpError::Target { .. }));
    assert_eq!(
        go(2.0, Target::Vertices(9.0), &h[1..]),
        LpError::Count { hessians: 8, vertices: 9 }
    );
    let mut bad = h.clone();
    bad[4].b = f64::NAN;
    assert_eq!(go(2.0, Target::Vertices(9.0), &bad), LpError::NotFinite(4));
}
