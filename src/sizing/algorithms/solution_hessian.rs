//! SOLUTION_HESSIAN: the Lp-optimal metric of a computed scalar field (a solution) on
//! the mesh being sized: the field's Hessian recovered at every vertex
//! ([`crate::solution::recovery`], the quadratic fit unless told otherwise), made into
//! M = D det(|H|)^(−1/(2p+2)) |H| and normalised to a vertex count
//! ([`crate::solution::lp`]). The field is the mesh's scalar point-data array FIELD; in a
//! recipe the step is intersected with the others in recipe order like any other, so the
//! geometry's sizes and the solution's both hold where each is the finer. No propagation:
//! every vertex some cell uses gets a tensor, in increasing index order.
//!
//! Bounds: unless given (the command line gives its own), h_max is the diagonal of the
//! mesh's bounding box, h_min 1e-6 of it and the aspect ratio at most 1e4; the plan's
//! global bounds clamp the field afterwards, which can move its vertex count away from
//! COMPLEXITY where they act.

use super::{
    Around, Arguments, Contribution, Declaration, Failure, Parameter, ParameterKind,
    SizingAlgorithm, Work,
};
use crate::mesh_graph::{MeshGraph, PointValues};
use crate::metric::{SizeBounds, SizeTensor};
use crate::sizing::plan::EntitySet;
use crate::solution::{lp_metric, recover, LpMetric, LpOptions, Method, P1Mesh, Target};
use crate::topology::Topology;

/// SOLUTION_HESSIAN: the Lp-optimal metric of point field `field`.
#[derive(Debug, Clone, PartialEq)]
pub struct SolutionHessian {
    /// The scalar point-data array.
    pub field: String,
    /// The normalisation.
    pub target: Target,
    /// The norm (≥ 1, or infinite).
    pub p: f64,
    /// How the Hessian is recovered.
    pub method: Method,
    /// h_min, h_max and the aspect ratio; `None`: from the mesh (see the module
    /// documentation).
    pub bounds: Option<SizeBounds>,
}

impl SolutionHessian {
    /// The bounds used when none are given, for a mesh whose bounding box has diagonal
    /// `diagonal`.
    pub fn default_bounds(diagonal: f64) -> Option<SizeBounds> {
        SizeBounds::try_new(1e-6 * diagonal, diagonal, 1e4)
    }

    /// The metric on the mesh of `graph`, with what the normalisation gave; an error in
    /// words naming the field.
    pub fn metric(&self, graph: &MeshGraph) -> Result<LpMetric, String> {
        let name = &self.field;
        let values = match graph.point_data().get(name) {
            Some(PointValues::Scalar(v)) => v,
            Some(PointValues::Other { components, items }) => {
                return Err(format!(
                    "point data `{name}` has {components} components and {items} items; a solution field is a scalar with one value per vertex ({})",
                    graph.num_vertices()
                ))
            }
            None => {
                let names: Vec<&str> = graph.point_data().keys().map(String::as_str).collect();
                return Err(format!(
                    "the mesh has no point data `{name}` (its arrays: {})",
                    if names.is_empty() { "none".to_string() } else { names.join(", ") }
                ));
            }
        };
        let why = |e: &dyn std::fmt::Display| format!("point data `{name}`: {e}");
        let mesh = P1Mesh::new(graph.points(), graph.cells()).map_err(|e| why(&e))?;
        let derivatives = recover(&mesh, values, self.method).map_err(|e| why(&e))?;
        let bounds = match self.bounds {
            Some(b) => b,
            None => graph
                .bounds()
                .and_then(|(lo, hi)| Self::default_bounds((hi[0] - lo[0]).hypot(hi[1] - lo[1])))
                .ok_or_else(|| format!("point data `{name}`: the mesh has no extent"))?,
        };
        let options = LpOptions { p: self.p, target: self.target, bounds };
        lp_metric(&mesh, &derivatives.hessian, &options).map_err(|e| why(&e))
    }
}

impl SizingAlgorithm for SolutionHessian {
    const DECLARATION: Declaration = Declaration {
        keyword: "SOLUTION_HESSIAN",
        name: "solution_hessian",
        doc: "The Lp-optimal metric (Loseille-Alauzet) of the scalar point field FIELD of the mesh being sized: its Hessian recovered by a least-squares quadratic on each vertex's patch, M = D det(|H|)^(-1/(2P+2)) |H|, normalised so that a mesh conforming to it has about COMPLEXITY vertices.",
        parameters: &[
            Parameter {
                field: "field",
                aliases: &[],
                keys: &["FIELD"],
                kind: ParameterKind::PointData,
                line_break_after: false,
                doc: "The scalar point-data array (a solution) of the mesh being sized.",
            },
            Parameter {
                field: "complexity",
                aliases: &[],
                keys: &["COMPLEXITY"],
                kind: ParameterKind::Size,
                line_break_after: false,
                doc: "The vertex count the metric asks for (its complexity).",
            },
            Parameter {
                field: "p",
                aliases: &[],
                keys: &["P"],
                kind: ParameterKind::Size,
                line_break_after: false,
                doc: "The Lp norm of the interpolation error the metric minimises (2 is usual; 1 resolves weak features more, large p the strongest).",
            },
        ],
    };

    type Tensor<'a> = std::convert::Infallible;

    fn from_arguments(arguments: &mut Arguments) -> Option<SolutionHessian> {
        Some(SolutionHessian {
            field: arguments.name("field")?,
            target: Target::Vertices(arguments.size("complexity")?),
            p: arguments.size("p")?,
            method: Method::QuadraticFit,
            bounds: None,
        })
    }

    fn entity_sets(&self) -> Vec<&EntitySet> {
        Vec::new()
    }

    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        None
    }

    fn work<'a>(
        &'a self,
        graph: &'a MeshGraph,
        _: &'a Topology,
    ) -> Result<Work<Self::Tensor<'a>>, Failure> {
        let metric = self.metric(graph).map_err(|why| Failure::Field { why })?;
        let used = used_vertices(graph);
        let tensors: Vec<SizeTensor> = used.iter().map(|&v| metric.tensors[v as usize]).collect();
        Ok(Work::Listed(Contribution { vertices: used, tensors, seeds: 0 }))
    }
}

/// The vertices some cell uses, in increasing order.
fn used_vertices(graph: &MeshGraph) -> Vec<u32> {
    let mut used = vec![false; graph.num_vertices()];
    for c in graph.cells() {
        for &v in c.iter().filter(|&&v| v != u32::MAX) {
            used[v as usize] = true;
        }
    }
    (0..used.len() as u32).filter(|&v| used[v as usize]).collect()
}
