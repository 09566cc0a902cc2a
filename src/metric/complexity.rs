//! How many vertices a metric asks for, before any of them is made: the metric's
//! complexity C = ∫ √det M over the domain (Loseille & Alauzet's continuous mesh
//! complexity), on plain points and triangles. A triangle of unit edges in the metric covers √3/4 of metric area, so a
//! mesh that conforms to M has about C/(√3/4) triangles and half as many vertices,
//! 2C/√3.
//!
//! The integral is exact for the field the remesher interpolates: between the input
//! vertices it takes the Log-Euclidean mean, exp(Σ λᵢ log Mᵢ), whose √det is
//! exp(½ Σ λᵢ tr log Mᵢ), the exponential of a linear function of the barycentric
//! coordinates. Its integral over a triangle of area A is 2A times the second divided
//! difference of exp at the three corner values (Hermite–Genocchi), evaluated below
//! without overflow or cancellation. A centroid rule would be wrong by orders of
//! magnitude exactly where it matters: one vertex asking for h = 10⁻⁶ among neighbours at
//! 10⁻¹.

use super::Sym2;

/// ½ ln det `m` for an SPD `m`, scaled so that entries up to f64's largest do not
/// overflow the determinant.
pub fn half_log_det(m: &Sym2) -> f64 {
    let s = m.a.abs().max(m.b.abs()).max(m.c.abs());
    if !(s > 0.0 && s.is_finite()) {
        return f64::NEG_INFINITY;
    }
    let (a, b, c) = (m.a / s, m.b / s, m.c / s);
    let d = (a * c - b * b).max(f64::MIN_POSITIVE);
    s.ln() + 0.5 * d.ln()
}

/// (eˣ − eʸ)/(x − y) for x ≥ y, without cancellation (eʸ when x = y).
fn divided_exp1(x: f64, y: f64) -> f64 {
    let d = x - y;
    if d > 0.0 {
        y.exp() * (d.exp_m1() / d)
    } else {
        y.exp()
    }
}

/// ∫ exp over a triangle of area `area` of the linear function with corner values `f`
/// (`ln` of the result, so that huge values stay representable).
pub fn log_integral_of_exp(area: f64, f: [f64; 3]) -> f64 {
    let mut f = f;
    f.sort_by(|x, y| y.total_cmp(x));
    let [f0, f1, f2] = f;
    if !(f0.is_finite() && f2.is_finite()) || area <= 0.0 {
        return if f0 == f64::INFINITY && area > 0.0 { f64::INFINITY } else { f64::NEG_INFINITY };
    }
    let (g1, g2) = (f1 - f0, f2 - f0);
    // Mean of exp(g) over the triangle, 2·exp[0, g1, g2]: with 0 ≥ g1 ≥ g2 the two first
    // differences are in (0, 1] and their difference is divided by at least 1e-6.
    let mean = if -g2 < 1e-6 {
        ((g1 + g2) / 3.0).exp()
    } else {
        2.0 * (divided_exp1(0.0, g1) - divided_exp1(g1, g2)) / -g2
    };
    area.ln() + f0 + mean.max(f64::MIN_POSITIVE).ln()
}

/// The complexity ∫ √det M over the triangles `tris` (either orientation) of `points`,
/// with M interpolated Log-Euclidean from the vertex metrics `half_log_dets` (½ ln det of
/// each vertex's metric, [`half_log_det`]). Infinite when it overflows.
pub fn complexity(points: &[[f64; 2]], tris: &[[usize; 3]], half_log_dets: &[f64]) -> f64 {
    let mut sum = 0.0;
    for t in tris {
        let [a, b, c] = t.map(|v| points[v]);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
        sum += log_integral_of_exp(area, t.map(|v| half_log_dets[v])).exp();
    }
    sum
}

/// The vertices of a mesh that conforms to a field of complexity `c`: 2c/√3.
pub fn vertices_of_complexity(c: f64) -> f64 {
    2.0 * c / 3f64.sqrt()
}

/// The expected vertex count of a remeshing of the triangles `tris` of `points` to
/// `metric` (one tensor per point), ignoring tensors no triangle uses.
pub fn expected_vertices(points: &[[f64; 2]], tris: &[[usize; 3]], metric: &[Sym2]) -> f64 {
    let f: Vec<f64> = metric.iter().map(half_log_det).collect();
    vertices_of_complexity(complexity(points, tris, &f))
}

/// Whether `estimate` is above `limit` (a NaN estimate, from a field no one could
/// measure, counts as above).
pub fn exceeds(estimate: f64, limit: usize) -> bool {
    estimate.is_nan() || estimate > limit as f64
}

/// A vertex count for a message: whole below a million, else three digits and a power of
/// ten; "more than 1e308" when it overflowed.
pub fn format_count(x: f64) -> String {
    if !x.is_finite() {
        "more than 1e308".to_string()
    } else if x < 1e6 {
        format!("{x:.0}")
    } else {
        format!("{x:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute-force twin: the triangle cut into n² similar triangles, exp at each centroid.
    fn by_subdivision(p: [[f64; 2]; 3], f: [f64; 3], n: usize) -> f64 {
        let at = |i: f64, j: f64| {
            let (u, v) = (i / n as f64, j / n as f64);
            let w = 1.0 - u - v;
            (
                [w * p[0][0] + u * p[1][0] + v * p[2][0], w * p[0][1] + u * p[1][1] + v * p[2][1]],
                w * f[0] + u * f[1] + v * f[2],
            )
        };
        let area = 0.5
            * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]))
                .abs();
        let small = area / (n * n) as f64;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n - i {
                let (i, j) = (i as f64, j as f64);
                sum += small * at(i + 1.0 / 3.0, j + 1.0 / 3.0).1.exp();
                if i + j + 2.0 <= n as f64 {
                    sum += small * at(i + 2.0 / 3.0, j + 2.0 / 3.0).1.exp();
                }
            }
        }
        sum
    }

    #[test]
    fn exact_integral_agrees_with_subdivision() {
        let p = [[0.0, 0.0], [0.3, 0.05], [0.1, 0.2]];
        for f in [
            [1.0, 1.0, 1.0],
            [1.0, 1.0 + 1e-9, 1.0 - 1e-9],
            [0.0, 2.0, -1.0],
            [5.0, 5.0, -3.0],
            [13.8, 2.3, 2.3],
            [-4.0, 3.0, 3.0 + 1e-8],
        ] {
            let exact = log_integral_of_exp(0.0275, f).exp();
            let brute = by_subdivision(p, f, 400);
            assert!((exact - brute).abs() <= 2e-3 * brute, "{f:?}: {exact} vs {brute}");
        }
    }

    #[test]
    fn one_tiny_size_dominates_and_nothing_overflows() {
        // h = 1e-6 at one corner among 0.1: the field grows geometrically away from it,
        // so the count is far above the centroid rule's and far below the corner's.
        let p = [[0.0, 0.0], [0.1, 0.0], [0.0, 0.1]];
        let f = [(1e12f64).ln(), (1e2f64).ln(), (1e2f64).ln()];
        let exact = log_integral_of_exp(0.005, f).exp();
        let brute = by_subdivision(p, f, 2000);
        assert!((exact - brute).abs() <= 0.05 * brute, "{exact} vs {brute}");
        assert!(exact > 100.0 * 0.005 * (f.iter().sum::<f64>() / 3.0).exp());
        // Entries of 1e300 give a determinant beyond f64, not a NaN: √det = 1e300.
        let huge = Sym2::new(1e300, 0.0, 1e300);
        assert!((half_log_det(&huge) - 300.0 * 10f64.ln()).abs() < 1e-9);
        let c = complexity(&p, &[[0, 1, 2]], &[half_log_det(&huge); 3]);
        assert!((c / 5e297 - 1.0).abs() < 1e-9, "{c}");
        assert_eq!(format_count(vertices_of_complexity(c)), "5.77e297");
        // Beyond f64: infinite, and said so.
        let c = complexity(&p, &[[0, 1, 2]], &[800.0; 3]);
        assert!(c.is_infinite() && c > 0.0);
        assert_eq!(format_count(vertices_of_complexity(c)), "more than 1e308");
    }

    #[test]
    fn a_uniform_field_counts_area_over_the_unit_triangle() {
        // h = 0.01 on the unit square: 10⁴ metric area, 2·10⁴/√3 vertices.
        let m = Sym2::new(1e4, 0.0, 1e4);
        let pts = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let n = expected_vertices(&pts, &[[0, 1, 2], [0, 2, 3]], &[m; 4]);
        assert!((n - 2e4 / 3f64.sqrt()).abs() < 1e-6 * n);
    }
}
