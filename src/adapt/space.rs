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
//! What the planar loop has and this one has not, and why:
//! - the solver (`--solver`): its metric is a 2D Hessian's (`sizing::solution`);
//! - the LAYER skin and periodic sides: both are planar algorithms (`layer`, `periodic`);
//! - the vertex budget (`--complexity`): it normalises the recipe's raw field with its
//!   bounds and gradation inside the scaling ([`super::budget`]), which needs the 3D
//!   sizing's raw field and a 3D gradation on the mesh's graph.
//!
//! [`run_space`] refuses options that ask for them ([`AdaptError::Planar`]). On a
//! surface the complexity is not taken (it is an integral over volume cells,
//! [`crate::metric_field::expected_vertices`]), so neither the vertex limit nor the
//! growth limit acts there: the field goes to `mmgs_O3` as it is.

use std::time::Instant;

use smartmesh_formats::{CellKind, TaggedMesh};

use super::driver::{self, Stepper};
use super::{AdaptError, AdaptOptions, Observer, Outcome, Phase, PhaseError, RUNNING};
use crate::adapters::{Adapted, Adapter, AdapterError};
use crate::conformity::Ugawg;
use crate::history::{History, IterationRecord, PhaseTimes, RemeshingRecord, SpaceRecord};
use crate::metric::{SizeTensor3, Sym3};
use crate::metric_field::{expected_vertices, MetricField};
use crate::periodic::Rechecked;
use crate::recipe::{size_mesh_in_space, Recipe};
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

/// How each mesh of the loop in space is sized (the recipe's 3D sizing in the CLI; an
/// analytic field in tests).
pub trait SpaceSizing {
    /// The field on `mesh`.
    fn size(&self, mesh: &TaggedMesh) -> Result<SpaceField, SpaceSizingError>;
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
        let topology = Topology::from_mesh(mesh);
        let sized = size_mesh_in_space(mesh, &topology, self.0, &[], &mut |_| {})?;
        let metric = sized.field.tensors.iter().map(SizeTensor3::to_metric).collect();
        Ok(SpaceField { metric, warnings: sized.field.warnings })
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
    adapter: &'a dyn Adapter,
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
        observer.phase(iteration, Phase::Size);
        let t = Instant::now();
        let field = self.sizing.size(&mesh).map_err(|e| (Phase::Size, PhaseError::Space(e)))?;
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
            solver: None,
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
}

/// Runs the loop in space from `start` (a tetrahedral mesh, or a triangulated surface in
/// space) with `sizing` and `adapter` (mmg3d or mmgs). `input` and `recipe_label` name the
/// input and the recipe in the history. `options.layer`, `options.budget` and periodic
/// sides are planar: asking for them is [`AdaptError::Planar`], before any work.
pub fn run_space(
    start: TaggedMesh,
    sizing: &dyn SpaceSizing,
    adapter: &dyn Adapter,
    options: &AdaptOptions,
    input: &str,
    recipe_label: &str,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdaptError> {
    if options.layer.is_some() {
        return Err(AdaptError::Planar("the LAYER skin"));
    }
    if options.budget.is_some() {
        return Err(AdaptError::Planar("the vertex budget (--complexity)"));
    }
    if !options.periodic.pairs.is_empty() {
        return Err(AdaptError::Planar("periodic sides"));
    }
    let history = History {
        input: input.to_string(),
        recipe: recipe_label.to_string(),
        adapter: adapter.name().to_string(),
        converged: false,
        best_iteration: 0,
        stopped: RUNNING.to_string(),
        iterations: Vec::new(),
        best_mesh: Vec::new(),
        layer: None,
        budget: None,
    };
    let mut space = Space { sizing, adapter };
    let driven = driver::drive(&mut space, start, history, options, observer)?;
    let driver::Driven { history, best, failure, warnings, .. } = driven;
    let periodic = Ok(Rechecked::default());
    Ok(Outcome { history, best, layer: None, periodic, failure, warnings })
}

#[cfg(test)]
#[path = "space_tests.rs"]
mod tests;
