//! Metric edge length and metric triangle quality: the kernels every measure of a mesh
//! against a metric shares (the remesher's operators, the partitioner, `conformity`).
//!
//! - The metric length of an edge ab, with metrics Ma and Mb at its ends, is the length of
//!   the segment in the metric interpolated along it. With la = √(abᵀ Ma ab) and
//!   lb = √(abᵀ Mb ab) and the size varying geometrically along the edge (the
//!   Log-Euclidean interpolation of [`crate::metric`]), the integral is
//!   (la − lb) / ln(la / lb), la when they are equal: the formula MMG and BAMG use.
//! - The metric quality of a triangle is the shape quality q = 4√3·A / Σ l² measured in
//!   the metric at its centroid (the Log-Euclidean mean of its corners' metrics): 1 for a
//!   triangle that is equilateral in the metric, 0 for a flat one, negative for an
//!   inverted one.
//! - A mesh conforms when its edges have metric lengths in [`CONFORMING`], [1/√2, √2].

use super::{SizeTensor, Sym2};

/// The band of metric edge lengths that counts as conforming: [1/√2, √2].
pub const CONFORMING: [f64; 2] = [std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::SQRT_2];

/// Metric length of the edge from `a` to `b` whose ends carry metrics `ma` and `mb`.
#[inline]
pub fn metric_edge_length(a: [f64; 2], b: [f64; 2], ma: &Sym2, mb: &Sym2) -> f64 {
    let e = [b[0] - a[0], b[1] - a[1]];
    let la = ma.quadratic_form(e).max(0.0).sqrt();
    let lb = mb.quadratic_form(e).max(0.0).sqrt();
    geometric_mean_length(la, lb)
}

/// The integral of a length that varies geometrically from `la` to `lb`:
/// (la − lb)/ln(la/lb), with a series where they are close (no cancellation).
#[inline]
pub fn geometric_mean_length(la: f64, lb: f64) -> f64 {
    if la <= 0.0 || lb <= 0.0 {
        return 0.5 * (la + lb);
    }
    let r = lb / la;
    let d = r - 1.0;
    if d.abs() < 1e-4 {
        // (r − 1)/ln r = 1 + d/2 − d²/12 + O(d³).
        la * (1.0 + d * (0.5 - d / 12.0))
    } else {
        (la - lb) / (la / lb).ln()
    }
}

/// The metric at a triangle's centroid: the Log-Euclidean mean of its corners' metrics
/// (falls back to the arithmetic mean when a corner is not SPD).
pub fn centroid_metric(m: [&Sym2; 3]) -> Sym2 {
    let sizes: Option<Vec<SizeTensor>> =
        m.iter().map(|x| SizeTensor::try_from_metric(x).ok()).collect();
    match sizes.and_then(|s| SizeTensor::log_euclidean_mean(s.iter().map(|t| (1.0 / 3.0, t)))) {
        Some(t) => t.to_metric(),
        None => (1.0 / 3.0) * (*m[0] + *m[1] + *m[2]),
    }
}

/// Shape quality of triangle `(a, b, c)` measured in the constant metric `m`:
/// 4√3·A_M / (l₁² + l₂² + l₃²) with every length and the area taken in `m`.
#[inline]
pub fn quality_in_metric(a: [f64; 2], b: [f64; 2], c: [f64; 2], m: &Sym2) -> f64 {
    let e = |p: [f64; 2], q: [f64; 2]| m.quadratic_form([q[0] - p[0], q[1] - p[1]]);
    let s = e(a, b) + e(b, c) + e(c, a);
    if s <= 0.0 {
        return 0.0;
    }
    let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    4.0 * 3f64.sqrt() * area * m.det().max(0.0).sqrt() / s
}

/// Metric quality of a triangle whose corners carry metrics `m`.
pub fn metric_triangle_quality(p: [[f64; 2]; 3], m: [&Sym2; 3]) -> f64 {
    quality_in_metric(p[0], p[1], p[2], &centroid_metric(m))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute-force twin: the metric length as a Simpson integral of √(eᵀ M(t) e) along the
    /// edge, with M(t) the Log-Euclidean interpolation of the end metrics.
    fn length_by_quadrature(a: [f64; 2], b: [f64; 2], ma: &Sym2, mb: &Sym2) -> f64 {
        let (sa, sb) =
            (SizeTensor::try_from_metric(ma).unwrap(), SizeTensor::try_from_metric(mb).unwrap());
        let e = [b[0] - a[0], b[1] - a[1]];
        let n = 2000;
        let f = |t: f64| {
            SizeTensor::log_euclidean_mean([(1.0 - t, &sa), (t, &sb)])
                .unwrap()
                .to_metric()
                .quadratic_form(e)
                .sqrt()
        };
        let h = 1.0 / n as f64;
        let mut s = f(0.0) + f(1.0);
        for i in 1..n {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * h);
        }
        s * h / 3.0
    }

    #[test]
    fn edge_length_matches_quadrature_for_isotropic_and_aligned_metrics() {
        // For metrics sharing their axes, the Log-Euclidean interpolation scales each
        // direction geometrically, so the closed form is exact along an axis.
        let a = [0.0, 0.0];
        let b = [1.0, 0.0];
        for (h0, h1) in [(1.0, 1.0), (0.1, 1.0), (1.0, 1e-3), (0.5, 0.50001)] {
            let ma = SizeTensor::isotropic(h0).to_metric();
            let mb = SizeTensor::isotropic(h1).to_metric();
            let exact = length_by_quadrature(a, b, &ma, &mb);
            let got = metric_edge_length(a, b, &ma, &mb);
            assert!((got - exact).abs() <= 1e-6 * exact, "{h0} {h1}: {got} vs {exact}");
        }
    }

    #[test]
    fn unit_equilateral_has_quality_one_and_length_one() {
        let m = Sym2::IDENTITY;
        let p = [[0.0, 0.0], [1.0, 0.0], [0.5, 3f64.sqrt() / 2.0]];
        assert!((metric_triangle_quality(p, [&m, &m, &m]) - 1.0).abs() < 1e-12);
        assert!((metric_edge_length(p[0], p[1], &m, &m) - 1.0).abs() < 1e-15);
    }
}
