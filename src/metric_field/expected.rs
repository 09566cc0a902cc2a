//! The vertex count a metric on a mesh asks for: its complexity
//! ([`crate::metric::complexity`]) over the mesh's triangles and quadrangles. What the
//! adaptation loop checks against its vertex limit before every remeshing, whatever the
//! remesher, what `size` reports, and what a solver's metric is scaled by.

use crate::metric::complexity;
use crate::metric::Sym2;
use smartmesh_formats::{CellKind, TaggedMesh};

/// The expected vertex count of a remeshing of `mesh` to `metric` (one tensor per point):
/// the metric's complexity over its triangles and quadrangles (each cut in two). 0 when
/// `metric` does not match the mesh's points.
pub fn expected_vertices(mesh: &TaggedMesh, metric: &[Sym2]) -> f64 {
    let (pts, tris) = planar_triangles(mesh);
    if metric.len() != pts.len() || tris.iter().flatten().any(|&v| v >= pts.len()) {
        return 0.0;
    }
    complexity::expected_vertices(&pts, &tris, metric)
}

/// The points of `mesh` in its plane and the triangles the complexity is taken over: its
/// triangles and its quadrangles each cut in two (the adaptation loop's budget scales a
/// field by the same count).
pub(crate) fn planar_triangles(mesh: &TaggedMesh) -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
    let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let mut tris = Vec::new();
    for (kind, n, _, _) in mesh.cells() {
        let n: Vec<usize> = n.iter().map(|&v| v as usize).collect();
        match kind {
            CellKind::Triangle | CellKind::Triangle6 => tris.push([n[0], n[1], n[2]]),
            CellKind::Quad | CellKind::Quad8 | CellKind::Quad9 => {
                tris.push([n[0], n[1], n[2]]);
                tris.push([n[0], n[2], n[3]]);
            }
            _ => {}
        }
    }
    (pts, tris)
}
