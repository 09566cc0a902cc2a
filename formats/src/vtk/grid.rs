//! What both readers produce, VTK's own layout ([`Grid`]), checked and turned into a
//! [`TaggedMesh`]: cells split or renumbered where VTK's types need it (`cells.rs`),
//! sorted into blocks, put into smartmesh's node order (`order.rs`), cell arrays into
//! tags and data.

use std::collections::BTreeMap;

use crate::error::Position;
use crate::{
    CellBlock, CellKind, DataArray, Error, ErrorKind, Layout, NodeIndex, ReadReport, Result,
    TaggedMesh,
};

use super::{cells, order, tag_slot, ENTITY_IDS};

/// A named array as read from a file, before it is sorted into tags and data.
#[derive(Debug)]
pub(crate) struct Named {
    pub name: String,
    /// Values per item as stored: 3 for a packed tensor.
    pub components: usize,
    pub values: Vec<f64>,
    pub layout: Layout,
    /// Where the array starts, for errors found when it is interpreted.
    pub at: Position,
}

impl Named {
    /// An array of `components` values per item in the file, laid out as `layout` says
    /// (a packed tensor keeps 3 of its 9).
    pub(crate) fn new(
        name: String,
        components: usize,
        values: Vec<f64>,
        layout: Layout,
        at: Position,
    ) -> Named {
        let components = if layout == Layout::Symmetric2 { 3 } else { components };
        Named { name, components, values, layout, at }
    }
}

/// What both readers produce: VTK's own layout, checked and turned into a
/// [`TaggedMesh`] by [`Grid::into_mesh`].
#[derive(Debug, Default)]
pub(crate) struct Grid {
    pub points: Vec<[f64; 3]>,
    /// VTK cell type of each cell.
    pub types: Vec<u8>,
    pub types_at: Option<Position>,
    /// `offsets[i]..offsets[i + 1]` is cell `i` in `connectivity`; `ncells + 1` entries.
    pub offsets: Vec<usize>,
    pub connectivity: Vec<NodeIndex>,
    pub cells_at: Option<Position>,
    pub point_arrays: Vec<Named>,
    pub cell_arrays: Vec<Named>,
    /// Cell tag arrays (`gmsh:physical`, `gmsh:geometrical`, `CellEntityIds`) of 32-bit
    /// integers, decoded straight into tags by a reader that can (no `f64` copy of
    /// them); taken before `cell_arrays`, where the same names may also appear.
    pub cell_tags: Vec<(String, Vec<i32>, Position)>,
    /// Dataset-level field data (tag names).
    pub field_arrays: Vec<Named>,
}

fn at_error(at: Option<Position>, kind: ErrorKind) -> Error {
    Error { path: None, at, kind }
}

/// A VTK cell type's name, for messages about types smartmesh does not read.
fn vtk_type_name(t: u8) -> &'static str {
    match t {
        0 => "empty cell",
        1 => "vertex",
        2 => "poly-vertex",
        3 => "line",
        4 => "poly-line",
        5 => "triangle",
        6 => "triangle strip",
        7 => "polygon",
        8 => "pixel",
        9 => "quad",
        10 => "tetra",
        11 => "voxel",
        12 => "hexahedron",
        13 => "wedge",
        14 => "pyramid",
        15 => "pentagonal prism",
        16 => "hexagonal prism",
        21 => "quadratic edge",
        22 => "quadratic triangle",
        23 => "quadratic quad",
        24 => "quadratic tetra",
        25 => "quadratic hexahedron",
        26 => "quadratic wedge",
        27 => "quadratic pyramid",
        28 => "biquadratic quad",
        29 => "triquadratic hexahedron",
        30 => "quadratic-linear quad",
        31 => "quadratic-linear wedge",
        32 => "biquadratic-quadratic wedge",
        33 => "biquadratic-quadratic hexahedron",
        34 => "biquadratic triangle",
        35 => "cubic line",
        36 => "quadratic polygon",
        37 => "triquadratic pyramid",
        42 => "polyhedron",
        51 => "parametric curve",
        60..=62 => "higher-order cell",
        68..=74 => "Lagrange cell",
        75..=81 => "Bezier cell",
        _ => "unknown",
    }
}

/// The cell types the readers take, for messages about the others.
const READ_TYPES: &str = "vertex (1), poly-vertex (2), line (3), poly-line (4), triangle (5), triangle strip (6), polygon (7), pixel (8), quad (9), tetra (10), voxel (11), hexahedron (12), wedge (13), pyramid (14), and the quadratic edge (21), triangle (22), quad (23, 28), tetra (24), hexahedron (25, 29), wedge (26, 32) and pyramid (27)";

/// Converts a tag array value to `i32`, refusing fractions and overflow.
#[inline]
fn tag_value(v: f64) -> Option<i32> {
    // `as` saturates (and maps NaN to 0): the round trip fails for fractions,
    // out-of-range values and NaN alike.
    let t = v as i32;
    (t as f64 == v).then_some(t)
}

impl Grid {
    /// Checks cells against points and types, sorts cell arrays into tags and cell
    /// data, and names tags from the field data.
    pub(crate) fn into_mesh(mut self) -> Result<(TaggedMesh, ReadReport)> {
        let notes = cells::normalize(&mut self)?;
        let Grid {
            points,
            types,
            types_at,
            offsets,
            connectivity,
            cells_at,
            point_arrays,
            cell_arrays,
            cell_tags,
            field_arrays,
        } = self;
        let n = types.len();
        if offsets.len() != n + 1 {
            return Err(at_error(
                cells_at.or(types_at),
                ErrorKind::Inconsistent(format!(
                    "{} cells have types but {} have nodes",
                    n,
                    offsets.len().saturating_sub(1)
                )),
            ));
        }
        let np = points.len();
        let mut mesh = TaggedMesh::new();
        mesh.coordinate_dim = if points.iter().all(|p| p[2] == 0.0) { 2 } else { 3 };

        // Tags first, so that blocks are built in one pass.
        let mut tag_arrays: [Option<Vec<i32>>; 3] = [None, None, None];
        let mut cell_data = BTreeMap::new();
        for (name, tags, at) in cell_tags {
            if tags.len() != n {
                return Err(at_error(
                    Some(at),
                    ErrorKind::Inconsistent(format!(
                        "cell array `{name}` has {} values, expected {n} ({n} cells)",
                        tags.len()
                    )),
                ));
            }
            let slot = tag_slot(&name).expect("readers keep only tag names here");
            tag_arrays[slot] = Some(tags);
        }
        for a in cell_arrays {
            if a.values.len() != n * a.components {
                return Err(at_error(
                    Some(a.at),
                    ErrorKind::Inconsistent(format!(
                        "cell array `{}` has {} values, expected {} ({} cells)",
                        a.name,
                        a.values.len(),
                        n * a.components,
                        n
                    )),
                ));
            }
            match tag_slot(&a.name) {
                Some(s) if a.components == 1 => {
                    let mut tags = Vec::with_capacity(n);
                    for (i, &v) in a.values.iter().enumerate() {
                        let t = tag_value(v).ok_or_else(|| {
                            at_error(
                                Some(a.at),
                                ErrorKind::Expected {
                                    expected: format!(
                                        "an integer tag in `{}` for cell {i}",
                                        a.name
                                    ),
                                    found: v.to_string(),
                                },
                            )
                        })?;
                        tags.push(t);
                    }
                    tag_arrays[s] = Some(tags);
                }
                _ => {
                    cell_data.insert(
                        a.name,
                        DataArray {
                            components: a.components.max(1),
                            values: a.values,
                            layout: a.layout,
                        },
                    );
                }
            }
        }
        let [phys, geom, ids] = tag_arrays;
        // `CellEntityIds` stands for both tags only when neither Gmsh array is there;
        // otherwise it is ordinary cell data.
        let (phys, geom) = match (phys, geom, ids) {
            (None, None, Some(ids)) => (Some(ids.clone()), Some(ids)),
            (p, g, ids) => {
                if let Some(ids) = ids {
                    cell_data.insert(
                        ENTITY_IDS.to_string(),
                        DataArray::new(1, ids.into_iter().map(f64::from).collect()),
                    );
                }
                let g = g.or_else(|| p.clone());
                (p, g)
            }
        };
        let mut phys = phys.unwrap_or_else(|| vec![0; n]);
        let mut geom = geom.unwrap_or_else(|| phys.clone());

        // Every reader checks node indices where it reads them, so that the error names
        // the line or byte; `read_bytes` relies on it (and checks it in debug builds).
        debug_assert!(connectivity.iter().all(|&v| (v as usize) < np), "node index out of range");
        // Cells go to blocks a run of one kind at a time. The largest run keeps the
        // connectivity and tag buffers themselves (moved to their front once every
        // other run has been copied out), so that a triangle mesh with a few boundary
        // lines allocates no second connectivity array.
        let mut runs: Vec<(CellKind, usize, usize)> = Vec::new();
        let mut i = 0;
        while i < n {
            let t = types[i];
            let kind = CellKind::from_vtk_type(t).ok_or_else(|| {
                if t == 42 {
                    return at_error(
                        types_at,
                        ErrorKind::Unsupported(format!(
                            "cell {i} is a VTK polyhedron (type 42): smartmesh holds cells of fixed shapes; split the polyhedra into tetrahedra first (ParaView's Tetrahedralize filter)"
                        )),
                    );
                }
                at_error(
                    types_at,
                    ErrorKind::Unsupported(format!(
                        "cell {i} has VTK type {t} ({}); smartmesh reads {}",
                        vtk_type_name(t),
                        READ_TYPES
                    )),
                )
            })?;
            let k = kind.nodes_per_cell();
            let mut j = i;
            while j < n && types[j] == t {
                j += 1;
            }
            // Each cell of the run must span k nodes: one comparison per cell, and the
            // cell named only when one fails.
            if offsets[i..=j].windows(2).any(|w| w[1].wrapping_sub(w[0]) != k) {
                let c = i + offsets[i..=j]
                    .windows(2)
                    .position(|w| w[1].wrapping_sub(w[0]) != k)
                    .unwrap_or(0);
                let (a, b) = (offsets[c], offsets[c + 1]);
                return Err(at_error(
                    cells_at,
                    ErrorKind::Expected {
                        expected: format!("{k} nodes for cell {c} (a {})", kind.name()),
                        found: format!("{}", b as i128 - a as i128),
                    },
                ));
            }
            if offsets[j] > connectivity.len() {
                return Err(at_error(
                    cells_at,
                    ErrorKind::Inconsistent(format!(
                        "cells {i}..{j} end at node {}, past the connectivity",
                        offsets[j]
                    )),
                ));
            }
            match runs.last_mut() {
                // Two VTK types of one kind in a row make one block, as `block_mut` would.
                Some(last) if last.0 == kind => last.2 = j,
                _ => runs.push((kind, i, j)),
            }
            i = j;
        }
        let big = (0..runs.len())
            .max_by_key(|&r| (offsets[runs[r].2] - offsets[runs[r].1], std::cmp::Reverse(r)));
        mesh.blocks = runs
            .iter()
            .enumerate()
            .map(|(r, &(kind, i, j))| {
                let mut b = CellBlock::new(kind);
                if Some(r) != big {
                    b.nodes = connectivity[offsets[i]..offsets[j]].to_vec();
                    b.physical = phys[i..j].to_vec();
                    b.geometrical = geom[i..j].to_vec();
                }
                b
            })
            .collect();
        if let Some(r) = big {
            let (_, i, j) = runs[r];
            let (a, b) = (offsets[i], offsets[j]);
            let mut conn = connectivity;
            conn.copy_within(a..b, 0);
            conn.truncate(b - a);
            phys.copy_within(i..j, 0);
            phys.truncate(j - i);
            geom.copy_within(i..j, 0);
            geom.truncate(j - i);
            let block = &mut mesh.blocks[r];
            block.nodes = conn;
            block.physical = phys;
            block.geometrical = geom;
        }
        for b in &mut mesh.blocks {
            order::from_vtk(b.kind, &mut b.nodes);
        }

        for a in point_arrays {
            if a.values.len() != np * a.components {
                return Err(at_error(
                    Some(a.at),
                    ErrorKind::Inconsistent(format!(
                        "point array `{}` has {} values, expected {} ({} points)",
                        a.name,
                        a.values.len(),
                        np * a.components,
                        np
                    )),
                ));
            }
            mesh.point_data.insert(
                a.name,
                DataArray { components: a.components.max(1), values: a.values, layout: a.layout },
            );
        }
        mesh.cell_data = cell_data;

        // meshio's `field_data` for Gmsh names: `name -> [tag, dim]`.
        for a in field_arrays {
            if let [tag, dim] = a.values[..] {
                if let (Some(tag), Some(dim @ 0..=3)) = (tag_value(tag), tag_value(dim)) {
                    mesh.tag_names.insert((dim as u8, tag), a.name);
                }
            }
        }
        mesh.points = points;
        Ok((mesh, ReadReport { notes }))
    }
}
