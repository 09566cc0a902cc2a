//! The Lp-optimal metric of the continuous mesh framework (Loseille & Alauzet, 2011):
//! the metric that minimises the Lp norm of the P1 interpolation error of a field of
//! Hessian H among metrics of a given complexity is, in 2D,
//!
//! M = D · det(|H|)^(−1/(2p+2)) · |H|,
//!
//! |H| the Hessian with its eigenvalues made absolute. The global factor D is the one
//! degree of freedom left; it is set by a target:
//!
//! - a vertex count N ([`Target::Vertices`]): the complexity C = ∫ √det M is what the
//!   remesher's estimate reads ([`crate::metric::complexity`]: a mesh conforming to M has
//!   about 2C/√3 vertices), computed exactly for the Log-Euclidean interpolation of the
//!   vertex metrics. Without bounds C is linear in D, so D is exact at once; with bounds
//!   (the clamp is monotone in D) D is found by bisection on ln D to 1e-4 relative;
//! - an interpolation error ε in the Lp norm ([`Target::Error`]): over a triangle whose
//!   edges have unit length in M, the mean of |u − Πu| for a quadratic u is
//!   tr(M^(−1/2) |H| M^(−1/2)) / 16 (the mean of λᵢλⱼ is 1/12 and Σ eeᵀ = (3/2) M⁻¹ for
//!   the three edges e), so the Lp error of the optimal metric is
//!   (1/(8D)) (∫ det|H|^(p/(2p+2)))^(1/p) and D follows in closed form. The bounds are
//!   applied after, and change the error a little where they act.
//!
//! Degenerate Hessians: each eigenvalue of |H| is floored at the larger of 1e-12 of the
//! largest over the mesh and λ_max/r² at its own vertex (r the maximum aspect ratio), so
//! det|H| > 0 and the anisotropy of M is at most r before the clamp. A field whose Hessian
//! is zero everywhere (a linear field: P1 interpolates it exactly) gets the identity, i.e.
//! a uniform mesh of the target's size.
//!
//! Bounds: sizes clamped to [h_min, h_max] and the aspect ratio to r
//! ([`SizeTensor::clamp`]). p is a real ≥ 1 or infinite (L∞: M = D |H|).
//!
//! Which p: p = 2 minimises the L2 norm of the error. The H1 seminorm (the gradient's
//! error, about h |H| in a cell of size h) asks for the density √det M ∝ |H| (for an
//! isotropic cell, |∇e|² h² ≈ h⁴ |H|² summed over the N ≈ 1/h² cells is least at fixed N
//! when h² |H| is constant), which is p = ∞; larger p also refines more at singularities.
//!
//! One normaliser for both dimensions: the functions here are generic over `LpSpace`
//! (`solution::lp_space`: the mesh, Hessian and tensor types of one dimension), with n
//! the dimension in the exponent −1/(2p+n), the complexity integrand and the vertex-count
//! guess D = (N / N(∫ …))^(2/n); [`lp_metric`] is n = 2, [`super::lp_metric3`] n = 3.

use crate::metric::{SizeBounds, SizeTensor, Sym2};
use crate::solution::lp_space::LpSpace;
use crate::solution::P1Mesh;

/// What the metric is normalised to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// About this many vertices in a mesh that conforms to it.
    Vertices(f64),
    /// This Lp norm of the interpolation error.
    Error(f64),
}

/// How the metric is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LpOptions {
    /// The norm, ≥ 1 or infinite; 2 by default in the CLI.
    pub p: f64,
    /// The normalisation.
    pub target: Target,
    /// h_min, h_max and the largest aspect ratio.
    pub bounds: SizeBounds,
}

/// The metric and how it came out, with size tensors `T` ([`LpMetric`] in the plane,
/// [`super::LpMetric3`] in space).
#[derive(Debug, Clone, PartialEq)]
pub struct LpMetricOf<T> {
    /// One size tensor per vertex.
    pub tensors: Vec<T>,
    /// The global factor D.
    pub scale: f64,
    /// The vertices a mesh conforming to `tensors` has (in 2D 2C/√3, C exact).
    pub vertices: f64,
    /// The predicted Lp interpolation error of the metric before the bounds act.
    pub predicted_error: f64,
    /// Whether the Hessian was zero everywhere (the metric is uniform).
    pub linear: bool,
}

/// The metric in the plane.
pub type LpMetric = LpMetricOf<SizeTensor>;

/// Why no metric could be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LpError {
    /// p must be at least 1.
    #[error("p = {0} is out of range: expected a number >= 1 (or infinity)")]
    P(f64),
    /// The target must be a finite positive number.
    #[error("the target {what} {value} is out of range: expected a finite number > 0")]
    Target {
        /// "vertex count" or "error".
        what: &'static str,
        /// As given.
        value: f64,
    },
    /// One Hessian per vertex is needed.
    #[error("{hessians} Hessians for {vertices} vertices")]
    Count {
        /// Hessians given.
        hessians: usize,
        /// Vertices of the mesh.
        vertices: usize,
    },
    /// A Hessian with a NaN or infinite entry.
    #[error("the Hessian at vertex {0} (0-based) is not finite")]
    NotFinite(usize),
    /// The mesh has no area.
    #[error("the mesh has no triangle of positive area")]
    NoArea,
    /// The mesh (of tetrahedra) has no volume.
    #[error("the mesh has no tetrahedron of positive volume")]
    NoVolume,
}

/// Per vertex: the axes of the |eigenvalues| (decreasing), ln of the floored
/// |eigenvalues|, and ln det|H|^(−1/(2p+n)); whether a cell uses the vertex.
pub(super) struct Prepared<const N: usize, M: LpSpace<N>> {
    pub(super) frame: Vec<M::Frame>,
    pub(super) ln_l: Vec<[f64; N]>,
    pub(super) ln_g: Vec<f64>,
    pub(super) used: Vec<bool>,
}

/// The Lp-optimal metric of `hessians` (one per vertex of `mesh`); see the module
/// documentation.
pub fn lp_metric(
    mesh: &P1Mesh<'_>,
    hessians: &[Sym2],
    options: &LpOptions,
) -> Result<LpMetric, LpError> {
    lp_metric_in(mesh, hessians, options)
}

/// [`lp_metric`] in any dimension (in space [`super::lp_metric3`]).
pub(super) fn lp_metric_in<const N: usize, M: LpSpace<N>>(
    mesh: &M,
    hessians: &[M::Hessian],
    options: &LpOptions,
) -> Result<LpMetricOf<M::Tensor>, LpError> {
    let p = options.p;
    let cells = check(mesh, hessians, options)?;
    let prepared = prepare(mesh, hessians, p, options.bounds.max_aspect_ratio());
    let field = |ln_d: f64| -> (Vec<M::Tensor>, f64) {
        let tensors = tensors_at(&prepared, ln_d, &options.bounds);
        let v = vertices_in(mesh, &cells, &tensors);
        (tensors, v)
    };
    let integral = integral(mesh, &prepared, &cells);
    let ln_d = match options.target {
        Target::Error(_) => unbounded_ln_d::<N, M>(integral, p, options.target),
        Target::Vertices(target) => {
            let guess = unbounded_ln_d::<N, M>(integral, p, options.target);
            solve(guess, target, |x| field(x).1)
        }
    };
    let (tensors, vertices) = field(ln_d);
    Ok(LpMetricOf {
        tensors,
        scale: ln_d.exp(),
        vertices,
        predicted_error: M::error_of(integral, p, ln_d),
        linear: is_linear(mesh, hessians),
    })
}

/// ∫ det|H|^(p/(2p+n)): the complexity of the unbounded metric of `prepared` at D = 1.
pub(super) fn integral<const N: usize, M: LpSpace<N>>(
    mesh: &M,
    prepared: &Prepared<N, M>,
    cells: &[M::Cell],
) -> f64 {
    let f1: Vec<f64> = (0..prepared.ln_g.len())
        .map(|i| M::unit_half_log_det(prepared.ln_g[i], &prepared.ln_l[i]))
        .collect();
    mesh.complexity(cells, &f1)
}

/// The ln D that meets `target` without bounds, for a field of [`integral`] `integral`:
/// exact for an error; for a vertex count, the guess the bounded solve starts from (exact
/// where no bound acts: C = D^(n/2) ∫ …).
pub(super) fn unbounded_ln_d<const N: usize, M: LpSpace<N>>(
    integral: f64,
    p: f64,
    target: Target,
) -> f64 {
    match target {
        Target::Error(e) => {
            let root_ln = if p.is_infinite() { 0.0 } else { integral.ln() / p };
            M::ln_d_of_error(root_ln, e)
        }
        Target::Vertices(n) => 2.0 / N as f64 * (n / M::vertices_of_complexity(integral)).ln(),
    }
}

/// The predicted Lp interpolation error at D = exp(`ln_d`) of a planar field of
/// [`integral`] `integral`, before the bounds act.
pub(super) fn error_of(integral: f64, p: f64, ln_d: f64) -> f64 {
    <P1Mesh<'_> as LpSpace<2>>::error_of(integral, p, ln_d)
}

/// Refuses a p, a target, a Hessian count or a Hessian that is out of range, and a mesh
/// without area (volume); the cells.
pub(super) fn check<const N: usize, M: LpSpace<N>>(
    mesh: &M,
    hessians: &[M::Hessian],
    options: &LpOptions,
) -> Result<Vec<M::Cell>, LpError> {
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
    let n = mesh.num_points();
    if hessians.len() != n {
        return Err(LpError::Count { hessians: hessians.len(), vertices: n });
    }
    if let Some(v) = hessians.iter().position(|h| !M::is_finite(h)) {
        return Err(LpError::NotFinite(v));
    }
    let cells = mesh.cells();
    let measure = mesh.complexity(&cells, &vec![0.0; n]);
    if measure.is_nan() || measure <= 0.0 {
        return Err(if N == 2 { LpError::NoArea } else { LpError::NoVolume });
    }
    Ok(cells)
}

/// Whether the Hessian is zero at every vertex a cell uses.
pub(super) fn is_linear<const N: usize, M: LpSpace<N>>(mesh: &M, hessians: &[M::Hessian]) -> bool {
    (0..hessians.len()).filter(|&v| mesh.is_used(v)).all(|v| M::is_zero(&hessians[v]))
}

pub(super) fn prepare<const N: usize, M: LpSpace<N>>(
    mesh: &M,
    hessians: &[M::Hessian],
    p: f64,
    max_aspect: f64,
) -> Prepared<N, M> {
    let n = hessians.len();
    let used: Vec<bool> = (0..n).map(|v| mesh.is_used(v)).collect();
    let eig: Vec<([f64; N], M::Frame)> = hessians.iter().map(M::abs_eigen).collect();
    let largest = (0..n).filter(|&v| used[v]).map(|v| eig[v].0[0]).fold(0.0f64, f64::max);
    let global_floor = if largest > 0.0 { 1e-12 * largest } else { 1.0 };
    let aspect2 = if max_aspect.is_finite() { max_aspect * max_aspect } else { f64::INFINITY };
    let exponent = if p.is_infinite() { 0.0 } else { 1.0 / (2.0 * p + N as f64) };
    let mut prepared = Prepared {
        frame: Vec::with_capacity(n),
        ln_l: Vec::with_capacity(n),
        ln_g: Vec::with_capacity(n),
        used,
    };
    for (mut values, frame) in eig {
        // The largest keeps its value: l0 / r² <= l0 as r >= 1.
        let l0 = values[0].max(global_floor);
        values[0] = l0;
        let ln_l = values.map(|l| l.max(global_floor).max(l0 / aspect2).ln());
        prepared.frame.push(frame);
        prepared.ln_g.push(-exponent * ln_l.iter().sum::<f64>());
        prepared.ln_l.push(ln_l);
    }
    prepared
}

/// The unbounded tensor of vertex `v` at D = exp(`ln_d`) (sizes within
/// [`SizeTensor::MIN_SIZE`], [`SizeTensor::MAX_SIZE`]); `None` for a vertex no cell
/// uses or a tensor that cannot be made.
pub(super) fn raw_tensor<const N: usize, M: LpSpace<N>>(
    prepared: &Prepared<N, M>,
    v: usize,
    ln_d: f64,
) -> Option<M::Tensor> {
    if !prepared.used[v] {
        return None;
    }
    let base = ln_d + prepared.ln_g[v];
    let h = prepared.ln_l[v]
        .map(|l| (-0.5 * (base + l)).exp().clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE));
    M::tensor(prepared.frame[v], h)
}

/// The bounded tensors at D = exp(`ln_d`); h_max isotropic where no cell is.
fn tensors_at<const N: usize, M: LpSpace<N>>(
    prepared: &Prepared<N, M>,
    ln_d: f64,
    bounds: &SizeBounds,
) -> Vec<M::Tensor> {
    let outside = M::isotropic(bounds.h_max());
    (0..prepared.frame.len())
        .map(|v| raw_tensor(prepared, v, ln_d).map_or(outside, |t| M::clamp(&t, bounds)))
        .collect()
}

/// The vertices a mesh conforming to `tensors` (one per vertex of `mesh`, whose cells
/// are `cells`) has: that of the exact complexity of their Log-Euclidean interpolation.
pub(super) fn vertices_in<const N: usize, M: LpSpace<N>>(
    mesh: &M,
    cells: &[M::Cell],
    tensors: &[M::Tensor],
) -> f64 {
    let f: Vec<f64> =
        tensors.iter().map(|t| -M::sizes(t).iter().map(|h| h.ln()).sum::<f64>()).collect();
    M::vertices_of_complexity(mesh.complexity(cells, &f))
}

/// The ln D at which the nondecreasing `vertices` reaches `target`, from `guess`: a
/// bracket grown by factors of 4, then bisection to 1e-4 relative. When the bounds keep
/// the count from reaching the target, the end of the range nearest to it.
pub(super) fn solve(guess: f64, target: f64, vertices: impl Fn(f64) -> f64) -> f64 {
    let step = 4f64.ln();
    let at = vertices(guess);
    if (at / target - 1.0).abs() < 1e-4 {
        return guess;
    }
    let (mut lo, mut hi) = (guess, guess);
    if at < target {
        let mut prev = at;
        loop {
            lo = hi;
            hi += step;
            let v = vertices(hi);
            if v >= target {
                break;
            }
            if v <= prev * (1.0 + 1e-12) && hi > guess + 40.0 * step {
                return hi;
            }
            prev = v;
        }
    } else {
        let mut prev = at;
        loop {
            hi = lo;
            lo -= step;
            let v = vertices(lo);
            if v <= target {
                break;
            }
            if v >= prev * (1.0 - 1e-12) && lo < guess - 40.0 * step {
                return lo;
            }
            prev = v;
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        let v = vertices(mid);
        if (v / target - 1.0).abs() < 1e-4 {
            return mid;
        }
        if v < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The vertices a mesh conforming to `tensors` (one per vertex of `mesh`) has, 2C/√3
/// with C the exact complexity of their Log-Euclidean interpolation.
pub fn vertices_of(mesh: &P1Mesh<'_>, tensors: &[SizeTensor]) -> f64 {
    vertices_in(mesh, &mesh.cells(), tensors)
}

/// `fields` combined in order by intersection (thesis 3.2.2): at each vertex the
/// largest ellipse inside all of them, so in every direction no larger than the smallest
/// size asked there. `None` for no field or fields of different lengths.
pub fn intersect_all(fields: &[Vec<SizeTensor>]) -> Option<Vec<SizeTensor>> {
    let (first, rest) = fields.split_first()?;
    if rest.iter().any(|f| f.len() != first.len()) {
        return None;
    }
    let mut out = first.clone();
    for f in rest {
        for (o, t) in out.iter_mut().zip(f) {
            *o = o.intersection(t);
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests;
