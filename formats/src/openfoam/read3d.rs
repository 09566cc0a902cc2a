//! Reading a 3D polyMesh (one without `empty` or `wedge` patches) back into tetrahedra,
//! hexahedra, prisms and pyramids.
//!
//! What it becomes:
//! - the points as they are, in polyMesh order;
//! - each cell, from its faces turned outward (an owner's face as it is, a
//!   neighbour's reversed): 4 triangles a tetrahedron, 6 quads a hexahedron, 2 triangles
//!   and 3 quads a prism, 4 triangles and a quad a pyramid, its nodes put in Gmsh's
//!   order from one outward face (whose points then turn clockwise seen from outside,
//!   as Gmsh's bottom faces do) and the edges leaving it; the result is checked to have
//!   exactly the cell's faces. Any other cell (a polyhedron from snappyHexMesh, a face
//!   of 5 points) is refused, naming the cell;
//! - cell tags from `cellZones` (zone k numbered k + 1, `tag<N>` read back as tag N
//!   without a name, the others named by the zone's name; cells in no zone get tag 0),
//!   or tag 1 for every cell without zones;
//! - each patch's faces triangles and quads, outward, tagged by patch (numbered 1, 2, …
//!   in file order, `tag<N>` as tag N, the others named), then each `faceZones` zone's
//!   faces as surface cells, numbered after the patches.

use std::collections::BTreeSet;

use super::read::PatchInfo;
use crate::skin::{face_key, faces};
use crate::{CellKind, NodeIndex, TaggedMesh};

/// The polyMesh lists the reader has checked.
pub(super) struct Poly<'a> {
    pub points: &'a [[f64; 3]],
    pub faces: &'a [Vec<u32>],
    pub owner: &'a [u32],
    pub neighbour: &'a [u32],
    pub n_cells: usize,
}

/// N when `name` is `tag<N>`.
fn generated(name: &str) -> Option<i32> {
    let d = name.strip_prefix("tag")?;
    let v: i32 = d.parse().ok()?;
    (v >= 0 && v.to_string() == d).then_some(v)
}

/// The tag of each name: `tag<N>` is N unnamed; the others 1, 2, … skipping those.
fn tags_of(names: &[&str]) -> Vec<(i32, Option<String>)> {
    let taken: BTreeSet<i32> = names.iter().filter_map(|n| generated(n)).collect();
    let mut next = 1;
    names
        .iter()
        .map(|n| match generated(n) {
            Some(t) => (t, None),
            None => {
                while taken.contains(&next) {
                    next += 1;
                }
                next += 1;
                (next - 1, Some(n.to_string()))
            }
        })
        .collect()
}

/// The cell of outward faces `fs` in Gmsh's order, or why not.
pub(crate) fn cell_nodes(fs: &[Vec<u32>]) -> Result<(CellKind, Vec<u32>), String> {
    let tris: Vec<&Vec<u32>> = fs.iter().filter(|f| f.len() == 3).collect();
    let quads: Vec<&Vec<u32>> = fs.iter().filter(|f| f.len() == 4).collect();
    if tris.len() + quads.len() != fs.len() {
        return Err("a face of more than 4 points (a polyhedral cell)".into());
    }
    let points: BTreeSet<u32> = fs.iter().flatten().copied().collect();
    // The other end of the edge leaving `v` (of the bottom `base`) for the top.
    let up = |v: u32, base: &[u32]| -> Option<u32> {
        let mut found = None;
        for f in fs {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                let w = if a == v {
                    b
                } else if b == v {
                    a
                } else {
                    continue;
                };
                if !base.contains(&w) {
                    if found.is_some_and(|x| x != w) {
                        return None;
                    }
                    found = Some(w);
                }
            }
        }
        found
    };
    let lifted = |base: Vec<u32>| -> Option<Vec<u32>> {
        let top: Option<Vec<u32>> = base.iter().map(|&v| up(v, &base)).collect();
        Some(base.into_iter().chain(top?).collect())
    };
    let (kind, nodes) = match (tris.len(), quads.len()) {
        (4, 0) => {
            let t = tris[0];
            let apex = points.iter().copied().find(|p| !t.contains(p));
            (CellKind::Tetra, apex.map(|d| vec![t[0], t[2], t[1], d]))
        }
        (4, 1) => {
            let q = quads[0];
            let apex = points.iter().copied().find(|p| !q.contains(p));
            (CellKind::Pyramid, apex.map(|e| vec![q[0], q[3], q[2], q[1], e]))
        }
        (2, 3) => (CellKind::Wedge, lifted(vec![tris[0][0], tris[0][2], tris[0][1]])),
        (0, 6) => {
            (CellKind::Hexa, lifted(vec![quads[0][0], quads[0][3], quads[0][2], quads[0][1]]))
        }
        (t, q) => {
            return Err(format!(
            "{t} triangles and {q} quadrilaterals: not a tetrahedron, hexahedron, prism or pyramid"
        ))
        }
    };
    let nodes = nodes.ok_or_else(|| format!("its faces do not make a {}", kind.name()))?;
    // The faces of the cell built must be the faces read.
    let mut want: Vec<[NodeIndex; 4]> = fs.iter().map(|f| face_key(f)).collect();
    let mut got: Vec<[NodeIndex; 4]> = faces(kind)
        .iter()
        .map(|f| face_key(&f.iter().map(|&k| nodes[k]).collect::<Vec<_>>()))
        .collect();
    want.sort_unstable();
    got.sort_unstable();
    if want != got || points.len() != kind.nodes_per_cell() {
        return Err(format!("its faces do not make a {}", kind.name()));
    }
    Ok((kind, nodes))
}

/// The 3D mesh of a polyMesh (see the module's header).
pub(super) fn to_3d(
    poly: &Poly<'_>,
    patches: &[PatchInfo],
    cell_zones: &[(String, Vec<u32>)],
    face_zones: &[(String, Vec<u32>)],
) -> Result<TaggedMesh, String> {
    // Each cell's faces, outward.
    let mut count = vec![0u32; poly.n_cells + 1];
    for (f, &o) in poly.owner.iter().enumerate() {
        count[o as usize + 1] += 1;
        if let Some(&n) = poly.neighbour.get(f) {
            count[n as usize + 1] += 1;
        }
    }
    for i in 1..count.len() {
        count[i] += count[i - 1];
    }
    let mut fill = count.clone();
    let mut of_cell = vec![(0u32, false); count[poly.n_cells] as usize];
    for (f, &o) in poly.owner.iter().enumerate() {
        of_cell[fill[o as usize] as usize] = (f as u32, false);
        fill[o as usize] += 1;
        if let Some(&n) = poly.neighbour.get(f) {
            of_cell[fill[n as usize] as usize] = (f as u32, true);
            fill[n as usize] += 1;
        }
    }
    let mut tag = vec![if cell_zones.is_empty() { 1 } else { 0 }; poly.n_cells];
    let mut mesh =
        TaggedMesh { coordinate_dim: 3, points: poly.points.to_vec(), ..TaggedMesh::default() };
    let names: Vec<&str> = cell_zones.iter().map(|z| z.0.as_str()).collect();
    for ((t, name), (_, cells)) in tags_of(&names).into_iter().zip(cell_zones) {
        for &c in cells {
            tag[c as usize] = t;
        }
        if let Some(name) = name {
            mesh.tag_names.insert((3, t), name);
        }
    }
    let mut fs: Vec<Vec<u32>> = Vec::new();
    for c in 0..poly.n_cells {
        fs.clear();
        for &(f, reversed) in &of_cell[count[c] as usize..count[c + 1] as usize] {
            let mut p = poly.faces[f as usize].clone();
            if reversed {
                p[1..].reverse();
            }
            fs.push(p);
        }
        let (kind, nodes) = cell_nodes(&fs).map_err(|why| format!("cell {c}: {why}"))?;
        mesh.block_mut(kind).push(&nodes, tag[c], tag[c]);
    }
    // Surface cells: the patches, then the face zones.
    let mut groups: Vec<(&str, Vec<usize>)> = patches
        .iter()
        .map(|p| (p.name.as_str(), (p.start..p.start + p.n_faces).collect()))
        .collect();
    for (name, items) in face_zones {
        groups.push((name.as_str(), items.iter().map(|&f| f as usize).collect()));
    }
    let names: Vec<&str> = groups.iter().map(|g| g.0).collect();
    for ((t, name), (gname, items)) in tags_of(&names).into_iter().zip(&groups) {
        for &f in items {
            let p = &poly.faces[f];
            let kind = match p.len() {
                3 => CellKind::Triangle,
                4 => CellKind::Quad,
                n => {
                    return Err(format!(
                        "face {f} of `{gname}` has {n} points (triangles and quads only)"
                    ))
                }
            };
            mesh.block_mut(kind).push(p, t, t);
        }
        if let Some(name) = name {
            mesh.tag_names.insert((2, t), name);
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind's outward faces, from `skin::faces` on a cell numbered 10.., shuffled
    /// in order and rotated in their points, come back as a cell of the same faces.
    #[test]
    fn cells_are_rebuilt_from_any_order_of_their_faces() {
        for kind in [CellKind::Tetra, CellKind::Pyramid, CellKind::Wedge, CellKind::Hexa] {
            let cell: Vec<u32> = (10..10 + kind.nodes_per_cell() as u32).collect();
            let mut fs: Vec<Vec<u32>> =
                faces(kind).iter().map(|f| f.iter().map(|&k| cell[k]).collect()).collect();
            fs.reverse();
            for (i, f) in fs.iter_mut().enumerate() {
                let n = f.len();
                f.rotate_left(i % n);
            }
            let (k, nodes) = cell_nodes(&fs).unwrap();
            assert_eq!(k, kind);
            let mut a: Vec<_> = faces(kind)
                .iter()
                .map(|f| {
                    let mut p: Vec<u32> = f.iter().map(|&i| nodes[i]).collect();
                    let m = (0..p.len()).min_by_key(|&i| p[i]).unwrap();
                    p.rotate_left(m);
                    p
                })
                .collect();
            let mut b: Vec<_> = fs
                .iter()
                .map(|f| {
                    let mut p = f.clone();
                    let m = (0..p.len()).min_by_key(|&i| p[i]).unwrap();
                    p.rotate_left(m);
                    p
                })
                .collect();
            a.sort();
            b.sort();
            // Same faces with the same orientation: the same cell, positively oriented.
            assert_eq!(a, b, "{kind:?}");
        }
    }
}
