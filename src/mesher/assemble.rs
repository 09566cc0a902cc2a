//! The refined triangulation as a [`TaggedMesh`]: the domain's triangles with their
//! region tags, every input segment as the chain of Line cells that now covers it
//! (carrying the segment's tags), and Vertex cells at the corners of the boundary so
//! that [`crate::Topology::from_mesh`] finds them as topological points.
//!
//! Spade splits constraint edges during refinement without telling which input segment a
//! piece came from, so each segment is walked from its first end to its second along
//! constraint edges, always taking the one that points most nearly at the far end (the
//! pieces are collinear with the segment up to the rounding of their split points).

use std::collections::{BTreeMap, HashMap};

use spade::handles::FixedVertexHandle;
use spade::Triangulation;

use smartmesh_formats::{CellBlock, CellKind, NodeIndex, TaggedMesh};

use super::domain::NO_REGION;
use super::pslg::Pslg;
use super::refine::Labelled;
use super::{Cdt, MeshError, MeshOptions};

/// An output Line cell before renumbering: spade vertices and the segment's tags.
struct Piece {
    ends: [usize; 2],
    physical: i32,
    geometrical: i32,
}

/// Walks every segment of `pslg` over the constraint edges of `cdt`.
fn segment_pieces(cdt: &Cdt, pslg: &Pslg) -> Result<Vec<Piece>, MeshError> {
    let pos = |v: usize| {
        let p = cdt.vertex(FixedVertexHandle::from_index(v)).position();
        [p.x, p.y]
    };
    let limit = cdt.num_vertices();
    let mut claimed: HashMap<(usize, usize), usize> = HashMap::new();
    let mut pieces = Vec::new();
    for (k, s) in pslg.segments.iter().enumerate() {
        let target = pos(s.b);
        let (mut v, mut prev, mut steps) = (s.a, usize::MAX, 0usize);
        while v != s.b {
            let pv = pos(v);
            let t = [target[0] - pv[0], target[1] - pv[1]];
            let tn = t[0].hypot(t[1]);
            let mut best: Option<(f64, usize)> = None;
            for e in cdt.vertex(FixedVertexHandle::from_index(v)).out_edges() {
                if !e.is_constraint_edge() {
                    continue;
                }
                let w = e.to().fix().index();
                if w == prev {
                    continue;
                }
                let pw = pos(w);
                let d = [pw[0] - pv[0], pw[1] - pv[1]];
                let cos = (d[0] * t[0] + d[1] * t[1]) / (d[0].hypot(d[1]) * tn);
                if best.map_or(true, |(c, b)| cos > c || (cos == c && w < b)) {
                    best = Some((cos, w));
                }
            }
            let w = match best {
                Some((cos, w)) if cos > 0.999 => w,
                _ => {
                    return Err(MeshError::Internal {
                        reason: format!(
                            "lost the way along segment {} after {steps} pieces",
                            k + 1
                        ),
                    })
                }
            };
            if let Some(j) = claimed.insert((v.min(w), v.max(w)), k) {
                return Err(MeshError::SegmentsOverlap { first: j + 1, second: k + 1 });
            }
            pieces.push(Piece { ends: [v, w], physical: s.physical, geometrical: s.geometrical });
            prev = v;
            v = w;
            steps += 1;
            if steps > limit {
                return Err(MeshError::Internal {
                    reason: format!("segment {} does not reach its end", k + 1),
                });
            }
        }
    }
    Ok(pieces)
}

/// Vertices of the Line cells that are corners: where the number of pieces is not two,
/// where the tag changes, or where the boundary turns by more than `corner_angle_deg`.
fn corners(pieces: &[Piece], cdt: &Cdt, corner_angle_deg: f64) -> Vec<usize> {
    let pos = |v: usize| {
        let p = cdt.vertex(FixedVertexHandle::from_index(v)).position();
        [p.x, p.y]
    };
    // vertex -> (number of pieces, first tag, tag changes, two neighbours)
    let mut at: BTreeMap<usize, (usize, i32, bool, [usize; 2])> = BTreeMap::new();
    for p in pieces {
        for (i, &v) in p.ends.iter().enumerate() {
            let other = p.ends[1 - i];
            let e = at.entry(v).or_insert((0, p.physical, false, [usize::MAX; 2]));
            if e.0 < 2 {
                e.3[e.0] = other;
            }
            e.0 += 1;
            e.2 |= e.1 != p.physical;
        }
    }
    let straight_enough = (180.0 - corner_angle_deg).to_radians().cos();
    at.into_iter()
        .filter(|&(v, (count, _, changes, nb))| {
            if count != 2 || changes {
                return true;
            }
            let (c, a, b) = (pos(v), pos(nb[0]), pos(nb[1]));
            let (u, w) = ([a[0] - c[0], a[1] - c[1]], [b[0] - c[0], b[1] - c[1]]);
            // cos of the angle between the two pieces; -1 when straight.
            let cos = (u[0] * w[0] + u[1] * w[1]) / (u[0].hypot(u[1]) * w[0].hypot(w[1]));
            cos > straight_enough
        })
        .map(|(v, _)| v)
        .collect()
}

/// Builds the output mesh from the refined `cdt` and the domain's triangles with their
/// labels ([`NO_REGION`] or a seed index).
pub(crate) fn assemble(
    cdt: &Cdt,
    domain: &[Labelled],
    pslg: &Pslg,
    input: &TaggedMesh,
    opts: &MeshOptions,
) -> Result<TaggedMesh, MeshError> {
    let seed = |l: u32| (l != NO_REGION).then(|| &pslg.seeds[l as usize]);
    let triangles: Vec<([usize; 3], i32)> =
        domain.iter().map(|&(t, l)| (t, seed(l).map_or(0, |s| s.tag))).collect();
    let pieces = segment_pieces(cdt, pslg)?;
    let corner_vertices = corners(&pieces, cdt, opts.corner_angle_deg);

    // Vertex cells: the input's listed points with their tags, then the corners they do
    // not list, numbered after the largest point tag in use.
    let mut vertex_cells: Vec<(usize, i32, i32)> = pslg.listed.clone();
    let listed: std::collections::BTreeSet<usize> = pslg.listed.iter().map(|l| l.0).collect();
    let mut next_tag = pslg
        .listed
        .iter()
        .map(|l| l.1.max(l.2))
        .chain(input.tag_names.keys().filter(|k| k.0 == 0).map(|k| k.1))
        .fold(0, i32::max)
        .saturating_add(1);
    for v in corner_vertices {
        if !listed.contains(&v) {
            vertex_cells.push((v, next_tag, next_tag));
            next_tag = next_tag.saturating_add(1);
        }
    }

    // Keep the vertices some cell uses, in spade's order (input vertices first).
    let nv = cdt.num_vertices();
    let mut used = vec![false; nv];
    for (t, _) in &triangles {
        for &v in t {
            used[v] = true;
        }
    }
    for p in &pieces {
        used[p.ends[0]] = true;
        used[p.ends[1]] = true;
    }
    for c in &vertex_cells {
        used[c.0] = true;
    }
    // spade numbers its vertices with 32-bit handles, so every index fits a NodeIndex.
    let mut new_index = vec![NodeIndex::MAX; nv];
    let mut points = Vec::new();
    for (v, vertex) in cdt.vertices().enumerate() {
        if used[v] {
            new_index[v] = points.len() as NodeIndex;
            let p = vertex.position();
            points.push([p.x, p.y, 0.0]);
        }
    }

    let mut vb = CellBlock::new(CellKind::Vertex);
    for &(v, p, g) in &vertex_cells {
        vb.push(&[new_index[v]], p, g);
    }
    let mut lb = CellBlock::new(CellKind::Line);
    for p in &pieces {
        lb.push(&[new_index[p.ends[0]], new_index[p.ends[1]]], p.physical, p.geometrical);
    }
    let mut tb = CellBlock::new(CellKind::Triangle);
    for (t, tag) in &triangles {
        tb.push(&[new_index[t[0]], new_index[t[1]], new_index[t[2]]], *tag, *tag);
    }
    let mut out = TaggedMesh::new();
    out.points = points;
    if pslg.real_attributes {
        // One value per cell in block order: Vertex and Line cells first, with 0.
        let before = vb.len() + lb.len();
        let mut values = vec![0.0; before];
        values.extend(domain.iter().map(|&(_, l)| seed(l).map_or(0.0, |s| s.attribute)));
        out.cell_data.insert(
            smartmesh_formats::triangle::attribute_name(1),
            smartmesh_formats::DataArray::new(1, values),
        );
    }
    out.blocks = [vb, lb, tb].into_iter().filter(|b| !b.is_empty()).collect();
    out.tag_names = input.tag_names.clone();
    Ok(out)
}
