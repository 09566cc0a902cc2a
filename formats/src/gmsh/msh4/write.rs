//! The MSH 4.1 sections written from the [plan](super::plan): `$Entities`, `$Nodes`
//! and `$Elements` in entity blocks, ASCII or binary (`size_t` of 8 bytes).

use std::collections::BTreeMap;

use super::plan::{plan, Plan};
use crate::gmsh::header::{write_mesh_format, write_physical_names};
use crate::gmsh::views::write_views;
use crate::gmsh::MAX_NODES;
use crate::text::{push_f64, push_int};
use crate::{NodeIndex, Result, TaggedMesh, WriteReport};

/// Appends a `size_t` (8 bytes: the files say so in `$MeshFormat`).
#[inline]
fn push_size(out: &mut Vec<u8>, v: usize) {
    out.extend_from_slice(&(v as u64).to_le_bytes());
}

fn push_f64s(out: &mut Vec<u8>, vs: &[f64], binary: bool) {
    for &v in vs {
        if binary {
            out.extend_from_slice(&v.to_le_bytes());
        } else {
            out.push(b' ');
            push_f64(out, v);
        }
    }
}

fn write_entities(out: &mut Vec<u8>, mesh: &TaggedMesh, plan: &Plan, binary: bool) {
    out.extend_from_slice(b"$Entities\n");
    let mut counts = [0usize; 4];
    for e in &plan.ents {
        counts[e.dim as usize] += 1;
    }
    if binary {
        for c in counts {
            push_size(out, c);
        }
    } else {
        for (i, c) in counts.iter().enumerate() {
            push_int(out, *c);
            out.push(if i < 3 { b' ' } else { b'\n' });
        }
    }
    let first_node: BTreeMap<u32, usize> =
        plan.node_groups.iter().map(|(e, r)| (*e, plan.nodes[r.start] as usize)).collect();
    for (ei, e) in plan.ents.iter().enumerate() {
        if binary {
            out.extend_from_slice(&e.tag.to_le_bytes());
        } else {
            push_int(out, e.tag);
        }
        if e.dim == 0 {
            let p = e
                .point
                .or_else(|| first_node.get(&(ei as u32)).copied())
                .map_or(if e.has_box { e.lo } else { [0.0; 3] }, |v| mesh.points[v]);
            push_f64s(out, &p, binary);
        } else {
            push_f64s(out, &e.lo, binary);
            push_f64s(out, &e.hi, binary);
        }
        if binary {
            push_size(out, e.phys.len());
            for p in &e.phys {
                out.extend_from_slice(&p.to_le_bytes());
            }
            if e.dim > 0 {
                push_size(out, 0);
            }
        } else {
            out.push(b' ');
            push_int(out, e.phys.len());
            for p in &e.phys {
                out.push(b' ');
                push_int(out, *p);
            }
            if e.dim > 0 {
                out.extend_from_slice(b" 0");
            }
            out.push(b'\n');
        }
    }
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndEntities\n");
}

fn write_header4(out: &mut Vec<u8>, blocks: usize, n: usize, binary: bool) {
    let (lo, hi) = if n == 0 { (0, 0) } else { (1, n) };
    if binary {
        for v in [blocks, n, lo, hi] {
            push_size(out, v);
        }
    } else {
        for (i, v) in [blocks, n, lo, hi].into_iter().enumerate() {
            push_int(out, v);
            out.push(if i < 3 { b' ' } else { b'\n' });
        }
    }
}

fn write_block_header(out: &mut Vec<u8>, dim: u8, tag: i32, third: i32, n: usize, binary: bool) {
    if binary {
        out.extend_from_slice(&(dim as i32).to_le_bytes());
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&third.to_le_bytes());
        push_size(out, n);
    } else {
        push_int(out, dim);
        out.push(b' ');
        push_int(out, tag);
        out.push(b' ');
        push_int(out, third);
        out.push(b' ');
        push_int(out, n);
        out.push(b'\n');
    }
}

fn write_nodes(out: &mut Vec<u8>, mesh: &TaggedMesh, plan: &Plan, binary: bool) {
    out.extend_from_slice(b"$Nodes\n");
    write_header4(out, plan.node_groups.len(), mesh.points.len(), binary);
    for (e, range) in &plan.node_groups {
        let ent = &plan.ents[*e as usize];
        let nodes = &plan.nodes[range.clone()];
        write_block_header(out, ent.dim, ent.tag, 0, nodes.len(), binary);
        if binary {
            for &v in nodes {
                push_size(out, v as usize + 1);
            }
            for &v in nodes {
                // One fixed-size record per point (one capacity check, not three).
                let mut rec = [0u8; 24];
                for (j, c) in mesh.points[v as usize].iter().enumerate() {
                    rec[8 * j..8 * j + 8].copy_from_slice(&c.to_le_bytes());
                }
                out.extend_from_slice(&rec);
            }
        } else {
            for &v in nodes {
                push_int(out, v + 1);
                out.push(b'\n');
            }
            for &v in nodes {
                let p = &mesh.points[v as usize];
                push_f64(out, p[0]);
                out.push(b' ');
                push_f64(out, p[1]);
                out.push(b' ');
                push_f64(out, p[2]);
                out.push(b'\n');
            }
        }
    }
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndNodes\n");
}

fn write_elements(out: &mut Vec<u8>, mesh: &TaggedMesh, plan: &Plan, binary: bool) {
    out.extend_from_slice(b"$Elements\n");
    write_header4(out, plan.groups.len(), mesh.num_cells(), binary);
    let offsets: Vec<usize> = mesh
        .blocks
        .iter()
        .scan(0, |s, b| {
            let r = *s;
            *s += b.len();
            Some(r)
        })
        .collect();
    for (e, kind, range) in &plan.groups {
        let ent = &plan.ents[*e as usize];
        let runs = &plan.runs[range.clone()];
        let n: usize = runs.iter().map(|r| r.len as usize).sum();
        write_block_header(out, ent.dim, ent.tag, kind.gmsh_type(), n, binary);
        for run in runs {
            let b = &mesh.blocks[run.block as usize];
            let k = b.kind.nodes_per_cell();
            let (s, len) = (run.start as usize, run.len as usize);
            // Element tags: the cell's index in the mesh + 1, consecutive along a run.
            let first = offsets[run.block as usize] + s + 1;
            let nodes = &b.nodes[s * k..(s + len) * k];
            if binary {
                by_nodes!(k, element_records(out, first, nodes));
                continue;
            }
            for (j, cell) in nodes.chunks_exact(k).enumerate() {
                push_int(out, first + j);
                for &v in cell {
                    out.push(b' ');
                    push_int(out, v + 1);
                }
                out.push(b'\n');
            }
        }
    }
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndElements\n");
}

/// The binary records of a run of `K`-node elements numbered from `first`: the element
/// tag and the node tags, 8 bytes each, assembled on the stack and appended whole (one
/// capacity check per element rather than per number; `K` known, so the copy is of a
/// fixed size).
fn element_records<const K: usize>(out: &mut Vec<u8>, first: usize, nodes: &[NodeIndex]) {
    let mut rec = [0u8; 8 * (1 + MAX_NODES)];
    for (j, cell) in nodes.chunks_exact(K).enumerate() {
        rec[..8].copy_from_slice(&((first + j) as u64).to_le_bytes());
        for (i, &v) in cell.iter().enumerate() {
            rec[8 + 8 * i..16 + 8 * i].copy_from_slice(&(v as u64 + 1).to_le_bytes());
        }
        out.extend_from_slice(&rec[..8 * (K + 1)]);
    }
}

/// Writes MSH 4.1.
pub(in crate::gmsh) fn write(
    mesh: &TaggedMesh,
    binary: bool,
    out: &mut Vec<u8>,
    report: &mut WriteReport,
) -> Result<()> {
    let plan = plan(mesh, report)?;
    write_mesh_format(out, "4.1", binary);
    write_physical_names(out, mesh, report);
    write_entities(out, mesh, &plan, binary);
    write_nodes(out, mesh, &plan, binary);
    write_elements(out, mesh, &plan, binary);
    write_views(out, mesh, binary, &|i| i as u64 + 1, report);
    Ok(())
}
