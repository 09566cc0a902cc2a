//! The faces of volume cells, and the skin of a volume mesh for the formats that hold
//! surfaces only (OBJ, glTF, STL).
//!
//! [`faces`] lists each linear volume kind's faces by the corner indices of Gmsh's node
//! order, each face's points turning counter-clockwise seen from outside the cell (the
//! right-hand rule gives the outward normal on a cell of positive volume). Checked on
//! Gmsh's reference elements: the tetrahedron's third point lies on the side of
//! (p1 - p0) × (p2 - p0), the wedge's bottom triangle 0-1-2 and the pyramid's base 0-1-2-3
//! turn counter-clockwise seen from the top, so their outward order is reversed.
//!
//! [`skin`] is what ParaView's *Extract Surface* draws and what a Blender user expects
//! from a volume mesh: every face that belongs to one volume cell only, as a triangle or
//! a quad, outward. A face that is already a surface cell of the mesh (a Gmsh physical
//! surface on the boundary) is that cell, with its own tags; the other skin faces take
//! the tags of the volume cell they bound, and the volume tag's name when the surface
//! tag of that number has none. Faces shared by two volume cells (internal interfaces
//! between volume tags too) are inside and not drawn. Faces are matched by their sorted
//! corner indices (exact: the same points, not the same coordinates), with a sort,
//! not a hash, so the result is the same bytes every run.

use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet};

use crate::{CellBlock, CellKind, NodeIndex, TaggedMesh, WriteReport};

/// The outward faces of a volume kind ([`CellKind::faces`]).
pub(crate) fn faces(kind: CellKind) -> &'static [&'static [usize]] {
    kind.faces()
}

/// A face's corner indices sorted, a triangle's padded with `NodeIndex::MAX`: equal
/// for two faces exactly when they have the same points.
pub(crate) fn face_key(nodes: &[NodeIndex]) -> [NodeIndex; 4] {
    let mut k = [NodeIndex::MAX; 4];
    k[..nodes.len()].copy_from_slice(nodes);
    k.sort_unstable();
    k
}

/// One face of a volume cell: its key, its cell (global index over the mesh's cells),
/// its block and its points in outward order.
struct CellFace {
    key: [NodeIndex; 4],
    block: u32,
    cell: u32,
    global: u32,
    points: [NodeIndex; 4],
    len: u8,
}

/// The faces that belong to exactly one volume cell: `(block, cell in block, global
/// cell index, outward points)`, sorted by their points (deterministic).
pub(crate) fn boundary_faces(mesh: &TaggedMesh) -> Vec<(usize, usize, usize, Vec<NodeIndex>)> {
    let mut all: Vec<CellFace> = Vec::new();
    let mut global = 0u32;
    for (bi, b) in mesh.blocks.iter().enumerate() {
        let fs = faces(b.kind);
        if fs.is_empty() {
            global += b.len() as u32;
            continue;
        }
        for (ci, c) in b.cells().enumerate() {
            for f in fs {
                let mut points = [NodeIndex::MAX; 4];
                for (p, &i) in points.iter_mut().zip(f.iter()) {
                    *p = c[i];
                }
                all.push(CellFace {
                    key: face_key(&points[..f.len()]),
                    block: bi as u32,
                    cell: ci as u32,
                    global,
                    points,
                    len: f.len() as u8,
                });
            }
            global += 1;
        }
    }
    all.sort_unstable_by_key(|f| (f.key, f.global));
    let mut out = Vec::new();
    let mut i = 0;
    while i < all.len() {
        let mut j = i + 1;
        while j < all.len() && all[j].key == all[i].key {
            j += 1;
        }
        if j == i + 1 {
            let f = &all[i];
            out.push((
                f.block as usize,
                f.cell as usize,
                f.global as usize,
                f.points[..f.len as usize].to_vec(),
            ));
        }
        i = j;
    }
    out
}

/// `mesh` as a surface: borrowed when it has no volume cell; else its volume cells
/// replaced by their boundary faces (see the module header), the change said in
/// `report` for `format`. Cell data and cell sets follow: a kept cell keeps its
/// values and its place in the sets, a skin face takes its volume cell's values.
pub(crate) fn skin<'a>(
    mesh: &'a TaggedMesh,
    format: &str,
    report: &mut WriteReport,
) -> Cow<'a, TaggedMesh> {
    let volumes: BTreeMap<CellKind, usize> =
        mesh.blocks.iter().filter(|b| b.kind.dim() == 3).fold(BTreeMap::new(), |mut m, b| {
            *m.entry(b.kind).or_insert(0) += b.len();
            m
        });
    if volumes.is_empty() {
        return Cow::Borrowed(mesh);
    }
    let surface_keys: BTreeSet<[NodeIndex; 4]> = mesh
        .blocks
        .iter()
        .filter(|b| matches!(b.kind.linear(), CellKind::Triangle | CellKind::Quad))
        .flat_map(|b| {
            let n = if b.kind.linear() == CellKind::Triangle { 3 } else { 4 };
            b.cells().map(move |c| face_key(&c[..n]))
        })
        .collect();
    let boundary = boundary_faces(mesh);

    let mut out = TaggedMesh {
        points: mesh.points.clone(),
        coordinate_dim: mesh.coordinate_dim,
        tag_names: mesh.tag_names.clone(),
        entities: mesh.entities.clone(),
        entity_boxes: mesh.entity_boxes.clone(),
        point_data: mesh.point_data.clone(),
        point_sets: mesh.point_sets.clone(),
        holes: mesh.holes.clone(),
        regions: mesh.regions.clone(),
        ..TaggedMesh::default()
    };
    // Old global cell index of each cell of `out`, in `out`'s order.
    let mut source: Vec<usize> = Vec::new();
    let mut old_to_new: Vec<Option<usize>> = vec![None; mesh.num_cells()];
    let mut global = 0usize;
    for b in &mesh.blocks {
        if b.kind.dim() == 3 {
            global += b.len();
            continue;
        }
        for i in 0..b.len() {
            old_to_new[global + i] = Some(source.len() + i);
        }
        source.extend(global..global + b.len());
        global += b.len();
        out.blocks.push(b.clone());
    }
    let (mut tri, mut quad) = (CellBlock::new(CellKind::Triangle), CellBlock::new(CellKind::Quad));
    let mut tri_source = Vec::new();
    let mut quad_source = Vec::new();
    let mut covered = 0usize;
    let mut named_from_volume: BTreeSet<i32> = BTreeSet::new();
    for (bi, ci, g, points) in &boundary {
        if surface_keys.contains(&face_key(points)) {
            covered += 1;
            continue;
        }
        let b = &mesh.blocks[*bi];
        let (p, geo) = (b.physical[*ci], b.geometrical[*ci]);
        if points.len() == 3 {
            tri.push(points, p, geo);
            tri_source.push(*g);
        } else {
            quad.push(points, p, geo);
            quad_source.push(*g);
        }
        named_from_volume.insert(p);
    }
    let added = tri.len() + quad.len();
    for (block, src) in [(tri, tri_source), (quad, quad_source)] {
        if !block.is_empty() {
            out.blocks.push(block);
            source.extend(src);
        }
    }
    let surface_tags: BTreeSet<i32> = mesh
        .blocks
        .iter()
        .filter(|b| b.kind.dim() == 2)
        .flat_map(|b| b.physical.iter().copied())
        .collect();
    // Volume names move to the skin faces' tags; none is left on dimension 3.
    out.tag_names.retain(|&(d, _), _| d != 3);
    for (&(d, p), name) in &mesh.tag_names {
        if d != 3 {
            continue;
        }
        if named_from_volume.contains(&p)
            && p != 0
            && mesh.tag_name(2, p).is_none()
            && !surface_tags.contains(&p)
        {
            out.tag_names.insert((2, p), name.clone());
        } else {
            report.drop(format!(
                "the name `{name}` of volume tag {p}: {format} holds surfaces, and no skin face takes it (surface tag {p} is another's)"
            ));
        }
    }
    for (name, a) in &mesh.cell_data {
        let a = a.expanded();
        let values = source.iter().flat_map(|&g| a.item(g).iter().copied()).collect();
        out.cell_data.insert(name.clone(), crate::DataArray::new(a.components, values));
    }
    for (name, set) in &mesh.cell_sets {
        let kept: Vec<usize> =
            set.iter().filter_map(|&c| old_to_new.get(c).copied().flatten()).collect();
        if kept.len() < set.len() {
            report.drop(format!(
                "{} volume cells of cell set `{name}`: {format} holds surfaces",
                set.len() - kept.len()
            ));
        }
        out.cell_sets.insert(name.clone(), kept);
    }
    let list: Vec<String> = volumes.iter().map(|(k, n)| format!("{n} {}", k.name())).collect();
    let second: bool = volumes.keys().any(|k| k.is_second_order());
    report.drop(format!(
        "the volume cells ({}) written as their boundary: {} faces that belong to one volume cell only{}{}, with the volume cells' tags; {format} holds surfaces, not volumes",
        list.join(", "),
        added + covered,
        if covered > 0 { format!(" ({covered} of them the mesh's own surface cells, kept with their tags)") } else { String::new() },
        if second { ", second-order cells by their corners" } else { "" },
    ));
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The signed volume of the cone from the centroid `c` to each face, summed: the
    /// cell's volume when every face turns counter-clockwise seen from outside.
    fn volume_by_faces(points: &[[f64; 3]], kind: CellKind) -> f64 {
        let n = kind.nodes_per_cell();
        let mut c = [0.0; 3];
        for p in &points[..n] {
            for k in 0..3 {
                c[k] += p[k] / n as f64;
            }
        }
        let tet = |a: [f64; 3], b: [f64; 3], d: [f64; 3]| {
            let u = [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
            let v = [b[0] - c[0], b[1] - c[1], b[2] - c[2]];
            let w = [d[0] - c[0], d[1] - c[1], d[2] - c[2]];
            (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]))
                / 6.0
        };
        faces(kind)
            .iter()
            .map(|f| {
                (1..f.len() - 1)
                    .map(|i| tet(points[f[0]], points[f[i]], points[f[i + 1]]))
                    .sum::<f64>()
            })
            .sum()
    }

    /// Gmsh's reference elements (its manual's node ordering), volumes known.
    #[test]
    fn faces_are_outward_on_gmsh_reference_elements() {
        let tet = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!((volume_by_faces(&tet, CellKind::Tetra) - 1.0 / 6.0).abs() < 1e-15);
        let hex: Vec<[f64; 3]> = [
            [-1., -1., -1.],
            [1., -1., -1.],
            [1., 1., -1.],
            [-1., 1., -1.],
            [-1., -1., 1.],
            [1., -1., 1.],
            [1., 1., 1.],
            [-1., 1., 1.],
        ]
        .to_vec();
        assert!((volume_by_faces(&hex, CellKind::Hexa) - 8.0).abs() < 1e-14);
        let wedge =
            [[0., 0., -1.], [1., 0., -1.], [0., 1., -1.], [0., 0., 1.], [1., 0., 1.], [0., 1., 1.]];
        assert!((volume_by_faces(&wedge, CellKind::Wedge) - 1.0).abs() < 1e-14);
        let pyr = [[-1., -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.], [0., 0., 1.]];
        assert!((volume_by_faces(&pyr, CellKind::Pyramid) - 4.0 / 3.0).abs() < 1e-14);
    }

    /// Two tetrahedra sharing a face: 6 boundary faces, the shared one left; a surface
    /// cell on the boundary keeps its tag, the others take the volume's tag and name.
    #[test]
    fn skin_of_two_tetrahedra() {
        let mut m = TaggedMesh::new();
        m.coordinate_dim = 3;
        m.points = vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [1., 1., 1.]];
        m.block_mut(CellKind::Tetra).push(&[0u32, 1, 2, 3], 7, 7);
        m.block_mut(CellKind::Tetra).push(&[1u32, 2, 3, 4], 7, 7);
        m.block_mut(CellKind::Triangle).push(&[0u32, 2, 1], 3, 3);
        m.tag_names.insert((3, 7), "solid".into());
        m.tag_names.insert((2, 3), "bottom".into());
        let mut r = WriteReport::default();
        let s = skin(&m, "OBJ", &mut r);
        assert_eq!(s.num_cells_of(CellKind::Tetra), 0);
        assert_eq!(s.num_cells_of(CellKind::Triangle), 6);
        let tags: Vec<i32> = s.cells().map(|c| c.2).collect();
        assert_eq!(tags.iter().filter(|&&t| t == 3).count(), 1);
        assert_eq!(tags.iter().filter(|&&t| t == 7).count(), 5);
        assert_eq!(s.tag_name(2, 7), Some("solid"));
        assert!(r.dropped[0].contains("6 faces"), "{:?}", r.dropped);
        // Closed and outward: the divergence theorem gives the volume of both tets.
        let vol: f64 = s
            .cells()
            .map(|(_, c, _, _)| {
                let [a, b, d] = [c[0], c[1], c[2]].map(|i| s.points[i as usize]);
                (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
                    + a[2] * (b[0] * d[1] - b[1] * d[0]))
                    / 6.0
            })
            .sum();
        assert!((vol - (1.0 / 6.0 + 1.0 / 3.0)).abs() < 1e-14, "{vol}");
    }
}
