//! VTK's node order of each cell kind against smartmesh's (Gmsh's).
//!
//! Linear cells, the quadrilaterals and the second-order triangle number their nodes
//! alike in both. The second-order volume cells differ in the order of their mid-edge
//! and mid-face nodes: for each, `VTK_FROM_GMSH[i]` is the Gmsh index of VTK's node
//! `i`. The tables were derived by matching the reference coordinates of every node,
//! Gmsh's (`gmsh.model.mesh.getElementProperties`) mapped onto VTK's
//! (`vtkCell::GetParametricCoords`) by the affine map of the corners (the pyramids by
//! their edges: VTK's parametric pyramid is a collapsed cube), and are proved in
//! `tests/vtk_3d_interop.rs`, where VTK measures each element of a file we wrote and
//! Gmsh measures the same element in its own order.
//!
//! - tetra10 (VTK 24): VTK's edges 8 and 9 are (1,3) and (2,3), Gmsh's (2,3) and (1,3);
//! - hexa20 (25) and hexa27 (29): VTK lists the bottom edges, the top edges, then the
//!   vertical ones; Gmsh its own edge order; hexa27's face centres are
//!   VTK -x +x -y +y -z +z against Gmsh's -z -y -x +x +y +z;
//! - wedge15 (26) and wedge18 (32): bottom, top, then vertical edges in VTK; VTK's
//!   quadrilateral face centres come (0,1,4,3), (1,2,5,4), (2,0,3,5);
//! - pyramid13 (27): VTK's base edges go round the base, Gmsh's do not.
//!
//! The linear wedge: VTK's class documentation says the right-hand normal of (0,1,2)
//! points out of the wedge, and meshio turns VTK's wedges over on reading for it
//! (`vtk_to_meshio_order`); but VTK 9.7's parametric coordinates (0,1,2 at t = 0,
//! 3,4,5 at t = 1), its Jacobian and `vtkCellValidator` all take Gmsh's orientation
//! (the normal pointing to 3,4,5), and the volume test above passes only with the
//! wedge as it is. So wedges go through unchanged.
//!
//! The 14-node pyramid has no VTK type (VTK's triquadratic pyramid has 19 nodes):
//! written as a 13-node quadratic pyramid, its base centre dropped and the loss listed
//! in the write report, rather than refused, so that a second-order mesh of mixed
//! kinds still opens in ParaView with every element in place.

use std::borrow::Cow;

use crate::{CellKind, NodeIndex, TaggedMesh};

/// `VTK_FROM_GMSH[i]`: the Gmsh (smartmesh) index of VTK's node `i`, for the kinds
/// whose orders differ.
fn vtk_from_gmsh(kind: CellKind) -> Option<&'static [usize]> {
    const TETRA10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];
    const HEXA20: [usize; 20] =
        [0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15];
    const HEXA27: [usize; 27] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15, 22, 23, 21, 24, 20,
        25, 26,
    ];
    const WEDGE15: [usize; 15] = [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11];
    const WEDGE18: [usize; 18] = [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11, 15, 17, 16];
    const PYRAMID13: [usize; 13] = [0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12];
    Some(match kind {
        CellKind::Tetra10 => &TETRA10,
        CellKind::Hexa20 => &HEXA20,
        CellKind::Hexa27 => &HEXA27,
        CellKind::Wedge15 => &WEDGE15,
        CellKind::Wedge18 => &WEDGE18,
        CellKind::Pyramid13 | CellKind::Pyramid14 => &PYRAMID13,
        _ => return None,
    })
}

/// Whether the VTK writers must rewrite cells of `kind`.
fn differs(kind: CellKind) -> bool {
    vtk_from_gmsh(kind).is_some()
}

/// The mesh with its cells in VTK's node order (borrowed when no kind needs it), and
/// what was lost on the way (the 14-node pyramids' base centres).
pub(crate) fn to_vtk(mesh: &TaggedMesh) -> (Cow<'_, TaggedMesh>, Vec<String>) {
    if !mesh.blocks.iter().any(|b| differs(b.kind) && !b.is_empty()) {
        return (Cow::Borrowed(mesh), Vec::new());
    }
    let mut lost = Vec::new();
    let mut m = mesh.clone();
    for b in &mut m.blocks {
        let Some(perm) = vtk_from_gmsh(b.kind) else { continue };
        let k = b.kind.nodes_per_cell();
        let mut nodes = Vec::with_capacity(b.len() * perm.len());
        for cell in b.nodes.chunks_exact(k) {
            nodes.extend(perm.iter().map(|&g| cell[g]));
        }
        if b.kind == CellKind::Pyramid14 && !b.is_empty() {
            lost.push(format!(
                "the base centre (node 14) of {} 14-node pyramids: VTK has no 14-node pyramid, they are written as 13-node quadratic pyramids (type 27)",
                b.len()
            ));
            b.kind = CellKind::Pyramid13;
        }
        b.nodes = nodes;
    }
    (Cow::Owned(m), lost)
}

/// Puts the cells of a block read from VTK (`kind` as VTK gives it) into smartmesh's
/// node order, in place.
pub(crate) fn from_vtk(kind: CellKind, nodes: &mut [NodeIndex]) {
    let Some(perm) = vtk_from_gmsh(kind) else { return };
    let k = perm.len();
    let mut cell = [0 as NodeIndex; 27];
    for c in nodes.chunks_exact_mut(k) {
        cell[..k].copy_from_slice(c);
        for (i, &g) in perm.iter().enumerate() {
            c[g] = cell[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_table_is_a_permutation_keeping_the_corners() {
        for kind in CellKind::ALL {
            let Some(p) = vtk_from_gmsh(kind) else { continue };
            let vtk = kind.vtk_type().map_or(13, |_| kind.nodes_per_cell());
            assert_eq!(p.len(), vtk, "{kind:?}");
            let mut s = p.to_vec();
            s.sort_unstable();
            assert_eq!(s, (0..vtk).collect::<Vec<_>>(), "{kind:?}");
            let corners = kind.linear().nodes_per_cell();
            assert!(p[..corners].iter().enumerate().all(|(i, &g)| i == g), "{kind:?}");
        }
    }

    #[test]
    fn from_vtk_undoes_to_vtk() {
        for kind in CellKind::ALL.into_iter().filter(|&k| k != CellKind::Pyramid14) {
            let k = kind.nodes_per_cell();
            let mut m = TaggedMesh::new();
            m.points = vec![[0.0; 3]; 2 * k];
            let mut b = crate::CellBlock::new(kind);
            let a: Vec<u32> = (0..k as u32).collect();
            let c: Vec<u32> = (0..k as u32).rev().map(|v| v + k as u32).collect();
            b.push(&a, 1, 1);
            b.push(&c, 2, 2);
            m.blocks.push(b.clone());
            let (v, lost) = to_vtk(&m);
            assert!(lost.is_empty());
            let mut nodes = v.blocks[0].nodes.clone();
            from_vtk(kind, &mut nodes);
            assert_eq!(nodes, b.nodes, "{kind:?}");
        }
    }
}
