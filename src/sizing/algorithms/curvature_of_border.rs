//! CURVATURE_OF_BORDER (thesis 3.3.2, 4.3.7.2): the tangent size on the border comes
//! from its curvature through the curvature-to-size function, and is carried inward
//! with the size projection function; the normal size is `perpendicular(d)`.
//!
//! Curvature at a polyline vertex: the inverse radius of the circle through the vertex
//! and its two neighbours (thesis Fig. 4.9), in the closed form κ = 2|AB × BC| /
//! (|AB| |BC| |AC|) (Menger curvature: the same circle as the thesis's 2×2 system, with
//! no system to solve). Between two vertices the curvature is interpolated linearly
//! along the segment (thesis 4.3.7.2), then turned into a size.
//!
//! Ends and corners (thesis 4.3.7.2 and 7.4.4 average the two neighbours, which smears
//! the huge three-point curvature of a corner over both sides). What is done here:
//!
//! - A polyline vertex is a *corner* when the border turns there by more than
//!   [`CORNER_ANGLE`] (45°, the ridge angle MMG uses by default): a corner is a feature
//!   of the geometry, not a discretised smooth arc, and the chord-error criterion says
//!   nothing about it. Corners split a polyline into smooth pieces.
//! - The ends of a piece (an open polyline's ends, corners, and every end of a curve
//!   at a topological point) take the one-sided circle: through the end and its next two
//!   points on the same piece, which is the circle of the next vertex. A piece of a
//!   single segment is straight: κ = 0.
//! - So each segment carries its own curvature at each of its ends, and the two sides
//!   of a corner never share a value. At a foot point on a vertex where several sides
//!   meet (a corner, a junction of curves), the tangent size on the border is the
//!   smallest of the sides' sizes (the finer side wins, as an intersection would).
//! - On a corner or junction vertex itself (d = 0), the tensor is the intersection of
//!   the tensors each side asks for (its tangent with its size, its normal with
//!   `perpendicular(0)`), rather than one tensor along an averaged direction: the mesh
//!   there must conform to both walls. At a square corner between straight sides this
//!   is the isotropic tensor of min(perpendicular(0), curvature-to-size(0)). At a smooth
//!   vertex (two sides of one polyline, no corner) the tangent is the averaged one.
//!
//! Border points (topological points) have no curvature and are refused as sources.
//! Reach: the larger maximum distance of the perpendicular and projection functions.

use super::{
    border_source, direction, normal_at, on_source, reach_of, tangent_at, tensor, Around,
    Arguments, Declaration, Failure, FunctionKind, Junctions, Parameter, ParameterKind,
    SizingAlgorithm, Tensor, Work,
};
use crate::geometry::Point2;
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use crate::sizing::functions::{CurvatureToSize, DistanceFunction, SizeProjectionFunction};
use super::EntitySet;
use crate::sizing::propagation::{ClosestPoint, Source};
use crate::topology::Topology;

/// A polyline vertex where the border turns by more than this (radians) is a corner.
pub const CORNER_ANGLE: f64 = std::f64::consts::FRAC_PI_4;

/// The curvature of the circle through `a`, `b`, `c` (0 when two points coincide or the
/// three are aligned).
pub fn three_point_curvature(a: Point2, b: Point2, c: Point2) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let bc = [c[0] - b[0], c[1] - b[1]];
    let ac = [c[0] - a[0], c[1] - a[1]];
    let den = ab[0].hypot(ab[1]) * bc[0].hypot(bc[1]) * ac[0].hypot(ac[1]);
    let k = 2.0 * (ab[0] * bc[1] - ab[1] * bc[0]).abs() / den;
    if den > 0.0 && k.is_finite() {
        k
    } else {
        0.0
    }
}

/// Curvature of every segment of a source at its two ends, and whether each end is a
/// smooth vertex (neither a piece end nor a corner).
#[derive(Debug, Clone)]
pub(crate) struct SegmentCurvatures {
    pub(crate) kappa: Vec<[f64; 2]>,
    pub(crate) smooth: Vec<[bool; 2]>,
}

impl SegmentCurvatures {
    pub(crate) fn new(source: &Source) -> SegmentCurvatures {
        let segs = source.segments();
        let mut kappa = vec![[0.0; 2]; segs.len()];
        let mut smooth = vec![[false; 2]; segs.len()];
        let cos_corner = CORNER_ANGLE.cos();
        for pl in source.polylines() {
            let (first, m) = (pl.first_segment as usize, pl.num_segments as usize);
            let seg = |k: usize| &segs[first + k];
            let npts = if pl.closed { m } else { m + 1 };
            let point = |k: usize| if k < m { seg(k).a } else { seg(m - 1).b };
            let dir = |k: usize| {
                let s = seg(k);
                let d = [s.b[0] - s.a[0], s.b[1] - s.a[1]];
                let n = d[0].hypot(d[1]);
                (n > 0.0).then(|| [d[0] / n, d[1] / n])
            };
            // Smooth vertices and their three-point curvature.
            let mut vertex_smooth = vec![false; npts];
            let mut vertex_kappa = vec![0.0; npts];
            for k in 0..npts {
                let interior = pl.closed || (k > 0 && k < m);
                if !interior || m < 2 {
                    continue;
                }
                let (prev, next) = ((k + m - 1) % m, k % m);
                if let (Some(u), Some(w)) = (dir(prev), dir(next)) {
                    if u[0] * w[0] + u[1] * w[1] >= cos_corner {
                        vertex_smooth[k] = true;
                        vertex_kappa[k] = three_point_curvature(
                            point((k + npts - 1) % npts),
                            point(k),
                            point((k + 1) % npts),
                        );
                    }
                }
            }
            for k in 0..m {
                let (i, j) = (k, (k + 1) % npts);
                let one_sided = |own: usize, other: usize| {
                    if vertex_smooth[own] {
                        vertex_kappa[own]
                    } else if vertex_smooth[other] {
                        vertex_kappa[other]
                    } else {
                        0.0
                    }
                };
                kappa[first + k] = [one_sided(i, j), one_sided(j, i)];
                smooth[first + k] = [vertex_smooth[i], vertex_smooth[j]];
            }
        }
        SegmentCurvatures { kappa, smooth }
    }

    /// The curvature at parameter `t` of segment `s`, interpolated linearly.
    pub(crate) fn at(&self, s: u32, t: f64) -> f64 {
        let [a, b] = self.kappa[s as usize];
        a + t * (b - a)
    }
}

/// CURVATURE_OF_BORDER: tangent size from the border's curvature through
/// `curvature`, carried inward with `projection`; normal size `perpendicular(distance)`.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvatureOfBorder {
    /// Size normal to the border against distance.
    pub perpendicular: DistanceFunction,
    /// Tangent size on the border against curvature.
    pub curvature: CurvatureToSize,
    /// How the tangent size on the border grows with distance.
    pub projection: SizeProjectionFunction,
    /// The border curves.
    pub borders: EntitySet,
}

impl SizingAlgorithm for CurvatureOfBorder {
    const DECLARATION: Declaration = Declaration {
        keyword: "CURVATURE_OF_BORDER",
        name: "curvature_of_border",
        doc: "The tangent size on the border from its curvature \
              (CURVATURE_TO_SIZE_FUNCTION), carried inward by PROJECTION_FUNCTION; the \
              normal size PERPENDICULAR_FUNCTION(d) (thesis 4.3.7.2).",
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
                field: "curvature_to_size",
                aliases: &[],
                keys: &["CURVATURE_TO_SIZE_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Curvature),
                line_break_after: false,
                doc: "Tangent size on the border against curvature.",
            },
            Parameter {
                field: "projection",
                aliases: &[],
                keys: &["PROJECTION_FUNCTION", "PARALLEL_PROJECTION_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Projection),
                line_break_after: false,
                doc: "How the tangent size on the border grows with distance.",
            },
            Parameter {
                field: "regions",
                aliases: &[],
                keys: &["REGIONS"],
                kind: ParameterKind::Regions { dimensions: &[1], optional: false },
                line_break_after: false,
                doc: "The border curves.",
            },
        ],
    };

    type Tensor<'a> = CurvatureTensor<'a>;

    fn from_arguments(arguments: &mut Arguments) -> Option<CurvatureOfBorder> {
        Some(CurvatureOfBorder {
            perpendicular: arguments.distance("perpendicular")?,
            curvature: arguments.curvature("curvature_to_size")?,
            projection: arguments.projection("projection")?,
            borders: arguments.entities("regions")?,
        })
    }

    fn entity_sets(&self) -> Vec<&EntitySet> {
        vec![&self.borders]
    }

    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        Some((Around::Entities(self.borders.clone()), self.perpendicular.max_distance()))
    }

    fn work<'a>(
        &'a self,
        graph: &'a MeshGraph,
        topology: &'a Topology,
    ) -> Result<Work<CurvatureTensor<'a>>, Failure> {
        let source = border_source(graph, topology, &self.borders, false)?;
        let junctions = Junctions::new(&source);
        let curvatures = SegmentCurvatures::new(&source);
        let reach = reach_of(&[self.perpendicular.max_distance(), self.projection.max_distance()]);
        let tensor = CurvatureTensor { algorithm: self, graph, junctions, curvatures };
        Ok(Work::FromSource { source, reach, tensor })
    }
}

/// The tensor of CURVATURE_OF_BORDER.
pub(crate) struct CurvatureTensor<'a> {
    algorithm: &'a CurvatureOfBorder,
    graph: &'a MeshGraph,
    junctions: Junctions,
    curvatures: SegmentCurvatures,
}

impl Tensor for CurvatureTensor<'_> {
    fn tensor(
        &self,
        sources: &[Source],
        v: usize,
        closest: &[ClosestPoint],
    ) -> Result<Option<SizeTensor>, Failure> {
        let a = self.algorithm;
        border_tensor(
            &sources[0],
            &self.junctions,
            &self.curvatures,
            &a.perpendicular,
            &a.curvature,
            &a.projection,
            self.graph.point(v),
            v,
            &closest[0],
        )
        .map(Some)
    }
}

/// The tensor of a vertex `p` from its closest point `c` on the border.
#[allow(clippy::too_many_arguments)]
fn border_tensor(
    source: &Source,
    junctions: &Junctions,
    curv: &SegmentCurvatures,
    perpendicular: &DistanceFunction,
    curvature: &CurvatureToSize,
    projection: &SizeProjectionFunction,
    p: Point2,
    v: usize,
    c: &ClosestPoint,
) -> Result<SizeTensor, Failure> {
    let d = c.distance;
    let h_normal = perpendicular.eval(d);
    let node = junctions.node(source, c);
    let Some(node) = node else {
        let h_border = curvature.eval(curv.at(c.segment, c.parameter));
        return tensor(
            v,
            normal_at(source, junctions, p, c),
            h_normal,
            projection.eval(d, h_border),
        );
    };
    let sides = junctions.sides(node);
    let side_size = |&(s, end): &(u32, u8)| curvature.eval(curv.kappa[s as usize][end as usize]);
    let smooth =
        sides.len() == 2 && sides.iter().all(|&(s, end)| curv.smooth[s as usize][end as usize]);
    if !on_source(source, c) || smooth {
        let h_border = sides.iter().map(side_size).fold(f64::INFINITY, f64::min);
        let normal = if smooth && on_source(source, c) {
            tangent_at(source, junctions, c).map(|t| [-t[1], t[0]])
        } else {
            normal_at(source, junctions, p, c)
        };
        return tensor(v, normal, h_normal, projection.eval(d, h_border));
    }
    // A corner, a junction or an open end, on the border: every side's tensor at once.
    let mut out: Option<SizeTensor> = None;
    for side in sides {
        let Some(t) = direction(source, side.0) else { continue };
        let s = tensor(v, Some([-t[1], t[0]]), h_normal, projection.eval(d, side_size(side)))?;
        out = Some(match out {
            Some(o) => o.intersection(&s),
            None => s,
        });
    }
    out.ok_or(Failure::Degenerate { vertex: v })
}
