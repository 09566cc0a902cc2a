//! The loop on a mesh in space: a tetrahedral mesh remeshed by `mmg3d_O3`, a
//! triangulated surface by `mmgs_O3` ([`Adapter::adapt_space`]), each mesh sized with a
//! 3D field ([`SpaceSizing`]: the recipe's, [`RecipeInSpace`], or any function of the
//! mesh) and measured as the UGAWG does
//! ([`Ugawg::of_mesh_3d`]: the share of edges of metric length in [1/√2, √2], the
//! mean-ratio quality of each cell in the Log-Euclidean mean of its corners' metrics).
//!
//! The loop itself — the best mesh, the stopping rules, the vertex limit, the growth
//! limit, Ctrl-C, the history and result files after every iteration — is the planar
//! loop's (`super::driver`); this file is only the `Stepper` of space. Each record
//! carries the 3D measures ([`SpaceRecord`]); its `triangles` counts the boundary (or
//! surface) triangles. Each mesh handed on carries the field it was measured against
//! (`metric`, `size_tensor`, `h1`…`h3`, `anisotropy`, `axis1`…`axis3`), as `size` writes
//! a 3D field, so that `info --metric` and ParaView read one file.
//!
//! The solver (`--solver`) and the vertex budget (`--complexity`) are the planar loop's
//! too, through the same pieces: the solver runs on each mesh before it is sized
//! ([`SolverLoop::solve`], the same files, script and checks), its field's Hessian is
//! recovered on the tetrahedra and made the Lp-optimal metric in 3D (a SOLUTION_HESSIAN
//! step after the recipe's, as in 2D), and with a budget the recipe's raw field, the
//! solution's metric or both are normalised by [`super::budget`]'s one root find
//! ([`super::budget::normalise3`], [`super::budget::share3`]: the complexity over the
//! tetrahedra, the bounds and the 3D gradation inside the scaling), the target corrected
//! by what the remesher made of the last fields ([`super::budget::corrected_target`]: the
//! planar loop's ratio of made to asked, then the secant through the last two, as
//! mmg3d's ratio drifts with the field's count).
//!
//! What the loop in space has not, and why:
//! - the LAYER skin and periodic sides: both are planar algorithms (`layer`, `periodic`);
//! - on a surface in space (no volume cell), the vertex budget and the solver: the
//!   complexity is an integral over volume cells
//!   ([`crate::metric_field::expected_vertices`]), so a surface's field asks for no
//!   count, and the Hessian is recovered on tetrahedra. Neither the vertex limit nor the
//!   growth limit acts there: the field goes to `mmgs_O3` as it is.
//!
//! [`run_space`] refuses options that ask for them ([`AdaptError::Planar`],
//! [`AdaptError::Surface`]), before any work.

use std::time::Instant;

use smartmesh_formats::{CellKind, TaggedMesh};

use super::budget::{self, corrected_target, normalise3, share3, Limits3, RawRecipe};
use super::driver::{self, Stepper};
use super::solver::SolverLoop;
use super::{AdaptError, AdaptOptions, Observer, Outcome, Phase, PhaseError};
use crate::adapters::{Adapted, Adapter, AdapterError};
use crate::conformity::Ugawg;
use crate::history::{
    History, IterationRecord, PhaseTimes, RemeshingRecord, SolverRecord, SpaceRecord,
};
use crate::metric::{SizeBounds, SizeTensor, SizeTensor3, Sym3};
use crate::metric_field::{expected_vertices, Complexity, MetricField};
use crate::periodic::Rechecked;
use crate::recipe::{size_mesh_in_space, Recipe};
use crate::sizing::{SpaceMesh, Step};
use crate::topology::Topology;

/// A 3D field on a mesh: one SPD tensor per point, and what the sizing warned about.
#[derive(Debug, Clone, PartialEq)]
pub struct SpaceField {
    /// One metric per point of the mesh.
    pub metric: Vec<Sym3>,
    /// The sizing's warnings on this mesh.
    pub warnings: Vec<String>,
}

/// Why a mesh in space got no field: the sizing's own error, as it says it.
pub type SpaceSizingError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// What the field on a mesh of the loop in space is normalised to (the planar loop's
/// [`super::Budget`] at one iteration): a vertex count, the hard h_min and h_max of the
/// command line, and the recipe's largest share of the count beside a solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normalisation {
    /// The vertex count.
    pub target: f64,
    /// The hard h_min and h_max (the recipe's own scale with the field).
    pub hard: (Option<f64>, Option<f64>),
    /// The recipe's largest share of `target` beside a solution ([`budget::share3`]).
    pub recipe_share: f64,
}

/// How each mesh of the loop in space is sized (the recipe's 3D sizing in the CLI; an
/// analytic field in tests).
pub trait SpaceSizing {
    /// The field on `mesh`.
    fn size(&self, mesh: &TaggedMesh) -> Result<SpaceField, SpaceSizingError>;

    /// The field on `mesh` with `extra` steps after its own (a solution's), normalised
    /// to `budget` when given. By default: [`SpaceSizing::size`] alone (no step can be
    /// added to it), normalised as a whole within the hard bounds, with no gradation.
    fn size_for(
        &self,
        mesh: &TaggedMesh,
        extra: &[Step],
        budget: Option<&Normalisation>,
    ) -> Result<SpaceField, SpaceSizingError> {
        if !extra.is_empty() {
            return Err("a solution's metric is intersected into a recipe's field: this sizing takes no step".into());
        }
        let field = self.size(mesh)?;
        let Some(b) = budget else { return Ok(field) };
        let bounds = SizeBounds::try_new(
            b.hard.0.unwrap_or(SizeTensor::MIN_SIZE),
            b.hard.1.unwrap_or(SizeTensor::MAX_SIZE),
            f64::INFINITY,
        )
        .ok_or("--hmin and --hmax are no range")?;
        let mut raw = Vec::with_capacity(field.metric.len());
        for (v, m) in field.metric.iter().enumerate() {
            raw.push(SizeTensor3::try_from_metric(m).map_err(|e| format!("vertex {v}: {e}"))?);
        }
        let limits = Limits3 { bounds, gradation: None };
        let b3 = normalise3(mesh, &raw, &limits, b.target);
        let mut warnings = field.warnings;
        warnings.extend(budget::unreached(b3.reached, b3.vertices, b.target));
        let metric = b3.tensors.iter().map(SizeTensor3::to_metric).collect();
        Ok(SpaceField { metric, warnings })
    }
}

impl<F> SpaceSizing for F
where
    F: Fn(&TaggedMesh) -> Result<SpaceField, SpaceSizingError>,
{
    fn size(&self, mesh: &TaggedMesh) -> Result<SpaceField, SpaceSizingError> {
        self(mesh)
    }
}

/// The recipe's 3D field on each mesh ([`size_mesh_in_space`]), its regions found again
/// on every mesh by their tag names (the topology of each mesh built afresh).
#[derive(Debug, Clone, Copy)]
pub struct RecipeInSpace<'a>(pub &'a Recipe);

impl SpaceSizing for RecipeInSpace<'_> {
    fn size(&self, mesh: &TaggedMesh) -> Result<SpaceField, SpaceSizingError> {
        self.size_for(mesh, &[], None)
    }

    /// The recipe's field (with `extra` steps after its own), normalised to the budget
    /// as the planar loop's is: a recipe with steps and a solution's steps share it
    /// ([`share3`]), any other field is scaled as a whole ([`normalise3`]), the recipe's
    /// gradation and the hard bounds inside the scaling.
    fn size_for(
        &self,
        mesh: &TaggedMesh,
        extra: &[Step],
        budget: Option<&Normalisation>,
    ) -> Result<SpaceField, SpaceSizingError> {
        let topology = Topology::from_mesh(mesh);
        let to_metric = |t: &[SizeTensor3]| t.iter().map(SizeTensor3::to_metric).collect();
        // Bounds that are no range are said by the sizing engine, on the recipe itself.
        let raw = budget.and_then(|b| Some((b, RawRecipe::of(self.0, b.hard)?)));
        let Some((b, raw)) = raw else {
            let sized = size_mesh_in_space(mesh, &topology, self.0, extra, &mut |_| {})?;
            return Ok(SpaceField {
                metric: to_metric(&sized.field.tensors),
                warnings: sized.field.warnings,
            });
        };
        let space = match raw.gradation {
            Some(_) => Some(SpaceMesh::new(mesh, &topology)?),
            None => None,
        };
        let limits = Limits3 { bounds: raw.bounds, gradation: raw.gradation.zip(space.as_ref()) };
        let (b3, mut warnings) = if raw.has_steps() && !extra.is_empty() {
            let r = size_mesh_in_space(mesh, &topology, &raw.recipe, &[], &mut |_| {})?;
            let s = size_mesh_in_space(mesh, &topology, &raw.empty, extra, &mut |_| {})?;
            let mut warnings = r.field.warnings;
            warnings.extend(s.field.warnings);
            let shared =
                share3(mesh, &r.field.tensors, &s.field.tensors, &limits, b.target, b.recipe_share);
            (shared, warnings)
        } else {
            let sized = size_mesh_in_space(mesh, &topology, &raw.recipe, extra, &mut |_| {})?;
            (normalise3(mesh, &sized.field.tensors, &limits, b.target), sized.field.warnings)
        };
        warnings.extend(budget::unreached(b3.reached, b3.vertices, b.target));
        Ok(SpaceField { metric: to_metric(&b3.tensors), warnings })
    }
}

/// A mesh in space with its field and record.
struct InSpace {
    mesh: TaggedMesh,
    metric: Vec<Sym3>,
    /// The vertex count `metric` asks for on `mesh` (0 on a surface).
    expected: f64,
    record: IterationRecord,
    warnings: Vec<String>,
}

/// The half of the loop in space ([`Stepper`]).
struct Space<'a> {
    sizing: &'a dyn SpaceSizing,
    solver: Option<&'a SolverLoop>,
    adapter: &'a dyn Adapter,
    options: &'a AdaptOptions,
    /// The vertices asked and made of the remeshings to fields not growth-limited, oldest
    /// first: the next target is corrected by them ([`budget::corrected_target`]).
    remeshings: Vec<(f64, usize)>,
}

impl Space<'_> {
    /// What iteration k's field is normalised to: the budget's count corrected by what
    /// the remesher made of the last fields; `None` without a budget.
    fn target(&self, k: usize) -> Option<Normalisation> {
        let b = self.options.budget.as_ref()?;
        Some(Normalisation {
            target: corrected_target(b.schedule.at(k), &self.remeshings),
            hard: b.hard,
            recipe_share: b.recipe_share,
        })
    }
}

impl Stepper for Space<'_> {
    type State = InSpace;
    type Best = ();

    fn dimension(&self) -> u8 {
        3
    }

    fn measure(
        &mut self,
        iteration: usize,
        mut mesh: TaggedMesh,
        remesh: f64,
        remeshing: Option<RemeshingRecord>,
        observer: &mut dyn Observer,
    ) -> Result<InSpace, (Phase, PhaseError)> {
        let mut solved = None;
        let mut extra = Vec::new();
        if let Some(s) = self.solver {
            observer.phase(iteration, Phase::Solve);
            let done = s.solve(iteration, &mut mesh).map_err(|e| (Phase::Solve, e.into()))?;
            extra.push(s.step(iteration, &done.fields));
            solved = Some(done);
        }
        observer.phase(iteration, Phase::Size);
        let t = Instant::now();
        let target = self.target(iteration);
        let field = self
            .sizing
            .size_for(&mesh, &extra, target.as_ref())
            .map_err(|e| (Phase::Size, PhaseError::Space(e)))?;
        if field.metric.len() != mesh.points.len() {
            let e = format!(
                "the field has {} tensors for {} vertices",
                field.metric.len(),
                mesh.points.len()
            );
            return Err((Phase::Size, PhaseError::Space(e.into())));
        }
        let size = t.elapsed().as_secs_f64();
        let SpaceField { metric, warnings } = field;
        observer.phase(iteration, Phase::Measure);
        let t = Instant::now();
        let u = Ugawg::of_mesh_3d(&mesh, &metric).ok_or((Phase::Measure, PhaseError::NoCell))?;
        let expected = expected_vertices(&mesh, &metric);
        let measure = t.elapsed().as_secs_f64();
        let solver = solved.map(|d| SolverRecord {
            seconds: d.seconds,
            field: d.fields.join(","),
            fields: d.fields,
            complexity_asked: d.complexity_asked,
            complexity_obtained: expected,
        });
        let record = IterationRecord {
            iteration,
            vertices: mesh.points.len(),
            triangles: mesh.num_cells_of(CellKind::Triangle),
            conforming_share: u.conforming_share,
            mean_edge_length: u.mean_edge_length,
            mean_quality: u.mean_quality,
            min_quality: u.min_quality,
            seconds: PhaseTimes { size, remesh, measure },
            remeshing,
            solver,
            space: Some(SpaceRecord {
                cell: u.cell.to_string(),
                cells: u.cells,
                edges: u.edges,
                edge_length_range: u.edge_length_range,
                geometric_mean_edge_length: u.geometric_mean_edge_length,
                geometric_mean_quality: u.geometric_mean_quality,
                non_positive: u.non_positive,
            }),
        };
        // The mesh handed on carries the field it was measured against.
        mesh.point_data.extend(MetricField::new(metric.clone(), "the recipe's field").arrays_3d());
        Ok(InSpace { mesh, metric, expected, record, warnings })
    }

    fn remesh(&self, state: &InSpace, scale: Option<f64>) -> Result<Adapted, AdapterError> {
        let scaled: Option<Vec<Sym3>> =
            scale.map(|s| state.metric.iter().map(|&m| s * m).collect());
        self.adapter.adapt_space(&state.mesh, scaled.as_deref().unwrap_or(&state.metric))
    }

    fn expected(&self, state: &InSpace) -> f64 {
        state.expected
    }

    fn record<'s>(&self, state: &'s InSpace) -> &'s IterationRecord {
        &state.record
    }

    fn mesh<'s>(&self, state: &'s InSpace) -> &'s TaggedMesh {
        &state.mesh
    }

    fn warnings<'s>(&self, state: &'s InSpace) -> &'s [String] {
        &state.warnings
    }

    fn best(&self, _state: &InSpace) {}

    fn remeshed(
        &mut self,
        k: usize,
        made: usize,
        expected: f64,
        scaled: bool,
        history: &mut History,
    ) {
        // As in the planar loop: a growth-limited remeshing measures the coarse mesh's
        // sampling of the field more than the remesher, and is not kept.
        if !scaled && expected > 0.0 {
            self.remeshings.push((expected, made));
        }
        if let (Some(b), Some(t)) = (&mut history.budget, self.target(k)) {
            b.normalised_to.push(t.target);
        }
    }

    fn on_budget(&self, r: &IterationRecord) -> Option<bool> {
        self.options.budget.as_ref().map(|b| budget::within(r.vertices, b.schedule.at(r.iteration)))
    }
}

/// Runs the loop in space from `start` (a tetrahedral mesh, or a triangulated surface in
/// space) with `sizing` and `adapter` (mmg3d or mmgs). `input` and `recipe_label` name the
/// input and the recipe in the history. `options.layer` and periodic sides are planar:
/// asking for them is [`AdaptError::Planar`], before any work.
pub fn run_space(
    start: TaggedMesh,
    sizing: &dyn SpaceSizing,
    adapter: &dyn Adapter,
    options: &AdaptOptions,
    input: &str,
    recipe_label: &str,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdaptError> {
    run_space_with_solver(start, sizing, None, adapter, options, input, recipe_label, observer)
}

/// [`run_space`] with a solver: each mesh is solved on, and its solution's metric
/// intersected into the field (see the module documentation). On a surface (no volume
/// cell) a budget or a solver is [`AdaptError::Surface`], before any work.
#[allow(clippy::too_many_arguments)]
pub fn run_space_with_solver(
    start: TaggedMesh,
    sizing: &dyn SpaceSizing,
    solver: Option<&SolverLoop>,
    adapter: &dyn Adapter,
    options: &AdaptOptions,
    input: &str,
    recipe_label: &str,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdaptError> {
    if options.layer.is_some() {
        return Err(AdaptError::Planar("the LAYER skin"));
    }
    if !options.periodic.pairs.is_empty() {
        return Err(AdaptError::Planar("periodic sides"));
    }
    if <Sym3 as Complexity>::simplices(&start).is_empty() {
        if options.budget.is_some() {
            return Err(AdaptError::Surface(SURFACE_BUDGET));
        }
        if solver.is_some() {
            return Err(AdaptError::Surface(SURFACE_SOLVER));
        }
    }
    let mut space = Space { sizing, solver, adapter, options, remeshings: Vec::new() };
    let first_target = space.target(0).map(|t| t.target);
    let history = super::starting_history(input, recipe_label, adapter, options, first_target);
    let driven = driver::drive(&mut space, start, history, options, observer)?;
    let driver::Driven { history, best, failure, warnings, .. } = driven;
    let periodic = Ok(Rechecked::default());
    Ok(Outcome { history, best, layer: None, periodic, failure, warnings })
}

/// Why a surface in space takes no vertex budget.
pub const SURFACE_BUDGET: &str = "the vertex budget (--complexity) counts the vertices a field asks for by its complexity, an integral of √det M over volume cells: a surface in space has none, so its field asks for no count (mmgs takes the recipe's field as it is; --hmin and --hmax bound it)";

/// Why a surface in space takes no solver.
pub const SURFACE_SOLVER: &str = "a solver's metric (--solver) comes from its solution's Hessian, recovered on tetrahedra: a surface in space has none";

#[cfg(test)]
#[path = "space_tests.rs"]
mod tests;
