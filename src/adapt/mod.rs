//! The adaptation loop of thesis 5.5 (Algorithm 5.3): size the current mesh with the
//! recipe, remesh it to that field, and again with the same recipe on the new mesh,
//! until the mesh stops changing or an iteration limit is reached.
//!
//! Iteration 0 is the starting mesh, measured against the recipe's field on it. Each
//! iteration k ≥ 1 remeshes mesh k−1 to field k−1 with the [`Adapter`], computes field k
//! on the new mesh, and measures mesh k against field k ([`Conformity`]): the figures of
//! one [`IterationRecord`]. The loop stops when the vertex count and the conforming share
//! are both stable ([`rules::converged`]), at the iteration limit, or when an iteration
//! fails. The best mesh so far ([`rules::is_better`]) is handed to the [`Observer`]
//! whenever it changes, and the history after every iteration, so that whatever happens
//! later — a failing tool, a killed run — the best mesh and a readable history are
//! there ([`files::ResultFiles`] writes both atomically).
//!
//! Each mesh's topology is built once, for its sizing and for the remeshing that
//! follows, and each mesh is measured once, against the recipe's field on it (the native
//! remesher is asked not to measure). Before each remeshing the field's complexity
//! ([`crate::metric_field::expected_vertices`], computed once per mesh: the solver's
//! record reads the same figure) is compared with [`AdaptOptions::max_vertices`],
//! whatever the remesher: a recipe asking for 10¹² vertices stops the loop at once
//! ([`AdaptError::TooManyVertices`]) instead of filling the memory.
//!
//! Before each remeshing the field's complexity is also compared with the current vertex
//! count: above [`AdaptOptions::max_growth`] times that count, the remesher is given the
//! field scaled down to that many vertices ([`rules::growth_scale`]), so that a coarse
//! starting mesh grows by steps the next sizing resolves instead of overshooting the
//! final count several times over. An iteration remeshed to a scaled field is never the
//! one the loop stops at as converged (its mesh answers another field).
//!
//! The recipe is resolved afresh on every mesh by its tag names, so the same recipe
//! serves every geometry variant with the same tags (thesis 6.3.1: the topology stays,
//! the geometry changes).
//!
//! With a solver ([`run_with_solver`], [`solver`]), each mesh is first handed to it, and
//! the metric of the solution it computes is intersected into the recipe's field on that
//! mesh (after the recipe's steps); a failing solver or a bad solution fails the
//! iteration like a failing remesher, and the best mesh so far stays. With a vertex
//! budget the recipe's field takes at most a share of it and the solution's metric is
//! scaled to the rest ([`budget::share`]).
//!
//! One loop for both dimensions: its skeleton — the best mesh, the stopping rules, the
//! vertex and growth limits, Ctrl-C, the records after every iteration — is
//! `driver`'s; the planar loop here is its 2D stepper, and [`space`] (a tetrahedral
//! mesh through mmg3d, a surface through mmgs, sized by the recipe's 3D engine and
//! measured as the UGAWG does) its 3D one. The solver, the budget, the LAYER skin and
//! periodic sides are the planar stepper's only ([`space`] says why).
//!
//! Once the loop has stopped of itself, the LAYER skin of [`AdaptOptions::layer`] is
//! inserted into the best mesh, its band remeshed to the best iteration's field as the
//! loop computed it ([`skin`]); the periodic sides of [`AdaptOptions::periodic`]
//! (snapped and measured on the starting mesh) are measured again on the result, and a
//! skinned mesh that broke their match is not handed on ([`Outcome::periodic`]).

pub mod budget;
mod driver;
pub mod files;
pub mod rules;
pub mod skin;
pub mod solver;
pub mod space;
pub mod start;

use std::cell::OnceCell;
use std::time::Instant;

use smartmesh_formats::TaggedMesh;

use crate::adapters::{Adapted, Adapter, AdapterError};
use crate::conformity::Conformity;
use crate::history::{
    BudgetRecord, History, IterationRecord, PhaseTimes, RemeshingRecord, SolverRecord,
};
use crate::layer::{LayerOptions, Layered};
use crate::mesh_graph::MeshGraph;
use crate::metric::complexity::format_count;
use crate::metric::Sym2;
use crate::metric_field::{expected_vertices, MetricField};
use crate::periodic::{PeriodicError, Rechecked, Sides};
use crate::recipe::Recipe;
use crate::recipe::{size_mesh_with_steps, SizeMeshError};
use crate::remesh::DEFAULT_MAX_VERTICES;
use crate::topology::Topology;
pub use budget::Budget;
use budget::{normalise, remesher_ratio, share, Limits, RawRecipe};
use solver::{SolverError, SolverLoop};

/// Ctrl-C for the external programs a run starts (a solver, `mmg2d_O3`, `gmsh`):
/// [`interrupt`] lets the current phase end and starts nothing new, [`stop_all`] kills
/// every program under way.
pub use crate::child::{interrupt, stop_all};
pub use rules::Tolerances;

/// `History::stopped` while the loop runs (every record but the last).
pub const RUNNING: &str = "running";

/// `History::stopped` of a run the user stopped ([`Observer::interrupted`]).
pub const INTERRUPTED: &str = "interrupted";
pub use start::{start, start_sized, starting_mesh, Start, StartError};

/// How long the loop may run, when it has converged, and what is done after it.
#[derive(Debug, Clone, PartialEq)]
pub struct AdaptOptions {
    /// Remeshing iterations at most (0: only measure the starting mesh).
    pub max_iterations: usize,
    /// When to stop before the limit.
    pub tolerances: Tolerances,
    /// Most vertices a remeshing may be asked for (the field's complexity); `None`: no
    /// limit.
    pub max_vertices: Option<usize>,
    /// Largest growth of the vertex count in one remeshing ([`rules::growth_scale`]);
    /// `None`: the field as it is.
    pub max_growth: Option<f64>,
    /// The LAYER skin inserted into the best mesh once the loop has stopped of itself
    /// ([`skin`]); `None`: none.
    pub layer: Option<LayerOptions>,
    /// The periodic sides of the starting mesh, snapped and measured
    /// ([`Sides::snap_and_check`]), measured again on the result.
    pub periodic: Sides,
    /// The vertex budget: the field on every mesh (the recipe's, the solution's, or both
    /// intersected) normalised to it with the recipe's bounds and gradation inside
    /// ([`budget`]); `None`: the field as the recipe and the solution give it.
    pub budget: Option<Budget>,
}

/// The default [`AdaptOptions::max_growth`].
pub const DEFAULT_MAX_GROWTH: f64 = 4.0;

impl Default for AdaptOptions {
    fn default() -> Self {
        AdaptOptions {
            max_iterations: 8,
            tolerances: Tolerances::default(),
            max_vertices: Some(DEFAULT_MAX_VERTICES),
            max_growth: Some(DEFAULT_MAX_GROWTH),
            layer: None,
            periodic: Sides::default(),
            budget: None,
        }
    }
}

/// The phases of an iteration, for progress and errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Running the solver on the current mesh.
    Solve,
    /// Computing the recipe's field on the current mesh.
    Size,
    /// Remeshing to the field.
    Remesh,
    /// Measuring conformity and quality.
    Measure,
}

impl std::fmt::Display for Phase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Phase::Solve => "solving",
            Phase::Size => "sizing",
            Phase::Remesh => "remeshing",
            Phase::Measure => "measuring",
        })
    }
}

/// What went wrong in one phase.
#[derive(Debug, thiserror::Error)]
pub enum PhaseError {
    /// The recipe gave no field on the mesh.
    #[error("{0}")]
    Sizing(#[from] SizeMeshError),
    /// The remesher gave no mesh.
    #[error("{0}")]
    Remesh(#[from] AdapterError),
    /// The solver gave no usable solution.
    #[error("{0}")]
    Solver(#[from] SolverError),
    /// The mesh has no triangle to measure.
    #[error("the mesh has no triangle")]
    NoTriangle,
    /// The 3D sizing gave no field on a mesh in space ([`space::SpaceSizing`]).
    #[error("{0}")]
    Space(space::SpaceSizingError),
    /// A mesh in space has neither tetrahedra nor triangles to measure.
    #[error("the mesh has no tetrahedron and no triangle")]
    NoCell,
}

impl PhaseError {
    /// Whether an external program was stopped because the user interrupted the run.
    pub fn is_interrupted(&self) -> bool {
        matches!(
            self,
            PhaseError::Solver(SolverError::Interrupted { .. })
                | PhaseError::Remesh(AdapterError::Interrupted { .. })
        )
    }
}

/// Why the loop stopped before its end.
#[derive(Debug, thiserror::Error)]
pub enum AdaptError {
    /// The starting mesh could not be sized or measured: bad input, nothing is written.
    #[error("the starting mesh ({phase}): {source}")]
    Start {
        /// The phase that failed.
        phase: Phase,
        /// What failed.
        source: PhaseError,
    },
    /// Iteration `iteration` failed; the best mesh so far has been handed on.
    #[error("iteration {iteration} failed while {phase}: {source}")]
    Iteration {
        /// The iteration, from 1.
        iteration: usize,
        /// The phase that failed.
        phase: Phase,
        /// What failed.
        source: PhaseError,
    },
    /// The field on the current mesh asks for more vertices than the limit: iteration
    /// `iteration` was not run; the best mesh so far has been handed on.
    #[error("iteration {iteration} refused: the recipe's field on the mesh of iteration {} asks for about {} vertices (its complexity), more than the limit of {limit}; raise it with --max-vertices, or raise the recipe's hmin", iteration - 1, format_count(*estimate))]
    TooManyVertices {
        /// The iteration refused, from 1.
        iteration: usize,
        /// The vertices the field asks for.
        estimate: f64,
        /// The limit.
        limit: usize,
    },
    /// The user interrupted the run before the starting mesh was measured (its solver
    /// was stopped): nothing is written.
    #[error("interrupted while {phase} the starting mesh; nothing was written")]
    Interrupted {
        /// The phase under way.
        phase: Phase,
    },
    /// The loop in space was asked for what only the planar loop does
    /// ([`space::run_space`]).
    #[error("{0} works on planar meshes only: the loop in space has none")]
    Planar(&'static str),
    /// The loop on a surface in space was asked for what needs volume cells
    /// ([`space::run_space_with_solver`]); the text says why.
    #[error("a surface in space: {0}")]
    Surface(&'static str),
    /// The observer could not write the result or the history.
    #[error("{0}")]
    Output(#[from] smartmesh_formats::Error),
    /// The LAYER step failed: nothing more was written (the loop's best mesh is).
    #[error(transparent)]
    Layer(#[from] skin::SkinError),
    /// The observer could not write the skinned mesh and the history naming it.
    #[error("writing the skinned mesh and its history: {0}")]
    LayerOutput(#[source] smartmesh_formats::Error),
}

impl AdaptError {
    /// Whether a vertex limit stopped the loop (valid input that asks for more than the
    /// user allowed), rather than a failure of the work.
    pub fn is_limit(&self) -> bool {
        matches!(
            self,
            AdaptError::TooManyVertices { .. }
                | AdaptError::Iteration { source: PhaseError::Remesh(AdapterError::Limit(_)), .. }
        )
    }
}

/// Sees the loop's progress, and keeps its results.
pub trait Observer {
    /// `phase` of `iteration` starts (for a progress display).
    fn phase(&mut self, _iteration: usize, _phase: Phase) {}

    /// Whether the user asked the run to stop (Ctrl-C). Asked before each remeshing and
    /// after it, and when a phase fails: the loop then stops with `stopped` =
    /// [`INTERRUPTED`], keeping the best mesh and the history of the iterations done (a
    /// remeshing or a solver run under way is discarded: an external program is stopped
    /// by [`crate::child::interrupt`], which whoever handles the signal calls).
    fn interrupted(&mut self) -> bool {
        false
    }

    /// Called after every iteration and once more when the loop stops, with the whole
    /// history so far; `new_best` is the mesh of the iteration just done when it became
    /// the best. An error stops the loop.
    fn record(
        &mut self,
        history: &History,
        new_best: Option<&TaggedMesh>,
    ) -> Result<(), smartmesh_formats::Error>;
}

/// How a run ended: the history, the best mesh, and the failure that stopped it early,
/// if one did (the best mesh is then still the best of the iterations done).
#[derive(Debug)]
pub struct Outcome {
    /// The history as last handed to the observer.
    pub history: History,
    /// The best mesh, that of `history.best_iteration`.
    pub best: TaggedMesh,
    /// The best mesh with its LAYER skin, when [`AdaptOptions::layer`] asked for one and
    /// the loop stopped of itself. It is the run's result, handed to the observer with
    /// the history naming it (`history.layer`), unless it broke a periodic match.
    pub layer: Option<Layered>,
    /// The periodic sides measured on the result (`layer`'s mesh, else `best`).
    pub periodic: Result<Rechecked, PeriodicError>,
    /// The failure of a later iteration, if any.
    pub failure: Option<AdaptError>,
    /// What the sizing engine warned about (each message once, with the first iteration
    /// that gave it).
    pub warnings: Vec<String>,
}

/// A mesh, its topology, the recipe's field on it as metrics, and its record.
struct Measured {
    mesh: TaggedMesh,
    topology: Topology,
    metric: Vec<Sym2>,
    /// The vertex count `metric` asks for on `mesh`, computed at most once per mesh: for
    /// the solver's record and for the check before the next remeshing.
    expected: OnceCell<f64>,
    record: IterationRecord,
    warnings: Vec<String>,
}

impl Measured {
    /// The vertex count the mesh's field asks for ([`expected_vertices`]).
    fn expected(&self) -> f64 {
        *self.expected.get_or_init(|| expected_vertices(&self.mesh, &self.metric))
    }
}

/// How each mesh is sized: the recipe, and with a budget the raw recipe, the vertex
/// count the field is normalised to and the recipe's largest share of it.
struct Sizer<'a> {
    recipe: &'a Recipe,
    budget: Option<(&'a RawRecipe, f64, f64)>,
}

/// The recipe's field on `mesh` (with `extra` steps after its own), normalised to the
/// budget when there is one: a recipe with steps and a solution's `extra` steps share it
/// ([`budget::share`]), any other field is scaled as a whole ([`normalise`]).
fn size_field(
    mesh: &TaggedMesh,
    topology: &Topology,
    sizer: &Sizer<'_>,
    extra: &[crate::sizing::plan::Step],
) -> Result<(Vec<crate::metric::SizeTensor>, Vec<String>), SizeMeshError> {
    let Some((raw, target, recipe_share)) = sizer.budget else {
        let sizing = size_mesh_with_steps(mesh, topology, sizer.recipe, extra, &mut |_| {})?;
        return Ok((sizing.field.tensors, sizing.field.warnings));
    };
    let graph = match raw.gradation {
        Some(_) => Some(MeshGraph::from_topology(topology, mesh).map_err(SizeMeshError::Graph)?),
        None => None,
    };
    let limits = Limits { bounds: raw.bounds, gradation: raw.gradation.zip(graph.as_ref()) };
    let (b, mut warnings) = if raw.has_steps() && !extra.is_empty() {
        let r = size_mesh_with_steps(mesh, topology, &raw.recipe, &[], &mut |_| {})?;
        let s = size_mesh_with_steps(mesh, topology, &raw.empty, extra, &mut |_| {})?;
        let mut warnings = r.field.warnings;
        warnings.extend(s.field.warnings);
        let b = share(mesh, &r.field.tensors, &s.field.tensors, &limits, target, recipe_share);
        (b, warnings)
    } else {
        let sizing = size_mesh_with_steps(mesh, topology, &raw.recipe, extra, &mut |_| {})?;
        (normalise(mesh, &sizing.field.tensors, &limits, target), sizing.field.warnings)
    };
    warnings.extend(budget::unreached(b.reached, b.vertices, target));
    Ok((b.tensors, warnings))
}

/// Sizes and measures `mesh` as iteration `iteration`; `remesh` is the time already spent
/// making it, `remeshing` what that remeshing did.
fn measure(
    iteration: usize,
    mesh: TaggedMesh,
    remesh: f64,
    remeshing: Option<RemeshingRecord>,
    sizer: &Sizer<'_>,
    solver: Option<&SolverLoop>,
    observer: &mut dyn Observer,
) -> Result<Measured, (Phase, PhaseError)> {
    let mut mesh = mesh;
    let mut solved = None;
    let mut extra = Vec::new();
    if let Some(s) = solver {
        observer.phase(iteration, Phase::Solve);
        let done = s.solve(iteration, &mut mesh).map_err(|e| (Phase::Solve, e.into()))?;
        extra.push(s.step(iteration, &done.fields));
        solved = Some(done);
    }
    observer.phase(iteration, Phase::Size);
    let t = Instant::now();
    let topology = Topology::from_mesh(&mesh);
    let (tensors, warnings) =
        size_field(&mesh, &topology, sizer, &extra).map_err(|e| (Phase::Size, e.into()))?;
    let metric: Vec<Sym2> = tensors.iter().map(|t| t.to_metric()).collect();
    let size = t.elapsed().as_secs_f64();
    let expected = OnceCell::new();
    let solver = solved.map(|d| SolverRecord {
        seconds: d.seconds,
        field: d.fields.join(","),
        fields: d.fields,
        complexity_asked: d.complexity_asked,
        complexity_obtained: *expected.get_or_init(|| expected_vertices(&mesh, &metric)),
    });
    // The result carries the recipe's field on it (`metric`, `size_tensor`, `h1` …, as
    // `size` writes them), so that `report`, `info --metric` and ParaView read one file.
    mesh.point_data.extend(MetricField::from_sizes(&tensors, "the recipe's field").arrays());
    observer.phase(iteration, Phase::Measure);
    let t = Instant::now();
    let c = Conformity::of_mesh(&mesh, &metric).ok_or((Phase::Measure, PhaseError::NoTriangle))?;
    let record = IterationRecord {
        iteration,
        vertices: mesh.points.len(),
        triangles: c.triangles,
        conforming_share: c.conforming_share,
        mean_edge_length: c.mean_edge_length,
        mean_quality: c.mean_quality,
        min_quality: c.min_quality,
        seconds: PhaseTimes { size, remesh, measure: t.elapsed().as_secs_f64() },
        remeshing,
        solver,
        space: None,
    };
    Ok(Measured { mesh, topology, metric, expected, record, warnings })
}

/// Runs the loop from `start` with `recipe` and `adapter`. `input` and `recipe_label`
/// name the input and the recipe in the history, as the user gave them.
pub fn run(
    start: TaggedMesh,
    recipe: &Recipe,
    adapter: &dyn Adapter,
    options: &AdaptOptions,
    input: &str,
    recipe_label: &str,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdaptError> {
    run_with_solver(start, recipe, None, adapter, options, input, recipe_label, observer)
}

/// The planar half of the loop ([`driver::Stepper`]): the recipe's 2D field (with the
/// solver's metric and the budget), [`Conformity`], `Adapter::adapt`.
struct Planar<'a> {
    recipe: &'a Recipe,
    raw: Option<RawRecipe>,
    solver: Option<&'a SolverLoop>,
    adapter: &'a dyn Adapter,
    options: &'a AdaptOptions,
    /// The ratio of vertices made to vertices asked of the last remeshing to a field not
    /// growth-limited (the budget is divided by it).
    ratio: f64,
}

impl Planar<'_> {
    /// The vertex count of iteration k's field: the budget's, divided by the remesher's
    /// ratio of made to asked measured on the last remeshing.
    /// With the recipe's largest share of it.
    fn target(&self, k: usize) -> Option<(&RawRecipe, f64, f64)> {
        let b = self.options.budget.as_ref()?;
        Some((self.raw.as_ref()?, b.schedule.at(k) / self.ratio, b.recipe_share))
    }
}

impl driver::Stepper for Planar<'_> {
    type State = Measured;
    type Best = Vec<Sym2>;

    fn dimension(&self) -> u8 {
        2
    }

    fn measure(
        &mut self,
        iteration: usize,
        mesh: TaggedMesh,
        seconds: f64,
        remeshing: Option<RemeshingRecord>,
        observer: &mut dyn Observer,
    ) -> Result<Measured, (Phase, PhaseError)> {
        let sizer = Sizer { recipe: self.recipe, budget: self.target(iteration) };
        measure(iteration, mesh, seconds, remeshing, &sizer, self.solver, observer)
    }

    fn remesh(&self, state: &Measured, scale: Option<f64>) -> Result<Adapted, AdapterError> {
        let scaled: Option<Vec<Sym2>> =
            scale.map(|s| state.metric.iter().map(|&m| s * m).collect());
        self.adapter.adapt(&state.mesh, &state.topology, scaled.as_deref().unwrap_or(&state.metric))
    }

    fn expected(&self, state: &Measured) -> f64 {
        state.expected()
    }

    fn record<'s>(&self, state: &'s Measured) -> &'s IterationRecord {
        &state.record
    }

    fn mesh<'s>(&self, state: &'s Measured) -> &'s TaggedMesh {
        &state.mesh
    }

    fn warnings<'s>(&self, state: &'s Measured) -> &'s [String] {
        &state.warnings
    }

    fn best(&self, state: &Measured) -> Vec<Sym2> {
        // The field the best mesh was measured against: the LAYER step's band is
        // remeshed to it.
        state.metric.clone()
    }

    fn remeshed(
        &mut self,
        k: usize,
        made: usize,
        expected: f64,
        scaled: bool,
        history: &mut History,
    ) {
        // A growth-limited remeshing of a coarse mesh measures the coarse mesh's
        // sampling of the field more than the remesher: its ratio is not kept.
        if !scaled {
            self.ratio = remesher_ratio(made, expected);
        }
        let t = self.target(k).map(|t| t.1);
        if let (Some(b), Some(t)) = (&mut history.budget, t) {
            b.normalised_to.push(t);
        }
    }

    fn on_budget(&self, r: &IterationRecord) -> Option<bool> {
        self.options.budget.as_ref().map(|b| budget::within(r.vertices, b.schedule.at(r.iteration)))
    }
}

/// [`run`] with a solver: each mesh is solved on, and its solution's metric intersected
/// into the recipe's field (see the module documentation).
#[allow(clippy::too_many_arguments)]
pub fn run_with_solver(
    start: TaggedMesh,
    recipe: &Recipe,
    solver: Option<&SolverLoop>,
    adapter: &dyn Adapter,
    options: &AdaptOptions,
    input: &str,
    recipe_label: &str,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdaptError> {
    let raw = options.budget.as_ref().and_then(|b| RawRecipe::of(recipe, b.hard));
    let mut planar = Planar { recipe, raw, solver, adapter, options, ratio: 1.0 };
    let first_target = planar.target(0).map(|t| t.1);
    let history = starting_history(input, recipe_label, adapter, options, first_target);
    let driven = driver::drive(&mut planar, start, history, options, observer)?;
    let driver::Driven { mut history, best, best_kept: best_metric, failure, warnings } = driven;
    let layer = match &options.layer {
        Some(o) if failure.is_none() && history.stopped != INTERRUPTED => {
            let max_vertices = options.max_vertices.unwrap_or(DEFAULT_MAX_VERTICES);
            Some(skin::skin(&best, &best_metric, o, max_vertices)?)
        }
        _ => None,
    };
    let periodic = options.periodic.recheck(layer.as_ref().map_or(&best, |l| &l.mesh));
    if let (Some(l), Ok(Rechecked { broken: None, .. })) = (&layer, &periodic) {
        // The skinned mesh and the history that describes it (its size, CRC and counts)
        // are handed on as one set, as every new best mesh of the loop was.
        history.layer = Some(skin::record(l));
        observer.record(&history, Some(&l.mesh)).map_err(AdaptError::LayerOutput)?;
    }
    Ok(Outcome { history, best, layer, periodic, failure, warnings })
}

/// The history of a run before its first iteration, in the plane and in space: nothing
/// converged, the run going on, and the budget (if any) with the count the field on the
/// start mesh is normalised to (`first_target`).
pub(crate) fn starting_history(
    input: &str,
    recipe_label: &str,
    adapter: &dyn Adapter,
    options: &AdaptOptions,
    first_target: Option<f64>,
) -> History {
    History {
        input: input.to_string(),
        recipe: recipe_label.to_string(),
        adapter: adapter.name().to_string(),
        converged: false,
        best_iteration: 0,
        stopped: RUNNING.to_string(),
        iterations: Vec::new(),
        best_mesh: Vec::new(),
        layer: None,
        budget: options.budget.as_ref().map(|b| BudgetRecord {
            vertices: b.schedule.target,
            from: b.from.clone(),
            normalised_to: first_target.into_iter().collect(),
        }),
    }
}
