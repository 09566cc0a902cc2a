//! Writing Triangle's file set (see the module documentation of `triangle` for which
//! files are written and what is reported as dropped).

use std::path::Path;

use crate::error::{Error, ErrorKind, Result};
use crate::text::{push_f64, push_int};
use crate::{CellKind, DataArray, RegionSeed, TaggedMesh, WriteOptions, WriteReport, Written};

use super::{attribute_name, Kind, AREA, ATTRIBUTE_PREFIX, MARKER, RAY_DIRECTION};

/// Scalar arrays `<prefix>1`, `<prefix>2`, ... present without a gap.
fn attribute_arrays(map: &std::collections::BTreeMap<String, DataArray>) -> Vec<&DataArray> {
    let mut out = Vec::new();
    while let Some(a) = map.get(&attribute_name(out.len() + 1)).filter(|a| a.components == 1) {
        out.push(a);
    }
    out
}

/// Integral values that fit in an `i32`, or `None`.
fn as_markers(a: &DataArray) -> Option<Vec<i32>> {
    if a.components != 1 {
        return None;
    }
    a.values
        .iter()
        .map(|&v| {
            (v.fract() == 0.0 && v >= i32::MIN as f64 && v <= i32::MAX as f64).then_some(v as i32)
        })
        .collect()
}

/// The vertex list: header and one vertex a line (shared by `.node` and a self-contained
/// `.poly`).
fn push_vertices(
    out: &mut Vec<u8>,
    mesh: &TaggedMesh,
    attrs: &[&DataArray],
    markers: Option<&[i32]>,
) {
    push_int(out, mesh.points.len());
    out.extend_from_slice(b" 2 ");
    push_int(out, attrs.len());
    out.extend_from_slice(if markers.is_some() { b" 1\n" } else { b" 0\n" });
    for (i, p) in mesh.points.iter().enumerate() {
        push_int(out, i + 1);
        out.push(b' ');
        push_f64(out, p[0]);
        out.push(b' ');
        push_f64(out, p[1]);
        for a in attrs {
            out.push(b' ');
            push_f64(out, a.values[i]);
        }
        if let Some(m) = markers {
            out.push(b' ');
            push_int(out, m[i]);
        }
        out.push(b'\n');
    }
}

/// The sections of a `.poly` after its vertex list.
fn push_poly_rest(
    out: &mut Vec<u8>,
    mesh: &TaggedMesh,
    nseg: usize,
    holes: &[[f64; 2]],
    regions: &[RegionSeed],
) {
    push_int(out, nseg);
    out.extend_from_slice(b" 1\n");
    let mut k = 0;
    for b in mesh.blocks.iter().filter(|b| b.kind == CellKind::Line) {
        for (cell, &tag) in b.cells().zip(&b.physical) {
            k += 1;
            push_int(out, k);
            out.push(b' ');
            push_int(out, cell[0] + 1);
            out.push(b' ');
            push_int(out, cell[1] + 1);
            out.push(b' ');
            push_int(out, tag);
            out.push(b'\n');
        }
    }
    push_int(out, holes.len());
    out.push(b'\n');
    for (i, h) in holes.iter().enumerate() {
        push_int(out, i + 1);
        out.push(b' ');
        push_f64(out, h[0]);
        out.push(b' ');
        push_f64(out, h[1]);
        out.push(b'\n');
    }
    // Triangle's own writer leaves the optional section out when it is empty.
    if !regions.is_empty() {
        push_int(out, regions.len());
        out.push(b'\n');
        for (i, r) in regions.iter().enumerate() {
            push_int(out, i + 1);
            for v in [r.point[0], r.point[1], r.attribute, r.max_area] {
                out.push(b' ');
                push_f64(out, v);
            }
            out.push(b'\n');
        }
    }
}

pub(super) fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    // Volume cells: refused, not dropped, since what would be left (their boundary, if
    // any) is not the mesh the user asked to convert.
    let volumes: Vec<String> = mesh
        .blocks
        .iter()
        .filter(|b| b.kind.dim() == 3 && !b.is_empty())
        .map(|b| format!("{} {} cells", b.len(), b.kind.name()))
        .collect();
    if !volumes.is_empty() {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: "Triangle",
            reason: format!(
                "the mesh has volume cells ({}): Triangle's files hold 2D triangulations; write a volume mesh to TetGen (`--to tetgen`, .node/.ele, or .smesh), Gmsh, VTK or Medit",
                volumes.join(", ")
            ),
        }));
    }
    let mut report = WriteReport::default();
    // Quads go as two triangles each (a skin of boundary-layer cells stays a mesh).
    let split;
    let mesh = if mesh.num_cells_of(CellKind::Quad) > 0 {
        let mut m = mesh.clone();
        let n = m.split_quads();
        report.drop(format!(
            "{n} quad cells: written as {} triangles (Triangle holds triangles only)",
            2 * n
        ));
        split = m;
        &split
    } else {
        mesh
    };
    let count = |k: CellKind| mesh.num_cells_of(k);
    let (ntri3, ntri6, nseg) =
        (count(CellKind::Triangle), count(CellKind::Triangle6), count(CellKind::Line));
    let ntri = ntri3 + ntri6;
    let pslg = nseg > 0 || !mesh.holes.is_empty() || !mesh.regions.is_empty();

    let main = match &opts.main_name {
        Some(name) => {
            let ext = Path::new(name).extension().and_then(|e| e.to_str()).unwrap_or("");
            Kind::from_ext(ext).ok_or_else(|| {
                Error::new(ErrorKind::CannotWrite {
                    format: "Triangle",
                    reason: format!("cannot tell which file of the set `{name}` is: name it .node, .ele, .poly, .edge or .area"),
                })
            })?
        }
        // stdout: one file when that is enough (a PSLG), else the .node and its siblings.
        None if ntri == 0 && pslg => Kind::Poly,
        None => Kind::Node,
    };

    // --- vertices
    let nz = mesh.points.iter().filter(|p| p[2] != 0.0).count();
    if nz > 0 {
        report.drop(format!("z coordinates of {nz} points: Triangle is two-dimensional"));
    }
    let markers = match mesh.point_data.get(MARKER) {
        Some(a) => {
            let m = as_markers(a);
            if m.is_none() {
                report.drop(format!(
                    "point data `{MARKER}`: not one integer per point, so not boundary markers"
                ));
            }
            m
        }
        None => None,
    };
    let pattrs = attribute_arrays(&mesh.point_data);
    for (name, a) in &mesh.point_data {
        let kept = (name == MARKER && markers.is_some())
            || name
                .strip_prefix(ATTRIBUTE_PREFIX)
                .and_then(|k| k.parse::<usize>().ok())
                .is_some_and(|k| k >= 1 && k <= pattrs.len());
        if !kept && name != MARKER {
            report.drop(format!(
                "point data `{name}` ({}): Triangle keeps only vertex markers (`{MARKER}`) and scalar attributes (`{ATTRIBUTE_PREFIX}1`, ...)",
                crate::words::components(a.expanded_components())
            ));
        }
    }

    // --- cells Triangle cannot hold
    // Volume cells too: a 3D mesh written as Triangle keeps its surface cells only.
    let lost = CellKind::ALL.into_iter().filter(|k| k.dim() == 3);
    for kind in [CellKind::Quad8, CellKind::Quad9, CellKind::Line3].into_iter().chain(lost) {
        let n = count(kind);
        if n > 0 {
            report.drop(format!(
                "{n} {} cells: Triangle holds triangles and segments only",
                kind.name()
            ));
        }
    }
    let nvert = count(CellKind::Vertex);
    let rays = match mesh.cell_data.get(RAY_DIRECTION) {
        Some(a) if a.components == 3 && !a.is_tensor() && main == Kind::Edge => Some(a),
        _ => None,
    };
    if nvert > 0 && rays.is_none() {
        let why = if main == Kind::Edge {
            format!("they are Voronoi rays only with cell data `{RAY_DIRECTION}`")
        } else {
            "Triangle has no point cells (Voronoi rays go to a .edge main file)".to_string()
        };
        report.drop(format!("{nvert} vertex cells: {why}"));
    }
    if ntri3 > 0 && ntri6 > 0 {
        report.drop(format!(
            "mid-edge nodes of {ntri6} triangle6 cells: a .ele holds one kind of triangle, they were written by their corners"
        ));
    }
    let tri_nodes = if ntri3 == 0 && ntri6 > 0 { 6 } else { 3 };

    // --- tags and cell data
    let tri_blocks = || {
        mesh.blocks.iter().filter(|b| matches!(b.kind, CellKind::Triangle | CellKind::Triangle6))
    };
    let use_tags = tri_blocks().any(|b| b.physical.iter().any(|&p| p != 0));
    let cattrs = attribute_arrays(&mesh.cell_data);
    let ncols = if use_tags { cattrs.len().max(1) } else { cattrs.len() };
    let mut offsets = Vec::with_capacity(mesh.blocks.len());
    let mut off = 0;
    for b in &mesh.blocks {
        offsets.push(off);
        off += b.len();
    }
    let mut geo_differs = [0usize; 2];
    let mut attr1_differs = 0;
    for (b, &off) in mesh.blocks.iter().zip(&offsets) {
        let slot = match b.kind {
            CellKind::Line => 0,
            CellKind::Triangle | CellKind::Triangle6 => 1,
            _ => continue,
        };
        for (i, (&p, &g)) in b.physical.iter().zip(&b.geometrical).enumerate() {
            if p != g {
                geo_differs[slot] += 1;
            }
            if slot == 1
                && use_tags
                && cattrs.first().is_some_and(|a| a.values[off + i] != p as f64)
            {
                attr1_differs += 1;
            }
        }
    }
    for (n, what) in geo_differs.iter().zip(["segments", "triangles"]) {
        if *n > 0 {
            report.drop(format!(
                "geometrical tags of {n} {what}: Triangle keeps one tag (the physical one, as {})",
                if what == "segments" { "boundary marker" } else { "first attribute" }
            ));
        }
    }
    if attr1_differs > 0 {
        report.drop(format!(
            "cell data `{ATTRIBUTE_PREFIX}1` of {attr1_differs} triangles: the physical tags were written as the first attribute instead"
        ));
    }
    let area = match mesh.cell_data.get(AREA) {
        Some(a) if a.components == 1 && ntri > 0 => Some(a),
        Some(_) => {
            report.drop(format!(
                "cell data `{AREA}`: {}",
                if ntri == 0 { "there are no triangles" } else { "not one scalar per cell" }
            ));
            None
        }
        None => None,
    };
    for (name, a) in &mesh.cell_data {
        let is_attr = name
            .strip_prefix(ATTRIBUTE_PREFIX)
            .and_then(|k| k.parse::<usize>().ok())
            .is_some_and(|k| k >= 1 && k <= cattrs.len());
        let kept =
            (is_attr && ntri > 0) || name == AREA || (name == RAY_DIRECTION && rays.is_some());
        // Ray directions without rays were reported with the vertex cells.
        if !(kept || name == RAY_DIRECTION && nvert > 0) {
            report.drop(format!(
                "cell data `{name}` ({}): Triangle keeps only triangle attributes (`{ATTRIBUTE_PREFIX}1`, ...) and area bounds (`{AREA}`)",
                crate::words::components(a.components)
            ));
        }
    }
    report_unheld(mesh, main, &mut report);

    // --- files
    let mut files: Vec<(Kind, Vec<u8>)> = Vec::new();
    if main == Kind::Poly && ntri == 0 {
        // A self-contained planar straight-line graph.
        let mut out =
            Vec::with_capacity(mesh.points.len() * (56 + 24 * pattrs.len()) + nseg * 40 + 64);
        push_vertices(&mut out, mesh, &pattrs, markers.as_deref());
        push_poly_rest(&mut out, mesh, nseg, &mesh.holes, &mesh.regions);
        files.push((Kind::Poly, out));
    } else {
        let mut node = Vec::with_capacity(mesh.points.len() * (56 + 24 * pattrs.len()) + 32);
        push_vertices(&mut node, mesh, &pattrs, markers.as_deref());
        files.push((Kind::Node, node));

        if ntri > 0 || main == Kind::Ele || main == Kind::Area {
            let cols = Columns { tri_nodes, ncols, use_tags, attrs: &cattrs };
            files.push((Kind::Ele, ele_file(mesh, &offsets, ntri, &cols)));
        }

        if main == Kind::Edge {
            files.push((Kind::Edge, edge_file(mesh, &offsets, nseg, nvert, rays)));
        } else if main == Kind::Poly || pslg {
            // The vertices are in the .node, as in the .poly files Triangle writes.
            let mut poly =
                Vec::with_capacity(nseg * 40 + (mesh.holes.len() + mesh.regions.len()) * 100 + 64);
            poly.extend_from_slice(b"0 2 ");
            push_int(&mut poly, pattrs.len());
            poly.extend_from_slice(if markers.is_some() { b" 1\n" } else { b" 0\n" });
            // A mesh that does not say where its holes and regions are (one read from
            // any format but Triangle) gets them from its triangles.
            let derived =
                (ntri > 0 && nseg > 0 && mesh.holes.is_empty() && mesh.regions.is_empty())
                    .then(|| super::seeds::derive(mesh));
            let (holes, regions) = match &derived {
                Some((h, r)) => (h.as_slice(), r.as_slice()),
                None => (mesh.holes.as_slice(), mesh.regions.as_slice()),
            };
            push_poly_rest(&mut poly, mesh, nseg, holes, regions);
            files.push((Kind::Poly, poly));
        }

        if area.is_some() || (main == Kind::Area) {
            files.push((Kind::Area, area_file(mesh, &offsets, ntri, area)));
        }
    }

    let mut written = Written { report, ..Default::default() };
    for (kind, bytes) in files {
        if kind == main {
            written.main = bytes;
        } else {
            written.siblings.push((kind.ext().to_string(), bytes));
        }
    }
    Ok(written)
}

/// What a `.ele` record holds besides its number.
struct Columns<'a> {
    /// 3 or 6.
    tri_nodes: usize,
    /// Attributes per triangle.
    ncols: usize,
    /// Whether the physical tag is the first attribute.
    use_tags: bool,
    /// The `triangle:attribute<k>` arrays.
    attrs: &'a [&'a DataArray],
}

/// The `.ele` file: `ntri` triangles (`offsets`: first global cell of each block).
fn ele_file(mesh: &TaggedMesh, offsets: &[usize], ntri: usize, c: &Columns<'_>) -> Vec<u8> {
    let (tri_nodes, ncols, use_tags, cattrs) = (c.tri_nodes, c.ncols, c.use_tags, c.attrs);
    let mut ele = Vec::with_capacity(ntri * (8 + 8 * tri_nodes + 24 * ncols) + 32);
    push_int(&mut ele, ntri);
    ele.push(b' ');
    push_int(&mut ele, tri_nodes);
    ele.push(b' ');
    push_int(&mut ele, ncols);
    ele.push(b'\n');
    let mut k = 0;
    for (b, &off) in mesh.blocks.iter().zip(offsets) {
        if !matches!(b.kind, CellKind::Triangle | CellKind::Triangle6) {
            continue;
        }
        for (i, cell) in b.cells().enumerate() {
            k += 1;
            push_int(&mut ele, k);
            // Back to Triangle's order: mid-edge nodes opposite corners 1, 2, 3.
            let order: &[usize] = if tri_nodes == 6 { &[0, 1, 2, 4, 5, 3] } else { &[0, 1, 2] };
            for &j in order {
                ele.push(b' ');
                push_int(&mut ele, cell[j] + 1);
            }
            if use_tags {
                ele.push(b' ');
                push_int(&mut ele, b.physical[i]);
            }
            // With tags, they take the place of `triangle:attribute1`.
            for a in cattrs.iter().skip(usize::from(use_tags)) {
                ele.push(b' ');
                push_f64(&mut ele, a.values[off + i]);
            }
            ele.push(b'\n');
        }
    }
    ele
}

/// The `.edge` file: the Line cells, and the Vertex cells as Voronoi rays when `rays`
/// gives their directions.
fn edge_file(
    mesh: &TaggedMesh,
    offsets: &[usize],
    nseg: usize,
    nvert: usize,
    rays: Option<&DataArray>,
) -> Vec<u8> {
    let nrays = if rays.is_some() { nvert } else { 0 };
    let any_tag = mesh
        .blocks
        .iter()
        .filter(|b| b.kind == CellKind::Line || (b.kind == CellKind::Vertex && nrays > 0))
        .any(|b| b.physical.iter().any(|&p| p != 0));
    // Voronoi .edge files have no markers; keep them when there is something to keep.
    let with_markers = nrays == 0 || any_tag;
    let mut edge = Vec::with_capacity((nseg + nrays) * 64 + 16);
    push_int(&mut edge, nseg + nrays);
    edge.extend_from_slice(if with_markers { b" 1\n" } else { b" 0\n" });
    let mut k = 0;
    for (b, &off) in mesh.blocks.iter().zip(offsets) {
        let is_ray = b.kind == CellKind::Vertex && nrays > 0;
        if b.kind != CellKind::Line && !is_ray {
            continue;
        }
        for (i, cell) in b.cells().enumerate() {
            k += 1;
            push_int(&mut edge, k);
            edge.push(b' ');
            push_int(&mut edge, cell[0] + 1);
            if let (true, Some(dir)) = (is_ray, rays) {
                edge.extend_from_slice(b" -1 ");
                push_f64(&mut edge, dir.values[3 * (off + i)]);
                edge.push(b' ');
                push_f64(&mut edge, dir.values[3 * (off + i) + 1]);
            } else {
                edge.push(b' ');
                push_int(&mut edge, cell[1] + 1);
            }
            if with_markers {
                edge.push(b' ');
                push_int(&mut edge, b.physical[i]);
            }
            edge.push(b'\n');
        }
    }
    edge
}

/// The `.area` file: each triangle's bound from `area`, -1 (none) without it.
fn area_file(
    mesh: &TaggedMesh,
    offsets: &[usize],
    ntri: usize,
    area: Option<&DataArray>,
) -> Vec<u8> {
    let mut out = Vec::with_capacity(ntri * 32 + 16);
    push_int(&mut out, ntri);
    out.push(b'\n');
    let mut k = 0;
    for (b, &off) in mesh.blocks.iter().zip(offsets) {
        if !matches!(b.kind, CellKind::Triangle | CellKind::Triangle6) {
            continue;
        }
        for i in 0..b.len() {
            k += 1;
            push_int(&mut out, k);
            out.push(b' ');
            push_f64(&mut out, area.map_or(-1.0, |a| a.values[off + i]));
            out.push(b'\n');
        }
    }
    out
}

/// What no file of the set holds: names, entities, sets, and the seeds an `.edge` main
/// file cannot carry.
fn report_unheld(mesh: &TaggedMesh, main: Kind, report: &mut WriteReport) {
    if main == Kind::Edge && (!mesh.holes.is_empty() || !mesh.regions.is_empty()) {
        report.drop(format!(
            "{} holes and {} regions: they need a .poly, which would take the place of the .edge when read back; write a .node or .poly instead",
            mesh.holes.len(),
            mesh.regions.len()
        ));
    }
    if !mesh.tag_names.is_empty() {
        report.drop(format!("{} tag names: Triangle has no names", mesh.tag_names.len()));
    }
    if !mesh.entities.is_empty() {
        report.drop(format!("{} Gmsh entities: Triangle has none", mesh.entities.len()));
    }
    for (name, s) in &mesh.point_sets {
        report.drop(format!("point set `{name}` ({} points): Triangle has no point sets", s.len()));
    }
    for (name, s) in &mesh.cell_sets {
        report.drop(format!("cell set `{name}` ({} cells): Triangle has no cell sets", s.len()));
    }
}
