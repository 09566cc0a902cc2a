//! The topological volumes of a mesh: the volume cells sharing a tag ([`super::cell_tag`]),
//! and the surfaces that bound each.
//!
//! A volume's boundary is every cell face that exactly one of its cells has (a face two
//! of its cells share is inside it); each boundary face is matched, by its corner set,
//! with the surface cells of the file, and the volume is *bounded by* the topological
//! faces (surfaces) those cells lie on — the one of smallest tag when several cells share
//! the corners. Boundary faces that no surface cell covers are counted apart
//! (`untagged_faces`): a file that lists no boundary triangles, or only some.
//!
//! Second-order cells are matched by their corners. Knows connectivity only (the measure
//! of a volume is `solid_topology`'s). Cost: O(F log F) for F cell faces (one sort, no
//! hash map, so the order of everything reported is that of the tags).

use std::collections::BTreeMap;

use smartmesh_formats::TaggedMesh;

use super::{cell_tag, SurfaceCell};

/// One topological volume.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopoVolume {
    /// The tag (physical, or geometrical when the cells have no physical tag).
    pub tag: i32,
    /// Its name, when the file names it.
    pub name: Option<String>,
    /// Volume cells carrying it.
    pub cells: usize,
    /// Mesh vertices of its cells (corners).
    pub vertices: usize,
    /// Cell faces on its boundary.
    pub boundary_faces: usize,
    /// The surfaces its boundary faces lie on: (index into `Topology::faces`, faces on
    /// it), by index (so by tag).
    pub bounded_by: Vec<(usize, usize)>,
    /// Boundary faces no surface cell of the file covers.
    pub untagged_faces: usize,
}

/// A face by its sorted corners, `u32::MAX` for a triangle's fourth.
type FaceKey = [u32; 4];

fn face_key(corners: impl Iterator<Item = u32>) -> FaceKey {
    let mut k = [u32::MAX; 4];
    for (slot, v) in k.iter_mut().zip(corners) {
        *slot = v;
    }
    k.sort_unstable();
    k
}

/// The topological volumes of `mesh`, by tag; `surface_cells` are the topology's (their
/// `face` an index into its faces, which are by tag). Empty without volume cells.
pub(super) fn volumes(mesh: &TaggedMesh, surface_cells: &[SurfaceCell]) -> Vec<TopoVolume> {
    let mut index: BTreeMap<i32, usize> = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 3) {
        for (&p, &g) in b.physical.iter().zip(&b.geometrical) {
            index.entry(cell_tag(p, g)).or_insert(0);
        }
    }
    if index.is_empty() {
        return Vec::new();
    }
    let mut out: Vec<TopoVolume> = index
        .keys()
        .map(|&t| TopoVolume {
            tag: t,
            name: mesh.tag_name(3, t).map(str::to_owned),
            cells: 0,
            vertices: 0,
            boundary_faces: 0,
            bounded_by: Vec::new(),
            untagged_faces: 0,
        })
        .collect();
    for (i, v) in index.values_mut().enumerate() {
        *v = i;
    }
    // Every face of every volume cell, with its volume's index; every corner, likewise.
    let mut faces: Vec<(FaceKey, u32)> = Vec::new();
    let mut corners: Vec<(u32, u32)> = Vec::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 3) {
        let n = b.kind.linear().nodes_per_cell();
        for (cell, (&ph, &g)) in b.cells().zip(b.physical.iter().zip(&b.geometrical)) {
            let vi = index[&cell_tag(ph, g)];
            out[vi].cells += 1;
            corners.extend(cell[..n].iter().map(|&v| (vi as u32, v)));
            for f in b.kind.faces() {
                faces.push((face_key(f.iter().map(|&c| cell[c])), vi as u32));
            }
        }
    }
    corners.sort_unstable();
    corners.dedup();
    for (vi, _) in corners {
        out[vi as usize].vertices += 1;
    }
    faces.sort_unstable();
    // The surface cells by face key, with their face (index order is tag order).
    let mut surfaces: Vec<(FaceKey, usize)> = surface_cells
        .iter()
        .map(|sc| (face_key(sc.vertices().iter().map(|&v| v as u32)), sc.face))
        .collect();
    surfaces.sort_unstable();
    let mut bounded: Vec<BTreeMap<usize, usize>> = vec![BTreeMap::new(); out.len()];
    let mut i = 0;
    while i < faces.len() {
        let mut j = i + 1;
        while j < faces.len() && faces[j] == faces[i] {
            j += 1;
        }
        // Exactly one cell of this volume has the face: it bounds the volume.
        if j - i == 1 {
            let (key, vi) = faces[i];
            let v = &mut out[vi as usize];
            v.boundary_faces += 1;
            let at = surfaces.partition_point(|s| s.0 < key);
            match surfaces.get(at) {
                Some(&(k, face)) if k == key => *bounded[vi as usize].entry(face).or_insert(0) += 1,
                _ => v.untagged_faces += 1,
            }
        }
        i = j;
    }
    for (v, b) in out.iter_mut().zip(bounded) {
        v.bounded_by = b.into_iter().collect();
    }
    out
}
