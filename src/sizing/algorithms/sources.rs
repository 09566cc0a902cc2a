//! The sources algorithms propagate from: entity sets checked against a topology and
//! turned into a [`Source`] (a [`SpaceSource`] on a mesh in space), and the reach of a
//! set of functions.

use super::EntitySet;
use super::Failure;
use crate::mesh_graph::MeshGraph;
use crate::sizing::propagation::{Source, SourceBuilder};
use crate::sizing::space::{SpaceMesh, SpaceSource, SpaceSourceBuilder};
use crate::topology::Topology;

/// Checks the indices of `set` against `topology`.
pub(crate) fn check_entities(topology: &Topology, set: &EntitySet) -> Result<(), Failure> {
    let check =
        |what: &'static str, list: &[usize], len: usize| match list.iter().find(|&&i| i >= len) {
            Some(&index) => Err(Failure::EntityOutOfRange { what, index, len }),
            None => Ok(()),
        };
    check("point", &set.points, topology.points.len())?;
    check("curve", &set.curves, topology.curves.len())?;
    check("face", &set.faces, topology.faces.len())
}

/// A border source: every polyline of the curves of `set`, and its points as point
/// sources when `points_allowed`. Faces are not borders.
pub(crate) fn border_source(
    graph: &MeshGraph,
    topology: &Topology,
    set: &EntitySet,
    points_allowed: bool,
) -> Result<Source, Failure> {
    check_entities(topology, set)?;
    if let Some(&index) = set.faces.first() {
        return Err(Failure::UnsupportedEntity { what: "face", index });
    }
    if !points_allowed {
        if let Some(&index) = set.points.first() {
            return Err(Failure::UnsupportedEntity { what: "point", index });
        }
    }
    let mut b = SourceBuilder::new(graph);
    for &c in &set.curves {
        b.topology_curve(topology, c);
    }
    for &p in &set.points {
        b.topology_point(topology, p);
    }
    let source = b.build()?;
    if source.segments().is_empty() {
        return Err(Failure::NoSource);
    }
    Ok(source)
}

/// A border source on a mesh in space: every cell of the surfaces (faces) of `set`,
/// every edge of its curves, and its points as point sources when `points_allowed`.
/// Volumes are no border.
pub(crate) fn space_border_source(
    mesh: &SpaceMesh<'_>,
    topology: &Topology,
    set: &EntitySet,
    points_allowed: bool,
) -> Result<SpaceSource, Failure> {
    check_entities(topology, set)?;
    if let Some(&index) = set.volumes.first() {
        return Err(Failure::UnsupportedEntity { what: "volume", index });
    }
    if !points_allowed {
        if let Some(&index) = set.points.first() {
            return Err(Failure::UnsupportedEntity { what: "point", index });
        }
    }
    let mut b = SpaceSourceBuilder::new(mesh.points());
    for &f in &set.faces {
        b.surface(topology, f)?;
    }
    for &c in &set.curves {
        b.curve(topology, c)?;
    }
    for &p in &set.points {
        b.topology_point(topology, p)?;
    }
    if b.is_empty() {
        return Err(Failure::NoSource);
    }
    Ok(b.build()?)
}

/// The largest of the maximum distances.
pub(crate) fn reach_of(distances: &[f64]) -> f64 {
    distances.iter().copied().fold(0.0, f64::max)
}
