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
//!
//! In space (`SpaceBorder`), the same meaning, one dimension up:
//!
//! - On a border surface, the principal curvatures and directions at each vertex
//!   (`geometry::space::curvature`: a cubic jet fit, O(h²)) give the tangential sizes:
//!   the curvature-to-size function of each principal curvature along its principal
//!   direction, carried inward by the projection function; the normal size is
//!   `perpendicular(d)` along the normal (the fitted normal on the surface, the way from
//!   the foot point off it), as the 2D normal. Between vertices the sign-free curvature
//!   tensors |k1| d1 d1ᵀ + |k2| d2 d2ᵀ are interpolated at the foot point (linearly, as
//!   the 2D curvature along a segment) and read in the plane across the normal.
//! - Ridges, and curves where surfaces meet, are not smoothed across: each smooth side
//!   of a ridge has its own curvature. A ridge is also a curve: on a curve in space
//!   (ridges, line cells) the tangent size comes from the three-point curvature of space
//!   points, with the 2D rules for smooth vertices, corners ([`CORNER_ANGLE`]) and ends;
//!   across a border curve the size is `perpendicular(d)` both ways.
//! - At a ridge or curve vertex (a corner of the border), every side's and arm's tensor
//!   at once, intersected, as at a 2D corner: on a cube's edge `perpendicular(0)` along
//!   both faces' normals and the largest size along the edge; at its corner
//!   `perpendicular(0)` every way. A ridge arm sizes only along itself.

use super::{
    border_source, check_entities, direction, normal_at, on_source, reach_of, tangent_at,
    tensor, Around, Arguments, Declaration, Failure, FunctionKind, Junctions, Parameter,
    ParameterKind, SizingAlgorithm, SpaceTensor, SpaceWork, Tensor, Work, ON_SOURCE,
};
use crate::geometry::space::curvature::{
    cross as cross3, dot as dot3, norm as norm3, sub as sub3, surface_curvature,
    tangent_basis as plane_basis, three_point_curvature as three_point_curvature3,
    unit as unit3, CurvatureError, CurvatureSide, SurfaceCurvature,
};
use crate::geometry::space::{Feature, Point3, SurfacePoint, TriangleProjection};
use crate::geometry::Point2;
use crate::mesh_graph::MeshGraph;
use crate::metric::{eigen2, SizeTensor, SizeTensor3, Sym2, Sym3};
use crate::sizing::functions::{CurvatureToSize, DistanceFunction, SizeProjectionFunction};
use super::EntitySet;
use crate::sizing::propagation::{ClosestPoint, Source};
use crate::sizing::space::{SpaceClosest, SpaceMesh, SpaceSource, SpaceSourceBuilder};
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
                kind: ParameterKind::Regions { dimensions: &[1], optional: false, lift: true },
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

    const IN_SPACE: bool = true;

    /// In space: the border's surfaces and curves in one source; the tensor from
    /// [`SpaceBorder`], whose ridges are every topological curve along a border triangle's
    /// edge (ridges, interface and boundary curves, line cells) and the border curves.
    fn work_in_space<'a>(
        &'a self,
        mesh: &'a SpaceMesh<'a>,
        topology: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        let set = &self.borders;
        check_entities(topology, set)?;
        if let Some(&index) = set.points.first() {
            return Err(Failure::UnsupportedEntity { what: "point", index });
        }
        if let Some(&index) = set.volumes.first() {
            return Err(Failure::UnsupportedEntity { what: "volume", index });
        }
        let points = mesh.points();
        let mut builder = SpaceSourceBuilder::new(points);
        // The pieces in the builder's order (each surface's cells, quads split along
        // 0–2; each curve's edges), in mesh vertices.
        let (mut pieces, mut triangles, mut edges) = (Vec::new(), Vec::new(), Vec::new());
        for &f in &set.faces {
            builder.surface(topology, f)?;
            for &c in &topology.faces[f].cells {
                let v: Vec<u32> =
                    topology.surface_cells[c].vertices().iter().map(|&x| x as u32).collect();
                let mut split = vec![[v[0], v[1], v[2]]];
                if v.len() == 4 {
                    split.push([v[0], v[2], v[3]]);
                }
                for t in split {
                    pieces.push(MeshPiece::Triangle(triangles.len() as u32));
                    triangles.push(t);
                }
            }
        }
        for &c in &set.curves {
            builder.curve(topology, c)?;
            for pl in &topology.curves[c].polylines {
                for [x, y] in pl.edges() {
                    if points[x] == points[y] {
                        pieces.push(MeshPiece::Point(x as u32));
                    } else {
                        pieces.push(MeshPiece::Segment([x as u32, y as u32]));
                        edges.push([x as u32, y as u32]);
                    }
                }
                if pl.num_edges() == 0 {
                    pieces.extend(pl.vertices.first().map(|&v| MeshPiece::Point(v as u32)));
                }
            }
        }
        if builder.is_empty() {
            return Err(Failure::NoSource);
        }
        let source = builder.build()?;
        debug_assert_eq!(source.len(), pieces.len());
        // Curves along the border triangles' edges: not smoothed across.
        let key = |a: u32, b: u32| (a.min(b), a.max(b));
        let mut along: Vec<(u32, u32)> =
            triangles.iter().flat_map(|t| [key(t[0], t[1]), key(t[1], t[2]), key(t[2], t[0])]).collect();
        along.sort_unstable();
        along.dedup();
        for curve in &topology.curves {
            for pl in &curve.polylines {
                for [x, y] in pl.edges() {
                    if along.binary_search(&key(x as u32, y as u32)).is_ok() {
                        edges.push([x as u32, y as u32]);
                    }
                }
            }
        }
        edges.sort_unstable_by_key(|e| key(e[0], e[1]));
        edges.dedup_by_key(|e| key(e[0], e[1]));
        let border = SpaceBorder::new(points, &triangles, &edges).map_err(
            |CurvatureError::VertexOutOfRange { vertex, len, .. }| Failure::EntityOutOfRange {
                what: "mesh vertex",
                index: vertex as usize,
                len,
            },
        )?;
        let reach = reach_of(&[self.perpendicular.max_distance(), self.projection.max_distance()]);
        let tensor = SpaceCurvatureTensor { algorithm: self, border, pieces };
        Ok(SpaceWork::FromSource { source, reach, tensor: Box::new(tensor) })
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

// ---------------------------------------------------------------------------------------
// In space: a border surface (its principal curvatures) and border curves (ridges, line
// cells: their three-point curvature), each vertex's tensor from its closest point.
// ---------------------------------------------------------------------------------------

/// The sign-free curvature tensor |k1| d1 d1ᵀ + |k2| d2 d2ᵀ of a side: sizes need |k|
/// only, and unlike the signed shape operator it interpolates between vertices whose
/// normals a file orients differently.
fn curvature_tensor(side: &CurvatureSide) -> Sym3 {
    let mut m = Sym3::ZERO;
    for (k, d) in side.k.iter().zip(&side.directions) {
        let k = k.abs();
        m.xx += k * d[0] * d[0];
        m.xy += k * d[0] * d[1];
        m.yy += k * d[1] * d[1];
        m.xz += k * d[0] * d[2];
        m.yz += k * d[1] * d[2];
        m.zz += k * d[2] * d[2];
    }
    m
}

fn lerp_sym3(a: &Sym3, b: &Sym3, t: f64) -> Sym3 {
    let l = |x: f64, y: f64| x + t * (y - x);
    Sym3 {
        xx: l(a.xx, b.xx),
        xy: l(a.xy, b.xy),
        yy: l(a.yy, b.yy),
        xz: l(a.xz, b.xz),
        yz: l(a.yz, b.yz),
        zz: l(a.zz, b.zz),
    }
}

/// The arms of the curves (ridges or line cells) at each vertex: the neighbour along
/// the curve and the curvature of that arm at the vertex, as the 2D pieces: the
/// three-point curvature at a smooth vertex (two arms turning by at most
/// [`CORNER_ANGLE`]), else (an end, a corner, a junction) the one-sided circle, the
/// curvature of the neighbour when it is smooth, else 0 (a straight piece).
#[derive(Debug, Clone, Default)]
pub(crate) struct CurveArms {
    /// Per curve vertex, its arms (neighbour, curvature) and whether it is smooth.
    arms: std::collections::BTreeMap<u32, (Vec<(u32, f64)>, bool)>,
}

impl CurveArms {
    /// The arms of the curves made of `edges` (vertex pairs into `points`, in range).
    pub(crate) fn new(points: &[Point3], edges: &[[u32; 2]]) -> CurveArms {
        let mut near: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
        for &[a, b] in edges {
            if a != b {
                near.entry(a).or_default().push(b);
                near.entry(b).or_default().push(a);
            }
        }
        for n in near.values_mut() {
            n.sort_unstable();
            n.dedup();
        }
        let cos_corner = CORNER_ANGLE.cos();
        let smooth = |v: u32| -> Option<f64> {
            let n = near.get(&v)?;
            if n.len() != 2 {
                return None;
            }
            let (p, a, b) = (points[v as usize], points[n[0] as usize], points[n[1] as usize]);
            let (u, w) = (unit3(sub3(p, a))?, unit3(sub3(b, p))?);
            (dot3(u, w) >= cos_corner).then(|| three_point_curvature3(a, p, b))
        };
        let arms = near
            .iter()
            .map(|(&v, n)| {
                let own = smooth(v);
                let arms = n.iter().map(|&u| (u, own.or_else(|| smooth(u)).unwrap_or(0.0))).collect();
                (v, (arms, own.is_some()))
            })
            .collect();
        CurveArms { arms }
    }

    /// The arms at `v` (none off the curves).
    pub(crate) fn at(&self, v: u32) -> &[(u32, f64)] {
        self.arms.get(&v).map_or(&[], |a| a.0.as_slice())
    }

    /// The directions a foot at curve vertex `v` sees with their curvatures: at a smooth
    /// vertex the one averaged tangent (as the 2D smooth vertex: the two arms' tensors,
    /// nearly parallel, would intersect into a size below both across the curve); at an
    /// end, a corner or a junction each arm's own direction (intersected by the caller,
    /// as at a 2D corner).
    fn directions(&self, points: &[Point3], v: u32) -> Vec<(Point3, f64)> {
        let Some((arms, smooth)) = self.arms.get(&v) else { return Vec::new() };
        let dir = |w: u32| unit3(sub3(points[w as usize], points[v as usize]));
        if *smooth {
            if let (Some(a), Some(b)) = (dir(arms[0].0), dir(arms[1].0)) {
                if let Some(t) = unit3(sub3(b, a)) {
                    return vec![(t, arms[0].1)];
                }
            }
        }
        arms.iter().filter_map(|&(w, k)| Some((dir(w)?, k))).collect()
    }

    /// The curvature of edge (a, b) at `a`, if it is one of the curves'.
    fn along(&self, a: u32, b: u32) -> Option<f64> {
        self.at(a).iter().find(|arm| arm.0 == b).map(|arm| arm.1)
    }
}

/// What CURVATURE_OF_BORDER knows of a border in space: its surface triangles with their
/// curvature (ridges apart), and the curves (ridges, interface curves, line cells) with
/// their arms. `points` are the mesh's; every index is in range.
pub(crate) struct SpaceBorder<'a> {
    points: &'a [Point3],
    triangles: Vec<[u32; 3]>,
    curvature: SurfaceCurvature,
    arms: CurveArms,
}

/// Where a vertex's closest point on a border in space lies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum SpaceFoot {
    /// On triangle `triangle` of the border (index into its triangles), as the surface
    /// index reports it.
    Surface(SurfacePoint),
    /// On curve edge (a, b) at parameter `t` from a, at `distance`, foot `foot`.
    Curve { edge: [u32; 2], t: f64, distance: f64, foot: Point3 },
}

impl<'a> SpaceBorder<'a> {
    /// The border made of `triangles` and the curve `edges` over `points`; `edges` are
    /// also the ridges the surface's curvature does not smooth across.
    pub(crate) fn new(
        points: &'a [Point3],
        triangles: &[[u32; 3]],
        edges: &[[u32; 2]],
    ) -> Result<SpaceBorder<'a>, CurvatureError> {
        let curvature = surface_curvature(points, triangles, edges)?;
        let arms = CurveArms::new(points, edges);
        Ok(SpaceBorder { points, triangles: triangles.to_vec(), curvature, arms })
    }

    /// The tensor of `p` (mesh vertex `v`, for errors) from its closest point `foot`: on
    /// the surface the normal size `perpendicular(d)` along the normal (from the foot to
    /// `p` off the surface), and in the tangent plane the curvature-to-size function of
    /// each principal curvature along its direction, carried by `projection(d, ·)`; the
    /// principal curvatures interpolated at the foot as sign-free tensors and read in the
    /// plane across the normal. On a curve the tangent size from the curve's curvature
    /// and `perpendicular(d)` across it. Where the foot is on a ridge or a curve vertex,
    /// every side's and arm's tensor at once (their intersection, as at a 2D corner).
    pub(crate) fn tensor(
        &self,
        algorithm: &CurvatureOfBorder,
        p: Point3,
        v: usize,
        foot: &SpaceFoot,
    ) -> Result<SizeTensor3, Failure> {
        match *foot {
            SpaceFoot::Surface(c) => self.surface_tensor(algorithm, p, v, &c),
            SpaceFoot::Curve { edge, t, distance, foot } => {
                self.curve_tensor(algorithm, p, v, edge, t, distance, foot)
            }
        }
    }

    fn surface_tensor(
        &self,
        a: &CurvatureOfBorder,
        p: Point3,
        v: usize,
        c: &SurfacePoint,
    ) -> Result<SizeTensor3, Failure> {
        let d = c.distance();
        let tri = *self.triangles.get(c.triangle as usize).ok_or(Failure::Degenerate { vertex: v })?;
        let patch = self.curvature.patch_of(c.triangle as usize);
        let scale = norm3(sub3(self.points[tri[1] as usize], self.points[tri[0] as usize]))
            .max(norm3(sub3(self.points[tri[2] as usize], self.points[tri[0] as usize])));
        let on = d == 0.0 || d <= ON_SOURCE * scale;
        let side_of = |u: u32, patch: u32| self.curvature.side(u as usize, patch);
        let k_of = |u: u32, patch: u32| side_of(u, patch).map_or(Sym3::ZERO, curvature_tensor);
        // The curvature tensors (each with its normal) the foot sees, and the arms.
        let mut sides: Vec<(Option<Point3>, Sym3)> = Vec::new();
        let mut arms: Vec<(Point3, f64)> = Vec::new();
        let away = if on { None } else { c.away(p) };
        // A foot on a corner to rounding (within ON_SOURCE of the triangle's size) is at
        // that vertex: the kernel may report a point on a vertex as in the face.
        let at_vertex = (0..3).find(|&i| {
            norm3(sub3(self.points[tri[i] as usize], c.projection.foot)) <= ON_SOURCE * scale
        });
        let feature = at_vertex.map_or(c.projection.feature, |i| Feature::Vertex(i as u8));
        match feature {
            Feature::Vertex(i) => {
                let u = tri[i as usize];
                for s in self.curvature.sides(u as usize) {
                    sides.push((Some(s.normal), curvature_tensor(s)));
                }
                arms = self.arms.directions(self.points, u);
            }
            Feature::Edge(e) => {
                let (x, y) = (tri[e as usize], tri[(e as usize + 1) % 3]);
                let (px, py) = (self.points[x as usize], self.points[y as usize]);
                let t = parameter(px, py, c.projection.foot);
                if let (Some(kx), Some(ky)) = (self.arms.along(x, y), self.arms.along(y, x)) {
                    // A ridge: each patch with a side at both ends, and the ridge itself.
                    for s in self.curvature.sides(x as usize) {
                        if let Some(o) = side_of(y, s.patch) {
                            let n = unit3(lerp3(s.normal, o.normal, t));
                            sides.push((n, lerp_sym3(&curvature_tensor(s), &curvature_tensor(o), t)));
                        }
                    }
                    if let Some(dir) = unit3(sub3(py, px)) {
                        arms.push((dir, kx + t * (ky - kx)));
                    }
                } else {
                    let n = match (side_of(x, patch), side_of(y, patch)) {
                        (Some(s), Some(o)) => unit3(lerp3(s.normal, o.normal, t)),
                        _ => None,
                    };
                    sides.push((n, lerp_sym3(&k_of(x, patch), &k_of(y, patch), t)));
                }
            }
            Feature::Face => {
                // The vertices' tensors and fitted normals, interpolated (the flat
                // triangle's normal only where a vertex has no side).
                let pts = tri.map(|u| self.points[u as usize]);
                let w = barycentric(pts, c.projection.foot);
                let (mut k, mut n) = (Sym3::ZERO, [0.0; 3]);
                let flat = triangle_normal(pts);
                for (i, &u) in tri.iter().enumerate() {
                    let ku = k_of(u, patch);
                    k.xx += w[i] * ku.xx;
                    k.xy += w[i] * ku.xy;
                    k.yy += w[i] * ku.yy;
                    k.xz += w[i] * ku.xz;
                    k.yz += w[i] * ku.yz;
                    k.zz += w[i] * ku.zz;
                    let mut nu = side_of(u, patch).map(|s| s.normal).or(flat).unwrap_or([0.0; 3]);
                    if flat.is_some_and(|f| dot3(f, nu) < 0.0) {
                        nu = scale3(nu, -1.0);
                    }
                    n = [n[0] + w[i] * nu[0], n[1] + w[i] * nu[1], n[2] + w[i] * nu[2]];
                }
                sides.push((unit3(n).or(flat), k));
            }
        }
        let h_normal = a.perpendicular.eval(d);
        let mut out: Option<SizeTensor3> = None;
        let mut meet = |s: SizeTensor3| {
            out = Some(match out {
                Some(o) => o.intersection(&s),
                None => s,
            })
        };
        for (normal, k) in sides {
            let Some(n) = away.or(normal) else { continue };
            meet(tangent_tensor(a, v, n, &k, d, h_normal)?);
        }
        for (t, k) in arms {
            // An arm sizes along itself only (across it, the surfaces' sides do).
            let h_t = a.projection.eval(d, a.curvature.eval(k));
            let h_free = a.projection.eval(d, a.curvature.max_size());
            meet(arm_tensor(v, t, away, h_t, h_normal, h_free)?);
        }
        out.ok_or(Failure::Degenerate { vertex: v })
    }

    #[allow(clippy::too_many_arguments)]
    fn curve_tensor(
        &self,
        a: &CurvatureOfBorder,
        p: Point3,
        v: usize,
        edge: [u32; 2],
        t: f64,
        d: f64,
        foot: Point3,
    ) -> Result<SizeTensor3, Failure> {
        let [x, y] = edge;
        let (px, py) = (self.points[x as usize], self.points[y as usize]);
        let h_normal = a.perpendicular.eval(d);
        let on = d == 0.0 || d <= ON_SOURCE * norm3(sub3(py, px));
        let away = if on { None } else { unit3(sub3(p, foot)) };
        // A foot at an end sees every arm there; inside, the edge's own curvature.
        let end = if t <= 0.0 || foot == px {
            Some(x)
        } else if t >= 1.0 || foot == py {
            Some(y)
        } else {
            None
        };
        let arms: Vec<(Point3, f64)> = match end {
            Some(u) => self.arms.directions(self.points, u),
            None => {
                let kx = self.arms.along(x, y).unwrap_or(0.0);
                let ky = self.arms.along(y, x).unwrap_or(0.0);
                unit3(sub3(py, px)).map(|dir| (dir, kx + t * (ky - kx))).into_iter().collect()
            }
        };
        let mut out: Option<SizeTensor3> = None;
        for (dir, k) in arms {
            let h_t = a.projection.eval(d, a.curvature.eval(k));
            let s = arm_tensor(v, dir, away, h_t, h_normal, h_normal)?;
            out = Some(match out {
                Some(o) => o.intersection(&s),
                None => s,
            });
        }
        out.ok_or(Failure::Degenerate { vertex: v })
    }
}

/// A piece of the source in space, in mesh vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
enum MeshPiece {
    /// A border triangle (index into the [`SpaceBorder`]'s triangles).
    Triangle(u32),
    /// A curve edge.
    Segment([u32; 2]),
    /// A curve of one vertex.
    Point(u32),
}

/// The tensor of CURVATURE_OF_BORDER in space.
struct SpaceCurvatureTensor<'a> {
    algorithm: &'a CurvatureOfBorder,
    border: SpaceBorder<'a>,
    /// The source's pieces, by piece index.
    pieces: Vec<MeshPiece>,
}

impl SpaceTensor for SpaceCurvatureTensor<'_> {
    fn tensor(
        &self,
        _: &[SpaceSource],
        v: usize,
        at: Point3,
        closest: &[SpaceClosest],
    ) -> Result<Option<SizeTensor3>, Failure> {
        let (a, c) = (self.algorithm, &closest[0]);
        let projection = TriangleProjection {
            distance_squared: c.distance_squared,
            foot: c.foot,
            feature: c.feature,
        };
        let foot = match self.pieces.get(c.piece as usize) {
            Some(&MeshPiece::Triangle(triangle)) => {
                SpaceFoot::Surface(SurfacePoint { triangle, projection })
            }
            Some(&MeshPiece::Segment(edge)) => {
                let (p, q) = (self.border.points[edge[0] as usize], self.border.points[edge[1] as usize]);
                let t = parameter(p, q, c.foot);
                SpaceFoot::Curve { edge, t, distance: c.distance, foot: c.foot }
            }
            // A curve of one point has no curvature: the normal size every way, or the
            // largest size carried inward where that is smaller.
            Some(&MeshPiece::Point(_)) => {
                let h = a.perpendicular.eval(c.distance).min(a.projection.eval(c.distance, a.curvature.max_size()));
                return SizeTensor3::try_new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [h; 3])
                    .map(Some)
                    .ok_or(Failure::Degenerate { vertex: v });
            }
            None => return Err(Failure::Degenerate { vertex: v }),
        };
        self.border.tensor(a, at, v, &foot).map(Some)
    }
}

/// `h_normal` along `n`, and in the plane across it the curvature-to-size function of
/// the principal curvatures of `k` read in that plane, carried by `projection(d, ·)`.
fn tangent_tensor(
    a: &CurvatureOfBorder,
    v: usize,
    n: Point3,
    k: &Sym3,
    d: f64,
    h_normal: f64,
) -> Result<SizeTensor3, Failure> {
    let (u, w) = plane_basis(n);
    let m = Sym2 { a: k.quadratic_form(u), b: dot3(k.mul_vec(u), w), c: k.quadratic_form(w) };
    let e = eigen2(m);
    let t1 = [
        e.vector[0] * u[0] + e.vector[1] * w[0],
        e.vector[0] * u[1] + e.vector[1] * w[1],
        e.vector[0] * u[2] + e.vector[1] * w[2],
    ];
    let h = |kappa: f64| a.projection.eval(d, a.curvature.eval(kappa.max(0.0)));
    SizeTensor3::try_new(n, t1, [h_normal, h(e.values[0]), h(e.values[1])])
        .ok_or(Failure::Degenerate { vertex: v })
}

/// `h_t` along the curve direction `t`; off the curve (`away` given) `h_away` along
/// `away`, the tangent's part across it along the second axis, `h_across` along the
/// third; on the curve `h_across` along both directions across `t`.
fn arm_tensor(
    v: usize,
    t: Point3,
    away: Option<Point3>,
    h_t: f64,
    h_away: f64,
    h_across: f64,
) -> Result<SizeTensor3, Failure> {
    let tensor = match away {
        // Seen along the tangent itself, any direction across it.
        Some(n) => {
            let along = sub3(t, scale3(n, dot3(t, n)));
            let second = unit3(along).unwrap_or_else(|| plane_basis(n).0);
            SizeTensor3::try_new(n, second, [h_away, h_t, h_across])
        }
        None => SizeTensor3::try_new(t, plane_basis(t).0, [h_t, h_across, h_across]),
    };
    tensor.ok_or(Failure::Degenerate { vertex: v })
}

/// The parameter of the projection of `q` on segment (a, b), clamped to [0, 1].
fn parameter(a: Point3, b: Point3, q: Point3) -> f64 {
    let ab = sub3(b, a);
    let l2 = dot3(ab, ab);
    if l2 > 0.0 {
        (dot3(sub3(q, a), ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The barycentric coordinates of `q` (on the triangle's plane) in triangle `t`, from
/// the sub-triangles' areas along the normal; a third each for a degenerate triangle.
fn barycentric(t: [Point3; 3], q: Point3) -> [f64; 3] {
    let n = cross3(sub3(t[1], t[0]), sub3(t[2], t[0]));
    let total = dot3(n, n);
    if total.is_nan() || total <= 0.0 {
        return [1.0 / 3.0; 3];
    }
    let area = |a: Point3, b: Point3| dot3(cross3(sub3(a, q), sub3(b, q)), n).max(0.0);
    let w = [area(t[1], t[2]), area(t[2], t[0]), area(t[0], t[1])];
    let s = w[0] + w[1] + w[2];
    if s > 0.0 {
        w.map(|x| x / s)
    } else {
        [1.0 / 3.0; 3]
    }
}

fn triangle_normal(t: [Point3; 3]) -> Option<Point3> {
    unit3(cross3(sub3(t[1], t[0]), sub3(t[2], t[0])))
}

fn scale3(a: Point3, s: f64) -> Point3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn lerp3(a: Point3, b: Point3, t: f64) -> Point3 {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])]
}

#[cfg(test)]
#[path = "curvature_of_border_space_tests.rs"]
mod space_tests;
