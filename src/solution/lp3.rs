//! The Lp-optimal metric in space: the 3D counterpart of [`super::lp`] (whose header
//! gives the framework), on tetrahedra with Hessians [`Sym3`]. In n dimensions the metric
//! that minimises the Lp norm of the P1 interpolation error of a field of Hessian H among
//! metrics of a given complexity is (Loseille & Alauzet, "Continuous mesh framework",
//! SIAM J. Numer. Anal. 49, 2011, part II, eq. for M_Lp)
//!
//! M = D · det(|H|)^(−1/(2p+n)) · |H|,  here n = 3: exponent −1/(2p+3),
//!
//! and its complexity C = ∫ √det M = D^(3/2) ∫ det(|H|)^(p/(2p+3)) (the 2D code's
//! C = D ∫ det(|H|)^(p/(2p+2)) with n = 2), so that D = (C / ∫ det|H|^(p/(2p+3)))^(2/3),
//! their D_Lp = N^(2/n) (∫ det|H|^(p/(2p+n)))^(−2/n) with N = C.
//!
//! - A vertex count N ([`Target::Vertices`]): C = N / (6√2 / [`TETS_PER_VERTEX`](crate::metric::complexity3::TETS_PER_VERTEX))
//!   ([`vertices_of_complexity3`]), computed exactly for the Log-Euclidean interpolation
//!   of the vertex metrics ([`complexity3`]); D exact at once without bounds, by the 2D
//!   code's bisection on ln D to 1e-4 relative with them.
//! - An error ε ([`Target::Error`]): over a tetrahedron whose edges have unit length in
//!   M, the mean of |u − Πu| for a quadratic u is tr(M^(−1/2) |H| M^(−1/2)) / 20 (u − Πu =
//!   −½ Σ λᵢλⱼ eᵢⱼᵀ H eᵢⱼ over the six edges, the mean of λᵢλⱼ is 1/20, and Σ eeᵀ = 2 M⁻¹
//!   over the edges of a regular unit tetrahedron; in 2D 1/12 and 3/2 give the 1/16 of
//!   [`super::lp`]). For the optimal metric that trace is 3/(D det|H|^(−1/(2p+3))), so
//!   the Lp error is (3/(20 D)) (∫ det|H|^(p/(2p+3)))^(1/p) and D follows in closed form;
//!   the bounds act after.
//!
//! Degenerate Hessians as in 2D: each |eigenvalue| floored at the larger of 1e-12 of the
//! largest over the mesh and λ_max/r² at its vertex (r the largest aspect ratio); a
//! Hessian zero everywhere gives the uniform metric of the target. Bounds: sizes clamped
//! to [h_min, h_max] and the aspect ratio to r ([`SizeTensor3::clamp`]).

use crate::metric::complexity3::{complexity3, vertices_of_complexity3};
use crate::metric::{SizeBounds, SizeTensor, SizeTensor3, Sym3};
use crate::solution::lp::solve;
use crate::solution::{LpError, LpOptions, P1Mesh3, Target};

/// The metric in space and how it came out.
#[derive(Debug, Clone, PartialEq)]
pub struct LpMetric3 {
    /// One size tensor per vertex.
    pub tensors: Vec<SizeTensor3>,
    /// The global factor D.
    pub scale: f64,
    /// The vertices a mesh conforming to `tensors` has ([`vertices_of_complexity3`] of
    /// the exact complexity).
    pub vertices: f64,
    /// The predicted Lp interpolation error of the metric before the bounds act.
    pub predicted_error: f64,
    /// Whether the Hessian was zero everywhere (the metric is uniform).
    pub linear: bool,
}

/// Per vertex: the frame of the |eigenvalues| (decreasing), ln of the floored
/// |eigenvalues|, and ln det|H|^(−1/(2p+3)).
struct Prepared {
    frame: Vec<[[f64; 3]; 3]>,
    ln_l: Vec<[f64; 3]>,
    ln_g: Vec<f64>,
    used: Vec<bool>,
}

/// The Lp-optimal metric of `hessians` (one per vertex of `mesh`); see the module
/// documentation.
pub fn lp_metric3(
    mesh: &P1Mesh3<'_>,
    hessians: &[Sym3],
    options: &LpOptions,
) -> Result<LpMetric3, LpError> {
    let p = options.p;
    let tets = check(mesh, hessians, options)?;
    let points = mesh.points();
    let prepared = prepare(mesh, hessians, p, options.bounds.max_aspect_ratio());
    let field = |ln_d: f64| -> (Vec<SizeTensor3>, f64) {
        let tensors = tensors_at(&prepared, ln_d, &options.bounds);
        let f: Vec<f64> = tensors.iter().map(half_log_det).collect();
        (tensors, vertices_of_complexity3(complexity3(points, &tets, &f)))
    };
    // ∫ det|H|^(p/(2p+3)): the complexity at D = 1 without bounds.
    let f1: Vec<f64> = (0..hessians.len())
        .map(|v| 0.5 * (3.0 * prepared.ln_g[v] + prepared.ln_l[v].iter().sum::<f64>()))
        .collect();
    let integral = complexity3(points, &tets, &f1);
    let root_ln = if p.is_infinite() { 0.0 } else { integral.ln() / p };
    let ln_d = match options.target {
        Target::Error(e) => root_ln + (3.0 / 20.0f64).ln() - e.ln(),
        Target::Vertices(n) => {
            let guess = 2.0 / 3.0 * (n / vertices_of_complexity3(integral)).ln();
            solve(guess, n, |x| field(x).1)
        }
    };
    let (tensors, vertices) = field(ln_d);
    let linear =
        (0..hessians.len()).filter(|&v| prepared.used[v]).all(|v| hessians[v] == Sym3::ZERO);
    Ok(LpMetric3 {
        tensors,
        scale: ln_d.exp(),
        vertices,
        predicted_error: (root_ln + (3.0 / 20.0f64).ln() - ln_d).exp(),
        linear,
    })
}

/// ½ ln det of the metric of `t`: −Σ ln hᵢ.
fn half_log_det(t: &SizeTensor3) -> f64 {
    -t.sizes().iter().map(|h| h.ln()).sum::<f64>()
}

/// Refuses what [`super::lp`] refuses, and a mesh without volume; the tetrahedra with
/// `usize` corners.
fn check(
    mesh: &P1Mesh3<'_>,
    hessians: &[Sym3],
    options: &LpOptions,
) -> Result<Vec<[usize; 4]>, LpError> {
    let p = options.p;
    if p.is_nan() || p < 1.0 {
        return Err(LpError::P(p));
    }
    let (what, value) = match options.target {
        Target::Vertices(n) => ("vertex count", n),
        Target::Error(e) => ("error", e),
    };
    if !(value.is_finite() && value > 0.0) {
        return Err(LpError::Target { what, value });
    }
    let n = mesh.points().len();
    if hessians.len() != n {
        return Err(LpError::Count { hessians: hessians.len(), vertices: n });
    }
    if let Some(v) = hessians.iter().position(|h| !h.is_finite()) {
        return Err(LpError::NotFinite(v));
    }
    let tets: Vec<[usize; 4]> = mesh.tets().iter().map(|t| t.map(|v| v as usize)).collect();
    let volume = complexity3(mesh.points(), &tets, &vec![0.0; n]);
    if volume.is_nan() || volume <= 0.0 {
        return Err(LpError::NoVolume);
    }
    Ok(tets)
}

fn prepare(mesh: &P1Mesh3<'_>, hessians: &[Sym3], p: f64, max_aspect: f64) -> Prepared {
    let n = hessians.len();
    let used: Vec<bool> = (0..n).map(|v| mesh.is_used(v)).collect();
    // |eigenvalues| in decreasing order with their vectors.
    let eig: Vec<([f64; 3], [[f64; 3]; 3])> = hessians
        .iter()
        .map(|h| {
            let e = h.eigen();
            let mut order = [0, 1, 2];
            order.sort_by(|&i, &j| e.values[j].abs().total_cmp(&e.values[i].abs()));
            (order.map(|i| e.values[i].abs()), order.map(|i| e.frame[i]))
        })
        .collect();
    let largest = (0..n).filter(|&v| used[v]).map(|v| eig[v].0[0]).fold(0.0f64, f64::max);
    let global_floor = if largest > 0.0 { 1e-12 * largest } else { 1.0 };
    let aspect2 = if max_aspect.is_finite() { max_aspect * max_aspect } else { f64::INFINITY };
    let exponent = if p.is_infinite() { 0.0 } else { 1.0 / (2.0 * p + 3.0) };
    let mut prepared = Prepared {
        frame: Vec::with_capacity(n),
        ln_l: Vec::with_capacity(n),
        ln_g: Vec::with_capacity(n),
        used,
    };
    for (values, frame) in eig {
        let l0 = values[0].max(global_floor);
        let ln_l = [l0, values[1], values[2]].map(|l| l.max(global_floor).max(l0 / aspect2).ln());
        prepared.frame.push(frame);
        prepared.ln_g.push(-exponent * ln_l.iter().sum::<f64>());
        prepared.ln_l.push(ln_l);
    }
    prepared
}

/// The bounded tensors at D = exp(`ln_d`); h_max isotropic where no tetrahedron is.
fn tensors_at(prepared: &Prepared, ln_d: f64, bounds: &SizeBounds) -> Vec<SizeTensor3> {
    let outside = SizeTensor3::isotropic(bounds.h_max());
    (0..prepared.frame.len())
        .map(|v| {
            if !prepared.used[v] {
                return outside;
            }
            let base = ln_d + prepared.ln_g[v];
            let h = prepared.ln_l[v].map(|l| {
                (-0.5 * (base + l)).exp().clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE)
            });
            let [e0, e1, _] = prepared.frame[v];
            SizeTensor3::try_new(e0, e1, h).map_or(outside, |t| t.clamp(bounds))
        })
        .collect()
}

/// The vertices a mesh conforming to `tensors` (one per vertex of `mesh`) has.
pub fn vertices_of3(mesh: &P1Mesh3<'_>, tensors: &[SizeTensor3]) -> f64 {
    let tets: Vec<[usize; 4]> = mesh.tets().iter().map(|t| t.map(|v| v as usize)).collect();
    let f: Vec<f64> = tensors.iter().map(half_log_det).collect();
    vertices_of_complexity3(complexity3(mesh.points(), &tets, &f))
}

#[cfg(test)]
mod tests;
