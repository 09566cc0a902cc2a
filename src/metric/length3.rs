//! Metric edge length and mean-ratio quality of a tetrahedron in 3D, the kernels of the
//! UGAWG-style measures of a tetrahedral mesh against a metric.
//!
//! - The metric length of an edge ab with metrics Ma, Mb at its ends: la = √(abᵀ Ma ab),
//!   lb = √(abᵀ Mb ab), and L = (la − lb)/ln(la/lb) (la when equal), the integral of a
//!   length varying geometrically along the edge: the 2D
//!   [`super::length::geometric_mean_length`], shared.
//! - The mean-ratio quality of a tetrahedron in a constant metric M:
//!   q = 12 (3 V_M)^(2/3) / Σ l_M², with V_M = V √det M and l_M the six metric edge
//!   lengths: 1 for the tetrahedron that is regular in M (V = √2/12 for unit edges, so
//!   12·(√2/4)^(2/3)/6 = 1), towards 0 for flat ones, negative for inverted ones. M is
//!   the Log-Euclidean mean of the four corners' metrics.

use super::eigen3::{cross, dot};
use super::length::geometric_mean_length;
use super::size_tensor3::SizeTensor3;
use super::sym3::Sym3;

fn sub(b: [f64; 3], a: [f64; 3]) -> [f64; 3] {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}

/// Metric length of the edge from `a` to `b` whose ends carry metrics `ma` and `mb`.
pub fn metric_edge_length3(a: [f64; 3], b: [f64; 3], ma: &Sym3, mb: &Sym3) -> f64 {
    let e = sub(b, a);
    let la = ma.quadratic_form(e).max(0.0).sqrt();
    let lb = mb.quadratic_form(e).max(0.0).sqrt();
    geometric_mean_length(la, lb)
}

/// Mean-ratio quality of tetrahedron `p` in the constant metric `m` (see the module
/// header); signed by the orientation of `p`.
pub fn mean_ratio_in_metric(p: [[f64; 3]; 4], m: &Sym3) -> f64 {
    let mut s = 0.0;
    for i in 0..4 {
        for j in i + 1..4 {
            s += m.quadratic_form(sub(p[j], p[i]));
        }
    }
    if s <= 0.0 {
        return 0.0;
    }
    let volume = dot(cross(sub(p[1], p[0]), sub(p[2], p[0])), sub(p[3], p[0])) / 6.0;
    let vm = volume * m.det().max(0.0).sqrt();
    12.0 * (3.0 * vm.abs()).powf(2.0 / 3.0) * vm.signum() / s
}

/// Mean-ratio quality of a tetrahedron whose corners carry metrics `m`, measured in their
/// Log-Euclidean mean (the arithmetic mean when a corner is not SPD).
pub fn metric_tet_quality(p: [[f64; 3]; 4], m: [&Sym3; 4]) -> f64 {
    let sizes: Option<Vec<SizeTensor3>> =
        m.iter().map(|x| SizeTensor3::try_from_metric(x).ok()).collect();
    let mean = sizes
        .and_then(|s| SizeTensor3::log_euclidean_mean(s.iter().map(|t| (0.25, t))))
        .map(|t| t.to_metric())
        .unwrap_or_else(|| 0.25 * (*m[0] + *m[1] + *m[2] + *m[3]));
    mean_ratio_in_metric(p, &mean)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn regular() -> [[f64; 3]; 4] {
        let s = 0.5 * 2f64.sqrt();
        // Alternate corners of a cube of side 1/√2: edges of length 1, positive volume.
        [[0.0, 0.0, 0.0], [s, s, 0.0], [s, 0.0, s], [0.0, s, s]]
    }

    #[test]
    fn regular_unit_tetrahedron_has_quality_one() {
        let m = Sym3::IDENTITY;
        let p = regular();
        let q = metric_tet_quality(p, [&m; 4]);
        assert!((q.abs() - 1.0).abs() < 1e-12, "{q}");
        for i in 0..4 {
            for j in i + 1..4 {
                assert!((metric_edge_length3(p[i], p[j], &m, &m) - 1.0).abs() < 1e-15);
            }
        }
        // The same tetrahedron stretched by 1000 along x is regular in the metric whose
        // size along x is 1000: anisotropy is measured, not penalised.
        let t = SizeTensor3::new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1000.0, 1.0, 1.0]);
        let ms = t.to_metric();
        let stretched = p.map(|x| [1000.0 * x[0], x[1], x[2]]);
        assert!((metric_tet_quality(stretched, [&ms; 4]).abs() - 1.0).abs() < 1e-9);
        assert!(metric_tet_quality(stretched, [&m; 4]).abs() < 0.01);
        // A flat tetrahedron has quality 0; swapping two corners flips the sign.
        let c = [0, 1, 2].map(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0);
        let flat = [p[0], p[1], p[2], c];
        assert!(mean_ratio_in_metric(flat, &m).abs() < 1e-12);
        let swapped = [p[1], p[0], p[2], p[3]];
        assert!((mean_ratio_in_metric(swapped, &m) + mean_ratio_in_metric(p, &m)).abs() < 1e-12);
    }

    /// Analytic twin: for metrics sharing their axes the Log-Euclidean interpolation
    /// scales each direction geometrically, so along an axis the metric length is the
    /// integral of h(t)⁻¹ with h geometric: (la − lb)/ln(la/lb) exactly; Simpson agrees.
    #[test]
    fn edge_length_matches_quadrature_along_an_axis() {
        let (a, b) = ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        for (h0, h1) in [(1.0, 1.0), (0.1, 1.0), (1.0, 1e-3), (0.5, 0.50001)] {
            let ta = SizeTensor3::new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [2.0, 3.0, h0]);
            let tb = SizeTensor3::new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, 3.0, h1]);
            let n = 2000;
            let f = |t: f64| {
                let m = SizeTensor3::log_euclidean_mean([(1.0 - t, &ta), (t, &tb)]).unwrap();
                m.metric_length(b)
            };
            let h = 1.0 / n as f64;
            let mut s = f(0.0) + f(1.0);
            for i in 1..n {
                s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * h);
            }
            let exact = s * h / 3.0;
            let got = metric_edge_length3(a, b, &ta.to_metric(), &tb.to_metric());
            assert!((got - exact).abs() <= 1e-6 * exact, "{h0} {h1}: {got} vs {exact}");
        }
    }
}
