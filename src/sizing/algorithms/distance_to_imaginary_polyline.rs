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
//!
//! In space (a vortex line): the polyline's points are (x, y, z) and its segments one
//! free source of the exact closest-point index (a segment is a degenerate triangle of
//! the one kernel, bit for bit a scan of every segment). With d and s' as above, the
//! tensor of a vertex off the line is a tube's: `perpendicular(d)` along the direction
//! from the closest point to the vertex and around the line, the projected tangent size
//! along the line's tangent at the foot (at a corner of the polyline, the mean of its two
//! segments' directions), made orthogonal to that direction. Around the line the size is
//! the perpendicular one, not the tangent one as DISTANCE_TO_BORDER gives around a curve
//! in space: a vortex core is round, and on the line itself (d within `ON_SOURCE` of the
//! foot's segment, where the direction is noise) the tensor is the tangent size along
//! the line and the smaller size across it in every direction, which this tube tensor
//! meets continuously as d goes to 0. Coarse meshes: the 3D driver also sizes the
//! corners of every cell a segment meets ([`crate::sizing::field3`]). A polyline
//! of (x, y) points on a mesh in space is refused, naming the step (there is no implied
//! z); `recipe check` lists such a step as not sized in space. `REGIONS` means in space
//! what it means in the plane: only the vertices of the named entities get a tensor —
//! a volume's (the corners of its cells), a surface's (the corners of its triangles) —
//! the distance still to the whole line, crossed cells' corners included.

use super::{
    normal_at, reach_of, tensor, Around, Arguments, Declaration, Failure, FunctionKind, Junctions,
    Marks, Parameter, ParameterKind, PolylinePoints, SizingAlgorithm, Tensor, Work,
};
use super::{SpaceTensor, SpaceWork};
use crate::mesh_graph::MeshGraph;
use crate::sizing::space::{SpaceMesh, SpaceSourceBuilder};
use crate::sizing::functions::{DistanceFunction, SizeProjectionFunction};
use super::EntitySet;
use super::{wall_tensor, Across};
use crate::metric::{SizeTensor, SizeTensor3};
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
                kind: ParameterKind::Regions { dimensions: &[2], optional: true, lift: true },
                line_break_after: false,
                doc: "The faces (in space: volumes or surfaces) where it applies; everywhere \
                      when left out.",
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

    fn sized_in_space(&self) -> bool {
        self.polyline.space().is_some()
    }

    const IN_SPACE: bool = true;

    fn work_in_space<'a>(
        &'a self,
        mesh: &'a SpaceMesh<'a>,
        topology: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        if self.polyline.is_empty() {
            return Err(Failure::EmptyPolyline);
        }
        let Some(points) = self.polyline.space() else {
            return Err(Failure::PolylineComponents { components: 2, in_space: true });
        };
        let mask = within_mask(mesh, topology, &self.within)?;
        let source = polyline_source(mesh, points)?;
        let reach = reach_of(&[self.perpendicular.max_distance(), self.projection.max_distance()]);
        let tensor = Box::new(TubeTensor::new(self, points, mask));
        Ok(SpaceWork::FromSource { source, reach, tensor })
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

/// The polyline in space as a free source of the 3D driver: segment `i` is piece `i`
/// (consecutive points differ: the recipe checks), a single point one point piece.
pub(crate) fn polyline_source(
    mesh: &SpaceMesh<'_>,
    points: &[[f64; 3]],
) -> Result<crate::sizing::space::SpaceSource, Failure> {
    let mut b = SpaceSourceBuilder::new(mesh.points());
    for (i, &p) in points.iter().enumerate() {
        b.free_point(p, i)?;
    }
    if points.len() == 1 {
        b.point(0);
    }
    for i in 1..points.len() {
        if points[i - 1] == points[i] {
            return Err(Failure::EmptyPolyline);
        }
        b.segment(i as u32 - 1, i as u32);
    }
    Ok(b.build()?)
}

/// Whether each vertex of the mesh in space lies in `within` (the vertices of its volumes
/// and surfaces, as UNIFORM takes them), or `None` when `within` is empty (everywhere).
pub(crate) fn within_mask(
    mesh: &SpaceMesh<'_>,
    topology: &Topology,
    within: &EntitySet,
) -> Result<Option<Vec<bool>>, Failure> {
    if within.is_empty() {
        return Ok(None);
    }
    let mut mask = vec![false; mesh.num_vertices()];
    for v in super::uniform::entity_vertices_in_space(mesh, topology, within)? {
        mask[v as usize] = true;
    }
    Ok(Some(mask))
}

/// The tensor of DISTANCE_TO_IMAGINARY_POLYLINE in space (see the module header).
pub(crate) struct TubeTensor<'a> {
    algorithm: &'a DistanceToImaginaryPolyline,
    points: &'a [[f64; 3]],
    /// Whether each vertex lies where the step applies (`None`: everywhere).
    mask: Option<Vec<bool>>,
    /// Curvilinear abscissa of each point from the first.
    abscissa: Vec<f64>,
    /// Unit direction of each segment.
    directions: Vec<[f64; 3]>,
}

impl<'a> TubeTensor<'a> {
    pub(crate) fn new(
        algorithm: &'a DistanceToImaginaryPolyline,
        points: &'a [[f64; 3]],
        mask: Option<Vec<bool>>,
    ) -> Self {
        let mut abscissa = vec![0.0; points.len()];
        let mut directions = Vec::with_capacity(points.len().saturating_sub(1));
        for i in 1..points.len() {
            let d = sub3(points[i], points[i - 1]);
            let len = dot3(d, d).sqrt();
            abscissa[i] = abscissa[i - 1] + len;
            directions.push([d[0] / len, d[1] / len, d[2] / len]);
        }
        TubeTensor { algorithm, points, mask, abscissa, directions }
    }

    /// The abscissa of `foot` on piece `piece`, and the line's unit tangent there (`None`
    /// on a single point, or where the two segments at a corner turn right back).
    pub(crate) fn along(&self, piece: usize, foot: [f64; 3]) -> (f64, Option<[f64; 3]>) {
        if self.directions.is_empty() {
            return (0.0, None);
        }
        let a = self.points[piece];
        let f = sub3(foot, a);
        let s = self.abscissa[piece] + dot3(f, f).sqrt();
        let own = self.directions[piece];
        // The index snaps a foot at a segment's end to that point exactly.
        let other = if foot == a && piece > 0 {
            Some(self.directions[piece - 1])
        } else if foot == self.points[piece + 1] && piece + 1 < self.directions.len() {
            Some(self.directions[piece + 1])
        } else {
            None
        };
        let t = match other {
            None => Some(own),
            Some(o) => unit(std::array::from_fn(|k| own[k] + o[k])),
        };
        (s, t)
    }
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    crate::sizing::space::unit3(v)
}

impl SpaceTensor for TubeTensor<'_> {
    fn tensor(
        &self,
        sources: &[crate::sizing::space::SpaceSource],
        v: usize,
        at: [f64; 3],
        closest: &[crate::sizing::space::SpaceClosest],
    ) -> Result<Option<SizeTensor3>, Failure> {
        if self.mask.as_ref().is_some_and(|m| !m[v]) {
            return Ok(None);
        }
        let (a, c) = (self.algorithm, &closest[0]);
        let (s, t) = self.along(c.piece as usize, c.foot);
        let h_perp = a.perpendicular.eval(c.distance);
        let h_tangent = a.projection.eval(c.distance, a.polyline_distance.eval(s));
        let frame = match (super::across(&sources[0], c, at), t) {
            (Across::Normal(n), Some(t)) => {
                // Radial n; the tangent made orthogonal to it (the third axis, around the
                // line, takes the perpendicular size too).
                match SizeTensor3::try_new(n, t, [h_perp, h_tangent, h_perp]) {
                    Some(tensor) => return Ok(Some(tensor)),
                    None => Across::Normal(n),
                }
            }
            (Across::Line(_), Some(t)) => Across::Line(t),
            (other, _) => other,
        };
        // Off the line with no tangent known (a single point, a foot straight beyond an
        // end along the line, a corner that turns back): `perpendicular` along the
        // direction, the smaller size across; on the line, the tangent size along it.
        let tensor = match frame {
            Across::Normal(n) => SizeTensor3::try_new(n, other_axis(n), [h_perp, h_perp.min(h_tangent), h_perp.min(h_tangent)]).ok_or(Failure::Degenerate { vertex: v })?,
            f => wall_tensor(v, f, h_perp, h_tangent)?,
        };
        Ok(Some(tensor))
    }
}

fn other_axis(n: [f64; 3]) -> [f64; 3] {
    let a = n.map(f64::abs);
    if a[0] <= a[1] && a[0] <= a[2] {
        [1.0, 0.0, 0.0]
    } else if a[1] <= a[2] {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    }
}
