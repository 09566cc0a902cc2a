//! From the sections read (`read::Raw`) to a tagged mesh: points, cells rebuilt from
//! their faces, boundary faces as tagged surface (3D) or line (2D) cells.
//!
//! Conventions (the writer's, measured with `fluentMeshToFoam` + `checkMesh`): a
//! polygon's right-hand normal points into `c0`, so a face turned outward of `c0` is
//! reversed and one of `c1` kept; an edge `n0 → n1` keeps `c0` on its left, so it runs
//! counter-clockwise round `c0` and clockwise round `c1`.
//!
//! - 3D cells: their outward faces make a tetrahedron, hexahedron, prism or pyramid in
//!   Gmsh's order (`openfoam::cell_nodes`, which checks the faces make that cell);
//! - 2D cells: their counter-clockwise edges chained into a triangle or quad;
//! - a cell built inside out (its file follows the opposite right-hand rule) is
//!   reordered to a positive volume or area, its boundary faces turned with it, and a
//!   note says how many;
//! - tags: a cell's tag is its cell zone's id; a boundary face's its face zone's id;
//!   names from the `(45 ...)`/`(39 ...)` records;
//! - interior face zones (bc-type 2) named as Fluent names its default ones
//!   (`default-interior`, `interior`, `interior-N`) are dropped, said in the report, as
//!   are inner faces of a boundary zone; another named interior zone is an inner
//!   surface (the writer's tagged inner faces) and kept as tagged cells;
//! - periodic face pairs (`(18 ...)`): each pair's faces must lie in the section's
//!   periodic and shadow zones (else the read fails at the section's line); the zones
//!   are read as named boundary tags and a note gives the pair count, the pairing
//!   itself is not kept (a tagged mesh holds no face pairs).

use std::collections::BTreeMap;

use super::read::Raw;
use crate::{CellKind, Error, ErrorKind, ReadReport, Result, TaggedMesh};

fn bad(what: String) -> Error {
    Error::new(ErrorKind::Expected { expected: "a valid Fluent mesh".into(), found: what })
}

/// `e` placed at the header line of the section holding face `f` (0-based).
fn at_face(raw: &Raw, f: usize, mut e: Error) -> Error {
    let k = raw.face_lines.partition_point(|&(first, _)| first <= f);
    if k > 0 {
        e.at = Some(crate::Position::Line(raw.face_lines[k - 1].1));
    }
    e
}

/// The mesh of `raw`.
pub(super) fn build(raw: &Raw, report: &mut ReadReport) -> Result<TaggedMesh> {
    let dim = raw.dim.ok_or_else(|| bad("no dimension section `(2 ND)`".into()))?;
    let mut mesh = TaggedMesh { coordinate_dim: dim, ..TaggedMesh::default() };
    mesh.points = points(raw)?;
    let np = mesh.points.len() as u64;
    let names: BTreeMap<u32, &str> = raw.names.iter().map(|(id, _, n)| (*id, n.as_str())).collect();
    let mut name_tag = |mesh: &mut TaggedMesh, d: u8, zone: u32| {
        if let Some(n) = names.get(&zone) {
            mesh.tag_names.insert((d, zone as i32), n.to_string());
        }
    };
    if raw.face_start.is_empty() {
        // meshio's cells by nodes.
        for (zone, et, list) in &raw.node_cells {
            let kind = kind_of(*et, dim).ok_or_else(|| bad(format!("cell type {et}")))?;
            for cell in list.chunks(kind.nodes_per_cell()) {
                let nodes = nodes0(cell, np, "a cell")?;
                mesh.block_mut(kind).push(&nodes, *zone as i32, *zone as i32);
            }
            name_tag(&mut mesh, dim, *zone);
        }
        return Ok(mesh);
    }
    let nf = raw.c0.len();
    // Each cell at least 3 faces, each face at most two cells: at most 2 nf / 3 cells.
    let nc = raw.c0.iter().chain(&raw.c1).copied().max().unwrap_or(0);
    if nc > 2 * nf as u64 {
        return Err(bad(format!("a face refers to cell {nc}, more than {nf} faces can bound")));
    }
    let nc = nc as usize;
    let mut tag = vec![0i32; nc];
    for &(zone, first, n) in &raw.cell_zones {
        if first == 0 || (first - 1).saturating_add(n) > nc as u64 {
            return Err(bad(format!("cell zone {zone} spans cells past the {nc} the faces bound")));
        }
        tag[first as usize - 1..(first - 1 + n) as usize].fill(zone as i32);
        name_tag(&mut mesh, dim, zone);
    }
    let face = |f: usize| {
        &raw.face_nodes[if f == 0 { 0 } else { raw.face_start[f - 1] }..raw.face_start[f]]
    };
    // Each cell's faces: CSR.
    let mut count = vec![0usize; nc + 1];
    for f in 0..nf {
        for c in [raw.c0[f], raw.c1[f]] {
            if c > 0 {
                count[c as usize] += 1;
            }
        }
        if raw.c0[f] == 0 {
            return Err(at_face(raw, f, bad(format!("face {} has no cell c0", f + 1))));
        }
    }
    for i in 1..=nc {
        count[i] += count[i - 1];
    }
    let mut fill = count.clone();
    let mut of_cell = vec![(0usize, false); count[nc]];
    for f in 0..nf {
        for (c, is_c1) in [(raw.c0[f], false), (raw.c1[f], true)] {
            if c > 0 {
                let c = c as usize - 1;
                of_cell[fill[c]] = (f, is_c1);
                fill[c] += 1;
            }
        }
    }
    let mut fs: Vec<Vec<u32>> = Vec::new();
    let mut flipped = vec![false; nc];
    for c in 0..nc {
        fs.clear();
        for &(f, is_c1) in &of_cell[count[c]..count[c + 1]] {
            let mut p = nodes0(face(f), np, "a face").map_err(|e| at_face(raw, f, e))?;
            // Outward of c: 3D reverse for c0; 2D reverse for c1.
            if (dim == 3) != is_c1 {
                p.reverse();
            }
            fs.push(p);
        }
        let (kind, mut nodes) =
            if dim == 3 { crate::openfoam::cell_nodes(&fs) } else { polygon(&fs) }.map_err(
                |why| {
                    let f = of_cell.get(count[c]).map_or(0, |x| x.0);
                    at_face(
                        raw,
                        f,
                        bad(format!("cell {} (a cell of this face section): {why}", c + 1)),
                    )
                },
            )?;
        // A file following the other right-hand rule: the cell comes out inside out.
        if signed_measure(kind, &nodes, &mesh.points) < 0.0 {
            mirror(kind, &mut nodes);
            flipped[c] = true;
        }
        mesh.block_mut(kind).push(&nodes, tag[c], tag[c]);
    }
    let n = flipped.iter().filter(|&&f| f).count();
    if n > 0 {
        report.note(format!(
            "{n} cells whose faces follow the opposite right-hand rule: reordered to a \
             positive volume, their boundary faces turned outward"
        ));
    }
    boundary(raw, dim, np, &face, &flipped, &mut mesh, report, &mut name_tag)?;
    Ok(mesh)
}

/// Six times the volume (3D, by the divergence theorem over the faces fanned into
/// triangles) or twice the area (2D) of a cell in Gmsh's order: positive when the
/// order is right.
fn signed_measure(kind: CellKind, nodes: &[u32], points: &[[f64; 3]]) -> f64 {
    let o = points[nodes[0] as usize];
    let p = |v: u32| {
        let q = points[v as usize];
        [q[0] - o[0], q[1] - o[1], q[2] - o[2]]
    };
    if kind.dim() == 2 {
        let n = nodes.len();
        return (0..n)
            .map(|i| {
                let (a, b) = (p(nodes[i]), p(nodes[(i + 1) % n]));
                a[0] * b[1] - a[1] * b[0]
            })
            .sum();
    }
    let mut v = 0.0;
    for f in kind.faces() {
        let a = p(nodes[f[0]]);
        for k in 1..f.len() - 1 {
            let (b, c) = (p(nodes[f[k]]), p(nodes[f[k + 1]]));
            v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]);
        }
    }
    v
}

/// The same cell with the opposite orientation, in Gmsh's order.
fn mirror(kind: CellKind, nodes: &mut [u32]) {
    let order: &[usize] = match kind {
        CellKind::Tetra => &[0, 2, 1, 3],
        CellKind::Pyramid => &[0, 3, 2, 1, 4],
        CellKind::Wedge => &[0, 2, 1, 3, 5, 4],
        CellKind::Hexa => &[0, 3, 2, 1, 4, 7, 6, 5],
        _ => {
            nodes.reverse();
            return;
        }
    };
    let old = nodes.to_vec();
    for (slot, &k) in nodes.iter_mut().zip(order) {
        *slot = old[k];
    }
}

/// The boundary face zones as tagged cells one dimension down.
#[allow(clippy::too_many_arguments)]
fn boundary<'r>(
    raw: &'r Raw,
    dim: u8,
    np: u64,
    face: &dyn Fn(usize) -> &'r [u64],
    flipped: &[bool],
    mesh: &mut TaggedMesh,
    report: &mut ReadReport,
    name_tag: &mut dyn FnMut(&mut TaggedMesh, u8, u32),
) -> Result<()> {
    let bc: BTreeMap<u32, u64> = raw.face_zones.iter().copied().collect();
    let names: BTreeMap<u32, &str> = raw.names.iter().map(|(id, _, n)| (*id, n.as_str())).collect();
    // Inner faces are kept only in a named interior zone (an inner surface, as the
    // writer writes a tagged one), not in Fluent's default ones.
    let keep_inner = |zone: u32| {
        bc.get(&zone) == Some(&2) && names.get(&zone).is_some_and(|n| !default_interior(n))
    };
    let mut dropped: BTreeMap<u32, usize> = BTreeMap::new();
    let mut kept = std::collections::BTreeSet::new();
    for f in 0..raw.c0.len() {
        let zone = raw.face_zone[f];
        let inner = bc.get(&zone) == Some(&2) || raw.c1[f] != 0;
        if inner && !keep_inner(zone) {
            *dropped.entry(zone).or_default() += 1;
            continue;
        }
        let mut p = nodes0(face(f), np, "a face").map_err(|e| at_face(raw, f, e))?;
        // Outward of c0: reversed in 3D, unless c0 was built from the other rule.
        let c0_flipped = flipped.get(raw.c0[f] as usize - 1).copied().unwrap_or(false);
        if (dim == 3) != c0_flipped {
            p.reverse();
        }
        let kind = match p.len() {
            2 => CellKind::Line,
            3 => CellKind::Triangle,
            4 => CellKind::Quad,
            n => {
                let e = bad(format!("boundary face {} has {n} nodes", f + 1));
                return Err(at_face(raw, f, e));
            }
        };
        mesh.block_mut(kind).push(&p, zone as i32, zone as i32);
        kept.insert(zone);
    }
    for zone in kept {
        name_tag(mesh, dim - 1, zone);
    }
    for (zone, n) in dropped {
        let name = raw.names.iter().find(|z| z.0 == zone).map_or("", |z| z.2.as_str());
        report.note(format!("face zone {zone} `{name}`: {n} inner faces dropped"));
    }
    Ok(())
}

/// Checks each periodic face-pair section against the faces' zones and notes it.
pub(super) fn check_periodic(raw: &Raw, report: &mut ReadReport) -> Result<()> {
    let name = |z: u32| raw.names.iter().find(|n| n.0 == z).map_or("", |n| n.2.as_str());
    for (line, pz, sz, pairs) in &raw.periodic {
        let at = |why: String| {
            let mut e = bad(why);
            e.at = Some(crate::Position::Line(*line));
            e
        };
        for &(f, s) in pairs {
            for (face, zone) in [(f, *pz), (s, *sz)] {
                let got = usize::try_from(face)
                    .ok()
                    .and_then(|i| i.checked_sub(1))
                    .and_then(|i| raw.face_zone.get(i));
                if got != Some(&zone) {
                    return Err(at(format!(
                        "periodic face pair ({f:x}, {s:x}): face {face:x} is not in zone {zone}"
                    )));
                }
            }
        }
        report.note(format!(
            "periodic zones {pz} `{}` and {sz} `{}`: {} face pairs (read as named boundary \
             tags; the pairing is not kept)",
            name(*pz),
            name(*sz),
            pairs.len()
        ));
    }
    Ok(())
}

/// Fluent's names for the inner faces of a mesh: `default-interior`, `interior`,
/// `interior-N` (with any suffix after `default-interior`).
fn default_interior(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    n.starts_with("default-interior")
        || n == "interior"
        || n.strip_prefix("interior-").is_some_and(|d| d.bytes().all(|c| c.is_ascii_digit()))
}

/// The points, node zones put in id order; ids must run 1..=N without a gap.
fn points(raw: &Raw) -> Result<Vec<[f64; 3]>> {
    let mut zones: Vec<&(u64, Vec<f64>, usize)> = raw.nodes.iter().collect();
    zones.sort_by_key(|z| z.0);
    let mut pts = Vec::new();
    for (first, xs, nd) in zones {
        // meshio numbers from 1 too; a gap or an overlap is refused.
        if *first != pts.len() as u64 + 1 {
            return Err(bad(format!(
                "node zone starting at {first:x} after {} nodes (ids must run 1, 2, …)",
                pts.len()
            )));
        }
        pts.extend(xs.chunks(*nd).map(|x| [x[0], x[1], if *nd == 3 { x[2] } else { 0.0 }]));
    }
    if pts.len() > crate::MAX_POINTS {
        return Err(bad(format!("{} nodes", pts.len())));
    }
    Ok(pts)
}

/// 1-based node ids to 0-based, each checked.
fn nodes0(ids: &[u64], np: u64, what: &str) -> Result<Vec<u32>> {
    ids.iter()
        .map(|&v| {
            if v == 0 || v > np {
                Err(Error::new(ErrorKind::IndexOutOfRange {
                    what: format!("{what} (1-based node ids)"),
                    index: v as i64,
                    available: np as usize,
                }))
            } else {
                Ok(v as u32 - 1)
            }
        })
        .collect()
}

fn kind_of(et: u64, dim: u8) -> Option<CellKind> {
    Some(match (et, dim) {
        (1, _) => CellKind::Triangle,
        (2, 3) => CellKind::Tetra,
        (3, _) => CellKind::Quad,
        (4, 3) => CellKind::Hexa,
        (5, 3) => CellKind::Pyramid,
        (6, 3) => CellKind::Wedge,
        _ => return None,
    })
}

/// A 2D cell from its counter-clockwise edges, chained from the first.
fn polygon(fs: &[Vec<u32>]) -> std::result::Result<(CellKind, Vec<u32>), String> {
    let kind = match fs.len() {
        3 => CellKind::Triangle,
        4 => CellKind::Quad,
        n => return Err(format!("{n} edges: not a triangle or quadrilateral")),
    };
    if fs.iter().any(|e| e.len() != 2) {
        return Err("a 2D face with other than 2 nodes".into());
    }
    let mut nodes = vec![fs[0][0]];
    let mut at = fs[0][1];
    while nodes.len() < fs.len() {
        if nodes.contains(&at) {
            return Err("its edges do not close into one polygon".into());
        }
        nodes.push(at);
        at = fs.iter().find(|e| e[0] == at).map(|e| e[1]).ok_or("its edges do not chain")?;
    }
    if at != nodes[0] {
        return Err("its edges do not close into one polygon".into());
    }
    Ok((kind, nodes))
}
