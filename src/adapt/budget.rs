//! The vertex budget of `adapt --complexity N`: the final field on a mesh (the recipe's,
//! the solution's, or both intersected) scaled as a whole so that a mesh conforming to
//! it has N vertices, with the bounds and the gradation applied inside the scaling.
//!
//! The field is given raw: the recipe's steps and the solution's metric intersected,
//! before the recipe's global h_min, maximum aspect ratio and gradation (its h_max stays
//! the size of the vertices no step reaches). For a factor s on the metric (sizes times
//! s^(−1/2)) the field is
//!
//!   F(s) = grade(clamp(s · raw)),
//!
//! clamp to [h_min, h_max] and the aspect ratio ([`SizeTensor::clamp`]), then the
//! gradation pass when there is one ([`apply_gradation`]). Its complexity V(s) (the
//! vertices a conforming mesh has, 2C/√3 with C exact for the Log-Euclidean
//! interpolation, [`crate::metric::complexity`]) is continuous and nondecreasing in s:
//! scaling and the clamp are monotone per vertex, and the gradation only shrinks, more
//! where the tensors it grows from are smaller. So s is the root of the 1D monotone
//! equation V(s) = N, found on ln s: bracketed from the unbounded guess (exact where no
//! bound acts, V being linear in s), then the Illinois variant of regula falsi on
//! ln V − ln N to 1e-12 relative. The bounds can therefore not break the budget: they
//! act inside the function whose root is taken. Only when N is out of reach — more than
//! the uniform field at h_min asks, or fewer than at h_max — the nearest end is returned
//! and [`Budgeted::reached`] is false.
//!
//! Scaling commutes with the intersection (s A ∩ s B = s (A ∩ B)), so the recipe and the
//! solution share the budget in the proportions the raw field gives them, instead of the
//! recipe's vertices coming on top of a solution metric already normalised to N.

use smartmesh_formats::TaggedMesh;

use crate::mesh_graph::MeshGraph;
use crate::metric::complexity::{complexity, vertices_of_complexity};
use crate::metric::{SizeBounds, SizeTensor};
use crate::metric_field::planar_triangles;
use crate::recipe::Recipe;
use crate::sizing::gradation::apply_gradation;

/// A recipe made to give the raw field, and the limits its globals put on the
/// normalisation instead.
#[derive(Debug, Clone)]
pub struct RawRecipe {
    /// The recipe without its global h_min, maximum aspect ratio and gradation (its h_max
    /// stays: the size of the vertices no step reaches, and the largest size).
    pub recipe: Recipe,
    /// The recipe's h_min, h_max and aspect ratio (none: the widest range).
    pub bounds: SizeBounds,
    /// The recipe's gradation.
    pub gradation: Option<f64>,
}

impl RawRecipe {
    /// `recipe` split in its raw part and its limits; `None` when its global bounds are
    /// no range (the sizing engine then says why).
    pub fn of(recipe: &Recipe) -> Option<RawRecipe> {
        let g = &recipe.global;
        let bounds = SizeBounds::try_new(
            g.h_min.unwrap_or(SizeTensor::MIN_SIZE),
            g.h_max.unwrap_or(SizeTensor::MAX_SIZE),
            g.max_aspect_ratio.unwrap_or(f64::INFINITY),
        )?;
        let mut raw = recipe.clone();
        raw.global.h_min = None;
        raw.global.max_aspect_ratio = None;
        raw.global.gradation = None;
        Some(RawRecipe { recipe: raw, bounds, gradation: g.gradation })
    }
}

/// The vertex budget of a run: the vertex count asked of the mesh at each iteration.
#[derive(Debug, Clone, PartialEq)]
pub struct Budget {
    /// The count at iteration k (a constant one: start = target).
    pub schedule: crate::adapt::solver::Schedule,
    /// Where it comes from, in words, for the history.
    pub from: String,
}

/// How far from the budget a mesh may be and count as on it (the loop does not stop off
/// it, and prefers a mesh on it as its result).
pub const TOLERANCE: f64 = 0.03;

/// Whether `vertices` is within [`TOLERANCE`] of the budget `n`.
pub fn within(vertices: usize, n: f64) -> bool {
    (vertices as f64 / n - 1.0).abs() <= TOLERANCE
}

/// The ratio of the vertices a remeshing made to the vertices its field asked for, kept
/// within [1/2, 2]: the next field is normalised to the budget divided by it, so that the
/// remesher's own bias (it makes a few percent more or fewer than the complexity says)
/// does not move the result off the budget. 1 when nothing was asked.
pub fn remesher_ratio(made: usize, asked: f64) -> f64 {
    let r = made as f64 / asked;
    if r.is_finite() && r > 0.0 {
        r.clamp(0.5, 2.0)
    } else {
        1.0
    }
}

/// How the raw field is bounded inside the normalisation.
#[derive(Debug, Clone, Copy)]
pub struct Limits<'a> {
    /// h_min, h_max, the largest aspect ratio.
    pub bounds: SizeBounds,
    /// The gradation factor (≥ 1) and the graph of the mesh it runs on; `None`: none.
    pub gradation: Option<(f64, &'a MeshGraph)>,
}

/// The field normalised to a vertex count.
#[derive(Debug, Clone, PartialEq)]
pub struct Budgeted {
    /// One tensor per vertex.
    pub tensors: Vec<SizeTensor>,
    /// The factor s on the metric.
    pub scale: f64,
    /// The vertices a conforming mesh has (the complexity of `tensors`, 2C/√3).
    pub vertices: f64,
    /// Whether the target was met (false: the bounds keep it out of reach).
    pub reached: bool,
}

/// The field at ln s = `ln_s`: every size times s^(−1/2), kept in the representable
/// range, clamped, then graded.
fn field_at(raw: &[SizeTensor], ln_s: f64, limits: &Limits<'_>) -> Vec<SizeTensor> {
    let factor = (-0.5 * ln_s).exp();
    let mut out: Vec<SizeTensor> = raw
        .iter()
        .map(|t| {
            let h =
                t.sizes().map(|h| (h * factor).clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE));
            SizeTensor::from_parts(t.axis(), h).clamp(&limits.bounds)
        })
        .collect();
    if let Some((g, graph)) = limits.gradation {
        apply_gradation(graph, &mut out, g.max(1.0));
    }
    out
}

/// The vertices a mesh of `tris` on `points` conforming to `tensors` has.
pub fn vertices_of(points: &[[f64; 2]], tris: &[[usize; 3]], tensors: &[SizeTensor]) -> f64 {
    let f: Vec<f64> =
        tensors.iter().map(|t| -t.sizes().iter().map(|h| h.ln()).sum::<f64>()).collect();
    vertices_of_complexity(complexity(points, tris, &f))
}

/// `raw` (one tensor per point of `mesh`) normalised to `target` vertices within
/// `limits`; see the module documentation.
pub fn normalise(
    mesh: &TaggedMesh,
    raw: &[SizeTensor],
    limits: &Limits<'_>,
    target: f64,
) -> Budgeted {
    let (points, mut tris) = planar_triangles(mesh);
    // A cell on a point the mesh does not have weighs nothing (a valid mesh has none).
    tris.retain(|t| t.iter().all(|&v| v < raw.len().min(points.len())));
    let v = |ln_s: f64| -> (Vec<SizeTensor>, f64) {
        let t = field_at(raw, ln_s, limits);
        let n = vertices_of(&points, &tris, &t);
        (t, n)
    };
    let done = |ln_s: f64, (tensors, vertices): (Vec<SizeTensor>, f64), reached: bool| Budgeted {
        tensors,
        scale: ln_s.exp(),
        vertices,
        reached,
    };
    // Out of reach: every size at h_min (the most any s asks) or at h_max (the least).
    let uniform = |h: f64| vertices_of(&points, &tris, &vec![SizeTensor::isotropic(h); raw.len()]);
    let (most, least) = (uniform(limits.bounds.h_min()), uniform(limits.bounds.h_max()));
    let at_one = vertices_of(&points, &tris, raw);
    let g = |n: f64| n.ln() - target.ln();
    let guess = if at_one > 0.0 && at_one.is_finite() { (target / at_one).ln() } else { 0.0 };
    if !(target.is_finite() && target > 0.0) || target >= most || target <= least {
        // Far enough out that every size is at the bound: the raw sizes times s^(-1/2)
        // pass it once s is past the ratio of the extreme sizes.
        let (lo, hi) = raw
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), t| (lo.min(t.h_min()), hi.max(t.h_max())));
        let span = 2.0
            * ((hi / limits.bounds.h_min()).ln().abs() + (lo / limits.bounds.h_max()).ln().abs())
            + 1.0;
        let ln_s = if target >= most { span } else { -span };
        let at = v(ln_s);
        let reached = (at.1 / target - 1.0).abs() < 1e-9;
        return done(ln_s, at, reached);
    }
    // Bracket [a, b] with g(a) < 0 <= g(b), from the guess by doubling steps.
    let (mut a, mut b) = (guess, guess);
    let (mut ga, mut gb) = {
        let g0 = g(v(guess).1);
        (g0, g0)
    };
    let mut step = 0.5f64;
    for _ in 0..200 {
        if ga < 0.0 && gb >= 0.0 {
            break;
        }
        if gb < 0.0 {
            a = b;
            ga = gb;
            b += step;
            gb = g(v(b).1);
        } else {
            b = a;
            gb = ga;
            a -= step;
            ga = g(v(a).1);
        }
        step *= 2.0;
    }
    if gb == 0.0 {
        return done(b, v(b), true);
    }
    // Illinois: regula falsi on g(ln s), halving the weight of an end kept twice.
    let mut side = 0i8;
    for _ in 0..200 {
        let x = (a * gb - b * ga) / (gb - ga);
        let x = if x > a && x < b { x } else { 0.5 * (a + b) };
        let gx = g(v(x).1);
        if gx.abs() < 1e-12 || (b - a) < 1e-15 * (1.0 + x.abs()) {
            return done(x, v(x), true);
        }
        if gx < 0.0 {
            a = x;
            ga = gx;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            b = x;
            gb = gx;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
    }
    let x = 0.5 * (a + b);
    let at = v(x);
    let reached = (at.1 / target - 1.0).abs() < 1e-6;
    done(x, at, reached)
}

#[cfg(test)]
mod tests;
