//! DISTANCE_TO_POINT (thesis 2.2.10.2, 4.3.6.2, Algorithm 4.2): the isotropic size
//! `function(d)`, d the Euclidean distance from the vertex to the nearest source point,
//! on every vertex within the function's maximum distance.
//!
//! Sources are topological points; a curve given as a source contributes each vertex of
//! its polylines as a point (not its segments: for the distance to a curve use
//! DISTANCE_TO_BORDER). Several sources act as one set: the distance is to the nearest,
//! as in the other algorithms, rather than one run per point intersected (which differs
//! only for functions that shrink away from the source, thesis 7.4.3).
//!
//! In space the same: the source points are the sources' mesh vertices in one
//! `SpaceSource`, each distance exact (bit for bit a
//! scan of every point).

use super::{
    check_entities, Around, Arguments, Declaration, Failure, FunctionKind, Marks, Parameter,
    ParameterKind, SizingAlgorithm, SpaceTensor, SpaceWork, Tensor, Work,
};
use crate::metric::SizeTensor3;
use crate::sizing::space::{SpaceClosest, SpaceMesh, SpaceSource, SpaceSourceBuilder};
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use crate::sizing::functions::DistanceFunction;
use super::EntitySet;
use crate::sizing::propagation::{ClosestPoint, Source, SourceBuilder};
use crate::topology::Topology;

/// DISTANCE_TO_POINT: isotropic size `function(distance)` from the sources' vertices
/// (topological points; a curve given here contributes its vertices).
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceToPoint {
    /// Size against distance.
    pub function: DistanceFunction,
    /// The sources.
    pub sources: EntitySet,
}

impl SizingAlgorithm for DistanceToPoint {
    const DECLARATION: Declaration = Declaration {
        keyword: "DISTANCE_TO_POINT",
        name: "distance_to_point",
        doc: "The isotropic size FUNCTION(d), d the distance to the nearest source point \
              (thesis 4.3.6.2).",
        parameters: &[
            Parameter {
                field: "function",
                aliases: &[],
                keys: &["FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: false,
                doc: "Size against distance.",
            },
            Parameter {
                field: "regions",
                aliases: &[],
                keys: &["REGIONS"],
                kind: ParameterKind::Regions { dimensions: &[0, 1], optional: false, lift: false },
                line_break_after: false,
                doc: "The sources: points, or curves whose vertices are point sources.",
            },
        ],
    };

    type Tensor<'a> = PointTensor<'a>;

    fn from_arguments(arguments: &mut Arguments) -> Option<DistanceToPoint> {
        Some(DistanceToPoint {
            function: arguments.distance("function")?,
            sources: arguments.entities("regions")?,
        })
    }

    fn entity_sets(&self) -> Vec<&EntitySet> {
        vec![&self.sources]
    }

    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        Some((Around::Entities(self.sources.clone()), self.function.max_distance()))
    }

    fn marks(&self) -> Marks<'_> {
        Marks { polyline: None, points: &self.sources.points }
    }

    fn work<'a>(
        &'a self,
        graph: &'a MeshGraph,
        topology: &'a Topology,
    ) -> Result<Work<PointTensor<'a>>, Failure> {
        let sources = &self.sources;
        check_entities(topology, sources)?;
        if let Some(&index) = sources.faces.first() {
            return Err(Failure::UnsupportedEntity { what: "face", index });
        }
        let mut b = SourceBuilder::new(graph);
        for &p in &sources.points {
            b.topology_point(topology, p);
        }
        for &c in &sources.curves {
            for pl in &topology.curves[c].polylines {
                for &v in &pl.vertices {
                    b.vertex(v);
                }
            }
        }
        let source = b.build()?;
        if source.segments().is_empty() {
            return Err(Failure::NoSource);
        }
        let reach = self.function.max_distance();
        Ok(Work::FromSource { source, reach, tensor: PointTensor(&self.function) })
    }

    const IN_SPACE: bool = true;

    fn work_in_space<'a>(
        &'a self,
        mesh: &'a SpaceMesh<'a>,
        topology: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        let sources = &self.sources;
        check_entities(topology, sources)?;
        if let Some(&index) = sources.faces.first() {
            return Err(Failure::UnsupportedEntity { what: "face", index });
        }
        if let Some(&index) = sources.volumes.first() {
            return Err(Failure::UnsupportedEntity { what: "volume", index });
        }
        let mut b = SpaceSourceBuilder::new(mesh.points());
        for &p in &sources.points {
            b.topology_point(topology, p)?;
        }
        for &c in &sources.curves {
            for pl in &topology.curves[c].polylines {
                for &v in &pl.vertices {
                    b.vertex(v)?;
                }
            }
        }
        if b.is_empty() {
            return Err(Failure::NoSource);
        }
        let source = b.build()?;
        let reach = self.function.max_distance();
        Ok(SpaceWork::FromSource { source, reach, tensor: Box::new(PointTensor(&self.function)) })
    }
}

impl SpaceTensor for PointTensor<'_> {
    fn tensor(
        &self,
        _: &[SpaceSource],
        v: usize,
        _: [f64; 3],
        closest: &[SpaceClosest],
    ) -> Result<Option<SizeTensor3>, Failure> {
        let h = self.0.eval(closest[0].distance);
        SizeTensor3::try_new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [h; 3])
            .map(Some)
            .ok_or(Failure::Degenerate { vertex: v })
    }
}

/// The tensor of DISTANCE_TO_POINT.
pub(crate) struct PointTensor<'a>(&'a DistanceFunction);

impl Tensor for PointTensor<'_> {
    #[inline(always)]
    fn tensor(
        &self,
        _: &[Source],
        v: usize,
        closest: &[ClosestPoint],
    ) -> Result<Option<SizeTensor>, Failure> {
        let h = self.0.eval(closest[0].distance);
        SizeTensor::try_new([1.0, 0.0], h, h).map(Some).ok_or(Failure::Degenerate { vertex: v })
    }
}
