//! The mesh assembled from what was read: points in node-tag order, cells in
//! element-tag order (moved, not copied, where a whole block is in place), 4.1 physical
//! tags from the entities, and the views' arrays.

use super::reader::Reader;
use super::tags::TagList;
use super::untagged;
use super::views::ViewKind;
use crate::{DataArray, ErrorKind, NodeIndex, ReadReport, Result, TaggedMesh};

impl Reader<'_> {
    /// The node views of a data-only file: item t − 1 of each array is node tag t's
    /// value, NaN where the view gives none, up to the largest tag it gives.
    pub(super) fn finish_node_data(mut self) -> Result<super::NodeData> {
        let mut out = super::NodeData::default();
        for v in std::mem::take(&mut self.views) {
            if v.kind != ViewKind::Node {
                // Element views of a file without elements: only empty ones get here.
                continue;
            }
            let n = v.targets.iter().max().map_or(0, |t| t + 1);
            // Tags far beyond the entries must not make a huge array: at most about the
            // file's size in values, as for a mesh's views.
            let limit = self.c.full.len() + (1 << 20);
            if n.checked_mul(v.ncomp).map_or(true, |t| t > limit) {
                return Err(self.c.err_at(
                    v.at,
                    ErrorKind::ImplausibleCount {
                        what: format!(
                            "view `{}` ({} values for each node tag up to {n})",
                            v.name, v.ncomp
                        ),
                        count: (n as u64).saturating_mul(v.ncomp as u64),
                        limit: format!(
                            "more values than the file's {} bytes justify",
                            self.c.full.len()
                        ),
                    },
                ));
            }
            let k = v.ncomp;
            let array = if v.targets.is_identity() {
                DataArray::new(k, v.values)
            } else {
                let mut values = vec![f64::NAN; n * k];
                for (e, t) in v.targets.iter().enumerate() {
                    values[t * k..(t + 1) * k].copy_from_slice(&v.values[e * k..(e + 1) * k]);
                }
                DataArray::new(k, values)
            };
            out.entries.insert(v.name.clone(), v.targets.len());
            out.arrays.insert(v.name, array);
        }
        Ok(out)
    }

    /// Puts points in node-tag order and cells in element-tag order, resolves 4.1
    /// physical tags and builds the data arrays.
    pub(super) fn finish(mut self) -> Result<(TaggedMesh, ReadReport)> {
        let mut mesh = TaggedMesh::new();
        mesh.tag_names = std::mem::take(&mut self.tag_names);

        // Points in ascending node-tag order; `node_rank[file position]` is the index.
        let node_rank: Option<Vec<usize>> = if self.node_tags.strictly_ascending() {
            mesh.points = std::mem::take(&mut self.points);
            None
        } else {
            let mut runs = Vec::new();
            runs_of(self.node_tags.iter(), 0, &mut runs);
            let runs = sorted_runs(runs).map_err(|dup| self.duplicate_node(dup))?;
            let mut rank = vec![0; self.points.len()];
            mesh.points.reserve(self.points.len());
            for &(_, pos, len) in &runs {
                for (j, r) in rank[pos..pos + len].iter_mut().enumerate() {
                    *r = mesh.points.len() + j;
                }
                mesh.points.extend_from_slice(&self.points[pos..pos + len]);
            }
            Some(rank)
        };

        // Physical tags of 4.1 blocks: the first physical tag of the entity; the cells
        // of a partitioned entity take its own and, as geometrical tag, its parent's.
        for b in &mut self.raw {
            if let Some(e) = b.entity {
                let p = match self.partitioned.get(&e) {
                    Some((parent, phys)) => {
                        b.geometrical.fill(*parent);
                        phys.first()
                    }
                    None => self.entities.get(&e).and_then(|v| v.first()),
                };
                b.physical = vec![p.copied().unwrap_or(0); b.tags.len()];
            }
            if let Some(rank) = &node_rank {
                for v in &mut b.nodes {
                    *v = rank[*v as usize] as NodeIndex;
                }
            }
        }

        // Cells in ascending element-tag order; `cell_rank[raw id]` is the index.
        let ascending =
            self.raw.iter().try_fold(0u64, |prev, b| b.tags.ascending_after(prev)).is_some();
        let cell_rank: Option<Vec<usize>> = if ascending {
            for b in std::mem::take(&mut self.raw) {
                match mesh.blocks.last_mut() {
                    Some(last) if last.kind == b.kind => {
                        last.nodes.extend_from_slice(&b.nodes);
                        last.physical.extend_from_slice(&b.physical);
                        last.geometrical.extend_from_slice(&b.geometrical);
                    }
                    _ => mesh.blocks.push(crate::CellBlock {
                        kind: b.kind,
                        nodes: b.nodes,
                        physical: b.physical,
                        geometrical: b.geometrical,
                    }),
                }
            }
            None
        } else {
            // Runs of consecutive tags within each block, put in tag order and copied.
            let mut runs = Vec::new();
            let mut starts = Vec::with_capacity(self.raw.len());
            let mut id = 0;
            for b in &self.raw {
                starts.push(id);
                match &b.tags {
                    TagList::Range { first, len } if *len > 0 => runs.push((*first, id, *len)),
                    TagList::Range { .. } => {}
                    TagList::List(v) => runs_of(v.iter().copied(), id, &mut runs),
                }
                id += b.tags.len();
            }
            let runs = sorted_runs(runs).map_err(|dup| self.duplicate_element(dup))?;
            // The rank of each cell is needed only to place element data.
            let mut rank = if self.views.iter().any(|v| v.kind != ViewKind::Node) {
                vec![0; id]
            } else {
                Vec::new()
            };
            let mut out = 0;
            for &(_, id, len) in &runs {
                let bi = starts.partition_point(|&s| s <= id) - 1;
                let b = &mut self.raw[bi];
                let (i, k) = (id - starts[bi], b.kind.nodes_per_cell());
                if i == 0
                    && len == b.tags.len()
                    && mesh.blocks.last().map(|l| l.kind) != Some(b.kind)
                {
                    // A whole block in place: moved, not copied.
                    let (nodes, physical, geometrical) = (
                        std::mem::take(&mut b.nodes),
                        std::mem::take(&mut b.physical),
                        std::mem::take(&mut b.geometrical),
                    );
                    mesh.blocks.push(crate::CellBlock {
                        kind: b.kind,
                        nodes,
                        physical,
                        geometrical,
                    });
                } else {
                    let dst = mesh.block_mut(b.kind);
                    dst.nodes.extend_from_slice(&b.nodes[i * k..(i + len) * k]);
                    dst.physical.extend_from_slice(&b.physical[i..i + len]);
                    dst.geometrical.extend_from_slice(&b.geometrical[i..i + len]);
                }
                if let Some(r) = rank.get_mut(id..id + len) {
                    for (j, r) in r.iter_mut().enumerate() {
                        *r = out + j;
                    }
                }
                out += len;
            }
            Some(rank)
        };

        // Data views.
        let n_points = mesh.points.len();
        let n_cells = mesh.num_cells();
        let mut partial = Vec::new();
        for v in std::mem::take(&mut self.views) {
            let (rank, n) = match v.kind {
                ViewKind::Node => (&node_rank, n_points),
                _ => (&cell_rank, n_cells),
            };
            let place = |t: usize| rank.as_ref().map_or(t, |r| r[t]);
            let width = if v.kind == ViewKind::ElementNode {
                v.offsets.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(v.ncomp)
            } else {
                v.ncomp
            };
            // A view covering few items with many components must not make the array
            // of every item huge: at most about the file's size in values.
            let limit = self.c.full.len() + (1 << 20);
            if n.checked_mul(width).map_or(true, |t| t > limit) {
                return Err(self.c.err_at(
                    v.at,
                    ErrorKind::ImplausibleCount {
                        what: format!("view `{}` ({width} values for each of {n} items)", v.name),
                        count: (n as u64).saturating_mul(width as u64),
                        limit: format!(
                            "more values than the file's {} bytes justify",
                            self.c.full.len()
                        ),
                    },
                ));
            }
            let array = if v.kind == ViewKind::ElementNode {
                let mut values = vec![f64::NAN; n * width];
                for (e, t) in v.targets.iter().enumerate() {
                    let src = &v.values[v.offsets[e]..v.offsets[e + 1]];
                    let dst = place(t) * width;
                    values[dst..dst + src.len()].copy_from_slice(src);
                    values[dst + src.len()..dst + width].fill(f64::NAN);
                }
                DataArray::new(width, values)
            } else if rank.is_none() && v.targets.len() == n && v.targets.is_identity() {
                // One value per item in item order (what Gmsh and smartmesh write):
                // the values read are the array.
                DataArray::new(v.ncomp, v.values)
            } else {
                let k = v.ncomp;
                let mut values = vec![f64::NAN; n * k];
                for (e, t) in v.targets.iter().enumerate() {
                    let dst = place(t) * k;
                    values[dst..dst + k].copy_from_slice(&v.values[e * k..(e + 1) * k]);
                }
                DataArray::new(k, values)
            };
            // A view that covers part of the items is kept as it is: the others NaN,
            // which the report says (writers keep NaN; where the data is used, NaN is
            // refused there).
            let given = if v.targets.is_identity() && v.targets.len() == n {
                n
            } else {
                let mut seen = vec![false; n];
                v.targets.iter().for_each(|t| seen[place(t)] = true);
                seen.iter().filter(|&&s| s).count()
            };
            if given < n {
                let items = if v.kind == ViewKind::Node { "nodes" } else { "elements" };
                partial.push(format!(
                    "view `{}` gives values for {given} of {n} {items}; the others are NaN",
                    v.name
                ));
            }
            match v.kind {
                ViewKind::Node => mesh.point_data.insert(v.name, array),
                _ => mesh.cell_data.insert(v.name, array),
            };
        }
        mesh.entities = std::mem::take(&mut self.entities);
        mesh.entity_boxes = std::mem::take(&mut self.entity_boxes);
        // MSH always stores z; a mesh is 2D when every z is 0 (the convention of the
        // other readers).
        mesh.coordinate_dim = if mesh.points.iter().all(|p| p[2] == 0.0) { 2 } else { 3 };
        untagged::ungroup(&mut mesh);
        let mut report = ReadReport::default();
        report.notes.extend(partial);
        if self.partitions > 1 {
            report.note(format!(
                "{} partitions read as one mesh (which partition each cell was in is not kept)",
                self.partitions
            ));
        }
        Ok((mesh, report))
    }
}

/// Appends the maximal runs of consecutive tags `(first tag, first position, length)`
/// of `tags`, whose first is at position `pos0`.
fn runs_of(tags: impl Iterator<Item = u64>, pos0: usize, out: &mut Vec<(u64, usize, usize)>) {
    let start = out.len();
    for (i, t) in tags.enumerate() {
        if out.len() > start {
            if let Some(r) = out.last_mut() {
                if r.0.checked_add(r.2 as u64) == Some(t) {
                    r.2 += 1;
                    continue;
                }
            }
        }
        out.push((t, pos0 + i, 1));
    }
}

/// Runs in tag order; `Err(tag)` names a tag two runs share.
fn sorted_runs(
    mut runs: Vec<(u64, usize, usize)>,
) -> std::result::Result<Vec<(u64, usize, usize)>, u64> {
    runs.sort_unstable();
    match runs.windows(2).find(|w| w[0].0.saturating_add(w[0].2 as u64) > w[1].0) {
        Some(w) => Err(w[1].0),
        None => Ok(runs),
    }
}
