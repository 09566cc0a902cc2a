//! DISTANCE_BETWEEN_TWO_BORDERS (thesis 3.4, 4.3.6.4, Algorithm 4.3, Fig. 4.6): sizes
//! from the local thickness of a gap between two borders.
//!
//! Thickness: d = d1 + d2, the exact distances from the vertex to the first and to the
//! second border, each from its own propagation up to the reach R. A vertex with
//! d <= R gets a tensor; d1, d2 <= d, so both propagations reach every such vertex.
//! This covers, as thesis 4.3.6.4's loop over the first border means to, every vertex
//! of the first border within reach (d = distance to the second border there), not only
//! the first one found.
//!
//! Sizes: thesis 4.3.6.4 feeds d1 + d2 to both distance functions in all three of its
//! cases (on the first border d "becomes the distance to the second", which is d1 + d2
//! with d1 = 0), so both are evaluated at the thickness: `perpendicular(d)` across the
//! gap, `parallel(d)` along it. Between two parallel walls the tensor is then constant.
//!
//! Orientation (thesis Fig. 4.6): with **d1**, **d2** the vectors from the vertex to its
//! closest points, the normal is w = d2 **d1**/d1 − d1 **d2**/d2, normalised: near one
//! border it follows that border's normal, halfway it is the mean of both. On a border
//! (d1 = 0 or d2 = 0) it is that border's normal, as in DISTANCE_TO_BORDER; when w
//! vanishes (both borders seen in the same direction at equal distances) it is the
//! direction of the nearer border.
//!
//! Reach R: the larger of the two functions' maximum distances (module [`super`]).
//!
//! In space the same, the borders surfaces, curves or points (as DISTANCE_TO_BORDER's),
//! each in its own exact closest-point index: thickness d1 + d2, the normal w of Fig. 4.6
//! from the two feet in space (on a border, that border's frame,
//! `super::frame3`), `perpendicular(d)` along it and `parallel(d)` twice across it.

use super::{
    border_source, normal_at, on_source, reach_of, tensor, unit, Around, Arguments, Declaration,
    Failure, FunctionKind, Junctions, Parameter, ParameterKind, SizingAlgorithm, Tensor, Work,
};
use crate::geometry::Point2;
use crate::mesh_graph::MeshGraph;
use crate::sizing::functions::DistanceFunction;
use super::EntitySet;
use crate::metric::SizeTensor;
use crate::sizing::propagation::{ClosestPoint, Source};
use super::{across, on_source3, space_border_source, wall_tensor, Across, SpaceTensor, SpaceWork};
use crate::metric::SizeTensor3;
use crate::sizing::space::{unit3, SpaceClosest, SpaceMesh, SpaceSource};
use crate::topology::Topology;

/// DISTANCE_BETWEEN_TWO_BORDERS: sizes from the local thickness d1 + d2 between
/// `first` and `second` (thesis figure 4.6).
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceBetweenTwoBorders {
    /// Size normal to the gap against thickness.
    pub perpendicular: DistanceFunction,
    /// Size along the gap against thickness.
    pub parallel: DistanceFunction,
    /// The first border (REGIONS).
    pub first: EntitySet,
    /// The second border (REGIONS2).
    pub second: EntitySet,
}

impl SizingAlgorithm for DistanceBetweenTwoBorders {
    const DECLARATION: Declaration = Declaration {
        keyword: "DISTANCE_BETWEEN_TWO_BORDERS",
        name: "distance_between_two_borders",
        doc: "Sizes from the local thickness d = d1 + d2 of the gap between two borders: \
              PERPENDICULAR_FUNCTION(d) across it, PARALLEL_FUNCTION(d) along it (thesis \
              4.3.6.4).",
        parameters: &[
            Parameter {
                field: "perpendicular",
                aliases: &[],
                keys: &["PERPENDICULAR_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: true,
                doc: "Size normal to the gap against thickness.",
            },
            Parameter {
                field: "parallel",
                aliases: &[],
                keys: &["PARALLEL_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: false,
                doc: "Size along the gap against thickness.",
            },
            Parameter {
                field: "regions",
                aliases: &[],
                keys: &["REGIONS"],
                kind: ParameterKind::Regions { dimensions: &[1, 0], optional: false, lift: true },
                line_break_after: false,
                doc: "The first border.",
            },
            Parameter {
                field: "second_regions",
                aliases: &["regions2"],
                keys: &["REGIONS2"],
                kind: ParameterKind::Regions { dimensions: &[1, 0], optional: false, lift: true },
                line_break_after: false,
                doc: "The second border.",
            },
        ],
    };

    type Tensor<'a> = GapTensor<'a>;

    fn from_arguments(arguments: &mut Arguments) -> Option<DistanceBetweenTwoBorders> {
        Some(DistanceBetweenTwoBorders {
            perpendicular: arguments.distance("perpendicular")?,
            parallel: arguments.distance("parallel")?,
            first: arguments.entities("regions")?,
            second: arguments.entities("second_regions")?,
        })
    }

    fn entity_sets(&self) -> Vec<&EntitySet> {
        vec![&self.first, &self.second]
    }

    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        Some((Around::Entities(self.first.union(&self.second)), 0.0))
    }

    fn work<'a>(
        &'a self,
        graph: &'a MeshGraph,
        topology: &'a Topology,
    ) -> Result<Work<GapTensor<'a>>, Failure> {
        let s1 = border_source(graph, topology, &self.first, true)?;
        let s2 = border_source(graph, topology, &self.second, true)?;
        let junctions = [Junctions::new(&s1), Junctions::new(&s2)];
        let reach = reach_of(&[self.perpendicular.max_distance(), self.parallel.max_distance()]);
        let tensor = GapTensor { algorithm: self, graph, junctions, reach };
        Ok(Work::FromTwoSources { sources: [s1, s2], reach, tensor })
    }

    const IN_SPACE: bool = true;

    fn work_in_space<'a>(
        &'a self,
        mesh: &'a SpaceMesh<'a>,
        topology: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        let s1 = space_border_source(mesh, topology, &self.first, true)?;
        let s2 = space_border_source(mesh, topology, &self.second, true)?;
        let reach = reach_of(&[self.perpendicular.max_distance(), self.parallel.max_distance()]);
        let tensor = Box::new(GapTensor3 { algorithm: self, reach });
        Ok(SpaceWork::FromTwoSources { sources: [s1, s2], reach, tensor })
    }
}

/// The tensor of DISTANCE_BETWEEN_TWO_BORDERS in space.
struct GapTensor3<'a> {
    algorithm: &'a DistanceBetweenTwoBorders,
    reach: f64,
}

impl SpaceTensor for GapTensor3<'_> {
    fn tensor(
        &self,
        sources: &[SpaceSource],
        v: usize,
        at: [f64; 3],
        closest: &[SpaceClosest],
    ) -> Result<Option<SizeTensor3>, Failure> {
        let (c1, c2) = (&closest[0], &closest[1]);
        let thickness = c1.distance + c2.distance;
        if thickness.is_nan() || thickness > self.reach {
            return Ok(None);
        }
        let frame = gap_frame(at, (&sources[0], c1), (&sources[1], c2));
        let a = self.algorithm;
        wall_tensor(v, frame, a.perpendicular.eval(thickness), a.parallel.eval(thickness)).map(Some)
    }
}

/// The weighted normal of thesis Fig. 4.6 in space (see the module header).
fn gap_frame(
    p: [f64; 3],
    first: (&SpaceSource, &SpaceClosest),
    second: (&SpaceSource, &SpaceClosest),
) -> Across {
    let ((s1, c1), (s2, c2)) = (first, second);
    if on_source3(s1, c1) {
        return across(s1, c1, p);
    }
    if on_source3(s2, c2) {
        return across(s2, c2, p);
    }
    let (d1, d2) = (c1.distance, c2.distance);
    let u1 = [0, 1, 2].map(|k| (c1.foot[k] - p[k]) / d1);
    let u2 = [0, 1, 2].map(|k| (c2.foot[k] - p[k]) / d2);
    let w = [0, 1, 2].map(|k| d2 * u1[k] - d1 * u2[k]);
    let norm = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let n = if norm > 1e-9 * (d1 + d2) {
        unit3(w)
    } else if d1 <= d2 {
        unit3(u1)
    } else {
        unit3(u2)
    };
    n.map_or(Across::Point, Across::Normal)
}

/// The tensor of DISTANCE_BETWEEN_TWO_BORDERS.
pub(crate) struct GapTensor<'a> {
    algorithm: &'a DistanceBetweenTwoBorders,
    graph: &'a MeshGraph,
    junctions: [Junctions; 2],
    reach: f64,
}

impl Tensor for GapTensor<'_> {
    fn tensor(
        &self,
        sources: &[Source],
        v: usize,
        closest: &[ClosestPoint],
    ) -> Result<Option<SizeTensor>, Failure> {
        let (c1, c2) = (&closest[0], &closest[1]);
        let thickness = c1.distance + c2.distance;
        // NaN distances (non-finite coordinates) fail this test too.
        if thickness.is_nan() || thickness > self.reach {
            return Ok(None);
        }
        let p = self.graph.point(v);
        let [j1, j2] = &self.junctions;
        let n = gap_normal(p, (&sources[0], j1, c1), (&sources[1], j2, c2));
        let a = self.algorithm;
        tensor(v, n, a.perpendicular.eval(thickness), a.parallel.eval(thickness)).map(Some)
    }
}

/// The weighted normal of thesis Fig. 4.6 (see the module header).
fn gap_normal(
    p: Point2,
    first: (&Source, &Junctions, &ClosestPoint),
    second: (&Source, &Junctions, &ClosestPoint),
) -> Option<Point2> {
    let (s1, j1, c1) = first;
    let (s2, j2, c2) = second;
    if on_source(s1, c1) {
        return normal_at(s1, j1, p, c1);
    }
    if on_source(s2, c2) {
        return normal_at(s2, j2, p, c2);
    }
    let (d1, d2) = (c1.distance, c2.distance);
    let u1 = [(c1.foot[0] - p[0]) / d1, (c1.foot[1] - p[1]) / d1];
    let u2 = [(c2.foot[0] - p[0]) / d2, (c2.foot[1] - p[1]) / d2];
    let w = [d2 * u1[0] - d1 * u2[0], d2 * u1[1] - d1 * u2[1]];
    if w[0].hypot(w[1]) > 1e-9 * (d1 + d2) {
        unit(w)
    } else if d1 <= d2 {
        unit(u1)
    } else {
        unit(u2)
    }
}
