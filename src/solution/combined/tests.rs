use super::*;
use crate::metric::SizeBounds;
use crate::solution::test_meshes::{brute_force_vertices, scattered, Mesh};
use crate::solution::{recover, Method};

fn bounds(h_min: f64, h_max: f64, aspect: f64) -> SizeBounds {
    SizeBounds::try_new(h_min, h_max, aspect).unwrap()
}

/// Three fields of different kinds and magnitudes: a front across x, a thin layer along
/// y = 0.2 a thousand times larger, and a smooth bump.
fn fields(m: &Mesh) -> Vec<Vec<Sym2>> {
    let pi = std::f64::consts::PI;
    let u: [Box<dyn Fn([f64; 2]) -> f64>; 3] = [
        Box::new(move |p| (20.0 * (p[0] - 0.5 - 0.1 * (2.0 * pi * p[1]).sin())).tanh()),
        Box::new(|p| 1e3 * (-((p[1] - 0.2) / 0.03).powi(2)).exp()),
        Box::new(|p| (-8.0 * ((p[0] - 0.3).powi(2) + (p[1] - 0.7).powi(2))).exp()),
    ];
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    u.iter()
        .map(|f| {
            let values: Vec<f64> = m.points.iter().map(|&p| f(p)).collect();
            recover(&mesh, &values, Method::QuadraticFit).unwrap().hessian
        })
        .collect()
}

/// Whether `a - b` (metrics) is positive semi-definite to rounding, by its eigenvalues.
fn at_least(a: &Sym2, b: &Sym2) -> bool {
    let d = Sym2::new(a.a - b.a, a.b - b.b, a.c - b.c);
    let scale = a.eigen().values[0].abs().max(a.eigen().values[1].abs());
    d.eigen().values.iter().all(|&l| l >= -1e-7 * scale)
}

#[test]
fn one_field_is_the_lp_metric_of_that_field() {
    let m = scattered(600, 11, [0.0, 0.0], 1.0);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let h = fields(&m);
    for target in [Target::Vertices(800.0), Target::Error(1e-3)] {
        let o = LpOptions { p: 2.0, target, bounds: bounds(1e-4, 0.5, 1e3) };
        let alone = lp_metric(&mesh, &h[0], &o).unwrap();
        assert_eq!(lp_metric_of_fields(&mesh, &[&h[0]], &o).unwrap(), alone);
        // A linear field asks nothing: left out.
        let linear = vec![Sym2::new(0.0, 0.0, 0.0); h[0].len()];
        assert_eq!(lp_metric_of_fields(&mesh, &[&linear, &h[0]], &o).unwrap(), alone);
    }
}

/// At every vertex, in metric terms, the combined field is at least each field's own
/// normalised metric scaled by the common factor (an eigenvalue check of the
/// difference: smaller or equal size in every direction), and it is their
/// intersection, not smaller: in some direction its size is that of the smallest.
#[test]
fn the_intersection_keeps_the_smaller_size_in_every_direction() {
    let m = scattered(1500, 3, [0.0, 0.0], 1.0);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let h = fields(&m);
    let wide = bounds(1e-9, 1e9, 1e9);
    for p in [1.0, 2.0, f64::INFINITY] {
        for target in [Target::Vertices(2000.0), Target::Error(2e-3)] {
            let o = LpOptions { p, target, bounds: wide };
            let combined = lp_metric_of_fields(&mesh, &[&h[0], &h[1], &h[2]], &o).unwrap();
            let s = combined.scale;
            // Each alone, normalised to the same target (no bound acts).
            let alone: Vec<LpMetric> = h.iter().map(|h| lp_metric(&mesh, h, &o).unwrap()).collect();
            for v in 0..m.points.len() {
                let c = combined.tensors[v].to_metric();
                for a in &alone {
                    let mi = a.tensors[v].to_metric();
                    let scaled = Sym2::new(s * mi.a, s * mi.b, s * mi.c);
                    assert!(at_least(&c, &scaled), "p {p}, {target:?}, vertex {v}");
                }
                let mut touches = false;
                for k in 0..360 {
                    let t = k as f64 * std::f64::consts::PI / 360.0;
                    let d = [t.cos(), t.sin()];
                    let smallest = alone
                        .iter()
                        .map(|a| a.tensors[v].size_along(d) / s.sqrt())
                        .fold(f64::INFINITY, f64::min);
                    let size = combined.tensors[v].size_along(d);
                    assert!(size <= smallest * (1.0 + 1e-6), "p {p}, vertex {v}, angle {t}");
                    touches |= size >= smallest * 0.99;
                }
                assert!(touches, "p {p}, {target:?}, vertex {v}: smaller than the intersection");
            }
            match target {
                // Every field meets the error, so the bound is the error itself.
                Target::Error(e) => {
                    assert_eq!(s, 1.0);
                    assert!((combined.predicted_error / e - 1.0).abs() < 1e-9);
                }
                // Scaled down to the target: coarser than each field's own share.
                Target::Vertices(_) => assert!(s < 1.0, "p {p}: {s}"),
            }
        }
    }
}

#[test]
fn the_combined_field_hits_the_target_vertex_count_by_an_independent_integral() {
    let m = scattered(1500, 5, [0.0, 0.0], 1.0);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let h = fields(&m);
    for (target, b) in [
        (500.0, bounds(1e-9, 1e9, 1e9)),
        (4000.0, bounds(1e-9, 1e9, 1e9)),
        // Bounds that act: h_max coarsens the flat parts, the aspect ratio caps the layer.
        (1500.0, bounds(1e-3, 0.1, 5.0)),
        (1500.0, bounds(0.01, 0.3, 100.0)),
    ] {
        for p in [1.0, 2.0, f64::INFINITY] {
            for set in [&[&h[0][..], &h[1][..]][..], &[&h[2][..], &h[0][..], &h[1][..]][..]] {
                let o = LpOptions { p, target: Target::Vertices(target), bounds: b };
                let r = lp_metric_of_fields(&mesh, set, &o).unwrap();
                let independent = brute_force_vertices(&m, &r.tensors, 6);
                assert!(
                    (independent / target - 1.0).abs() < 0.1,
                    "target {target}, p {p}, {b:?}: {independent} ({} by the closed form)",
                    r.vertices
                );
                assert!((r.vertices / target - 1.0).abs() < 1e-3, "{}", r.vertices);
                for t in &r.tensors {
                    assert!(t.h_min() >= b.h_min() * (1.0 - 1e-12));
                    assert!(t.h_max() <= b.h_max() * (1.0 + 1e-12));
                    assert!(t.aspect_ratio() <= b.max_aspect_ratio() * (1.0 + 1e-9));
                }
            }
        }
    }
}

#[test]
fn a_bad_field_is_named_by_its_index() {
    let m = scattered(200, 2, [0.0, 0.0], 1.0);
    let mesh = P1Mesh::from_triangles(&m.points, &m.triangles).unwrap();
    let h = fields(&m);
    let mut nan = h[1].clone();
    nan[4] = Sym2::new(f64::NAN, 0.0, 0.0);
    let o = LpOptions { p: 2.0, target: Target::Vertices(300.0), bounds: bounds(1e-6, 1.0, 1e3) };
    assert_eq!(
        lp_metric_of_fields(&mesh, &[&h[0], &nan], &o).unwrap_err(),
        (1, LpError::NotFinite(4))
    );
    assert_eq!(
        lp_metric_of_fields(&mesh, &[&h[0], &h[1][1..]], &o).unwrap_err(),
        (1, LpError::Count { hessians: h[1].len() - 1, vertices: h[1].len() })
    );
    assert!(matches!(lp_metric_of_fields(&mesh, &[], &o), Err((0, LpError::Count { .. }))));
}
