//! A 3D mesh (tetrahedra, hexahedra, prisms, pyramids) written directly as an OpenFOAM
//! polyMesh, without extrusion.
//!
//! Invariants of the result (what `checkMesh` checks):
//! - the cells are the mesh's volume cells, in mesh order, by their corners (second
//!   order ones too); each face's points turn counter-clockwise seen from outside its
//!   cell ([`crate::skin::faces`]); a cell whose faces enclose a negative volume (its
//!   nodes given in the mirrored order) has them reversed, said in the report;
//! - faces are matched exactly by their sorted points: a face of two cells is internal,
//!   its owner the smaller cell, its points as the owner sees them (normal from owner to
//!   neighbour); the internal faces come first, sorted by owner then neighbour
//!   (upper-triangular order); a face of three cells or more is refused;
//! - then the boundary faces, patch by patch: one patch per physical tag of the surface
//!   cells (triangles and quads) lying on the boundary, in increasing tag order, named
//!   and typed by the caller; boundary faces without a surface cell in `defaultFaces`;
//!   each patch's faces sorted by owner;
//! - every point is used: points no volume cell uses are left out (reported);
//! - `cellZones`: one zone per physical tag of the volume cells when they are named or
//!   several; `faceZones`: one zone per physical tag of surface cells lying on internal
//!   faces (an interface between two volumes), flipMap false (the owner's side).

use std::collections::BTreeMap;

use super::extrude::{Patch, PolyMesh, Refusal};
use crate::skin::{face_key, faces};
use crate::{CellKind, NodeIndex, TaggedMesh, WriteReport};

/// One face of a cell: its key, its cell and its outward points.
struct CellFace {
    key: [NodeIndex; 4],
    cell: u32,
    points: [NodeIndex; 4],
    len: u8,
}

/// The signed volume of a cell enclosed by its faces (cones from the cell's first
/// point, which the faces through it add nothing to).
fn enclosed_volume(points: &[[f64; 3]], c: &[NodeIndex], kind: CellKind) -> f64 {
    let o = points[c[0] as usize];
    let mut v = 0.0;
    for f in faces(kind) {
        for i in 1..f.len() - 1 {
            let [a, b, d] = [f[0], f[i], f[i + 1]].map(|k| {
                let p = points[c[k] as usize];
                [p[0] - o[0], p[1] - o[1], p[2] - o[2]]
            });
            v += a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
                + a[2] * (b[0] * d[1] - b[1] * d[0]);
        }
    }
    v / 6.0
}

/// The polyMesh of the volume cells of `mesh`; `patch_name` gives the name and type of
/// a surface tag's patch, `zone_name` the name of a volume (3) or surface (2) tag's zone.
pub fn volume_poly_mesh(
    mesh: &TaggedMesh,
    mut patch_name: impl FnMut(i32, &mut WriteReport) -> (String, String),
    zone_name: impl Fn(u8, i32) -> String,
    report: &mut WriteReport,
) -> Result<PolyMesh, Refusal> {
    // Points: those the volume cells use, in mesh order.
    let mut new_of = vec![NodeIndex::MAX; mesh.points.len()];
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 3) {
        let n = b.kind.linear().nodes_per_cell();
        for c in b.cells() {
            for &v in &c[..n] {
                new_of[v as usize] = 0;
            }
        }
    }
    let mut points = Vec::new();
    for (i, slot) in new_of.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = points.len() as NodeIndex;
            points.push(mesh.points[i]);
        }
    }
    let unused = mesh.points.len() - points.len();
    if unused > 0 {
        report.drop(format!(
            "{unused} points no volume cell uses (mid-edge nodes, a circle's centre): OpenFOAM's checkMesh refuses unused points"
        ));
    }

    let mut all: Vec<CellFace> = Vec::new();
    let mut cell_tags: Vec<i32> = Vec::new();
    let mut flipped = 0usize;
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 3) {
        for (c, &tag) in b.cells().zip(&b.physical) {
            let cell = cell_tags.len() as u32;
            let vol = enclosed_volume(&mesh.points, c, b.kind);
            if vol == 0.0 || !vol.is_finite() {
                return Err(format!("volume cell {cell} ({}) has no volume", b.kind.name()));
            }
            let flip = vol < 0.0;
            flipped += usize::from(flip);
            for f in faces(b.kind) {
                let mut p = [NodeIndex::MAX; 4];
                for (slot, &k) in p.iter_mut().zip(f.iter()) {
                    *slot = new_of[c[k] as usize];
                }
                if flip {
                    p[1..f.len()].reverse();
                }
                all.push(CellFace {
                    key: face_key(&p[..f.len()]),
                    cell,
                    points: p,
                    len: f.len() as u8,
                });
            }
            cell_tags.push(tag);
        }
    }
    if cell_tags.len() >= u32::MAX as usize / 2 {
        return Err("more cells than OpenFOAM's 32-bit labels address".into());
    }
    if flipped > 0 {
        report.drop(format!("{flipped} volume cells given in the mirrored node order written with their faces turned outward"));
    }
    all.sort_unstable_by_key(|f| (f.key, f.cell));

    // The tag of each surface cell, by its face key (first one wins).
    let mut surface: BTreeMap<[NodeIndex; 4], i32> = BTreeMap::new();
    let mut off_mesh = 0usize;
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 2) {
        let n = b.kind.linear().nodes_per_cell();
        for (c, &tag) in b.cells().zip(&b.physical) {
            let p: Vec<NodeIndex> = c[..n].iter().map(|&v| new_of[v as usize]).collect();
            if p.contains(&NodeIndex::MAX) {
                off_mesh += 1;
                continue;
            }
            surface.entry(face_key(&p)).or_insert(tag);
        }
    }

    let mut internal: Vec<(u32, u32, Vec<NodeIndex>, Option<i32>)> = Vec::new();
    let mut boundary: BTreeMap<Option<i32>, Vec<(u32, Vec<NodeIndex>)>> = BTreeMap::new();
    let mut i = 0;
    while i < all.len() {
        let mut j = i + 1;
        while j < all.len() && all[j].key == all[i].key {
            j += 1;
        }
        let tag = surface.remove(&all[i].key);
        let f = &all[i];
        let pts = f.points[..f.len as usize].to_vec();
        match j - i {
            1 => boundary.entry(tag).or_default().push((f.cell, pts)),
            2 => {
                let g = &all[i + 1];
                if f.cell == g.cell {
                    return Err(format!("volume cell {} has one face twice", f.cell));
                }
                internal.push((f.cell, g.cell, pts, tag));
            }
            n => {
                return Err(format!(
                    "a face of points {:?} is shared by {n} cells: the mesh is not conforming",
                    &pts
                ))
            }
        }
        i = j;
    }
    off_mesh += surface.len();
    if off_mesh > 0 {
        report.drop(format!(
            "{off_mesh} surface cells on no volume cell's face: a patch holds faces of cells"
        ));
    }
    internal.sort_by_key(|&(o, n, _, _)| (o, n));

    let mut poly = PolyMesh { points, n_cells: cell_tags.len(), ..PolyMesh::default() };
    let mut face_zones: BTreeMap<i32, Vec<u32>> = BTreeMap::new();
    for (o, n, f, tag) in internal {
        if let Some(t) = tag {
            face_zones.entry(t).or_default().push(poly.faces.len() as u32);
        }
        poly.faces.push(f);
        poly.owner.push(o);
        poly.neighbour.push(n);
    }
    let mut used_names: BTreeMap<String, ()> = BTreeMap::new();
    for (tag, mut list) in boundary {
        let (mut name, kind) = match tag {
            Some(t) => patch_name(t, report),
            None => {
                report.drop(format!(
                    "{} boundary faces without a surface cell written as the patch `defaultFaces`",
                    list.len()
                ));
                ("defaultFaces".to_string(), "patch".to_string())
            }
        };
        if used_names.contains_key(&name) {
            let unique = format!("{name}_{}", poly.patches.len());
            report.drop(format!(
                "patch name `{name}` is taken by another tag: written as `{unique}`"
            ));
            name = unique;
        }
        used_names.insert(name.clone(), ());
        list.sort_by(|a, b| (a.0, &a.1).cmp(&(b.0, &b.1)));
        let n_faces = list.len();
        for (c, f) in list {
            poly.faces.push(f);
            poly.owner.push(c);
        }
        poly.patches.push(Patch { name, kind, n_faces, entries: Vec::new() });
    }

    let mut zones: BTreeMap<i32, Vec<u32>> = BTreeMap::new();
    for (c, &t) in cell_tags.iter().enumerate() {
        zones.entry(t).or_default().push(c as u32);
    }
    let named = zones.keys().any(|&t| mesh.tag_name(3, t).is_some());
    if zones.len() > 1 || named {
        poly.cell_zones = zones.into_iter().map(|(t, cells)| (zone_name(3, t), cells)).collect();
    }
    poly.face_zones = face_zones.into_iter().map(|(t, f)| (zone_name(2, t), f)).collect();
    Ok(poly)
}
