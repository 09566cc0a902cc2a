//! The vertex count a metric on a mesh asks for: its complexity
//! ([`crate::metric::complexity`] over the mesh's triangles and quadrangles for a 2D
//! field, [`crate::metric::complexity3`] over its volume cells for a 3D one). What the
//! adaptation loop checks against its vertex limit before every remeshing, whatever the
//! remesher, what `size` and `info --metric` report, and what a solver's metric is scaled
//! by. The two dimensions differ only in the cells they cut into simplices and in the
//! simplex integral, which [`Complexity`] names; the checks are shared.

use crate::metric::{complexity, complexity3};
use crate::metric::{Sym2, Sym3};
use smartmesh_formats::{CellKind, TaggedMesh};

/// A metric tensor whose field's complexity can be taken over a mesh's cells: the
/// simplices it is taken over, and the vertex count of a unit mesh.
pub trait Complexity: Sized {
    /// The simplex (vertex indices) of this dimension.
    type Simplex: AsRef<[usize]>;
    /// The cells of `mesh` cut into simplices at their corners.
    fn simplices(mesh: &TaggedMesh) -> Vec<Self::Simplex>;
    /// The vertex count of a unit mesh of `metric` over `simplices` of `mesh`'s points.
    fn count(mesh: &TaggedMesh, simplices: &[Self::Simplex], metric: &[Self]) -> f64;
}

impl Complexity for Sym2 {
    type Simplex = [usize; 3];
    fn simplices(mesh: &TaggedMesh) -> Vec<[usize; 3]> {
        planar_triangles(mesh).1
    }
    fn count(mesh: &TaggedMesh, tris: &[[usize; 3]], metric: &[Sym2]) -> f64 {
        let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
        complexity::expected_vertices(&pts, tris, metric)
    }
}

impl Complexity for Sym3 {
    type Simplex = [usize; 4];
    fn simplices(mesh: &TaggedMesh) -> Vec<[usize; 4]> {
        tetrahedra(mesh)
    }
    fn count(mesh: &TaggedMesh, tets: &[[usize; 4]], metric: &[Sym3]) -> f64 {
        complexity3::expected_vertices3(&mesh.points, tets, metric)
    }
}

/// The expected vertex count of a remeshing of `mesh` to `metric` (one tensor per point):
/// the metric's complexity over its triangles and quadrangles (each cut in two) for a 2D
/// metric, over its volume cells (cut into tetrahedra) for a 3D one. 0 when `metric` does
/// not match the mesh's points.
pub fn expected_vertices<T: Complexity>(mesh: &TaggedMesh, metric: &[T]) -> f64 {
    let simplices = T::simplices(mesh);
    let n = mesh.points.len();
    if metric.len() != n || simplices.iter().any(|s| s.as_ref().iter().any(|&v| v >= n)) {
        return 0.0;
    }
    T::count(mesh, &simplices, metric)
}

impl<T: super::FieldTensor + Complexity> super::MetricField<T> {
    /// The expected vertex count of a remeshing of `mesh`, which this field lives on, to
    /// it ([`expected_vertices`]).
    pub fn expected_vertices(&self, mesh: &TaggedMesh) -> f64 {
        expected_vertices(mesh, self.tensors())
    }
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

/// The volume cells of `mesh` cut into tetrahedra at their corners (corners come first in
/// every cell kind): a hexahedron into six about its diagonal 0–6, a wedge into three, a
/// pyramid into two. A cell with non-planar faces counts the volume of its cut.
fn tetrahedra(mesh: &TaggedMesh) -> Vec<[usize; 4]> {
    const HEXA: [[usize; 4]; 6] =
        [[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]];
    const WEDGE: [[usize; 4]; 3] = [[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]];
    const PYRAMID: [[usize; 4]; 2] = [[0, 1, 2, 4], [0, 2, 3, 4]];
    let mut tets = Vec::new();
    for (kind, n, _, _) in mesh.cells() {
        let cut: &[[usize; 4]] = match kind.linear() {
            CellKind::Tetra => &[[0, 1, 2, 3]],
            CellKind::Hexa => &HEXA,
            CellKind::Wedge => &WEDGE,
            CellKind::Pyramid => &PYRAMID,
            _ => &[],
        };
        tets.extend(cut.iter().map(|t| t.map(|i| n[i] as usize)));
    }
    tets
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube as one hexahedron, as two wedges and as six tetrahedra agree.
    #[test]
    fn every_volume_cell_counts_its_volume() {
        let corners = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ];
        let m = Sym3::from_eigen(
            [400.0, 100.0, 25.0],
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        );
        let want = 1000.0 * complexity3::vertices_of_complexity3(1.0);
        let mut hex = TaggedMesh::new();
        hex.points = corners.to_vec();
        hex.block_mut(CellKind::Hexa).push(&[0, 1, 2, 3, 4, 5, 6, 7], 1, 1);
        let mut wedges = hex.clone();
        wedges.blocks.clear();
        wedges.block_mut(CellKind::Wedge).push(&[0, 1, 2, 4, 5, 6], 1, 1);
        wedges.block_mut(CellKind::Wedge).push(&[0, 2, 3, 4, 6, 7], 1, 1);
        let mut pyramids = hex.clone();
        pyramids.blocks.clear();
        pyramids.points.push([0.5, 0.5, 0.5]);
        for base in
            [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
        {
            pyramids.block_mut(CellKind::Pyramid).push(
                &[base[0], base[1], base[2], base[3], 8],
                1,
                1,
            );
        }
        for mesh in [&hex, &wedges, &pyramids] {
            let n = expected_vertices(mesh, &vec![m; mesh.points.len()]);
            assert!((n - want).abs() < 1e-9 * want, "{n} vs {want}");
        }
        // A metric that does not match the points counts nothing.
        assert_eq!(expected_vertices(&hex, &[m; 3]), 0.0);
        // A 2D field on the same mesh has no triangle to count.
        assert_eq!(expected_vertices(&hex, &[Sym2::IDENTITY; 8]), 0.0);
    }
}
