//! The volumes of a 3D mesh recovered from its tags, and the surfaces that bound each:
//! the 3D layer above [`crate::topology`], which recovers the surfaces, curves and points.
//!
//! A topological volume is the set of volume cells sharing a tag ([`cell_tag`]). Its
//! boundary is every cell face that exactly one of its cells has (a face two of its cells
//! share is inside it); each boundary face is matched, by its corner set, with the
//! surface cells of the file, and the volume is *bounded by* the surfaces whose tags
//! those cells carry. Boundary faces that no surface cell covers are counted apart
//! (`untagged_faces`): a file that lists no boundary triangles, or only some.
//!
//! Second-order cells are matched by their corners, and measured as
//! [`crate::signed_volume`] does. Knows connectivity and coordinates
//! only. Cost: O(F log F) for F cell faces (one sort, no hash map, so the order of
//! everything reported is that of the tags).

use std::collections::BTreeMap;

use serde::Serialize;
use smartmesh_formats::TaggedMesh;

use crate::quality3d::{cell_faces, signed_volume};
use crate::topology::cell_tag;

/// One topological volume.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TopoVolume {
    /// The tag (physical, or geometrical when the cells have no physical tag).
    pub tag: i32,
    /// Its name, when the file names it.
    pub name: Option<String>,
    /// Volume cells carrying it.
    pub cells: usize,
    /// The sum of its cells' signed volumes ([`signed_volume`]).
    pub volume: f64,
    /// Cell faces on its boundary.
    pub boundary_faces: usize,
    /// The surfaces its boundary faces lie on, by tag.
    pub bounded_by: Vec<BoundingSurface>,
    /// Boundary faces no surface cell of the file covers.
    pub untagged_faces: usize,
}

/// A surface on the boundary of a volume.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundingSurface {
    /// The surface's tag.
    pub tag: i32,
    /// Its name, when the file names it.
    pub name: Option<String>,
    /// The volume's boundary faces on it.
    pub faces: usize,
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

/// The topological volumes of `mesh`, by tag; empty when it has no volume cell.
pub(crate) fn volumes(mesh: &TaggedMesh) -> Vec<TopoVolume> {
    let mut index: BTreeMap<i32, usize> = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 3) {
        for (&p, &g) in b.physical.iter().zip(&b.geometrical) {
            index.entry(cell_tag(p, g)).or_insert(0);
        }
    }
    let mut out: Vec<TopoVolume> = index
        .keys()
        .map(|&t| TopoVolume {
            tag: t,
            name: mesh.tag_name(3, t).map(str::to_owned),
            cells: 0,
            volume: 0.0,
            boundary_faces: 0,
            bounded_by: Vec::new(),
            untagged_faces: 0,
        })
        .collect();
    for (i, v) in index.values_mut().enumerate() {
        *v = i;
    }
    // Every face of every volume cell, with its volume's index.
    let mut faces: Vec<(FaceKey, u32)> = Vec::new();
    let mut p = Vec::with_capacity(27);
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 3) {
        let n = b.kind.nodes_per_cell();
        for (cell, (&ph, &g)) in b.cells().zip(b.physical.iter().zip(&b.geometrical)) {
            let vi = index[&cell_tag(ph, g)];
            let v = &mut out[vi];
            v.cells += 1;
            p.clear();
            p.extend(cell[..n].iter().map(|&i| mesh.points[i as usize]));
            v.volume += signed_volume(b.kind, &p).unwrap_or(0.0);
            for f in cell_faces(b.kind) {
                // Faces by their corners, the first nodes of every kind.
                faces.push((face_key(f.iter().map(|&c| cell[c])), vi as u32));
            }
        }
    }
    faces.sort_unstable();
    // The surface cells by face key, with their tags.
    let mut surfaces: Vec<(FaceKey, i32)> = mesh
        .cells()
        .filter(|(k, ..)| k.dim() == 2)
        .map(|(k, nodes, p, g)| {
            let n = k.linear().nodes_per_cell();
            (face_key(nodes[..n].iter().copied()), cell_tag(p, g))
        })
        .collect();
    surfaces.sort_unstable();
    let mut bounded: Vec<BTreeMap<i32, usize>> = vec![BTreeMap::new(); out.len()];
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
            // The first surface cell with this corner set, if any.
            let at = surfaces.partition_point(|s| s.0 < key);
            match surfaces.get(at) {
                Some(&(k, tag)) if k == key => *bounded[vi as usize].entry(tag).or_insert(0) += 1,
                _ => v.untagged_faces += 1,
            }
        }
        i = j;
    }
    for (v, b) in out.iter_mut().zip(bounded) {
        v.bounded_by = b
            .into_iter()
            .map(|(tag, faces)| BoundingSurface {
                tag,
                name: mesh.tag_name(2, tag).map(str::to_owned),
                faces,
            })
            .collect();
    }
    out
}
