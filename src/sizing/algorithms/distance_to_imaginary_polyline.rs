//! DISTANCE_TO_IMAGINARY_POLYLINE (thesis 4.3.6.5, Algorithm 4.4): a polyline given by
//! coordinates (a wake, a shock) that need not follow mesh edges. With d the distance
//! to it and s' the curvilinear abscissa of the closest point (0 at its first point):
//! normal size `perpendicular(d)`, tangent size `projection(d, polyline_distance(s'))`,
//! the normal from the closest point to the vertex (the polyline's own normal for a
//! vertex on it, averaged at its corners).
//!
//! Coarse meshes (issue item 5): the propagation seeds the corners of every cell the
//! polyline touches, and reports them whatever their distance, so a polyline whose
//! reach is smaller than the local edge length still marks every cell it crosses. Those
//! corners get the tensor of their true distance (the functions hold their end values
//! past their maximum distance): the mesh is refined towards the polyline, and an
//! adaptation loop then brings vertices within reach. Giving them the size at the
//! polyline instead would refine the whole crossed cells to that size.
//!
//! `within`: when it names entities, only their vertices get a tensor (a face's: the
//! corners of its cells). The
//! distance is still the Euclidean distance to the whole polyline (the propagation runs
//! over the whole mesh and the result is filtered), so a face boundary cuts the field
//! without bending it.
//!
//! Reach: the larger maximum distance of the perpendicular and projection functions
//! (the abscissa function's maximum distance is along the polyline, not away from it).

use super::{
    normal_at, reach_of, tensor, Around, Arguments, Declaration, Failure, FunctionKind, Junctions,
    Marks, Parameter, ParameterKind, PolylinePoints, SizingAlgorithm, Tensor, Work,
};
use crate::mesh_graph::MeshGraph;
use crate::sizing::functions::{DistanceFunction, SizeProjectionFunction};
use super::EntitySet;
use crate::metric::SizeTensor;
use crate::sizing::propagation::{ClosestPoint, Source, SourceBuilder};
use crate::topology::Topology;

/// DISTANCE_TO_IMAGINARY_POLYLINE: a user polyline (wake, shock); normal size
/// `perpendicular(distance)`, tangent size `polyline_distance(abscissa)` projected with
/// `projection`.
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceToImaginaryPolyline {
    /// Size normal to the polyline against distance.
    pub perpendicular: DistanceFunction,
    /// Tangent size on the polyline against curvilinear abscissa from its first point.
    pub polyline_distance: DistanceFunction,
    /// How the tangent size grows away from the polyline.
    pub projection: SizeProjectionFunction,
    /// The polyline, at least one point; consecutive points distinct: (x, y) points for
    /// a planar mesh, (x, y, z) for a mesh in space.
    pub polyline: PolylinePoints,
    /// Where the algorithm applies (faces); empty means everywhere.
    pub within: EntitySet,
}

impl SizingAlgorithm for DistanceToImaginaryPolyline {
    const DECLARATION: Declaration = Declaration {
        keyword: "DISTANCE_TO_IMAGINARY_POLYLINE",
        name: "distance_to_imaginary_polyline",
        doc: "A polyline given by coordinates (a wake, a shock): normal size \
              PERPENDICULAR_FUNCTION(d), tangent size POLYLINE_DISTANCE_FUNCTION(s') carried \
              away by the projection function, s' the abscissa of the closest point \
              (thesis 4.3.6.5).",
        parameters: &[
            Parameter {
                field: "perpendicular",
                aliases: &[],
                keys: &["PERPENDICULAR_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: true,
                doc: "Size normal to the polyline against distance.",
            },
            Parameter {
                field: "polyline_distance",
                aliases: &[],
                keys: &["POLYLINE_DISTANCE_FUNCTION", "PARALLEL_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: true,
                doc: "Tangent size on the polyline against its curvilinear abscissa.",
            },
            Parameter {
                field: "projection",
                aliases: &[],
                keys: &["PARALLEL_PROJECTION_FUNCTION", "PROJECTION_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Projection),
                line_break_after: true,
                doc: "How the tangent size grows away from the polyline.",
            },
            Parameter {
                field: "polyline",
                aliases: &[],
                keys: &["COORDINATES"],
                kind: ParameterKind::Polyline,
                line_break_after: false,
                doc: "The name of a polyline of the recipe.",
            },
            Parameter {
                field: "regions",
                aliases: &[],
                keys: &["REGIONS"],
                kind: ParameterKind::Regions { dimensions: &[2], optional: true },
                line_break_after: false,
                doc: "The faces where it applies; everywhere when left out.",
            },
        ],
    };

    type Tensor<'a> = PolylineTensor<'a>;

    fn from_arguments(arguments: &mut Arguments) -> Option<DistanceToImaginaryPolyline> {
        Some(DistanceToImaginaryPolyline {
            perpendicular: arguments.distance("perpendicular")?,
            polyline_distance: arguments.distance("polyline_distance")?,
            projection: arguments.projection("projection")?,
            polyline: arguments.polyline("polyline")?,
            within: arguments.entities("regions")?,
        })
    }

    fn entity_sets(&self) -> Vec<&EntitySet> {
        vec![&self.within]
    }

    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        let points = self.polyline.plane()?;
        Some((Around::Points(points), self.perpendicular.max_distance()))
    }

    fn marks(&self) -> Marks<'_> {
        Marks { polyline: self.polyline.plane(), points: &[] }
    }

    fn work<'a>(
        &'a self,
        graph: &'a MeshGraph,
        topology: &'a Topology,
    ) -> Result<Work<PolylineTensor<'a>>, Failure> {
        if self.polyline.is_empty() {
            return Err(Failure::EmptyPolyline);
        }
        let Some(polyline) = self.polyline.plane() else {
            return Err(Failure::PolylineComponents { components: 3, in_space: false });
        };
        let within = &self.within;
        let inside = if within.is_empty() {
            None
        } else {
            Some(super::uniform::entity_vertices(graph, topology, within)?)
        };
        let mut mask = vec![inside.is_none(); graph.num_vertices()];
        if let Some(vs) = &inside {
            for &v in vs {
                mask[v as usize] = true;
            }
        }
        let source = SourceBuilder::new(graph).polyline(polyline, false).build()?;
        let junctions = Junctions::new(&source);
        let reach = reach_of(&[self.perpendicular.max_distance(), self.projection.max_distance()]);
        let tensor = PolylineTensor { algorithm: self, graph, junctions, mask };
        Ok(Work::FromSource { source, reach, tensor })
    }
}

/// The tensor of DISTANCE_TO_IMAGINARY_POLYLINE.
pub(crate) struct PolylineTensor<'a> {
    algorithm: &'a DistanceToImaginaryPolyline,
    graph: &'a MeshGraph,
    junctions: Junctions,
    /// Whether each mesh vertex lies where the algorithm applies.
    mask: Vec<bool>,
}

impl Tensor for PolylineTensor<'_> {
    fn tensor(
        &self,
        sources: &[Source],
        v: usize,
        closest: &[ClosestPoint],
    ) -> Result<Option<SizeTensor>, Failure> {
        if !self.mask[v] {
            return Ok(None);
        }
        let (source, c) = (&sources[0], &closest[0]);
        let a = self.algorithm;
        let n = normal_at(source, &self.junctions, self.graph.point(v), c);
        let h_line = a.polyline_distance.eval(c.abscissa);
        let h_tangent = a.projection.eval(c.distance, h_line);
        tensor(v, n, a.perpendicular.eval(c.distance), h_tangent).map(Some)
    }
}
