//! A 2D mesh extruded one cell thick into an OpenFOAM polyMesh: points, faces with
//! owner and neighbour, and patches, in the order OpenFOAM requires.
//!
//! Invariants of the result (what `checkMesh` checks):
//! - every cell is a 2D cell (triangle or quad) made counter-clockwise seen from +z,
//!   then extruded from z = 0 to z = `dz`: a prism or a hexahedron;
//! - the first `n_internal` faces are the internal ones, sorted by owner then
//!   neighbour (upper-triangular order), with owner < neighbour and their normal
//!   (right-hand rule on the point order) pointing from owner to neighbour;
//! - then each patch's faces, contiguous, in patch order, each pointing out of the
//!   domain: the boundary curves first (by tag), then `front` (z = dz) and `back`
//!   (z = 0);
//! - every point is used: points no 2D cell uses are left out;
//! - a wedge ([`Layer::Wedge`]) turns the points about the x axis instead of lifting
//!   them, keeps one point where a point lies on the axis, and leaves out the faces that
//!   collapse there (so a cell on the axis is a tetrahedron or a pyramid).

use std::collections::BTreeMap;

use crate::{CellKind, TaggedMesh, WriteReport};

/// One patch: its name, its OpenFOAM type, and how many faces it has.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// The patch name (an OpenFOAM word).
    pub name: String,
    /// `patch`, `wall`, `empty`, …
    pub kind: String,
    /// Number of faces (they follow the previous patch's).
    pub n_faces: usize,
    /// More entries of its `boundary` dictionary, in order (a `cyclic` patch's
    /// `neighbourPatch` and transform).
    pub entries: Vec<(String, String)>,
}

/// The extruded mesh.
#[derive(Debug, Clone, Default)]
pub struct PolyMesh {
    /// Points, the bottom layer (z = 0) then the top one (z = dz).
    pub points: Vec<[f64; 3]>,
    /// Faces as point lists (3 or 4 points).
    pub faces: Vec<Vec<u32>>,
    /// The owner cell of every face.
    pub owner: Vec<u32>,
    /// The neighbour of each internal face.
    pub neighbour: Vec<u32>,
    /// Number of cells.
    pub n_cells: usize,
    /// The patches, in the order their faces follow the internal ones.
    pub patches: Vec<Patch>,
    /// `cellZones`: each zone's name and cells (none written when empty).
    pub cell_zones: Vec<(String, Vec<u32>)>,
    /// `faceZones`: each zone's name and faces (none written when empty).
    pub face_zones: Vec<(String, Vec<u32>)>,
}

/// One edge of a 2D cell, as the cell runs through it counter-clockwise.
#[derive(Clone, Copy)]
struct Side {
    /// The edge's points, smaller first: the key edges are matched on.
    key: (u32, u32),
    cell: u32,
    /// The edge's points in the cell's counter-clockwise order.
    from: u32,
    to: u32,
}

/// Why a mesh cannot be extruded.
pub type Refusal = String;

/// The one cell layer a 2D mesh becomes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Layer {
    /// From z = 0 to z = dz; `front` and `back` are `empty`.
    Slab(f64),
    /// An axisymmetric wedge of this angle (degrees) about the x axis, from -angle/2
    /// (`back`) to +angle/2 (`front`), both `wedge` patches; the mesh lies in y >= 0,
    /// and its points on the axis (y = 0) are shared by both planes, so the faces there
    /// collapse and are left out.
    Wedge(f64),
}

/// Extrudes `mesh` by `dz`; `patch_name` gives the patch name and type of a line tag
/// (called once per tag, in increasing tag order). What is left out goes to `report`.
pub fn extrude(
    mesh: &TaggedMesh,
    dz: f64,
    patch_name: impl FnMut(i32, &mut WriteReport) -> (String, String),
    report: &mut WriteReport,
) -> Result<PolyMesh, Refusal> {
    extrude_layer(mesh, Layer::Slab(dz), patch_name, report)
}

/// [`extrude`] into a slab or a wedge.
pub fn extrude_layer(
    mesh: &TaggedMesh,
    layer: Layer,
    mut patch_name: impl FnMut(i32, &mut WriteReport) -> (String, String),
    report: &mut WriteReport,
) -> Result<PolyMesh, Refusal> {
    // The 2D cells, by their corners, counter-clockwise.
    let mut cells: Vec<Vec<u32>> = Vec::new();
    let mut flipped = 0usize;
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 2) {
        let corners = match b.kind {
            CellKind::Triangle | CellKind::Triangle6 => 3,
            _ => 4,
        };
        for c in b.cells() {
            let mut c = c[..corners].to_vec();
            let area = signed_area(mesh, &c);
            if area == 0.0 || !area.is_finite() {
                return Err(format!(
                    "2D cell {} has zero area: an extruded cell would have no volume",
                    cells.len()
                ));
            }
            if area < 0.0 {
                c.reverse();
                flipped += 1;
            }
            cells.push(c);
        }
    }
    if cells.is_empty() {
        return Err("it has no triangle or quad to extrude into cells".into());
    }
    if cells.len() >= u32::MAX as usize / 2 {
        return Err("more cells than OpenFOAM's 32-bit labels address".into());
    }
    if flipped > 0 {
        report.drop(format!(
            "{flipped} clockwise 2D cells written as counter-clockwise prisms or hexahedra (OpenFOAM cells are oriented)"
        ));
    }

    // Points: those the cells use, in mesh order.
    let mut new_of = vec![u32::MAX; mesh.points.len()];
    let mut bottom: Vec<usize> = Vec::new();
    for c in &cells {
        for &v in c {
            if new_of[v as usize] == u32::MAX {
                new_of[v as usize] = 0;
            }
        }
    }
    for (i, slot) in new_of.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = bottom.len() as u32;
            bottom.push(i);
        }
    }
    let unused = mesh.points.len() - bottom.len();
    if unused > 0 {
        report.drop(format!(
            "{unused} points no triangle or quad uses: OpenFOAM's checkMesh refuses unused points"
        ));
    }
    let mut points = Vec::with_capacity(2 * bottom.len());
    // `top[v]`: the point above bottom point v (itself on a wedge's axis).
    let mut top: Vec<u32> = Vec::with_capacity(bottom.len());
    match layer {
        Layer::Slab(dz) => {
            points.extend(bottom.iter().map(|&i| [mesh.points[i][0], mesh.points[i][1], 0.0]));
            for &i in &bottom {
                top.push(points.len() as u32);
                points.push([mesh.points[i][0], mesh.points[i][1], dz]);
            }
        }
        Layer::Wedge(angle) => {
            if !(angle > 0.0 && angle < 180.0) {
                return Err(format!(
                    "a wedge angle of {angle} degrees (expected between 0 and 180)"
                ));
            }
            if let Some(&i) = bottom.iter().find(|&&i| mesh.points[i][1] < 0.0) {
                return Err(format!(
                    "point {i} has y < 0: an axisymmetric wedge turns the half plane y >= 0 about the x axis"
                ));
            }
            let (s, c) = (angle.to_radians() / 2.0).sin_cos();
            let at = |i: usize, sign: f64| {
                let [x, y, _] = mesh.points[i];
                [x, y * c, sign * y * s]
            };
            points.extend(bottom.iter().map(|&i| at(i, -1.0)));
            for (v, &i) in bottom.iter().enumerate() {
                if mesh.points[i][1] == 0.0 {
                    top.push(v as u32);
                } else {
                    top.push(points.len() as u32);
                    points.push(at(i, 1.0));
                }
            }
        }
    }
    let empty_kind = if matches!(layer, Layer::Wedge(_)) { "wedge" } else { "empty" };
    for c in &mut cells {
        for v in c.iter_mut() {
            *v = new_of[*v as usize];
        }
    }

    // Sides matched by their key; sorting makes the order independent of any hash.
    let mut sides: Vec<Side> = Vec::with_capacity(4 * cells.len());
    for (ci, c) in cells.iter().enumerate() {
        for k in 0..c.len() {
            let (a, b) = (c[k], c[(k + 1) % c.len()]);
            sides.push(Side { key: (a.min(b), a.max(b)), cell: ci as u32, from: a, to: b });
        }
    }
    sides.sort_by_key(|s| (s.key, s.cell));

    // Line cells: the patch tag of each boundary edge (first tag wins).
    let mut line_tag: BTreeMap<(u32, u32), i32> = BTreeMap::new();
    let mut off_mesh = 0usize;
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 1) {
        for (i, c) in b.cells().enumerate() {
            let (a, z) = (new_of[c[0] as usize], new_of[c[1] as usize]);
            if a == u32::MAX || z == u32::MAX {
                off_mesh += 1;
                continue;
            }
            line_tag.entry((a.min(z), a.max(z))).or_insert(b.physical[i]);
        }
    }

    let mut internal: Vec<(u32, u32, [u32; 2])> = Vec::new();
    let mut boundary: BTreeMap<Option<i32>, Vec<(u32, [u32; 2])>> = BTreeMap::new();
    let mut inner_lines = 0usize;
    let mut i = 0;
    while i < sides.len() {
        let mut j = i + 1;
        while j < sides.len() && sides[j].key == sides[i].key {
            j += 1;
        }
        let tag = line_tag.remove(&sides[i].key);
        match j - i {
            1 => {
                let s = sides[i];
                boundary.entry(tag).or_default().push((s.cell, [s.from, s.to]));
            }
            2 => {
                let (s, t) = (sides[i], sides[i + 1]);
                if s.from == t.from {
                    return Err(format!(
                        "cells {} and {} run through their shared edge the same way: the mesh folds over itself",
                        s.cell, t.cell
                    ));
                }
                inner_lines += usize::from(tag.is_some());
                // `s` has the smaller cell: the owner, its edge direction outward of it.
                internal.push((s.cell, t.cell, [s.from, s.to]));
            }
            n => {
                return Err(format!(
                    "the edge between points {} and {} is shared by {n} cells: the mesh is not conforming",
                    bottom[sides[i].key.0 as usize], bottom[sides[i].key.1 as usize]
                ))
            }
        }
        i = j;
    }
    off_mesh += line_tag.len();
    if off_mesh > 0 {
        report
            .drop(format!("{off_mesh} line cells on no cell's edge: a patch holds faces of cells"));
    }
    if inner_lines > 0 {
        report.drop(format!(
            "{inner_lines} line cells inside the domain: OpenFOAM patches are on the boundary (faceZones are not written)"
        ));
    }
    internal.sort_by_key(|&(o, n, _)| (o, n));

    // [a, b, b', a'] with the points a wedge's axis shares left once; `None` when the
    // face collapses to the axis.
    let side_face = |[a, b]: [u32; 2]| -> Option<Vec<u32>> {
        let mut f = vec![a, b];
        if top[b as usize] != b {
            f.push(top[b as usize]);
        }
        if top[a as usize] != a {
            f.push(top[a as usize]);
        }
        (f.len() >= 3).then_some(f)
    };
    let mut poly = PolyMesh { points, n_cells: cells.len(), ..PolyMesh::default() };
    for &(o, n, e) in &internal {
        let Some(f) = side_face(e) else {
            return Err("an inner edge lies on the wedge's axis".into());
        };
        poly.faces.push(f);
        poly.owner.push(o);
        poly.neighbour.push(n);
    }
    let mut on_axis = 0usize;
    let mut used_names: BTreeMap<String, ()> = BTreeMap::new();
    let reserved = ["front", "back"];
    for (tag, mut faces) in boundary {
        let (mut name, kind) = match tag {
            Some(t) => patch_name(t, report),
            None => {
                report.drop(format!(
                    "{} boundary edges without a line cell written as the patch `defaultFaces`",
                    faces.len()
                ));
                ("defaultFaces".to_string(), "patch".to_string())
            }
        };
        if reserved.contains(&name.as_str()) || used_names.contains_key(&name) {
            let unique = format!("{name}_{}", poly.patches.len());
            report.drop(format!(
                "patch name `{name}` is taken (by another tag or the empty `front`/`back`): written as `{unique}`"
            ));
            name = unique;
        }
        used_names.insert(name.clone(), ());
        faces.sort_by_key(|&(c, e)| (c, e));
        let mut n_faces = 0;
        for &(c, e) in &faces {
            match side_face(e) {
                Some(f) => {
                    poly.faces.push(f);
                    poly.owner.push(c);
                    n_faces += 1;
                }
                None => on_axis += 1,
            }
        }
        if n_faces > 0 {
            poly.patches.push(Patch { name, kind, n_faces, entries: Vec::new() });
        }
    }
    // Front (z = dz): counter-clockwise from +z, the outward normal. Back (z = 0):
    // reversed.
    for (ci, c) in cells.iter().enumerate() {
        poly.faces.push(c.iter().map(|&v| top[v as usize]).collect());
        poly.owner.push(ci as u32);
    }
    if on_axis > 0 {
        report.drop(format!(
            "{on_axis} boundary edges on the wedge's axis: their faces collapse, so they are in no patch"
        ));
    }
    poly.patches.push(Patch {
        name: "front".into(),
        kind: empty_kind.into(),
        n_faces: cells.len(),
        entries: Vec::new(),
    });
    for (ci, c) in cells.iter().enumerate() {
        poly.faces.push(std::iter::once(c[0]).chain(c[1..].iter().rev().copied()).collect());
        poly.owner.push(ci as u32);
    }
    poly.patches.push(Patch {
        name: "back".into(),
        kind: empty_kind.into(),
        n_faces: cells.len(),
        entries: Vec::new(),
    });
    Ok(poly)
}

/// Twice the signed area of a polygon of mesh points (positive counter-clockwise).
fn signed_area(mesh: &TaggedMesh, c: &[u32]) -> f64 {
    let mut s = 0.0;
    for k in 0..c.len() {
        let p = mesh.points[c[k] as usize];
        let q = mesh.points[c[(k + 1) % c.len()] as usize];
        s += p[0] * q[1] - q[0] * p[1];
    }
    s
}
