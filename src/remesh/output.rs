//! From the working state back to a [`TaggedMesh`]: live vertices in index order (input
//! vertices keep their relative order, nodes no triangle used included), vertex cells of
//! the input, line cells along every piece the input had line cells on (in curve order,
//! with its tags) then the kept line cells, live triangles with their face tags then the
//! kept triangles, the kept quads, tag names and entities, and the point data `metric`
//! (written by [`MetricField::to_array`], as every metric is).

use super::work::Work;
use crate::metric::Sym2;
use crate::metric_field::{MetricField, METRIC};
use smartmesh_formats::{CellBlock, CellKind, TaggedMesh};

/// The output mesh and its metric.
pub(super) fn assemble(
    input: &TaggedMesh,
    w: &Work,
    faces: &[(i32, i32)],
    vertex_cells: &[(u32, i32, i32)],
    kept: &[(CellKind, Vec<u32>, i32, i32)],
    kept_lines: &[([u32; 2], i32, i32)],
) -> (TaggedMesh, Vec<Sym2>) {
    let mut new_id = vec![u32::MAX; w.num_vertices()];
    let mut mesh = TaggedMesh::new();
    mesh.coordinate_dim = input.coordinate_dim;
    mesh.tag_names = input.tag_names.clone();
    mesh.entities = input.entities.clone();
    let mut metric = Vec::new();
    for (v, id) in new_id.iter_mut().enumerate() {
        let v = v as u32;
        if w.is_dead(v) {
            continue;
        }
        *id = mesh.points.len() as u32;
        let p = w.point(v);
        mesh.points.push([p[0], p[1], 0.0]);
        metric.push(w.metric(v));
    }
    let id = |v: u32| new_id[v as usize];

    if !vertex_cells.is_empty() {
        let mut b = CellBlock::new(CellKind::Vertex);
        for &(v, p, g) in vertex_cells {
            b.push(&[id(v)], p, g);
        }
        mesh.blocks.push(b);
    }
    // Constrained edges by piece, in parameter order.
    let mut on_piece = w.piece_edges();
    on_piece
        .sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)).then((x.2, x.3).cmp(&(y.2, y.3))));
    if !on_piece.is_empty() || !kept_lines.is_empty() {
        let mut b = CellBlock::new(CellKind::Line);
        for &(p, _, u, v) in &on_piece {
            let (ph, g) = w.boundary().pieces[p as usize].tags.unwrap_or((0, 0));
            b.push(&[id(u), id(v)], ph, g);
        }
        for &([u, v], ph, g) in kept_lines {
            b.push(&[id(u), id(v)], ph, g);
        }
        mesh.blocks.push(b);
    }
    let mut tb = CellBlock::new(CellKind::Triangle);
    for t in 0..w.num_slots() as u32 {
        if w.is_alive(t) {
            let v = w.tri(t);
            let (p, g) = faces[w.face(t) as usize];
            tb.push(&[id(v[0]), id(v[1]), id(v[2])], p, g);
        }
    }
    let mut qb = CellBlock::new(CellKind::Quad);
    for (kind, nodes, p, g) in kept {
        let nodes: Vec<u32> = nodes.iter().map(|&v| id(v)).collect();
        match kind {
            CellKind::Triangle => tb.push(&nodes, *p, *g),
            _ => qb.push(&nodes, *p, *g),
        }
    }
    mesh.blocks.push(tb);
    if !qb.is_empty() {
        mesh.blocks.push(qb);
    }
    let field = MetricField::new(metric, "the remeshed field");
    mesh.point_data.insert(METRIC.into(), field.to_array());
    (mesh, field.into_tensors())
}
