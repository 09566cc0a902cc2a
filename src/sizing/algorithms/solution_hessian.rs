//! SOLUTION_HESSIAN: the Lp-optimal metric of a computed scalar field (a solution) on
//! the mesh being sized: the field's Hessian recovered at every vertex
//! ([`crate::solution::recovery`], the quadratic fit unless told otherwise), made into
//! M = D det(|H|)^(−1/(2p+2)) |H| and normalised to a vertex count or to an Lp norm of
//! the interpolation error ([`crate::solution::lp`]). The field is the mesh's scalar point-data array FIELD
//! (the command line may give several: each normalised to the target alone, intersected
//! in the order given, the intersection scaled to the target, [`crate::solution::combined`]); in a
//! recipe the step is intersected with the others in recipe order like any other, so the
//! geometry's sizes and the solution's both hold where each is the finer. No propagation:
//! every vertex some cell uses gets a tensor, in increasing index order.
//!
//! In space: the same with the recovery on tetrahedra ([`crate::solution::recovery3`])
//! and M = D det(|H|)^(−1/(2p+3)) |H| ([`crate::solution::lp3`]), one field, bounds from
//! the diagonal of the box in space; every vertex some volume cell uses gets a tensor.
//! Hexahedra, prisms and pyramids are split into tetrahedra on their own corners by a
//! fixed table (`tetrahedra`): both recoveries stay exact on quadratics at every vertex
//! (they need the edges and the tetrahedra's volumes, not a conforming mesh), and the
//! normalisation integrates over the cells' volumes (exact for planar faces).
//!
//! In a recipe: FIELD, and exactly one of COMPLEXITY (a vertex count) and ERROR (the Lp
//! norm of the interpolation error); optional P (default 2), RECOVERY (`quadratic-fit`,
//! the default, or `l2-projection`), HMIN, HMAX and MAX_ANISOTROPY.
//!
//! Bounds: each one not given (the command line gives its own) comes from the mesh: h_max
//! the diagonal of its bounding box, h_min 1e-6 of it and the aspect ratio at most 1e4.
//! The normalisation honours them (the vertex count is that of the bounded metric); the
//! plan's global bounds clamp the field afterwards, which can move its vertex count away
//! from COMPLEXITY where they act.

use super::{
    Around, Arguments, Contribution, Declaration, Failure, Given, Parameter, ParameterKind,
    Refusal, SizingAlgorithm, SpaceWork, Work,
};
use crate::sizing::space::SpaceMesh;
use crate::mesh_graph::{MeshGraph, PointValues};
use crate::metric::{SizeBounds, SizeTensor, Sym2};
use super::EntitySet;
use crate::solution::{
    lp_metric3, lp_metric_of_fields, recover, recover3, LpMetric, LpMetric3, LpOptions, Method,
    P1Mesh, P1Mesh3, Target,
};
use smartmesh_formats::{CellKind, TaggedMesh};
use crate::topology::Topology;

/// SOLUTION_HESSIAN: the Lp-optimal metric of point field `fields` (one in a recipe;
/// several, from the command line, normalised together and intersected in order:
/// [`crate::solution::combined`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SolutionHessian {
    /// The scalar point-data arrays, at least one.
    pub fields: Vec<String>,
    /// The normalisation.
    pub target: Target,
    /// The norm (≥ 1, or infinite).
    pub p: f64,
    /// How the Hessian is recovered.
    pub method: Method,
    /// The smallest size; `None`: from the mesh (see the module documentation).
    pub h_min: Option<f64>,
    /// The largest size; `None`: from the mesh.
    pub h_max: Option<f64>,
    /// The largest aspect ratio; `None`: 1e4.
    pub max_aspect: Option<f64>,
}

impl SolutionHessian {
    /// The bounds used when none are given, for a mesh whose bounding box has diagonal
    /// `diagonal`.
    pub fn default_bounds(diagonal: f64) -> Option<SizeBounds> {
        SizeBounds::try_new(1e-6 * diagonal, diagonal, 1e4)
    }

    /// The label of a step made in code (not from a recipe): "solution `u`, `p`
    /// (SOLUTION_HESSIAN, quadratic-fit)".
    pub fn label(&self) -> String {
        let quoted: Vec<String> = self.fields.iter().map(|n| format!("`{n}`")).collect();
        format!("solution {} (SOLUTION_HESSIAN, {})", quoted.join(", "), self.method.name())
    }

    /// The metric on the mesh of `graph`, with what the normalisation gave; an error in
    /// words naming the field.
    pub fn metric(&self, graph: &MeshGraph) -> Result<LpMetric, String> {
        let mut values = Vec::with_capacity(self.fields.len());
        for name in &self.fields {
            values.push(match graph.point_data().get(name) {
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
            });
        }
        let why = |name: &str, e: &dyn std::fmt::Display| format!("point data `{name}`: {e}");
        let first = self.fields.first().ok_or("no solution field named")?;
        let mesh = P1Mesh::new(graph.points(), graph.cells()).map_err(|e| why(first, &e))?;
        let mut hessians = Vec::with_capacity(values.len());
        for (name, v) in self.fields.iter().zip(values) {
            hessians.push(recover(&mesh, v, self.method).map_err(|e| why(name, &e))?.hessian);
        }
        let bounds = self.bounds(graph).map_err(|e| why(first, &e))?;
        let options = LpOptions { p: self.p, target: self.target, bounds };
        let slices: Vec<&[Sym2]> = hessians.iter().map(Vec::as_slice).collect();
        lp_metric_of_fields(&mesh, &slices, &options).map_err(|(i, e)| why(&self.fields[i], &e))
    }

    /// Its bounds on the mesh of `graph`: those given, the others from the mesh's extent.
    pub fn bounds(&self, graph: &MeshGraph) -> Result<SizeBounds, String> {
        let given = match (self.h_min, self.h_max, self.max_aspect) {
            (Some(lo), Some(hi), Some(r)) => SizeBounds::try_new(lo, hi, r),
            _ => None,
        };
        if let Some(b) = given {
            return Ok(b);
        }
        let default = graph
            .bounds()
            .and_then(|(lo, hi)| Self::default_bounds((hi[0] - lo[0]).hypot(hi[1] - lo[1])))
            .ok_or("the mesh has no extent")?;
        let h_max = self.h_max.unwrap_or(default.h_max());
        let h_min = self.h_min.unwrap_or(default.h_min().min(h_max));
        let r = self.max_aspect.unwrap_or(default.max_aspect_ratio());
        SizeBounds::try_new(h_min, h_max, r).ok_or_else(|| {
            format!("bounds hmin {h_min}, hmax {h_max}, aspect ratio {r} are out of range")
        })
    }
}

impl SolutionHessian {
    /// The metric on the tetrahedra of `mesh`, a mesh in space: the field's Hessian
    /// recovered on them ([`crate::solution::recovery3`]) and made the Lp-optimal metric
    /// in 3D ([`crate::solution::lp3`]); an error in words naming the field. One field
    /// in space so far; hexahedra, prisms and pyramids are refused (the recovery is P1
    /// on tetrahedra).
    pub fn metric_in_space(&self, mesh: &TaggedMesh) -> Result<LpMetric3, String> {
        let [name] = self.fields.as_slice() else {
            return Err(format!(
                "{} fields given; a metric from a solution takes one field in space so far",
                self.fields.len()
            ));
        };
        let why = |e: &dyn std::fmt::Display| format!("point data `{name}`: {e}");
        let values = scalar_values(mesh, name)?;
        let tets = tetrahedra(mesh)?;
        let mesh3 = P1Mesh3::new(&mesh.points, &tets).map_err(|e| why(&e))?;
        let hessians = recover3(&mesh3, values, self.method).map_err(|e| why(&e))?.hessian;
        let bounds = self.bounds_in_space(mesh)?;
        let options = LpOptions { p: self.p, target: self.target, bounds };
        lp_metric3(&mesh3, &hessians, &options).map_err(|e| why(&e))
    }

    /// Its bounds on a mesh in space: those given, the others from the diagonal of the
    /// mesh's bounding box.
    pub fn bounds_in_space(&self, mesh: &TaggedMesh) -> Result<SizeBounds, String> {
        let diagonal = mesh
            .bounding_box()
            .map(|(lo, hi)| (hi[0] - lo[0]).hypot(hi[1] - lo[1]).hypot(hi[2] - lo[2]));
        let default = diagonal.and_then(Self::default_bounds).ok_or("the mesh has no extent")?;
        let h_max = self.h_max.unwrap_or(default.h_max());
        let h_min = self.h_min.unwrap_or(default.h_min().min(h_max));
        let r = self.max_aspect.unwrap_or(default.max_aspect_ratio());
        SizeBounds::try_new(h_min, h_max, r).ok_or_else(|| {
            format!("bounds hmin {h_min}, hmax {h_max}, aspect ratio {r} are out of range")
        })
    }
}

/// The values of the scalar point-data array `name` of `mesh`, one per vertex.
fn scalar_values<'m>(mesh: &'m TaggedMesh, name: &str) -> Result<&'m [f64], String> {
    match mesh.point_data.get(name) {
        Some(a) if a.components == 1 && a.len() == mesh.points.len() => Ok(&a.values),
        Some(a) => Err(format!(
            "point data `{name}` has {} components and {} items; a solution field is a scalar with one value per vertex ({})",
            a.components,
            a.len(),
            mesh.points.len()
        )),
        None => {
            let names: Vec<&str> = mesh.point_data.keys().map(String::as_str).collect();
            Err(format!(
                "the mesh has no point data `{name}` (its arrays: {})",
                if names.is_empty() { "none".to_string() } else { names.join(", ") }
            ))
        }
    }
}

/// The split of a hexahedron (Gmsh's corner order) into the six tetrahedra around its
/// diagonal 0–6, each from 0 to 6 along three edges.
const HEXA_SPLIT: [[usize; 4]; 6] =
    [[0, 1, 2, 6], [0, 1, 5, 6], [0, 3, 2, 6], [0, 3, 7, 6], [0, 4, 5, 6], [0, 4, 7, 6]];
/// A prism (bottom 0-1-2, top 3-4-5) into three, along the diagonals 0–4, 1–5 and 0–5.
const WEDGE_SPLIT: [[usize; 4]; 3] = [[0, 1, 2, 5], [0, 1, 5, 4], [0, 4, 5, 3]];
/// A pyramid (base 0-1-2-3, apex 4) into two along the base's diagonal 0–2.
const PYRAMID_SPLIT: [[usize; 4]; 2] = [[0, 1, 2, 4], [0, 2, 3, 4]];

/// The tetrahedra the recovery works on: those of `mesh`, and its other volume cells
/// split by the fixed tables above (second-order ones by their corners); an error when it
/// has no volume cell. The split of each cell covers it (for planar faces exactly) with
/// tetrahedra on its own corners: the recovery needs only edges joining vertices and
/// tetrahedra whose volumes sum to the cells', not a conforming mesh, so neighbours may
/// split a shared face along different diagonals.
fn tetrahedra(mesh: &TaggedMesh) -> Result<Vec<[u32; 4]>, String> {
    let mut tets = Vec::with_capacity(mesh.num_cells_of(CellKind::Tetra));
    for (kind, nodes, _, _) in mesh.cells() {
        let split: &[[usize; 4]] = match kind.linear() {
            CellKind::Tetra => &[[0, 1, 2, 3]],
            CellKind::Hexa => &HEXA_SPLIT,
            CellKind::Wedge => &WEDGE_SPLIT,
            CellKind::Pyramid => &PYRAMID_SPLIT,
            _ => continue,
        };
        tets.extend(split.iter().map(|t| t.map(|k| nodes[k])));
    }
    if tets.is_empty() {
        return Err("the mesh has no volume cells".into());
    }
    Ok(tets)
}

/// A parameter of this algorithm that may be left out.
const fn optional(
    field: &'static str,
    keys: &'static [&'static str],
    doc: &'static str,
) -> Parameter {
    Parameter {
        field,
        aliases: &[],
        keys,
        kind: ParameterKind::OptionalSize,
        line_break_after: false,
        doc,
    }
}

impl SizingAlgorithm for SolutionHessian {
    const DECLARATION: Declaration = Declaration {
        keyword: "SOLUTION_HESSIAN",
        name: "solution_hessian",
        doc: "The Lp-optimal metric (Loseille-Alauzet) of the scalar point field FIELD of the mesh being sized: its Hessian recovered (RECOVERY), M = D det(|H|)^(-1/(2P+2)) |H|, normalised so that a mesh conforming to it has about COMPLEXITY vertices, or an interpolation error of about ERROR in the Lp norm; sizes within HMIN, HMAX and MAX_ANISOTROPY.",
        parameters: &[
            Parameter {
                field: "field",
                aliases: &[],
                keys: &["FIELD"],
                kind: ParameterKind::PointData,
                line_break_after: false,
                doc: "The scalar point-data array (a solution) of the mesh being sized.",
            },
            optional(
                "complexity",
                &["COMPLEXITY"],
                "The vertex count the metric asks for (its complexity); or ERROR.",
            ),
            optional(
                "error",
                &["ERROR"],
                "The Lp norm of the interpolation error the metric asks for, instead of COMPLEXITY.",
            ),
            Parameter {
                field: "p",
                aliases: &[],
                keys: &["P"],
                kind: ParameterKind::OptionalNorm,
                line_break_after: false,
                doc: "The Lp norm of the interpolation error the metric minimises (>= 1, or \"inf\"; 2 when left out, for the L2 norm; 1 resolves weak features more; \"inf\" is the density |H| the H1 seminorm of the error asks for).",
            },
            Parameter {
                field: "recovery",
                aliases: &[],
                keys: &["RECOVERY"],
                kind: ParameterKind::Choice(&["quadratic-fit", "l2-projection"]),
                line_break_after: false,
                doc: "How the Hessian is recovered, both exact on quadratics at every vertex of any mesh: quadratic-fit (the default; a quadratic fitted to each vertex's patch) or l2-projection (a gradient fitted to the P1 gradient's edge components, then its gradient's lumped L2 projection).",
            },
            optional("hmin", &["HMIN"], "The smallest size (1e-6 of the mesh's diagonal when left out)."),
            optional("hmax", &["HMAX"], "The largest size (the mesh's diagonal when left out)."),
            optional(
                "max_anisotropy",
                &["MAX_ANISOTROPY"],
                "The largest aspect ratio of a tensor (>= 1; 1e4 when left out).",
            ),
        ],
    };

    type Tensor<'a> = std::convert::Infallible;

    fn from_arguments(arguments: &mut Arguments) -> Option<SolutionHessian> {
        let field = arguments.name("field")?;
        let target = match (arguments.size("complexity"), arguments.size("error")) {
            (Some(n), None) => Target::Vertices(n),
            (None, Some(e)) => Target::Error(e),
            _ => return None,
        };
        let p = arguments.size("p").unwrap_or(2.0);
        let method = match arguments.name("recovery") {
            Some(word) => Method::from_name(&word)?,
            None => Method::default(),
        };
        Some(SolutionHessian {
            fields: vec![field],
            target,
            p,
            method,
            h_min: arguments.size("hmin"),
            h_max: arguments.size("hmax"),
            max_aspect: arguments.size("max_anisotropy"),
        })
    }

    fn check(given: Given<'_>) -> Result<(), Refusal> {
        let refuse = |field, why: String| Err(Refusal { field, why });
        match (given.get("complexity"), given.get("error")) {
            (None, None) => {
                return refuse("complexity", "give a vertex count (COMPLEXITY) or ERROR".into())
            }
            (Some(_), Some(_)) => {
                return refuse("error", "give COMPLEXITY or ERROR, not both".into())
            }
            _ => {}
        }
        if let Some(p) = given.get("p").filter(|&p| p < 1.0) {
            return refuse("p", format!("{p} is not a norm (expected a number >= 1)"));
        }
        if let Some(r) = given.get("max_anisotropy").filter(|&r| r < 1.0) {
            return refuse(
                "max_anisotropy",
                format!("{r} is not an aspect ratio (expected a number >= 1)"),
            );
        }
        if let (Some(lo), Some(hi)) = (given.get("hmin"), given.get("hmax")) {
            if lo > hi {
                return refuse("hmin", format!("{lo} is larger than HMAX {hi}"));
            }
        }
        Ok(())
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

    const IN_SPACE: bool = true;

    /// In space: the metric of [`SolutionHessian::metric_in_space`] at every vertex some
    /// tetrahedron uses, in increasing order.
    /// The recovery and the normalisation work on volume cells: not on a surface alone.
    fn sized_on_surface_in_space(&self) -> bool {
        false
    }

    fn work_in_space<'a>(
        &'a self,
        mesh: &'a SpaceMesh<'a>,
        _: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        let tagged = mesh.tagged();
        let metric = self.metric_in_space(tagged).map_err(|why| Failure::Field { why })?;
        let mut used = vec![false; tagged.points.len()];
        for t in tetrahedra(tagged).map_err(|why| Failure::Field { why })? {
            t.iter().for_each(|&v| used[v as usize] = true);
        }
        let vertices: Vec<u32> = (0..used.len() as u32).filter(|&v| used[v as usize]).collect();
        let tensors = vertices.iter().map(|&v| metric.tensors[v as usize]).collect();
        Ok(SpaceWork::Listed { vertices, tensors })
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The recipe's RECOVERY words are the methods' names, the default first.
    #[test]
    fn the_recovery_words_are_the_method_names() {
        let p = SolutionHessian::DECLARATION.parameters.iter().find(|p| p.field == "recovery");
        let Some(ParameterKind::Choice(words)) = p.map(|p| p.kind) else { panic!("{p:?}") };
        let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        assert_eq!(words, names.as_slice());
        assert_eq!(words[0], Method::default().name());
    }
}
