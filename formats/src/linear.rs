//! Second-order cells made linear, for the commands that compute on linear cells.
//!
//! Every reader keeps second-order cells as the file has them, so that a conversion
//! loses nothing. The sizing, the remeshers and the skin take segments, triangles and
//! quadrangles through their corners: before them, [`TaggedMesh::linearise`] makes a
//! second-order mesh (`gmsh -2 -order 2`: 3-node lines, 6-node triangles, 8- and 9-node
//! quadrangles) the linear mesh of its corners — every format smartmesh reads numbers
//! the corners first — and drops the nodes that only second-order cells use beyond
//! their corners (mid-edge and mid-face nodes) with their point data, as a linear
//! mesher would never have made them. Nodes that no cell uses at all (a circle's centre)
//! are kept, as always. Cell data is kept cell for cell (an `$ElementNodeData` view
//! keeps its values for every node of the second-order cell).

use crate::{CellKind, NodeIndex, TaggedMesh};

/// The linear kind of a second-order one.
fn linear(kind: CellKind) -> CellKind {
    match kind {
        CellKind::Line3 => CellKind::Line,
        CellKind::Triangle6 => CellKind::Triangle,
        CellKind::Quad8 | CellKind::Quad9 => CellKind::Quad,
        k => k,
    }
}

/// `6-node triangles` for a second-order kind, `3-node` for its linear one.
fn nodes_word(kind: CellKind) -> String {
    let what = match kind {
        CellKind::Line3 | CellKind::Line => "lines",
        CellKind::Triangle6 | CellKind::Triangle => "triangles",
        _ => "quadrangles",
    };
    format!("{}-node {what}", kind.nodes_per_cell())
}

impl TaggedMesh {
    /// Reduces the second-order cells to their corners and drops the nodes only they
    /// used beyond their corners; says what it did (`None`: nothing to do), e.g.
    /// `second-order cells made linear: 96 6-node triangles as 3-node, 24 3-node lines
    /// as 2-node; 228 mid-edge nodes dropped`.
    pub fn linearise(&mut self) -> Option<String> {
        reduce(self)
    }
}

fn reduce(mesh: &mut TaggedMesh) -> Option<String> {
    if !mesh.blocks.iter().any(|b| b.kind.is_second_order()) {
        return None;
    }
    // Cells reduced, by kind, in the order met.
    let mut reduced: Vec<(CellKind, usize)> = Vec::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.is_second_order()) {
        let cells = b.nodes.len() / b.kind.nodes_per_cell();
        match reduced.iter_mut().find(|(k, _)| *k == b.kind) {
            Some((_, n)) => *n += cells,
            None => reduced.push((b.kind, cells)),
        }
    }
    let mid_face = reduced.iter().any(|(k, _)| *k == CellKind::Quad9);
    // Nodes before: used by a cell at all; after: used by a corner.
    let n = mesh.points.len();
    let mut used = vec![false; n];
    let mut corner = vec![false; n];
    for b in &mut mesh.blocks {
        let k = b.kind.nodes_per_cell();
        let lin = linear(b.kind);
        let c = lin.nodes_per_cell();
        for cell in b.nodes.chunks_exact(k) {
            for (i, &v) in cell.iter().enumerate() {
                used[v as usize] = true;
                corner[v as usize] |= i < c;
            }
        }
        if lin != b.kind {
            b.nodes = b.nodes.chunks_exact(k).flat_map(|cell| cell[..c].iter().copied()).collect();
            b.kind = lin;
        }
    }
    // Consecutive blocks of one kind are one block again (cell order unchanged).
    let mut blocks: Vec<crate::CellBlock> = Vec::with_capacity(mesh.blocks.len());
    for b in std::mem::take(&mut mesh.blocks) {
        match blocks.last_mut() {
            Some(last) if last.kind == b.kind => {
                last.nodes.extend_from_slice(&b.nodes);
                last.physical.extend_from_slice(&b.physical);
                last.geometrical.extend_from_slice(&b.geometrical);
            }
            _ => blocks.push(b),
        }
    }
    mesh.blocks = blocks;
    // Nodes kept: corners, and nodes no cell used.
    let keep: Vec<bool> = used.iter().zip(&corner).map(|(&u, &c)| c || !u).collect();
    let dropped = keep.iter().filter(|&&k| !k).count();
    let kinds: Vec<String> = reduced
        .iter()
        .map(|&(k, n)| {
            let linear_nodes = linear(k).nodes_per_cell();
            format!("{n} {} as {linear_nodes}-node", nodes_word(k))
        })
        .collect();
    let what = if mid_face { "mid-edge and mid-face nodes" } else { "mid-edge nodes" };
    let note = format!(
        "second-order cells made linear: {}; {dropped} {what} dropped{}",
        kinds.join(", "),
        if mesh.point_data.is_empty() || dropped == 0 { "" } else { " with their point data" }
    );
    if keep.iter().any(|&k| !k) {
        let mut new_index = vec![NodeIndex::MAX; n];
        for (next, (v, _)) in keep.iter().enumerate().filter(|(_, &k)| k).enumerate() {
            // Fewer points than before, which the reader kept within `NodeIndex`.
            new_index[v] = next as NodeIndex;
        }
        let mut v = 0;
        mesh.points.retain(|_| {
            v += 1;
            keep[v - 1]
        });
        for b in &mut mesh.blocks {
            for x in &mut b.nodes {
                *x = new_index[*x as usize];
            }
        }
        for a in mesh.point_data.values_mut() {
            let k = a.components;
            let mut values = Vec::with_capacity(mesh.points.len() * k);
            for (item, _) in a.values.chunks_exact(k).zip(&keep).filter(|(_, &k)| k) {
                values.extend_from_slice(item);
            }
            a.values = values;
        }
    }
    Some(note)
}
