//! How many vertices a 3D metric asks for: its complexity C = ∫ √det M over tetrahedra
//! (the 3D counterpart of [`super::complexity`], whose header gives the argument).
//!
//! Exactness: with M the Log-Euclidean mean exp(Σ λᵢ log Mᵢ) of the corners' metrics,
//! √det M = exp(½ Σ λᵢ tr log Mᵢ) is the exponential of a linear function of the
//! barycentric coordinates, and by Hermite–Genocchi its mean over a tetrahedron is
//! 3!·exp[f₀, f₁, f₂, f₃], the third divided difference of exp at the corner values. It is
//! evaluated shifted by the largest value (no overflow), recursively on sorted nodes where
//! they spread by 1 or more (each step divides by at least 1, so rounding grows at most
//! threefold per level) and by the Taylor series Σₖ hₖ(d)/(n+k)! about their midpoint
//! where they cluster (|dᵢ| ≤ ½: no cancellation, 24 terms reach rounding).
//!
//! The vertex count: a regular tetrahedron of unit edge has volume √2/12, so a mesh unit
//! in M has about C/(√2/12) = 6√2·C tetrahedra, and [`TETS_PER_VERTEX`] of them per
//! vertex. That ratio was measured on `mmg3d_O3 box_cyl_input.mesh -hsiz h` (the public
//! fixture, a 2×1×1 box with a cylinder cut out, adapted to a constant metric): h = 0.1:
//! 4446 vertices, 21791 tetrahedra (4.90); h = 0.05: 30264, 163522 (5.40); h = 0.035:
//! 83103, 467716 (5.63). It grows with the mesh as the boundary's share shrinks; 5.6 is
//! taken, the figure of meshes of 10⁴–10⁵ vertices. MMG's tetrahedra are not regular, so
//! it makes about 1.25 times the count this predicts (measured in tests/complexity3.rs).

use super::Sym3;

/// Tetrahedra per vertex of a unit mesh (measured with mmg3d, see the module header).
pub const TETS_PER_VERTEX: f64 = 5.6;

/// ½ ln det `m` for an SPD `m`, from its eigenvalues (exact on graded tensors, where the
/// determinant of the entries would cancel); −∞ for a tensor that is not SPD or finite.
pub fn half_log_det3(m: &Sym3) -> f64 {
    if !m.is_finite() {
        return f64::NEG_INFINITY;
    }
    let values = m.eigen().values;
    // NaN eigenvalues fall here too.
    if values[2].is_nan() || values[2] <= 0.0 {
        return f64::NEG_INFINITY;
    }
    0.5 * values.iter().map(|v| v.ln()).sum::<f64>()
}

/// exp[x₀, …, xₙ], the divided difference of exp at `x` (sorted decreasing, x₀ ≤ 0 so
/// that nothing overflows).
fn divided_exp(x: &[f64]) -> f64 {
    let n = x.len() - 1;
    let spread = x[0] - x[n];
    if n == 0 {
        return x[0].exp();
    }
    if spread >= 1.0 {
        return (divided_exp(&x[..n]) - divided_exp(&x[1..])) / spread;
    }
    // Taylor series about the midpoint c: exp[x] = e^c Σₖ hₖ(x − c)/(n+k)!, hₖ the
    // complete homogeneous symmetric polynomials, built one variable at a time.
    let c = 0.5 * (x[0] + x[n]);
    const TERMS: usize = 24;
    let mut h = [0.0; TERMS];
    h[0] = 1.0;
    for &xi in x {
        let d = xi - c;
        for k in 1..TERMS {
            h[k] += d * h[k - 1];
        }
    }
    let mut factorial: f64 = (1..=n).map(|i| i as f64).product();
    let mut sum = 0.0;
    for (k, hk) in h.iter().enumerate() {
        if k > 0 {
            factorial *= (n + k) as f64;
        }
        sum += hk / factorial;
    }
    c.exp() * sum
}

/// ln ∫ exp over a tetrahedron of volume `volume` of the linear function with corner
/// values `f` (the logarithm, so that huge values stay representable).
pub fn log_integral_of_exp3(volume: f64, f: [f64; 4]) -> f64 {
    let mut f = f;
    f.sort_by(|x, y| y.total_cmp(x));
    if !(f[0].is_finite() && f[3].is_finite()) || volume <= 0.0 {
        return if f[0] == f64::INFINITY && volume > 0.0 {
            f64::INFINITY
        } else {
            f64::NEG_INFINITY
        };
    }
    let g = f.map(|x| x - f[0]);
    let mean = 6.0 * divided_exp(&g);
    volume.ln() + f[0] + mean.max(f64::MIN_POSITIVE).ln()
}

/// The volume of the tetrahedron `t` of `points` (either orientation).
fn volume(points: &[[f64; 3]], t: &[usize; 4]) -> f64 {
    let [a, b, c, d] = t.map(|v| points[v]);
    let e = |p: [f64; 3]| [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let (u, v, w) = (e(b), e(c), e(d));
    let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0]);
    det.abs() / 6.0
}

/// The complexity ∫ √det M over the tetrahedra `tets` of `points`, M interpolated
/// Log-Euclidean from the vertex values `half_log_dets` ([`half_log_det3`]). Infinite
/// when it overflows.
pub fn complexity3(points: &[[f64; 3]], tets: &[[usize; 4]], half_log_dets: &[f64]) -> f64 {
    tets.iter()
        .map(|t| log_integral_of_exp3(volume(points, t), t.map(|v| half_log_dets[v])).exp())
        .sum()
}

/// The vertices of a unit mesh of a 3D field of complexity `c`: 6√2·c tetrahedra,
/// [`TETS_PER_VERTEX`] per vertex.
pub fn vertices_of_complexity3(c: f64) -> f64 {
    6.0 * 2f64.sqrt() * c / TETS_PER_VERTEX
}

/// The expected vertex count of a remeshing of the tetrahedra `tets` of `points` to
/// `metric` (one tensor per point).
pub fn expected_vertices3(points: &[[f64; 3]], tets: &[[usize; 4]], metric: &[Sym3]) -> f64 {
    let f: Vec<f64> = metric.iter().map(half_log_det3).collect();
    vertices_of_complexity3(complexity3(points, tets, &f))
}

#[cfg(test)]
#[path = "complexity3_twins.rs"]
mod twins;
