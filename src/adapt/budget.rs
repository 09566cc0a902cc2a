//! The vertex budget of `adapt --complexity N`: the final field on a mesh (the recipe's,
//! the solution's, or both intersected) scaled so that a mesh conforming to it has N
//! vertices, with the hard bounds and the gradation applied inside the scaling.
//!
//! The recipe's field is a shape: its steps, its h_min, h_max and aspect ratio say where
//! the mesh is finer and how stretched, relative to the rest; the budget says how many
//! vertices. So the recipe's own bounds scale with its field (a recipe whose HMAX alone
//! asks for more vertices than the budget is coarsened as a whole, not stopped at its
//! HMAX), and only the bounds given on the command line (`--hmin`, `--hmax`) and the
//! aspect ratio (which no scaling changes) are hard. For a factor s on the metric (sizes
//! times s^(−1/2)) the field is
//!
//!   F(s) = grade(clamp(s · raw ∩ fixed)),
//!
//! clamp to the hard [h_min, h_max] and aspect ratio ([`SizeTensor::clamp`]), then the
//! gradation pass when there is one ([`apply_gradation`]); `fixed` is absent for one
//! field alone. Its complexity V(s) (the vertices a conforming mesh has, 2C/√3 with C
//! exact for the Log-Euclidean interpolation, [`crate::metric::complexity`]) is
//! continuous and nondecreasing in s: scaling, the intersection and the clamp are
//! monotone per vertex, and the gradation only shrinks, more where the tensors it grows
//! from are smaller. So s is the root of the 1D monotone equation V(s) = N, found on
//! ln s: bracketed from a guess (exact for one field where no bound acts, V being linear
//! in s), then the Illinois variant of regula falsi on ln V − ln N to 1e-12 relative. The
//! bounds can therefore not break the budget: they act inside the function whose root
//! is taken. Only when N is out of reach — more than the field at s → ∞ asks, or fewer
//! than at s → 0 — the nearest end is returned and [`Budgeted::reached`] is false.
//!
//! The recipe and a solution ([`share`]): the recipe's field R takes at most a share f of
//! the budget — R itself when it asks for fewer than f·N vertices (a floor the user's
//! sizes hold), else R scaled as a whole to f·N — and the solution's metric S is scaled
//! by the root find so that the intersection R' ∩ s·S has N vertices. Scaling R ∩ S as a
//! whole instead shares the budget in the raw proportions: a recipe asking for its own
//! count takes all of it and the solution's metric none, and the error stays the
//! recipe's (measured in `benches/solution_error.py`, column (e)). Where R' is finer than
//! s·S the recipe's vertices are spent, elsewhere they cost nothing, so the solution has
//! at least (1 − f)·N of the vertices.
//!
//! One normalisation for both dimensions: what differs is the tensor ([`Scalable`]:
//! [`SizeTensor`] in the plane, [`SizeTensor3`] in space), the cells the complexity is
//! taken over (triangles and V = 2C/√3; tetrahedra and V = 6√2·C/5.6,
//! [`crate::metric::complexity3`]) and the gradation pass (on the planar graph; on the
//! edges of a [`SpaceMesh`]). In space V(s) goes as s^(3/2) where no bound acts, so the
//! guess is (N/V(1))^(2/3); the root find on ln s is the same. [`normalise3`] and
//! [`share3`] are the loop in space's.

use smartmesh_formats::TaggedMesh;

use crate::mesh_graph::MeshGraph;
use crate::metric::complexity::{complexity, format_count, vertices_of_complexity};
use crate::metric::complexity3::{complexity3, vertices_of_complexity3};
use crate::metric::{SizeBounds, SizeTensor, SizeTensor3, Sym3};
use crate::metric_field::{planar_triangles, Complexity};
use crate::recipe::Recipe;
use crate::sizing::gradation::apply_gradation;
use crate::sizing::gradation3::apply_gradation3;
use crate::sizing::SpaceMesh;

/// A recipe made to give the raw field, the hard limits of its normalisation, and the
/// empty recipe a solution's step is run in alone.
#[derive(Debug, Clone)]
pub struct RawRecipe {
    /// The recipe without its gradation (its h_min, h_max and aspect ratio stay: they
    /// are part of the shape the budget scales).
    pub recipe: Recipe,
    /// The hard bounds: the command line's h_min and h_max (none: the widest range), the
    /// recipe's aspect ratio.
    pub bounds: SizeBounds,
    /// The recipe's gradation.
    pub gradation: Option<f64>,
    /// No step and no bound: the solution's steps are run in it to give S alone.
    pub empty: Recipe,
}

impl RawRecipe {
    /// `recipe` split in its raw part and its limits, `hard` the h_min and h_max given on
    /// the command line; `None` when these are no range (the sizing engine then says why).
    pub fn of(recipe: &Recipe, hard: (Option<f64>, Option<f64>)) -> Option<RawRecipe> {
        let g = &recipe.global;
        let bounds = SizeBounds::try_new(
            hard.0.unwrap_or(SizeTensor::MIN_SIZE),
            hard.1.unwrap_or(SizeTensor::MAX_SIZE),
            g.max_aspect_ratio.unwrap_or(f64::INFINITY),
        )?;
        let mut raw = recipe.clone();
        raw.global.gradation = None;
        let mut empty = raw.clone();
        empty.algorithms.clear();
        empty.global.h_min = None;
        empty.global.max_aspect_ratio = None;
        // Every vertex a cell uses is reached by a solution's step; one no cell uses
        // weighs nothing, and gets the largest size rather than a warning.
        empty.global.h_max = Some(SizeTensor::MAX_SIZE);
        Some(RawRecipe { recipe: raw, bounds, gradation: g.gradation, empty })
    }

    /// Whether the recipe has steps of its own (else its field is only its h_max, which
    /// a solution's field is bounded by instead of sharing the budget with).
    pub fn has_steps(&self) -> bool {
        !self.recipe.algorithms.is_empty()
    }
}

/// The vertex budget of a run: the vertex count asked of the mesh at each iteration.
#[derive(Debug, Clone, PartialEq)]
pub struct Budget {
    /// The count at iteration k (a constant one: start = target).
    pub schedule: crate::adapt::solver::Schedule,
    /// Where it comes from, in words, for the history.
    pub from: String,
    /// The hard h_min and h_max (the command line's); the recipe's own scale with it.
    pub hard: (Option<f64>, Option<f64>),
    /// The largest share of the budget the recipe's field takes beside a solution's
    /// ([`share`]).
    pub recipe_share: f64,
}

/// The default [`Budget::recipe_share`].
pub const RECIPE_SHARE: f64 = 0.25;

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

/// The vertex count to normalise the next field to so that the remesher makes `n`,
/// from its last remeshings to fields not growth-limited (`(asked, made)`, oldest first).
/// With one, `n` divided by its ratio ([`remesher_ratio`]). With two whose asked counts
/// differ by 2 % or more, the secant of ln made against ln asked through them, its slope
/// kept in [1/2, 2], solved for `n`, and kept within [n/2, 2n] as the ratio is: a
/// remesher's ratio drifts with the field's count (mmg3d refines a curved boundary to
/// its Hausdorff distance whatever the field asks, so a coarser field makes
/// proportionally more), which the ratio alone follows one iteration late.
pub fn corrected_target(n: f64, remeshings: &[(f64, usize)]) -> f64 {
    let ratio = |&(asked, made): &(f64, usize)| remesher_ratio(made, asked);
    match remeshings {
        [] => n,
        [.., a, b] if a.0 > 0.0 && b.0 > 0.0 && (b.0 / a.0).ln().abs() >= 0.02 => {
            let (ma, mb) = (a.1 as f64, b.1 as f64);
            let slope = (mb / ma).ln() / (b.0 / a.0).ln();
            if !(slope.is_finite() && ma > 0.0 && mb > 0.0) {
                return n / ratio(b);
            }
            let t = b.0 * (n / mb).powf(1.0 / slope.clamp(0.5, 2.0));
            if t.is_finite() {
                t.clamp(0.5 * n, 2.0 * n)
            } else {
                n / ratio(b)
            }
        }
        [.., b] => n / ratio(b),
    }
}

/// The warning of a field the bounds kept from the budget (`reached` false): it asks for
/// `vertices` at least or at most, not `target`.
pub fn unreached(reached: bool, vertices: f64, target: f64) -> Option<String> {
    (!reached).then(|| {
        format!(
            "the bounds keep the field from the budget: it asks for {} vertices at {}, not {} (widen --hmin or --hmax)",
            format_count(vertices),
            if vertices > target { "least" } else { "most" },
            format_count(target)
        )
    })
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
pub struct Budgeted<T = SizeTensor> {
    /// One tensor per vertex.
    pub tensors: Vec<T>,
    /// The factor s on the metric.
    pub scale: f64,
    /// The vertices a conforming mesh has (from the complexity of `tensors`: 2C/√3 in
    /// the plane, 6√2·C/5.6 in space).
    pub vertices: f64,
    /// Whether the target was met (false: the bounds keep it out of reach).
    pub reached: bool,
}

/// A size tensor the normalisation scales: [`SizeTensor`] in the plane, [`SizeTensor3`]
/// in space.
pub trait Scalable: Copy {
    /// The tensor with every size times `factor`, kept in the representable range.
    fn scaled(&self, factor: f64) -> Self;
    /// The largest tensor inside both.
    fn meet(&self, other: &Self) -> Self;
    /// The tensor within `bounds` (h_min, h_max, the aspect ratio).
    fn bounded(&self, bounds: &SizeBounds) -> Self;
    /// The smallest and the largest size.
    fn extremes(&self) -> (f64, f64);
    /// −Σ ln hᵢ: ½ ln det of its metric, what the complexity integrates.
    fn half_log_det(&self) -> f64;
}

impl Scalable for SizeTensor {
    fn scaled(&self, factor: f64) -> Self {
        let h =
            self.sizes().map(|h| (h * factor).clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE));
        SizeTensor::from_parts(self.axis(), h)
    }
    fn meet(&self, other: &Self) -> Self {
        self.intersection(other)
    }
    fn bounded(&self, bounds: &SizeBounds) -> Self {
        self.clamp(bounds)
    }
    fn extremes(&self) -> (f64, f64) {
        (self.h_min(), self.h_max())
    }
    fn half_log_det(&self) -> f64 {
        -self.sizes().iter().map(|h| h.ln()).sum::<f64>()
    }
}

impl Scalable for SizeTensor3 {
    fn scaled(&self, factor: f64) -> Self {
        // `from_parts` keeps the sizes in the representable range.
        SizeTensor3::from_parts(self.frame(), self.sizes().map(|h| h * factor))
    }
    fn meet(&self, other: &Self) -> Self {
        self.intersection(other)
    }
    fn bounded(&self, bounds: &SizeBounds) -> Self {
        self.clamp(bounds)
    }
    fn extremes(&self) -> (f64, f64) {
        (self.h_min(), self.h_max())
    }
    fn half_log_det(&self) -> f64 {
        -self.sizes().iter().map(|h| h.ln()).sum::<f64>()
    }
}

/// The cells a field's vertex count is taken over, and its gradation pass.
trait Cells<T> {
    /// The dimension d: a factor s on the metric scales the count by s^(d/2).
    fn dimension(&self) -> f64;
    /// The vertices a mesh conforming to `tensors` has.
    fn vertices(&self, tensors: &[T]) -> f64;
    /// The gradation pass on `tensors`, when there is one.
    fn grade(&self, tensors: &mut [T]);
    /// h_min, h_max, the largest aspect ratio.
    fn bounds(&self) -> &SizeBounds;
}

/// A planar mesh's triangles (quadrangles cut in two) and its limits.
struct Plane<'a> {
    points: Vec<[f64; 2]>,
    tris: Vec<[usize; 3]>,
    limits: &'a Limits<'a>,
}

impl<'a> Plane<'a> {
    /// The triangles of `mesh` on its first `n` points (a cell on a point the field does
    /// not have weighs nothing: a valid mesh has none).
    fn new(mesh: &TaggedMesh, n: usize, limits: &'a Limits<'a>) -> Plane<'a> {
        let (points, mut tris) = planar_triangles(mesh);
        tris.retain(|t| t.iter().all(|&v| v < n.min(points.len())));
        Plane { points, tris, limits }
    }
}

impl Cells<SizeTensor> for Plane<'_> {
    fn dimension(&self) -> f64 {
        2.0
    }
    fn vertices(&self, tensors: &[SizeTensor]) -> f64 {
        vertices_of(&self.points, &self.tris, tensors)
    }
    fn grade(&self, tensors: &mut [SizeTensor]) {
        if let Some((g, graph)) = self.limits.gradation {
            apply_gradation(graph, tensors, g.max(1.0));
        }
    }
    fn bounds(&self) -> &SizeBounds {
        &self.limits.bounds
    }
}

/// How the raw field of a mesh in space is bounded inside the normalisation.
#[derive(Debug, Clone, Copy)]
pub struct Limits3<'a> {
    /// h_min, h_max, the largest aspect ratio.
    pub bounds: SizeBounds,
    /// The gradation factor (≥ 1) and the mesh it runs on; `None`: none.
    pub gradation: Option<(f64, &'a SpaceMesh<'a>)>,
}

/// A mesh in space's volume cells cut into tetrahedra, and its limits.
struct Solid<'a> {
    points: &'a [[f64; 3]],
    tets: Vec<[usize; 4]>,
    limits: &'a Limits3<'a>,
}

impl<'a> Solid<'a> {
    fn new(mesh: &'a TaggedMesh, n: usize, limits: &'a Limits3<'a>) -> Solid<'a> {
        let mut tets = <Sym3 as Complexity>::simplices(mesh);
        tets.retain(|t| t.iter().all(|&v| v < n.min(mesh.points.len())));
        Solid { points: &mesh.points, tets, limits }
    }
}

impl Cells<SizeTensor3> for Solid<'_> {
    fn dimension(&self) -> f64 {
        3.0
    }
    fn vertices(&self, tensors: &[SizeTensor3]) -> f64 {
        vertices_of3(self.points, &self.tets, tensors)
    }
    fn grade(&self, tensors: &mut [SizeTensor3]) {
        if let Some((g, mesh)) = self.limits.gradation {
            apply_gradation3(mesh, tensors, g.max(1.0));
        }
    }
    fn bounds(&self) -> &SizeBounds {
        &self.limits.bounds
    }
}

/// The field at ln s = `ln_s`: every size of `raw` times s^(−1/2), intersected with
/// `fixed` when given, clamped, then graded.
fn field_at<T: Scalable>(
    raw: &[T],
    fixed: Option<&[T]>,
    ln_s: f64,
    cells: &dyn Cells<T>,
) -> Vec<T> {
    let factor = (-0.5 * ln_s).exp();
    let bounds = cells.bounds();
    let mut out: Vec<T> = raw
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let t = t.scaled(factor);
            let t = match fixed {
                Some(f) => t.meet(&f[i]),
                None => t,
            };
            t.bounded(bounds)
        })
        .collect();
    cells.grade(&mut out);
    out
}

/// The vertices a mesh of `tris` on `points` conforming to `tensors` has.
pub fn vertices_of(points: &[[f64; 2]], tris: &[[usize; 3]], tensors: &[SizeTensor]) -> f64 {
    let f: Vec<f64> = tensors.iter().map(Scalable::half_log_det).collect();
    vertices_of_complexity(complexity(points, tris, &f))
}

/// The vertices a mesh of `tets` on `points` conforming to `tensors` has.
pub fn vertices_of3(points: &[[f64; 3]], tets: &[[usize; 4]], tensors: &[SizeTensor3]) -> f64 {
    let f: Vec<f64> = tensors.iter().map(Scalable::half_log_det).collect();
    vertices_of_complexity3(complexity3(points, tets, &f))
}

/// `raw` (one tensor per point of `mesh`) normalised to `target` vertices within
/// `limits`; see the module documentation.
pub fn normalise(
    mesh: &TaggedMesh,
    raw: &[SizeTensor],
    limits: &Limits<'_>,
    target: f64,
) -> Budgeted {
    normalise_over(&Plane::new(mesh, raw.len(), limits), raw, None, target)
}

/// The recipe's field `recipe` and a solution's metric `solution` (one tensor per point
/// of `mesh` each) made one field of `target` vertices, the recipe taking at most
/// `share` of it; see the module documentation. When the recipe's part leaves the
/// solution no room (the hard bounds or the gradation asking for more), the
/// intersection is scaled as a whole ([`normalise`]).
pub fn share(
    mesh: &TaggedMesh,
    recipe: &[SizeTensor],
    solution: &[SizeTensor],
    limits: &Limits<'_>,
    target: f64,
    share: f64,
) -> Budgeted {
    share_over(&Plane::new(mesh, recipe.len(), limits), recipe, solution, target, share)
}

/// [`normalise`] on a mesh in space: the complexity over its volume cells, the gradation
/// on its edges.
pub fn normalise3(
    mesh: &TaggedMesh,
    raw: &[SizeTensor3],
    limits: &Limits3<'_>,
    target: f64,
) -> Budgeted<SizeTensor3> {
    normalise_over(&Solid::new(mesh, raw.len(), limits), raw, None, target)
}

/// [`share`] on a mesh in space.
pub fn share3(
    mesh: &TaggedMesh,
    recipe: &[SizeTensor3],
    solution: &[SizeTensor3],
    limits: &Limits3<'_>,
    target: f64,
    share: f64,
) -> Budgeted<SizeTensor3> {
    share_over(&Solid::new(mesh, recipe.len(), limits), recipe, solution, target, share)
}

/// [`share`] over `cells`.
fn share_over<T: Scalable>(
    cells: &dyn Cells<T>,
    recipe: &[T],
    solution: &[T],
    target: f64,
    share: f64,
) -> Budgeted<T> {
    let own = cells.vertices(recipe);
    let cap = share.clamp(0.0, 1.0) * target;
    let floor: Vec<T> = if own > cap && cap > 0.0 && own.is_finite() {
        // Sizes times (own/cap)^(1/d) bring the count from own to cap.
        let factor = (own / cap).powf(1.0 / cells.dimension());
        recipe.iter().map(|t| t.scaled(factor)).collect()
    } else {
        recipe.to_vec()
    };
    let b = normalise_over(cells, solution, Some(&floor), target);
    if b.reached {
        return b;
    }
    let whole: Vec<T> = recipe.iter().zip(solution).map(|(r, s)| r.meet(s)).collect();
    normalise_over(cells, &whole, None, target)
}

/// `raw` scaled, intersected with `fixed` when given, to `target` vertices within the
/// limits of `cells` (see the module documentation).
fn normalise_over<T: Scalable>(
    cells: &dyn Cells<T>,
    raw: &[T],
    fixed: Option<&[T]>,
    target: f64,
) -> Budgeted<T> {
    let v = |ln_s: f64| -> (Vec<T>, f64) {
        let t = field_at(raw, fixed, ln_s, cells);
        let n = cells.vertices(&t);
        (t, n)
    };
    let done = |ln_s: f64, (tensors, vertices): (Vec<T>, f64), reached: bool| Budgeted {
        tensors,
        scale: ln_s.exp(),
        vertices,
        reached,
    };
    let at_one = cells.vertices(raw);
    let g = |n: f64| n.ln() - target.ln();
    // V(s) = s^(d/2) V(1) where no bound acts.
    let guess = if at_one > 0.0 && at_one.is_finite() {
        (target / at_one).ln() * 2.0 / cells.dimension()
    } else {
        0.0
    };
    // Far enough out that every scaled size is at a bound: the raw sizes times s^(-1/2)
    // pass it once s is past the ratio of the extreme sizes. There the field asks for
    // the most (every size at h_min) or the least (the scaled part at h_max, the fixed
    // part as it is) any s gives.
    let (lo, hi) = raw.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), t| {
        let (a, b) = t.extremes();
        (lo.min(a), hi.max(b))
    });
    let bounds = cells.bounds();
    let span = 2.0 * ((hi / bounds.h_min()).ln().abs() + (lo / bounds.h_max()).ln().abs()) + 1.0;
    let (most, least) = (v(span), v(-span));
    if !(target.is_finite() && target > 0.0) || target >= most.1 || target <= least.1 {
        let (ln_s, at) = if target >= most.1 { (span, most) } else { (-span, least) };
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
