//! The sizing engine: runs a [`SizingPlan`] on a mesh and returns one size tensor per
//! vertex (thesis 4.3.6, Algorithms 4.1–4.5, and 7.4.1).
//!
//! Order of work:
//! 1. each step of the plan, in plan order, computes its tensors on the vertices it
//!    reaches ([`crate::sizing::algorithms`], evaluated by `crate::sizing::evaluate`); each is *intersected* into the vertex's
//!    current tensor (thesis 3.2.2; the first one a vertex gets is taken as it is). The
//!    intersection is not associative, so the order is the plan's, always;
//! 2. vertices no step reaches take the default size: the plan's h_max, or the
//!    bounding-box diagonal of the mesh when it has none (with a warning);
//! 3. when the plan gives h_min, h_max or a maximum aspect ratio, every tensor is
//!    clamped ([`SizeTensor::clamp`]);
//! 4. when the plan gives a gradation, the gradation pass ([`crate::sizing::gradation`])
//!    bounds the growth of sizes between neighbours. It only shrinks tensors, so the
//!    bounds of step 3 still hold (an intersection of two ellipses that contain the disc
//!    of radius h_min contains it, and its aspect ratio cannot exceed the larger of
//!    theirs); the clamp is applied once more to remove rounding.
//!
//! Deterministic: every algorithm commits its tensors in a fixed order whatever the
//! number of threads, and steps 1–4 run in a fixed order.

use crate::mesh_graph::MeshGraph;
use crate::metric::{SizeBounds, SizeTensor};
use crate::sizing::algorithms::{Contribution, Failure};
use crate::sizing::evaluate::{
    self, merge, merge_closest_in_vertex_order, merge_in_vertex_order, Collect, Sink,
};
use crate::sizing::gradation::{apply_gradation, GradationReport};
use crate::sizing::plan::{Algorithm, SizingPlan};
use crate::sizing::propagation::{
    propagate, reach_covers_mesh, ClosestPoint, PropagationOptions, Reach, Source,
};
use crate::topology::Topology;

/// Progress of [`compute_size_field`], for a progress bar.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StepEvent {
    /// Step `index` (0-based) of `of`, labelled `label`, starts.
    Started {
        /// The step, 0-based.
        index: usize,
        /// Its label.
        label: String,
        /// Number of steps.
        of: usize,
    },
    /// Step `index` finished, having given tensors to `reached` vertices.
    Finished {
        /// The step, 0-based.
        index: usize,
        /// Vertices it gave a tensor.
        reached: usize,
    },
}

/// What one step did, for summaries (`--json`).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct StepReport {
    /// The step's label.
    pub label: String,
    /// The recipe keyword of its algorithm.
    pub algorithm: &'static str,
    /// Vertices that got a tensor from it.
    pub vertices_reached: usize,
    /// Vertices its propagation started from (0 for UNIFORM).
    pub seeds: usize,
}

/// One size tensor per mesh vertex, and how they came about.
#[derive(Debug, Clone, PartialEq)]
pub struct SizeField {
    /// The tensor of each mesh vertex, by vertex index.
    pub tensors: Vec<SizeTensor>,
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

/// Why a plan could not be run. Step errors name the step (0-based) and its label.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SizingError {
    /// A step names a topological entity (or a mesh vertex or cell) the mesh does not
    /// have: the plan was resolved against another mesh.
    #[error("step {step} ({label}): {what} {index} is out of range (the mesh has {len})")]
    EntityOutOfRange {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// "point", "curve", "face", "mesh vertex" or "surface cell".
        what: &'static str,
        /// The index.
        index: usize,
        /// How many there are.
        len: usize,
    },
    /// An entity of a kind the algorithm cannot use (a face as a border, a point as a
    /// curvature source): name curves there.
    #[error("step {step} ({label}): {what} {index} cannot be a source of this algorithm")]
    UnsupportedEntity {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// "point", "curve" or "face".
        what: &'static str,
        /// Its index.
        index: usize,
    },
    /// The step's sources make no segment and no point (no entity, or curves without
    /// edges): give it at least one.
    #[error("step {step} ({label}): the source has no segment")]
    NoSource {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
    },
    /// An imaginary polyline without any point: give at least one.
    #[error("step {step} ({label}): the polyline is empty")]
    EmptyPolyline {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
    },
    /// A polyline point with a NaN or infinite coordinate.
    #[error("step {step} ({label}): polyline point {point} is not finite")]
    NonFinitePoint {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// The point, 0-based.
        point: usize,
    },
    /// A size outside [1e-30, 1e30] (e.g. a UNIFORM size of 0).
    #[error(
        "step {step} ({label}): size {size} is out of range: expected a size in [1e-30, 1e30]"
    )]
    InvalidSize {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// The size.
        size: f64,
    },
    /// No tensor could be formed at a vertex: its coordinates are not finite.
    #[error(
        "step {step} ({label}): no size tensor at vertex {vertex} (are its coordinates finite?)"
    )]
    Degenerate {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// The vertex.
        vertex: usize,
    },
    /// The field a step sizes from (SOLUTION_HESSIAN's point data) is missing or
    /// unusable: the message says which array and why.
    #[error("step {step} ({label}): {why}")]
    Field {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// What is wrong.
        why: String,
    },
    /// The step's algorithm does not size a mesh in space yet (`recipe check RECIPE
    /// MESH` says which steps do).
    #[error("step {step} ({label}): {keyword} is not available on a mesh in space yet")]
    NotInSpace {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// The algorithm's keyword.
        keyword: &'static str,
    },
    /// The step's algorithm sizes meshes in space only (a sheet in space).
    #[error("step {step} ({label}): {keyword} sizes a mesh in space only (tetrahedra, or a surface off one plane)")]
    OnlyInSpace {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// The algorithm's keyword.
        keyword: &'static str,
    },
    /// A polyline of (x, y) points on a mesh in space, or of (x, y, z) points on a
    /// planar mesh: give each point the coordinates of the mesh (there is no implied z).
    #[error("step {step} ({label}): the polyline's points have {components} coordinates, but the mesh is {}: give every point {}", if *in_space { "in space" } else { "planar" }, if *in_space { "x, y and z (Z_COORDS in libconfig, [x, y, z] in TOML/JSON)" } else { "x and y only" })]
    PolylineComponents {
        /// The step.
        step: usize,
        /// Its label.
        label: String,
        /// The polyline's coordinates per point.
        components: usize,
        /// Whether the mesh is in space.
        in_space: bool,
    },
    /// The global bounds contradict each other or are out of range: need
    /// 1e-30 <= h_min <= h_max <= 1e30 and max_aspect_ratio >= 1.
    #[error("invalid global bounds: h_min = {h_min:?}, h_max = {h_max:?}, max_aspect_ratio = {max_aspect_ratio:?} (need 1e-30 <= h_min <= h_max <= 1e30, aspect ratio >= 1)")]
    InvalidBounds {
        /// As given.
        h_min: Option<f64>,
        /// As given.
        h_max: Option<f64>,
        /// As given.
        max_aspect_ratio: Option<f64>,
    },
    /// The gradation must be a finite number >= 1.
    #[error("gradation {0} is out of range: expected a finite number >= 1")]
    InvalidGradation(f64),
    /// Some vertex is reached by no step, the plan gives no h_max, and the mesh's
    /// bounding box has no usable diagonal (a single point, or non-finite coordinates):
    /// give h_max.
    #[error("no default size: the plan has no h_max and the bounding-box diagonal is {0}")]
    NoDefaultSize(f64),
}

impl Failure {
    pub(crate) fn at(self, step: usize, label: &str) -> SizingError {
        let label = label.to_string();
        match self {
            Failure::EntityOutOfRange { what, index, len } => {
                SizingError::EntityOutOfRange { step, label, what, index, len }
            }
            Failure::UnsupportedEntity { what, index } => {
                SizingError::UnsupportedEntity { step, label, what, index }
            }
            Failure::NoSource => SizingError::NoSource { step, label },
            Failure::EmptyPolyline => SizingError::EmptyPolyline { step, label },
            Failure::NonFinitePoint { point } => SizingError::NonFinitePoint { step, label, point },
            Failure::InvalidSize { size } => SizingError::InvalidSize { step, label, size },
            Failure::Degenerate { vertex } => SizingError::Degenerate { step, label, vertex },
            Failure::Field { why } => SizingError::Field { step, label, why },
            Failure::NotInSpace { keyword } => SizingError::NotInSpace { step, label, keyword },
            Failure::OnlyInSpace { keyword } => SizingError::OnlyInSpace { step, label, keyword },
            Failure::PolylineComponents { components, in_space } => {
                SizingError::PolylineComponents { step, label, components, in_space }
            }
        }
    }
}

/// The tensors one algorithm asks for on `graph`, before any combination: the vertices
/// it reaches, each with its tensor (`step` and `label` only name it in errors).
pub fn run_algorithm(
    graph: &MeshGraph,
    topology: &Topology,
    algorithm: &Algorithm,
    step: usize,
    label: &str,
) -> Result<Contribution, SizingError> {
    evaluate::run(graph, topology, algorithm, Collect).map_err(|f| f.at(step, label))
}

/// The driver's sink: each step's tensors are intersected into the field as they come
/// (the first tensor a vertex gets is taken as it is), never kept as a list when the
/// step reaches a large share of the mesh. For the last step it may also finish the
/// field in the same pass ([`Finish`]).
struct IntoField<'f> {
    tensors: &'f mut [SizeTensor],
    reached: &'f mut [bool],
    finish: Option<Finish>,
}

/// The field's last pass: the default tensor on the vertices no step reached, the
/// clamp on the others (the default is clamped already).
#[derive(Clone, Copy)]
struct Finish {
    default: SizeTensor,
    bounds: Option<SizeBounds>,
}

impl Finish {
    #[inline]
    fn apply(&self, t: &mut SizeTensor, reached: bool) {
        if !reached {
            *t = self.default;
        } else if let Some(b) = &self.bounds {
            *t = t.clamp(b);
        }
    }
}

/// What one step merged into the field.
struct Merged {
    vertices: usize,
    seeds: usize,
    /// Whether the step also finished the field.
    finished: bool,
}

/// A reach of at least `1 / DENSE_SHARE` of the mesh is merged in vertex order (one pass
/// over every vertex, no list of tensors); a smaller one as a list, so that a step costs
/// what it reaches, not what the mesh has.
const DENSE_SHARE: usize = 8;

impl Sink for IntoField<'_> {
    type Output = Merged;

    fn take_reach<F>(self, reach: Reach<'_>, f: F) -> Result<Merged, Failure>
    where
        F: Fn(usize, &ClosestPoint) -> Result<Option<SizeTensor>, Failure> + Sync,
    {
        if reach.len() < self.tensors.len() / DENSE_SHARE {
            return self.take_list(Collect.take_reach(reach, f)?);
        }
        let seeds = reach.report().seeds;
        let (vertices, finished) = match self.finish {
            Some(finish) => (
                merge_in_vertex_order(&reach, f, self.tensors, self.reached, |t, r| {
                    finish.apply(t, r)
                })?,
                true,
            ),
            None => {
                (merge_in_vertex_order(&reach, f, self.tensors, self.reached, |_, _| {})?, false)
            }
        };
        Ok(Merged { vertices, seeds, finished })
    }

    /// A step that reaches every vertex is evaluated in vertex order and merged as it
    /// goes ([`merge_closest_in_vertex_order`]); any other is propagated.
    fn take_source<F>(
        self,
        graph: &MeshGraph,
        source: &Source,
        max_distance: f64,
        options: &PropagationOptions,
        f: F,
    ) -> Result<Merged, Failure>
    where
        F: Fn(usize, &ClosestPoint) -> Result<Option<SizeTensor>, Failure> + Sync,
    {
        let Some(farthest) = reach_covers_mesh(graph, source, max_distance) else {
            return self.take_reach(propagate(graph, source, max_distance, options), f);
        };
        let seeds = source.seeds().len();
        let parallel = options.parallel;
        let (vertices, finished) = match self.finish {
            Some(finish) => (
                merge_closest_in_vertex_order(
                    graph,
                    source,
                    farthest,
                    f,
                    self.tensors,
                    self.reached,
                    |t, r| finish.apply(t, r),
                    parallel,
                )?,
                true,
            ),
            None => (
                merge_closest_in_vertex_order(
                    graph,
                    source,
                    farthest,
                    f,
                    self.tensors,
                    self.reached,
                    |_, _| {},
                    parallel,
                )?,
                false,
            ),
        };
        Ok(Merged { vertices, seeds, finished })
    }

    fn take_list(self, c: Contribution) -> Result<Merged, Failure> {
        for (&v, t) in c.vertices.iter().zip(&c.tensors) {
            merge(&mut self.tensors[v as usize], &mut self.reached[v as usize], t);
        }
        Ok(Merged { vertices: c.len(), seeds: c.seeds, finished: false })
    }
}

/// The global bounds of `plan`, if it gives any.
pub fn plan_bounds(plan: &SizingPlan) -> Result<Option<SizeBounds>, SizingError> {
    if plan.h_min.is_none() && plan.h_max.is_none() && plan.max_aspect_ratio.is_none() {
        return Ok(None);
    }
    SizeBounds::try_new(
        plan.h_min.unwrap_or(SizeTensor::MIN_SIZE),
        plan.h_max.unwrap_or(SizeTensor::MAX_SIZE),
        plan.max_aspect_ratio.unwrap_or(f64::INFINITY),
    )
    .map(Some)
    .ok_or(SizingError::InvalidBounds {
        h_min: plan.h_min,
        h_max: plan.h_max,
        max_aspect_ratio: plan.max_aspect_ratio,
    })
}

/// Runs `plan` on the mesh of `graph` and `topology` (see the module header);
/// `observer` hears each step start and finish.
pub fn compute_size_field(
    graph: &MeshGraph,
    topology: &Topology,
    plan: &SizingPlan,
    observer: &mut dyn FnMut(StepEvent),
) -> Result<SizeField, SizingError> {
    let bounds = plan_bounds(plan)?;
    if let Some(g) = plan.gradation {
        if !(g >= 1.0 && g.is_finite()) {
            return Err(SizingError::InvalidGradation(g));
        }
    }
    let n = graph.num_vertices();
    // The default size, known before any step: h_max, or the bounding-box diagonal
    // (an error only where some vertex needs it, reported after the steps as before).
    let diagonal = if plan.h_max.is_none() { bounding_box_diagonal(graph) } else { f64::NAN };
    let default_size =
        plan.h_max.unwrap_or_else(|| diagonal.clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE));
    let diagonal_usable =
        plan.h_max.is_some() || (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&diagonal);
    // The field's last pass, with the default clamped once; the last step may do it in
    // its own pass when the default is sure to be needed as it is.
    let finish = SizeTensor::try_new([1.0, 0.0], default_size, default_size)
        .map(|d| Finish { default: bounds.as_ref().map_or(d, |b| d.clamp(b)), bounds });
    let last_step_finish = finish.filter(|_| diagonal_usable);
    let mut tensors: Vec<SizeTensor> = vec![SizeTensor::isotropic(1.0); n];
    let mut reached = vec![false; n];
    let mut steps = Vec::with_capacity(plan.steps.len());
    let mut warnings = Vec::new();
    let mut finished = false;
    for (index, step) in plan.steps.iter().enumerate() {
        observer(StepEvent::Started { index, label: step.label.clone(), of: plan.steps.len() });
        let last = index + 1 == plan.steps.len();
        let sink = IntoField {
            tensors: &mut tensors,
            reached: &mut reached,
            finish: last_step_finish.filter(|_| last),
        };
        let c = evaluate::run(graph, topology, &step.algorithm, sink)
            .map_err(|f| f.at(index, &step.label))?;
        finished = c.finished;
        if c.vertices == 0 {
            warnings.push(format!("step {index} ({}): reached no vertex", step.label));
        }
        observer(StepEvent::Finished { index, reached: c.vertices });
        steps.push(StepReport {
            label: step.label.clone(),
            algorithm: step.algorithm.keyword(),
            vertices_reached: c.vertices,
            seeds: c.seeds,
        });
    }

    let unreached = reached.iter().filter(|r| !**r).count();
    if plan.h_max.is_none() && unreached > 0 {
        if !diagonal_usable {
            return Err(SizingError::NoDefaultSize(diagonal));
        }
        warnings.push(format!("no h_max: {unreached} vertices that no step reaches get the bounding-box diagonal {diagonal} as their size"));
    }
    let finish = finish.ok_or(SizingError::NoDefaultSize(default_size))?;
    if !finished {
        // The default size and the clamp in one pass over the field.
        tensors.iter_mut().zip(&reached).for_each(|(t, &r)| finish.apply(t, r));
    }
    let gradation = plan.gradation.map(|g| {
        let report = apply_gradation(graph, &mut tensors, g);
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
    Ok(SizeField { tensors, reached, default_size, warnings, steps, gradation })
}

/// Length of the diagonal of the box of the vertices (0 with none), as the graph folded
/// it when it was built ([`MeshGraph::extent`]).
fn bounding_box_diagonal(graph: &MeshGraph) -> f64 {
    graph.extent().map_or(0.0, |(lo, hi)| (hi[0] - lo[0]).hypot(hi[1] - lo[1]))
}
