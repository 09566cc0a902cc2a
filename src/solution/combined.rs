//! Several solution fields in one metric: the Lp-optimal metrics of fields u₁ … u_k
//! (say a velocity component and the pressure), each made as [`crate::solution::lp`]
//! makes one, combined by intersection and normalised together.
//!
//! Fields have their own units and magnitudes, so their Hessians are not compared
//! directly. Each field's metric Mᵢ = Dᵢ det(|Hᵢ|)^(−1/(2p+2)) |Hᵢ| gets its own factor
//! Dᵢ from the target alone, without bounds: for a vertex count N, the Dᵢ at which Mᵢ
//! alone asks for N vertices; for an error ε, the Dᵢ at which field i's predicted Lp
//! error is ε. The normalised metrics are intersected at each vertex in the order given
//! (thesis 3.2.2: the largest ellipse inside all of them), so in every direction the
//! result is no larger than any field asks.
//!
//! - For an error target that is the metric: every field meets ε (the intersection is
//!   finer than each), then the bounds clamp it.
//! - For a vertex count the intersection asks for more than N (up to kN), so it is scaled
//!   as a whole: M = s · (M₁ ∩ … ∩ M_k), clamped by the bounds, with s found by the same
//!   bisection as one field's (the clamp is monotone in s), to N within 1e-4 relative.
//!   Scaling commutes with the intersection (s M₁ ∩ s M₂ = s (M₁ ∩ M₂)), so every field
//!   keeps its share: at each vertex the result is the intersection of s Dᵢ Mᵢ.
//!
//! A field whose Hessian is zero everywhere (linear: P1 interpolates it exactly) asks
//! nothing and is left out, unless every field is linear (then the uniform metric of one).
//! One field gives exactly [`lp_metric`]'s result.
//!
//! The reported `scale` is s (1 for an error target); `predicted_error` the largest over
//! the fields of the error bound s Dᵢ gives each (each field is at least that fine).

use crate::metric::{SizeTensor, Sym2};
use crate::solution::lp::{
    check, error_of, integral, is_linear, prepare, raw_tensor, solve, unbounded_ln_d, vertices_in,
    Prepared,
};
use crate::solution::lp_space::LpSpace;
use crate::solution::{lp_metric, LpError, LpMetric, LpOptions, P1Mesh, Target};

/// The metric of the fields of Hessians `hessians` (one slice per field, one Hessian per
/// vertex of `mesh` each), normalised together; see the module documentation. An error
/// names the field by its index.
pub fn lp_metric_of_fields(
    mesh: &P1Mesh<'_>,
    hessians: &[&[Sym2]],
    options: &LpOptions,
) -> Result<LpMetric, (usize, LpError)> {
    for (i, h) in hessians.iter().enumerate() {
        check(mesh, h, options).map_err(|e| (i, e))?;
    }
    let asking: Vec<usize> =
        (0..hessians.len()).filter(|&i| !is_linear(mesh, hessians[i])).collect();
    match asking.as_slice() {
        [] if hessians.is_empty() => {
            return Err((0, LpError::Count { hessians: 0, vertices: mesh.points().len() }))
        }
        [] => return lp_metric(mesh, hessians[0], options).map_err(|e| (0, e)),
        &[one] => return lp_metric(mesh, hessians[one], options).map_err(|e| (one, e)),
        _ => {}
    }
    let p = options.p;
    let bounds = &options.bounds;
    let tris = mesh.cells();
    let points = mesh.points();
    let n = points.len();
    let fields: Vec<(Prepared<2, P1Mesh<'_>>, f64, f64)> = asking
        .iter()
        .map(|&i| {
            let prepared = prepare(mesh, hessians[i], p, bounds.max_aspect_ratio());
            let integral = integral(mesh, &prepared, &tris);
            let ln_d = unbounded_ln_d::<2, P1Mesh<'_>>(integral, p, options.target);
            (prepared, integral, ln_d)
        })
        .collect();
    // The normalised fields intersected in order; `None` where no triangle is.
    let together: Vec<Option<SizeTensor>> = (0..n)
        .map(|v| {
            let mut it = fields.iter().map(|(f, _, ln_d)| raw_tensor(f, v, *ln_d));
            let first = it.next()??;
            it.try_fold(first, |acc, t| Some(acc.intersection(&t?)))
        })
        .collect();
    let outside = SizeTensor::isotropic(bounds.h_max());
    let scaled = |ln_s: f64| -> Vec<SizeTensor> {
        let factor = (-0.5 * ln_s).exp();
        together
            .iter()
            .map(|t| match t {
                Some(t) => SizeTensor::try_new(
                    t.axis(),
                    (t.h1() * factor).clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE),
                    (t.h2() * factor).clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE),
                )
                .map_or(outside, |t| t.clamp(bounds)),
                None => outside,
            })
            .collect()
    };
    let vertices = |tensors: &[SizeTensor]| vertices_in(mesh, &tris, tensors);
    let ln_s = match options.target {
        Target::Error(_) => 0.0,
        Target::Vertices(target) => {
            // Unused vertices weigh nothing in the complexity; any tensor will do.
            let at_one: Vec<SizeTensor> =
                together.iter().map(|t| t.unwrap_or(SizeTensor::isotropic(1.0))).collect();
            let guess = (target / vertices(&at_one)).ln();
            solve(guess, target, |x| vertices(&scaled(x)))
        }
    };
    let tensors = scaled(ln_s);
    let predicted_error = fields
        .iter()
        .map(|(_, integral, ln_d)| error_of(*integral, p, ln_d + ln_s))
        .fold(0.0f64, f64::max);
    Ok(LpMetric {
        vertices: vertices(&tensors),
        tensors,
        scale: ln_s.exp(),
        predicted_error,
        linear: false,
    })
}

#[cfg(test)]
mod tests;
