//! DISTANCE_TO_BORDER (thesis 2.2.10.4, 4.3.7.1, Algorithm 4.5): anisotropic sizes from
//! the distance d to the border curves — `perpendicular(d)` along the normal,
//! `parallel(d)` along the tangent, the axes taken at the exact closest point:
//!
//! - off the border, the normal is the direction from the closest point to the vertex
//!   (at a foot on a polyline corner, the direction the vertex is seen from the corner);
//! - on the border (d = 0), the normal of the border there: the segment's, or at a
//!   polyline vertex that of the averaged neighbour segments (the segments of every
//!   border polyline meeting at that vertex).
//!
//! Points in the border set are point sources: around them the normal is radial, and
//! on the point itself the tensor is isotropic, of the smaller size.
//!
//! Reach: the larger of the two functions' maximum distances (see the module
//! [`super`]).
//!
//! In space the border is surfaces (every cell of them, quads split), curves (their
//! edges) and points, in one exact closest-point index; the tensor is wall-aligned
//! (`super::frame3`): `perpendicular(d)` along the direction from the foot to the
//! vertex, `parallel(d)` twice in the plane across it; on a surface (d = 0) the normal is
//! the surface's, area-weighted at a foot on an edge or a vertex of its cells
//! (`SpaceSource::surface_normal`).

use super::{
    border_source, normal_at, reach_of, tensor, Around, Arguments, Declaration, Failure,
    FunctionKind, Junctions, Marks, Parameter, ParameterKind, SizingAlgorithm, Tensor, Work,
};
use super::{across, space_border_source, wall_tensor, SpaceTensor, SpaceWork};
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use crate::sizing::functions::DistanceFunction;
use super::EntitySet;
use crate::sizing::propagation::{ClosestPoint, Source};
use crate::metric::SizeTensor3;
use crate::sizing::space::{SpaceClosest, SpaceMesh, SpaceSource};
use crate::topology::Topology;

/// DISTANCE_TO_BORDER: anisotropic; normal size `perpendicular(distance)`, tangent
/// size `parallel(distance)`, axes normal and tangent to the border at the closest
/// point.
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceToBorder {
    /// Size normal to the border against distance.
    pub perpendicular: DistanceFunction,
    /// Size tangent to the border against distance.
    pub parallel: DistanceFunction,
    /// The border curves (points are point sources).
    pub borders: EntitySet,
}

impl SizingAlgorithm for DistanceToBorder {
    const DECLARATION: Declaration = Declaration {
        keyword: "DISTANCE_TO_BORDER",
        name: "distance_to_border",
        doc: "Anisotropic sizes from the distance d to the border curves: \
              PERPENDICULAR_FUNCTION(d) along the normal, PARALLEL_FUNCTION(d) along the \
              tangent at the closest point (thesis 4.3.7.1).",
        parameters: &[
            Parameter {
                field: "perpendicular",
                aliases: &[],
                keys: &["PERPENDICULAR_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: true,
                doc: "Size normal to the border against distance.",
            },
            Parameter {
                field: "parallel",
                aliases: &[],
                keys: &["PARALLEL_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: false,
                doc: "Size tangent to the border against distance.",
            },
            Parameter {
                field: "regions",
                aliases: &[],
                keys: &["REGIONS"],
                kind: ParameterKind::Regions { dimensions: &[1, 0], optional: false, lift: true },
                line_break_after: false,
                doc: "The border: curves, or points as point sources (surfaces too in space).",
            },
        ],
    };

    type Tensor<'a> = BorderTensor<'a>;

    fn from_arguments(arguments: &mut Arguments) -> Option<DistanceToBorder> {
        Some(DistanceToBorder {
            perpendicular: arguments.distance("perpendicular")?,
            parallel: arguments.distance("parallel")?,
            borders: arguments.entities("regions")?,
        })
    }

    fn entity_sets(&self) -> Vec<&EntitySet> {
        vec![&self.borders]
    }

    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        Some((Around::Entities(self.borders.clone()), self.perpendicular.max_distance()))
    }

    fn marks(&self) -> Marks<'_> {
        Marks { polyline: None, points: &self.borders.points }
    }

    fn work<'a>(
        &'a self,
        graph: &'a MeshGraph,
        topology: &'a Topology,
    ) -> Result<Work<BorderTensor<'a>>, Failure> {
        let source = border_source(graph, topology, &self.borders, true)?;
        let junctions = Junctions::new(&source);
        let reach = reach_of(&[self.perpendicular.max_distance(), self.parallel.max_distance()]);
        Ok(Work::FromSource { source, reach, tensor: BorderTensor { algorithm: self, graph, junctions } })
    }

    const IN_SPACE: bool = true;

    fn work_in_space<'a>(
        &'a self,
        mesh: &'a SpaceMesh<'a>,
        topology: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        let source = space_border_source(mesh, topology, &self.borders, true)?;
        let reach = reach_of(&[self.perpendicular.max_distance(), self.parallel.max_distance()]);
        Ok(SpaceWork::FromSource { source, reach, tensor: Box::new(BorderTensor3(self)) })
    }
}

/// The tensor of DISTANCE_TO_BORDER in space.
struct BorderTensor3<'a>(&'a DistanceToBorder);

impl SpaceTensor for BorderTensor3<'_> {
    fn tensor(
        &self,
        sources: &[SpaceSource],
        v: usize,
        at: [f64; 3],
        closest: &[SpaceClosest],
    ) -> Result<Option<SizeTensor3>, Failure> {
        let (a, c) = (self.0, &closest[0]);
        let frame = across(&sources[0], c, at);
        wall_tensor(v, frame, a.perpendicular.eval(c.distance), a.parallel.eval(c.distance))
            .map(Some)
    }
}

/// The tensor of DISTANCE_TO_BORDER.
pub(crate) struct BorderTensor<'a> {
    algorithm: &'a DistanceToBorder,
    graph: &'a MeshGraph,
    junctions: Junctions,
}

impl Tensor for BorderTensor<'_> {
    /// Always inlined, so that a driver that evaluates every vertex in one loop has it
    /// there, with what the closest point holds that it does not read (side, abscissa)
    /// left uncomputed.
    #[inline(always)]
    fn tensor(
        &self,
        sources: &[Source],
        v: usize,
        closest: &[ClosestPoint],
    ) -> Result<Option<SizeTensor>, Failure> {
        let (source, c) = (&sources[0], &closest[0]);
        let a = self.algorithm;
        let n = normal_at(source, &self.junctions, self.graph.point(v), c);
        tensor(v, n, a.perpendicular.eval(c.distance), a.parallel.eval(c.distance)).map(Some)
    }
}
