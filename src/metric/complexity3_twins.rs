//! Twins of the 3D complexity: the exact integral against a Gauss–Legendre product rule
//! on the collapsed cube (Duffy) and against the closed form Σ e^{xᵢ}/Πⱼ(xᵢ − xⱼ); the
//! complexity of boxes against closed-form integrals; a refinement study.

use super::*;

/// Gauss–Legendre nodes and weights on [0, 1], by Newton on Pₙ.
fn gauss(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / dp;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            ((1.0 - x) / 2.0, 1.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// ∫ exp(linear) over a tetrahedron of volume `v` by an n³ Gauss rule on the Duffy cube.
fn by_quadrature(v: f64, f: [f64; 4], n: usize) -> f64 {
    let g = gauss(n);
    let mut sum = 0.0;
    for &(u, wu) in &g {
        for &(s, ws) in &g {
            for &(t, wt) in &g {
                let l1 = u;
                let l2 = s * (1.0 - u);
                let l3 = t * (1.0 - u) * (1.0 - s);
                let l0 = 1.0 - l1 - l2 - l3;
                let jac = (1.0 - u) * (1.0 - u) * (1.0 - s);
                let x = l0 * f[0] + l1 * f[1] + l2 * f[2] + l3 * f[3];
                sum += wu * ws * wt * jac * x.exp();
            }
        }
    }
    6.0 * v * sum
}

/// 3!·exp[x] by the closed form for distinct nodes.
fn closed_form_mean(x: [f64; 4]) -> f64 {
    let mut s = 0.0;
    for i in 0..4 {
        let p: f64 = (0..4).filter(|&j| j != i).map(|j| x[i] - x[j]).product();
        s += x[i].exp() / p;
    }
    6.0 * s
}

#[test]
fn exact_integral_agrees_with_quadrature_and_closed_form() {
    for f in [
        [1.0, 1.0, 1.0, 1.0],
        [1.0, 1.0 + 1e-9, 1.0 - 1e-9, 1.0 + 3e-10],
        [0.0, 2.0, -1.0, 0.5],
        [5.0, 5.0, -3.0, -3.0],
        [13.8, 2.3, 2.3, 2.3],
        [-4.0, 3.0, 3.0 + 1e-8, 0.9],
        [0.0, 0.3, 0.6, 0.95],
    ] {
        let exact = log_integral_of_exp3(0.02, f).exp();
        let brute = by_quadrature(0.02, f, 40);
        assert!((exact - brute).abs() <= 1e-9 * brute, "{f:?}: {exact} vs {brute}");
    }
    // Well-separated nodes: the closed form has no cancellation to fear.
    for x in [[0.0, -1.5, -3.2, -7.0], [4.0, 1.0, -2.0, -20.0], [0.0, -2.0, -4.0, -6.0]] {
        let exact = log_integral_of_exp3(1.0, x).exp();
        let closed = closed_form_mean(x);
        assert!((exact - closed).abs() <= 1e-13 * closed, "{x:?}: {exact} vs {closed}");
    }
}

#[test]
fn one_tiny_size_dominates_and_nothing_overflows() {
    // h = 1e-6 at one corner among 0.1 (½ ln det = 3 ln(1/h)).
    let f = [3.0 * 1e6f64.ln(), 3.0 * 10f64.ln(), 3.0 * 10f64.ln(), 3.0 * 10f64.ln()];
    let exact = log_integral_of_exp3(1e-3, f).exp();
    let brute = by_quadrature(1e-3, f, 120);
    assert!((exact - brute).abs() <= 1e-6 * brute, "{exact} vs {brute}");
    let centroid = 1e-3 * (f.iter().sum::<f64>() / 4.0).exp();
    assert!(exact > 100.0 * centroid);
    // 1e200 on the diagonal: det 1e600 is beyond f64, √det = 1e300 is not.
    let huge = Sym3::from_eigen([1e200; 3], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    assert!((half_log_det3(&huge) - 300.0 * 10f64.ln()).abs() < 1e-9);
    let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let c = complexity3(&pts, &[[0, 1, 2, 3]], &[half_log_det3(&huge); 4]);
    assert!((c / (1e300 / 6.0) - 1.0).abs() < 1e-9, "{c}");
    let c = complexity3(&pts, &[[0, 1, 2, 3]], &[800.0; 4]);
    assert!(c.is_infinite() && c > 0.0);
    // A tensor that is not SPD counts nothing rather than NaN.
    let bad =
        Sym3::from_eigen([1.0, 1.0, -1.0], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    assert_eq!(half_log_det3(&bad), f64::NEG_INFINITY);
    assert_eq!(complexity3(&pts, &[[0, 1, 2, 3]], &[half_log_det3(&bad); 4]), 0.0);
}

/// The box [0, a]×[0, b]×[0, c] cut into n³ cells of six tetrahedra each (Kuhn).
fn box_mesh(size: [f64; 3], n: usize) -> (Vec<[f64; 3]>, Vec<[usize; 4]>) {
    let id = |i: usize, j: usize, k: usize| (i * (n + 1) + j) * (n + 1) + k;
    let mut pts = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            for k in 0..=n {
                let s = |q: usize, l: f64| l * q as f64 / n as f64;
                pts.push([s(i, size[0]), s(j, size[1]), s(k, size[2])]);
            }
        }
    }
    let mut tets = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                for perm in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
                    let mut c = [i, j, k];
                    let mut t = [id(c[0], c[1], c[2]); 4];
                    for (s, &axis) in perm.iter().enumerate() {
                        c[axis] += 1;
                        t[s + 1] = id(c[0], c[1], c[2]);
                    }
                    tets.push(t);
                }
            }
        }
    }
    (pts, tets)
}

#[test]
fn a_constant_metric_on_a_box_counts_volume_times_root_det() {
    let (pts, tets) = box_mesh([2.0, 1.0, 0.5], 3);
    let r = [[0.6, 0.8, 0.0], [-0.8, 0.6, 0.0], [0.0, 0.0, 1.0]];
    let m = Sym3::from_eigen([1e4, 400.0, 25.0], r);
    let c = complexity3(&pts, &tets, &vec![half_log_det3(&m); pts.len()]);
    let want = 1.0 * m.det().sqrt();
    assert!((c - want).abs() < 1e-12 * want, "{c} vs {want}");
    let n = expected_vertices3(&pts, &tets, &vec![m; pts.len()]);
    assert!((n - want * 6.0 * 2f64.sqrt() / TETS_PER_VERTEX).abs() < 1e-9 * n);
}

#[test]
fn a_metric_exponential_along_x_is_integrated_exactly_on_any_mesh() {
    // h₁ = e^(−a x) along x: √det = e^(a x)/(h₂ h₃), whose log is linear, so the
    // Log-Euclidean field is the analytic one and C = (e^(a L) − 1)/a · b c/(h₂ h₃).
    let (a, size, h2, h3): (f64, [f64; 3], f64, f64) = (3.0, [1.5, 1.0, 0.5], 0.1, 0.2);
    let exact = ((a * size[0]).exp() - 1.0) / a * size[1] * size[2] / (h2 * h3);
    for n in [1, 2, 5] {
        let (pts, tets) = box_mesh(size, n);
        let metric: Vec<Sym3> = pts
            .iter()
            .map(|p| {
                let frame = [[0.0, 0.6, 0.8], [0.0, -0.8, 0.6], [1.0, 0.0, 0.0]];
                Sym3::from_eigen([1.0 / (h2 * h2), 1.0 / (h3 * h3), (2.0 * a * p[0]).exp()], frame)
            })
            .collect();
        let f: Vec<f64> = metric.iter().map(half_log_det3).collect();
        let c = complexity3(&pts, &tets, &f);
        assert!((c - exact).abs() < 1e-12 * exact, "n = {n}: {c} vs {exact}");
    }
}

#[test]
fn refinement_converges_to_the_analytic_complexity_at_second_order() {
    // Isotropic h = 0.2 + x on the unit cube: C = ∫ (0.2 + x)⁻³ = ½(0.2⁻² − 1.2⁻²). The
    // interpolated log differs from the analytic one by O(δ²) on cells of side δ.
    let exact = 0.5 * (0.2f64.powi(-2) - 1.2f64.powi(-2));
    let mut errors = Vec::new();
    for n in [4, 8, 16, 32] {
        let (pts, tets) = box_mesh([1.0; 3], n);
        let f: Vec<f64> = pts.iter().map(|p| -3.0 * (0.2 + p[0]).ln()).collect();
        let c = complexity3(&pts, &tets, &f);
        errors.push((c - exact).abs() / exact);
    }
    // Halving δ divides the error by 3.3, 3.7, then nearly 4.
    for w in errors.windows(2) {
        assert!(w[1] < w[0] / 3.2, "{errors:?}");
    }
    assert!(errors[2] / errors[3] > 3.8 && errors[3] < 4e-3, "{errors:?}");
}
