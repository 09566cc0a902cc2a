//! The sizing engine on a mesh in space (tetrahedra, or a triangulated surface off one
//! plane): runs the steps of a [`SizingPlan`] — the same plan, resolved from the same
//! recipe by the same table — and returns one [`SizeTensor3`] per vertex, or the
//! [`MetricField<Sym3>`](crate::metric_field::MetricField) every metric format writes.
//!
//! Order of work, as the 2D engine's ([`crate::sizing::field`]):
//! 1. each step, in plan order, asks for its work (`Algorithm::work_in_space`; an
//!    algorithm that does not size in space refuses, naming its keyword); its tensors
//!    are intersected into the vertex's current one ([`SizeTensor3::intersection`], the
//!    first one taken as it is), in plan order always;
//! 2. vertices no step reaches take the default size: h_max, or the diagonal of the
//!    mesh's bounding box (with a warning);
//! 3. the plan's h_min, h_max and maximum aspect ratio clamp every tensor
//!    ([`SizeTensor3::clamp`]);
//! 4. the gradation pass, when the plan asks for one, then the clamp once
//!    more to remove rounding (the pass only shrinks, by intersection;
//!    `crate::sizing::gradation3`).
//!
//! Evaluation of a work from a source: no propagation over the mesh; every vertex whose
//! box distance to the source's pieces is within the reach asks the source's index for
//! its exact closest point (bit for bit the scan of every piece), and is reached when
//! the squared distance is at most reach² (the squared form, so that the box pre-test
//! never drops a vertex the test would keep). Vertices go in fixed chunks of `CHUNK`
//! in parallel (rayon), each chunk merging into its own slice of the field, each query
//! seeded by the previous one of its chunk (the answer does not depend on the seed): the
//! field is the same on every thread count. An error is the first in vertex order.
//!
//! Coarse meshes: a source made of mesh entities has its own vertices at distance 0, so
//! it always reaches them. A free source (an imaginary polyline or sheet) also reaches
//! the corners of every cell one of its pieces meets, whatever their distance
//! (`sizing::space::crossed_corners`, exact: the volume cells of every kind, or a surface
//! mesh's triangles and quadrilaterals), each with the tensor of its true distance (the
//! functions hold their end values past their maximum distance), as the 2D propagation
//! seeds the corners of the cells a free polyline crosses: a source thinner than the
//! cells still refines the cells it passes through, and the adaptation loop then brings
//! vertices within reach. The step's report counts those corners as its seeds. A free
//! source that meets no cell and is out of reach of every vertex reaches none (a warning
//! says so).

use rayon::prelude::*;

use crate::metric::{SizeBounds, SizeTensor, SizeTensor3, Sym3};
use crate::metric_field::MetricField;
use crate::sizing::algorithms::{Failure, SpaceTensor, SpaceWork};
use crate::sizing::field::{plan_bounds, SizingError, StepEvent, StepReport};
use crate::sizing::gradation::GradationReport;
use crate::sizing::gradation3::apply_gradation3;
use crate::sizing::plan::SizingPlan;
use crate::sizing::space::{crossed_corners, SpaceClosest, SpaceMesh, SpaceSource};
use crate::topology::Topology;

/// Vertices per parallel chunk (fixed: the chunking does not depend on the thread count).
pub(crate) const CHUNK: usize = 1024;

/// One size tensor per vertex of a mesh in space, and how they came about.
#[derive(Debug, Clone, PartialEq)]
pub struct SizeField3 {
    /// The tensor of each mesh vertex, by vertex index.
    pub tensors: Vec<SizeTensor3>,
    /// Whether some step reached the vertex (false: it has the default size).
    pub reached: Vec<bool>,
    /// The size of the vertices no step reached (before clamping).
    pub default_size: f64,
    /// Things the user should know that did not stop the work.
    pub warnings: Vec<String>,
    /// One report per step, in plan order.
    pub steps: Vec<StepReport>,
    /// What the gradation pass did, when the plan asks for one.
    pub gradation: Option<GradationReport>,
}

impl SizeField3 {
    /// The field as metrics M = R diag(1/h²) Rᵀ, for every metric format.
    pub fn metric_field(&self, source: impl Into<String>) -> MetricField<Sym3> {
        MetricField::new(self.tensors.iter().map(SizeTensor3::to_metric).collect(), source)
    }
}

/// Runs `plan` on the mesh in space `mesh` with its `topology` (see the module header);
/// `observer` hears each step start and finish.
pub fn compute_size_field3(
    mesh: &SpaceMesh<'_>,
    topology: &Topology,
    plan: &SizingPlan,
    observer: &mut dyn FnMut(StepEvent),
) -> Result<SizeField3, SizingError> {
    let bounds = plan_bounds(plan)?;
    if let Some(g) = plan.gradation {
        if !(g >= 1.0 && g.is_finite()) {
            return Err(SizingError::InvalidGradation(g));
        }
    }
    let n = mesh.num_vertices();
    let mut tensors = vec![SizeTensor3::isotropic(1.0); n];
    let mut reached = vec![false; n];
    let mut steps = Vec::with_capacity(plan.steps.len());
    let mut warnings = Vec::new();
    for (index, step) in plan.steps.iter().enumerate() {
        observer(StepEvent::Started { index, label: step.label.clone(), of: plan.steps.len() });
        let at = |f: Failure| f.at(index, &step.label);
        let work = step.algorithm.work_in_space(mesh, topology).map_err(at)?;
        let (vertices, seeds) = merge_work(mesh, work, &mut tensors, &mut reached).map_err(at)?;
        if vertices == 0 {
            warnings.push(format!("step {index} ({}): reached no vertex", step.label));
        }
        observer(StepEvent::Finished { index, reached: vertices });
        steps.push(StepReport {
            label: step.label.clone(),
            algorithm: step.algorithm.keyword(),
            vertices_reached: vertices,
            seeds,
        });
    }
    let unreached = reached.iter().filter(|r| !**r).count();
    let diagonal = bounding_box_diagonal(mesh.points());
    let default_size = match plan.h_max {
        Some(h) => h,
        None if unreached == 0 => diagonal.clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE),
        None if (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&diagonal) => {
            warnings.push(format!("no h_max: {unreached} vertices that no step reaches get the bounding-box diagonal {diagonal} as their size"));
            diagonal
        }
        None => return Err(SizingError::NoDefaultSize(diagonal)),
    };
    let default = SizeTensor3::try_new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [default_size; 3])
        .ok_or(SizingError::NoDefaultSize(default_size))?;
    finish(&mut tensors, &reached, default, bounds.as_ref());
    let gradation = plan.gradation.map(|g| {
        let report = apply_gradation3(mesh, &mut tensors, g);
        if let Some(b) = &bounds {
            tensors.iter_mut().for_each(|t| *t = t.clamp(b));
        }
        if !report.converged {
            warnings.push(format!(
                "gradation stopped after {} updates before reaching its fixed point",
                report.updates
            ));
        }
        report
    });
    Ok(SizeField3 { tensors, reached, default_size, warnings, steps, gradation })
}

/// The default tensor on the vertices no step reached, the clamp on every tensor.
fn finish(
    tensors: &mut [SizeTensor3],
    reached: &[bool],
    default: SizeTensor3,
    bounds: Option<&SizeBounds>,
) {
    for (t, &r) in tensors.iter_mut().zip(reached) {
        if !r {
            *t = default;
        }
        if let Some(b) = bounds {
            *t = t.clamp(b);
        }
    }
}

#[inline]
fn merge(slot: &mut SizeTensor3, has: &mut bool, t: &SizeTensor3) {
    *slot = if *has { slot.intersection(t) } else { *t };
    *has = true;
}

/// Evaluates one step's work and intersects it into the field; returns the vertices it
/// reached and its seeds (0 in space: nothing is propagated).
fn merge_work(
    mesh: &SpaceMesh<'_>,
    work: SpaceWork<'_>,
    tensors: &mut [SizeTensor3],
    reached: &mut [bool],
) -> Result<(usize, usize), Failure> {
    let n = tensors.len();
    match work {
        SpaceWork::Listed { vertices, tensors: listed } => {
            for (&v, t) in vertices.iter().zip(&listed) {
                let v = v as usize;
                if v >= n {
                    return Err(Failure::EntityOutOfRange {
                        what: "mesh vertex",
                        index: v,
                        len: n,
                    });
                }
                merge(&mut tensors[v], &mut reached[v], t);
            }
            Ok((vertices.len().min(listed.len()), 0))
        }
        SpaceWork::FromSource { source, reach, tensor } => {
            // The coarse-mesh rule of a free source (see the module header).
            let crossed = source.is_free().then(|| crossed_corners(mesh.tagged(), &source));
            let seeds = crossed.as_ref().map_or(0, |c| c.iter().filter(|&&x| x).count());
            let sources = std::slice::from_ref(&source);
            let work = Reaching { sources, reach, crossed: crossed.as_deref() };
            Ok((from_sources(mesh, work, tensor.as_ref(), tensors, reached)?, seeds))
        }
        SpaceWork::FromTwoSources { sources, reach, tensor } => {
            let work = Reaching { sources: &sources, reach, crossed: None };
            Ok((from_sources(mesh, work, tensor.as_ref(), tensors, reached)?, 0))
        }
    }
}

/// The closest point on each of `sources` of the vertex at `p` when all are within
/// `reach` (squared distances at most reach²), the query on each seeded by `seeds`
/// (updated); `Ok(None)` out of reach, [`Failure::Degenerate`] for a vertex whose
/// coordinates are not finite.
#[inline]
pub(crate) fn closest_within(
    sources: &[SpaceSource],
    reach: f64,
    v: usize,
    p: [f64; 3],
    seeds: &mut [u32; 2],
) -> Result<Option<[SpaceClosest; 2]>, Failure> {
    let r2 = reach * reach;
    if sources.iter().any(|s| s.box_distance_squared(p) > r2) {
        return Ok(None);
    }
    let mut out = [None; 2];
    for (k, s) in sources.iter().enumerate() {
        let c = s.closest_from(p, seeds[k]).ok_or(Failure::Degenerate { vertex: v })?;
        seeds[k] = c.piece;
        // NaN is out of reach too.
        if c.distance_squared > r2 || c.distance_squared.is_nan() {
            return Ok(None);
        }
        out[k] = Some(c);
    }
    let first = out[0].ok_or(Failure::NoSource)?;
    Ok(Some([first, out[1].unwrap_or(first)]))
}

/// What a step reaches: the vertices within `reach` of all `sources`, and those
/// `crossed` marks whatever their distance.
#[derive(Clone, Copy)]
struct Reaching<'s> {
    sources: &'s [SpaceSource],
    reach: f64,
    crossed: Option<&'s [bool]>,
}

/// Every vertex `work` reaches gets `tensor`'s tensor, intersected into the field in
/// fixed chunks run in parallel (see the module header); returns how many.
fn from_sources(
    mesh: &SpaceMesh<'_>,
    work: Reaching<'_>,
    tensor: &dyn SpaceTensor,
    tensors: &mut [SizeTensor3],
    reached: &mut [bool],
) -> Result<usize, Failure> {
    let points = mesh.points();
    let sources = work.sources;
    let counts: Vec<Result<usize, Failure>> = tensors
        .par_chunks_mut(CHUNK)
        .zip(reached.par_chunks_mut(CHUNK))
        .enumerate()
        .map(|(chunk, (ts, rs))| {
            let mut seeds = [u32::MAX; 2];
            let mut count = 0;
            for (i, (t, r)) in ts.iter_mut().zip(rs.iter_mut()).enumerate() {
                let v = chunk * CHUNK + i;
                let p = points[v];
                let forced = work.crossed.is_some_and(|c| c[v]);
                let reach = if forced { f64::INFINITY } else { work.reach };
                let Some(closest) = closest_within(sources, reach, v, p, &mut seeds)? else {
                    continue;
                };
                if let Some(new) = tensor.tensor(sources, v, p, &closest[..sources.len()])? {
                    merge(t, r, &new);
                    count += 1;
                }
            }
            Ok(count)
        })
        .collect();
    let mut total = 0;
    for c in counts {
        total += c?;
    }
    Ok(total)
}

/// Length of the diagonal of the box of `points` (0 with none; NaN when one is not finite).
fn bounding_box_diagonal(points: &[[f64; 3]]) -> f64 {
    let Some(first) = points.first() else { return 0.0 };
    let (mut lo, mut hi) = (*first, *first);
    for p in points {
        if !p.iter().all(|c| c.is_finite()) {
            return f64::NAN;
        }
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1]).hypot(hi[2] - lo[2])
}

#[cfg(test)]
#[path = "field3_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "field3_twins.rs"]
mod twins;

#[cfg(test)]
#[path = "field3_imaginary.rs"]
mod imaginary;

#[cfg(test)]
#[path = "field3_crossed.rs"]
mod crossed;
