//! The MSH 4.1 writer's plan: which entity every cell and node goes to, with the
//! physical groups and bounding box of each entity, before any byte is written.
//!
//! MSH 4.1 gives physical groups to entities, not cells: an entity is made per
//! (dimension, geometrical tag), cells of another physical tag than their entity's
//! first go to new entities (the report says so), cells without a positive geometrical
//! tag too; each node goes to the lowest-dimensional entity that uses it. Cost: one
//! pass over the cells by runs of equal tags, and counting sorts (stable, so the mesh's
//! order is kept within each block).

use std::collections::BTreeMap;

use crate::{CellKind, Error, ErrorKind, Result, TaggedMesh, WriteReport};

const UNSET: u32 = u32::MAX;

/// A model entity as written.
pub(super) struct Ent {
    pub(super) dim: u8,
    pub(super) tag: i32,
    pub(super) phys: Vec<i32>,
    pub(super) lo: [f64; 3],
    pub(super) hi: [f64; 3],
    pub(super) has_box: bool,
    /// The node of a point entity's vertex cell.
    pub(super) point: Option<usize>,
}

impl Ent {
    fn grow(&mut self, p: &[f64; 3]) {
        if self.has_box {
            for ((lo, hi), &c) in self.lo.iter_mut().zip(&mut self.hi).zip(p) {
                *lo = lo.min(c);
                *hi = hi.max(c);
            }
        } else {
            self.lo = *p;
            self.hi = *p;
            self.has_box = true;
        }
    }
}

fn kind_index(k: CellKind) -> usize {
    CellKind::ALL.iter().position(|&x| x == k).unwrap_or(0)
}

/// Consecutive cells of one mesh block with the same physical and geometrical tag:
/// `len` cells from `start` in block `block`.
#[derive(Clone, Copy)]
pub(super) struct Run {
    pub(super) block: u32,
    pub(super) start: u32,
    pub(super) len: u32,
}

/// Where every cell and node goes: entities, element blocks, node blocks.
pub(super) struct Plan {
    pub(super) ents: Vec<Ent>,
    /// Element blocks `(entity, kind)` with their cells as runs (a range of `runs`),
    /// in mesh order within each.
    pub(super) groups: Vec<(u32, CellKind, std::ops::Range<usize>)>,
    pub(super) runs: Vec<Run>,
    /// Node blocks `(entity, nodes)`.
    pub(super) node_groups: Vec<(u32, std::ops::Range<usize>)>,
    pub(super) nodes: Vec<u32>,
}

/// Where every cell and node goes, in seven steps (each a function below): the cells'
/// tag combinations, the free entity tags, the entities, their order, the element
/// blocks, the node of each entity, the node blocks.
pub(super) fn plan(mesh: &TaggedMesh, report: &mut WriteReport) -> Result<Plan> {
    let Combinations { ids, first_phys, cell_runs } = cell_combinations(mesh);
    let mut free = FreeTags::new(mesh, &ids);
    let (ents, combo_ent, host_key) = entities(mesh, &ids, &first_phys, &mut free, report)?;

    // 4. Entities in (dimension, tag) order.
    let index: BTreeMap<(u8, i32), u32> =
        ents.keys().enumerate().map(|(i, &k)| (k, i as u32)).collect();
    let mut ents: Vec<Ent> = ents
        .into_iter()
        .map(|((dim, tag), phys)| Ent {
            dim,
            tag,
            phys,
            lo: [0.0; 3],
            hi: [0.0; 3],
            has_box: false,
            point: None,
        })
        .collect();
    let combo_idx: Vec<u32> = combo_ent.iter().map(|k| index[k]).collect();

    let (groups, runs) = element_blocks(mesh, ents.len(), &combo_idx, cell_runs);
    let host = host_key.map(|k| index[&k]);
    let node_ent = node_entities(mesh, &mut ents, &groups, &runs, host);
    given_boxes(mesh, &mut ents);
    let (node_groups, nodes) = node_blocks(ents.len(), &node_ent);
    Ok(Plan { ents, groups, runs, node_groups, nodes })
}

/// Step 1: the (dimension, geometrical tag, physical tag) combinations of the cells.
struct Combinations {
    /// Each combination and its number, in order of first appearance.
    ids: BTreeMap<(u8, i32, i32), u32>,
    /// The physical tag first met on each (dimension, geometrical tag).
    first_phys: BTreeMap<(u8, i32), i32>,
    /// `(run, combination)` in mesh order.
    cell_runs: Vec<(Run, u32)>,
}

/// 1. The (dimension, geometrical tag, physical tag) of every cell, by runs of
///    consecutive cells that share them (a mesh's cells are mostly grouped so).
fn cell_combinations(mesh: &TaggedMesh) -> Combinations {
    let mut combos: BTreeMap<(u8, i32, i32), u32> = BTreeMap::new();
    let mut first_phys: BTreeMap<(u8, i32), i32> = BTreeMap::new();
    let mut cell_runs: Vec<(Run, u32)> = Vec::new();
    let mut last: Option<((u8, i32, i32), u32)> = None;
    for (bi, b) in mesh.blocks.iter().enumerate() {
        let dim = b.kind.dim();
        let (phys, geom) = (&b.physical[..], &b.geometrical[..b.physical.len()]);
        let mut i = 0;
        while i < phys.len() {
            let (p, g) = (phys[i], geom[i]);
            let mut j = i + 1;
            while j < phys.len() && phys[j] == p && geom[j] == g {
                j += 1;
            }
            let key = (dim, g, p);
            let id = match last {
                Some((k, id)) if k == key => id,
                _ => {
                    let n = combos.len() as u32;
                    let id = *combos.entry(key).or_insert(n);
                    first_phys.entry((dim, g)).or_insert(p);
                    last = Some((key, id));
                    id
                }
            };
            cell_runs.push((Run { block: bi as u32, start: i as u32, len: (j - i) as u32 }, id));
            i = j;
        }
    }
    Combinations { ids: combos, first_phys, cell_runs }
}

/// 2. Free entity tags per dimension, above every tag in use.
struct FreeTags {
    next: [i64; 4],
}

impl FreeTags {
    fn new(mesh: &TaggedMesh, combos: &BTreeMap<(u8, i32, i32), u32>) -> Self {
        let mut next_free = [1i64; 4];
        for &(d, g, _) in combos.keys() {
            next_free[d as usize] = next_free[d as usize].max(g as i64 + 1);
        }
        for &(d, t) in mesh.entities.keys() {
            if d <= 3 {
                next_free[d as usize] = next_free[d as usize].max(t as i64 + 1);
            }
        }
        FreeTags { next: next_free }
    }

    fn alloc(&mut self, d: u8) -> Result<i32> {
        let t = self.next[d as usize];
        self.next[d as usize] += 1;
        i32::try_from(t).map_err(|_| {
            Error::new(ErrorKind::CannotWrite {
                format: "Gmsh MSH",
                reason: format!("no free {d}D entity tag is left above the largest one in use"),
            })
        })
    }
}

/// The entities to write (`(dimension, tag)` → physical tags), the entity of each
/// combination, and the entity made for nodes when no cell is there to hold them.
type Entities = (BTreeMap<(u8, i32), Vec<i32>>, Vec<(u8, i32)>, Option<(u8, i32)>);

/// 3. An entity per (dimension, geometrical tag); cells of other physical tags than
///    the entity's first move to new entities.
fn entities(
    mesh: &TaggedMesh,
    combos: &BTreeMap<(u8, i32, i32), u32>,
    first_phys: &BTreeMap<(u8, i32), i32>,
    free: &mut FreeTags,
    report: &mut WriteReport,
) -> Result<Entities> {
    let mut ents: BTreeMap<(u8, i32), Vec<i32>> = BTreeMap::new();
    let mut combo_ent: Vec<(u8, i32)> = vec![(0, 0); combos.len()];
    let by_entity = {
        let mut m: BTreeMap<(u8, i32), Vec<(i32, u32)>> = BTreeMap::new();
        for (&(d, g, p), &id) in combos {
            m.entry((d, g)).or_default().push((p, id));
        }
        m
    };
    let mut untagged = 0usize;
    for ((d, g), list) in &by_entity {
        let (d, g) = (*d, *g);
        if g <= 0 {
            for &(p, id) in list {
                let t = free.alloc(d)?;
                ents.insert((d, t), if p != 0 { vec![p] } else { vec![] });
                combo_ent[id as usize] = (d, t);
                untagged += 1;
            }
            continue;
        }
        let listed = mesh.entities.get(&(d, g)).filter(|l| !l.is_empty());
        let home = match listed {
            Some(l) if list.iter().any(|&(p, _)| p == l[0]) => l[0],
            _ => first_phys.get(&(d, g)).copied().unwrap_or(0),
        };
        let tags = match listed {
            Some(l) if l.contains(&home) => {
                std::iter::once(home).chain(l.iter().copied().filter(|&p| p != home)).collect()
            }
            Some(l) => {
                report.drop(format!(
                    "{d}D entity {g}: its physical groups {l:?} do not include its cells' group {home}; written with group {home} only"
                ));
                if home != 0 {
                    vec![home]
                } else {
                    vec![]
                }
            }
            None if home != 0 => vec![home],
            None => vec![],
        };
        ents.insert((d, g), tags);
        let mut moved = Vec::new();
        for &(p, id) in list {
            if p == home {
                combo_ent[id as usize] = (d, g);
            } else {
                let t = free.alloc(d)?;
                ents.insert((d, t), if p != 0 { vec![p] } else { vec![] });
                combo_ent[id as usize] = (d, t);
                moved.push(format!("group {p} → entity {t}"));
            }
        }
        if !moved.is_empty() {
            report.drop(format!(
                "{d}D entity {g} holds cells of several physical groups; MSH 4.1 gives groups to entities, not cells, so those of the other groups are written as cells of new entities ({}), with another geometrical tag",
                moved.join(", ")
            ));
        }
    }
    if untagged > 0 {
        report.drop(format!(
            "cells without a positive geometrical tag written as cells of {untagged} new entities (Gmsh entity tags are strictly positive)"
        ));
    }
    // Entities without cells keep their groups.
    for (&(d, t), list) in &mesh.entities {
        if d > 3 || t <= 0 {
            report.drop(format!(
                "entity ({d}, {t}): Gmsh entities have a dimension 0 to 3 and a positive tag"
            ));
        } else {
            ents.entry((d, t)).or_insert_with(|| list.clone());
        }
    }
    // Nodes with no cell need an entity to be written in.
    let host_key = if mesh.num_cells() == 0 && !mesh.points.is_empty() {
        let key = (2, free.alloc(2)?);
        ents.insert(key, Vec::new());
        Some(key)
    } else {
        None
    };
    Ok((ents, combo_ent, host_key))
}

/// 5. Element blocks by (entity, kind): a counting sort of the runs (stable, so the
///    cells of a block keep the mesh's order).
#[allow(clippy::type_complexity)]
fn element_blocks(
    mesh: &TaggedMesh,
    n_ents: usize,
    combo_idx: &[u32],
    cell_runs: Vec<(Run, u32)>,
) -> (Vec<(u32, CellKind, std::ops::Range<usize>)>, Vec<Run>) {
    let nk = CellKind::ALL.len();
    let mut counts = vec![0usize; n_ents * nk + 1];
    let run_key = |&(run, id): &(Run, u32)| {
        combo_idx[id as usize] as usize * nk + kind_index(mesh.blocks[run.block as usize].kind)
    };
    for cr in &cell_runs {
        counts[run_key(cr) + 1] += 1;
    }
    for i in 1..counts.len() {
        counts[i] += counts[i - 1];
    }
    let mut runs = vec![Run { block: 0, start: 0, len: 0 }; cell_runs.len()];
    {
        let mut fill = counts.clone();
        for cr in &cell_runs {
            let key = run_key(cr);
            runs[fill[key]] = cr.0;
            fill[key] += 1;
        }
    }
    drop(cell_runs);
    let mut groups = Vec::new();
    for key in 0..n_ents * nk {
        if counts[key + 1] > counts[key] {
            groups.push(((key / nk) as u32, CellKind::ALL[key % nk], counts[key]..counts[key + 1]));
        }
    }
    (groups, runs)
}

/// 6. Each node on the first (lowest-dimensional) entity that uses it, and the
///    entities' bounding boxes; nodes no cell uses on `host` (the entity made for them),
///    else on the first entity of the highest dimension with cells.
fn node_entities(
    mesh: &TaggedMesh,
    ents: &mut [Ent],
    groups: &[(u32, CellKind, std::ops::Range<usize>)],
    runs: &[Run],
    host: Option<u32>,
) -> Vec<u32> {
    let mut node_ent = vec![UNSET; mesh.points.len()];
    for (e, kind, range) in groups {
        let ent = &mut ents[*e as usize];
        for run in &runs[range.clone()] {
            let b = &mesh.blocks[run.block as usize];
            let k = b.kind.nodes_per_cell();
            let (s, n) = (run.start as usize, run.len as usize);
            for &v in &b.nodes[s * k..(s + n) * k] {
                let v = v as usize;
                // A node first met in this entity has grown its box already: a triangle
                // mesh shares each node among about six cells, so most grows are skipped.
                if node_ent[v] == UNSET {
                    node_ent[v] = *e;
                    ent.grow(&mesh.points[v]);
                } else if node_ent[v] != *e {
                    ent.grow(&mesh.points[v]);
                }
                if *kind == CellKind::Vertex && ent.point.is_none() {
                    ent.point = Some(v);
                }
            }
        }
    }
    // Nodes no cell uses: on the first entity of the highest dimension with cells.
    let host = match host {
        Some(h) => Some(h),
        None => groups
            .iter()
            .map(|g| g.0)
            .max_by_key(|&e| (ents[e as usize].dim, std::cmp::Reverse(ents[e as usize].tag))),
    };
    if let Some(h) = host {
        for (v, e) in node_ent.iter_mut().enumerate() {
            if *e == UNSET {
                *e = h;
                ents[h as usize].grow(&mesh.points[v]);
            }
        }
    }
    node_ent
}

/// The boxes the mesh was read with ([`TaggedMesh::entity_boxes`]) where they hold the
/// box of the entity's nodes (or the entity has none): a box from Gmsh's model round
/// trips as read; a box its nodes have left (a moved or remeshed mesh) is computed.
fn given_boxes(mesh: &TaggedMesh, ents: &mut [Ent]) {
    if mesh.entity_boxes.is_empty() {
        return;
    }
    for e in ents.iter_mut() {
        let Some(b) = mesh.entity_boxes.get(&(e.dim, e.tag)) else { continue };
        let (lo, hi) = ([b[0], b[1], b[2]], [b[3], b[4], b[5]]);
        let finite = b.iter().all(|x| x.is_finite()) && (0..3).all(|k| lo[k] <= hi[k]);
        // A point entity is where its node is; its given point serves one without.
        let holds = if e.dim == 0 {
            !e.has_box
        } else {
            !e.has_box || (0..3).all(|k| lo[k] <= e.lo[k] && e.hi[k] <= hi[k])
        };
        if finite && holds {
            e.lo = lo;
            e.hi = hi;
            e.has_box = true;
        }
    }
}

/// 7. Node blocks: a counting sort of the nodes by entity.
#[allow(clippy::type_complexity)]
fn node_blocks(n_ents: usize, node_ent: &[u32]) -> (Vec<(u32, std::ops::Range<usize>)>, Vec<u32>) {
    let mut ncounts = vec![0usize; n_ents + 1];
    for &e in node_ent {
        ncounts[e as usize + 1] += 1;
    }
    for i in 1..ncounts.len() {
        ncounts[i] += ncounts[i - 1];
    }
    let mut nodes = vec![0u32; node_ent.len()];
    let mut fill = ncounts.clone();
    for (v, &e) in node_ent.iter().enumerate() {
        nodes[fill[e as usize]] = v as u32;
        fill[e as usize] += 1;
    }
    let node_groups = (0..n_ents)
        .filter(|&e| ncounts[e + 1] > ncounts[e])
        .map(|e| (e as u32, ncounts[e]..ncounts[e + 1]))
        .collect();
    (node_groups, nodes)
}
