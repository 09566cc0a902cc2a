//! A recipe's size field on one mesh, from the mesh alone: topology, resolution of the
//! recipe's regions on the mesh's tags, the mesh graph, then the engine. `smartmesh size`
//! runs it once; the adaptation loop runs it on every new mesh with the same recipe
//! (thesis 5.5: the same configuration at each iteration), so the sequence lives here once.
//! On a mesh in space ([`size_mesh_in_space`]) the same resolution feeds the 3D driver
//! ([`crate::sizing::field3`]) instead of the mesh graph and the 2D engine.

use smartmesh_formats::TaggedMesh;

use super::{Recipe, RecipeError, Resolved};
use crate::mesh_graph::{MeshGraph, MeshGraphError};
use crate::sizing::field::{compute_size_field, SizeField, SizingError, StepEvent};
use crate::sizing::field3::{compute_size_field3, SizeField3};
use crate::sizing::plan::Step;
use crate::sizing::space::SpaceMesh;
use crate::topology::Topology;

/// Why a recipe gave no field on a mesh. Each variant keeps its source's message, so
/// that a caller can add the mesh's name where it helps.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SizeMeshError {
    /// The recipe's regions do not resolve on the mesh's tags (a name the mesh lacks).
    #[error("{0}")]
    Resolve(RecipeError),
    /// The mesh is not a graph the engine can walk.
    #[error("{0}")]
    Graph(MeshGraphError),
    /// The engine refused the plan on this mesh.
    #[error("{0}")]
    Sizing(SizingError),
}

/// The field and how the recipe resolved on the mesh.
#[derive(Debug, Clone)]
pub struct MeshSizing {
    /// The recipe resolved on the mesh (plan and per-region report).
    pub resolved: Resolved,
    /// One size tensor per mesh vertex.
    pub field: SizeField,
}

/// The size field `recipe` gives on `mesh`; `observer` sees each step start and finish
/// (for a progress bar).
///
/// ```
/// use std::path::Path;
/// use smartmesh::formats::read_path;
///
/// let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
/// let mesh = read_path(&dir.join("cylinder.msh"), None)?;
/// let text = std::fs::read_to_string(dir.join("cylinder.toml"))?;
/// let recipe = smartmesh::recipe::serde_io::read_toml(&text, &dir.join("cylinder.toml"))?;
/// let sized = smartmesh::recipe::size_mesh(&mesh, &recipe, &mut |_| {})?;
/// // One size tensor per vertex, finest on the cylinder wall.
/// assert_eq!(sized.field.tensors.len(), mesh.points.len());
/// let finest = sized.field.tensors.iter().map(|t| t.h_min()).fold(f64::INFINITY, f64::min);
/// assert!(finest < 0.01, "{finest}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn size_mesh(
    mesh: &TaggedMesh,
    recipe: &Recipe,
    observer: &mut dyn FnMut(StepEvent),
) -> Result<MeshSizing, SizeMeshError> {
    size_mesh_with_topology(mesh, &Topology::from_mesh(mesh), recipe, observer)
}

/// [`size_mesh`] for a caller that has `mesh`'s topology already (the adaptation loop
/// builds it once per mesh, for the sizing and the remeshing).
pub fn size_mesh_with_topology(
    mesh: &TaggedMesh,
    topology: &Topology,
    recipe: &Recipe,
    observer: &mut dyn FnMut(StepEvent),
) -> Result<MeshSizing, SizeMeshError> {
    size_mesh_with_steps(mesh, topology, recipe, &[], observer)
}

/// [`size_mesh_with_topology`] with `extra` steps after the recipe's (a solution's
/// metric from the command line), intersected in that order.
pub fn size_mesh_with_steps(
    mesh: &TaggedMesh,
    topology: &Topology,
    recipe: &Recipe,
    extra: &[Step],
    observer: &mut dyn FnMut(StepEvent),
) -> Result<MeshSizing, SizeMeshError> {
    let mut resolved = recipe.resolve(topology).map_err(SizeMeshError::Resolve)?;
    resolved.plan.steps.extend_from_slice(extra);
    let graph = MeshGraph::from_topology(topology, mesh).map_err(SizeMeshError::Graph)?;
    let field = compute_size_field(&graph, topology, &resolved.plan, observer)
        .map_err(SizeMeshError::Sizing)?;
    Ok(MeshSizing { resolved, field })
}

/// The field and how the recipe resolved on a mesh in space.
#[derive(Debug, Clone)]
pub struct MeshSizing3 {
    /// The recipe resolved on the mesh (plan and per-region report).
    pub resolved: Resolved,
    /// One 3D size tensor per mesh vertex.
    pub field: SizeField3,
}

/// The size field `recipe` (then the `extra` steps) gives on the mesh in space `mesh`
/// (tetrahedra, or a surface off one plane) with its `topology`; a step whose algorithm
/// does not size in space yet is refused ([`SizingError::NotInSpace`]).
pub fn size_mesh_in_space(
    mesh: &TaggedMesh,
    topology: &Topology,
    recipe: &Recipe,
    extra: &[Step],
    observer: &mut dyn FnMut(StepEvent),
) -> Result<MeshSizing3, SizeMeshError> {
    let mut resolved = recipe.resolve(topology).map_err(SizeMeshError::Resolve)?;
    resolved.plan.steps.extend_from_slice(extra);
    let space = SpaceMesh::new(mesh, topology).map_err(SizeMeshError::Graph)?;
    let field = compute_size_field3(&space, topology, &resolved.plan, observer)
        .map_err(SizeMeshError::Sizing)?;
    Ok(MeshSizing3 { resolved, field })
}
