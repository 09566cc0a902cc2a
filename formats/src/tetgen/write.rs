//! Writing TetGen's files: the mesh set (`.node`, `.ele`, `.face`, `.edge`) or one PLC
//! (`.smesh`, `.poly`); see the module documentation of `tetgen` for the rules.

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::{Error, ErrorKind, Result};
use crate::text::{push_f64, push_int};
use crate::{CellKind, TaggedMesh, WriteOptions, WriteReport, Written};

use super::{attribute_name, Kind, ATTRIBUTE_PREFIX, MARKER, TETGEN_TO_GMSH};

/// The kinds a PLC holds, as facet polygons.
const PLC_KINDS: [CellKind; 4] =
    [CellKind::Vertex, CellKind::Line, CellKind::Triangle, CellKind::Quad];

/// The point arrays written as TetGen's: the marker when it holds integers, and the
/// attributes `tetgen:attribute1..k` while they run on without a gap.
fn point_arrays(mesh: &TaggedMesh) -> (Option<Vec<i32>>, Vec<&[f64]>) {
    let markers = mesh.point_data.get(MARKER).filter(|a| a.components == 1).and_then(|a| {
        a.values
            .iter()
            .map(|&v| (v.fract() == 0.0 && v.abs() <= i32::MAX as f64).then_some(v as i32))
            .collect()
    });
    let attrs = (1..)
        .map_while(|k| mesh.point_data.get(&attribute_name(k)).filter(|a| a.components == 1))
        .map(|a| a.values.as_slice())
        .collect();
    (markers, attrs)
}

fn node_file(mesh: &TaggedMesh, markers: &Option<Vec<i32>>, attrs: &[&[f64]]) -> Vec<u8> {
    let mut out = Vec::with_capacity(mesh.points.len() * 80 + 64);
    push_int(&mut out, mesh.points.len());
    out.extend_from_slice(b" 3 ");
    push_int(&mut out, attrs.len());
    out.extend_from_slice(if markers.is_some() { b" 1\n" } else { b" 0\n" });
    for (i, p) in mesh.points.iter().enumerate() {
        push_int(&mut out, i + 1);
        for c in p {
            out.push(b' ');
            push_f64(&mut out, *c);
        }
        for a in attrs {
            out.push(b' ');
            push_f64(&mut out, a[i]);
        }
        if let Some(m) = markers {
            out.push(b' ');
            push_int(&mut out, m[i]);
        }
        out.push(b'\n');
    }
    out
}

/// One record per cell of `kind`: `<number> <nodes...> [tag]`, tags written when
/// `tagged`.
fn cells_file(mesh: &TaggedMesh, kind: CellKind, header: &[u8], tagged: bool) -> Vec<u8> {
    let n = mesh.num_cells_of(kind);
    let mut out = Vec::with_capacity(n * 48 + 32);
    push_int(&mut out, n);
    out.extend_from_slice(header);
    out.extend_from_slice(if tagged { b" 1\n" } else { b" 0\n" });
    for (i, (_, nodes, tag, _)) in mesh.cells().filter(|c| c.0 == kind).enumerate() {
        push_int(&mut out, i + 1);
        for j in 0..nodes.len() {
            let v = if kind == CellKind::Tetra10 { nodes[TETGEN_TO_GMSH[j]] } else { nodes[j] };
            out.push(b' ');
            push_int(&mut out, v + 1);
        }
        if tagged {
            out.push(b' ');
            push_int(&mut out, tag);
        }
        out.push(b'\n');
    }
    out
}

/// A PLC: the vertices, each point, segment, triangle and quadrilateral as a facet, no
/// holes, one region seed per tetrahedron tag.
fn plc_file(
    mesh: &TaggedMesh,
    poly: bool,
    markers: &Option<Vec<i32>>,
    attrs: &[&[f64]],
) -> Vec<u8> {
    let mut out = node_file(mesh, markers, attrs);
    let facets: Vec<(&[u32], i32)> = mesh
        .cells()
        .filter(|c| PLC_KINDS.contains(&c.0))
        .map(|(_, nodes, tag, _)| (nodes, tag))
        .collect();
    push_int(&mut out, facets.len());
    out.extend_from_slice(b" 1\n");
    for (nodes, tag) in facets {
        if poly {
            out.extend_from_slice(b"1 0 ");
            push_int(&mut out, tag);
            out.push(b'\n');
        }
        push_int(&mut out, nodes.len());
        for &v in nodes {
            out.push(b' ');
            push_int(&mut out, v + 1);
        }
        if !poly {
            out.push(b' ');
            push_int(&mut out, tag);
        }
        out.push(b'\n');
    }
    out.extend_from_slice(b"0\n");
    // One seed per tag: the centroid of its first tetrahedron, strictly inside it.
    let mut seeds: BTreeMap<i32, [f64; 3]> = BTreeMap::new();
    for (_, nodes, tag, _) in mesh.cells().filter(|c| c.0 == CellKind::Tetra) {
        seeds.entry(tag).or_insert_with(|| {
            let mut c = [0.0; 3];
            for &v in nodes {
                for (k, x) in c.iter_mut().enumerate() {
                    *x += 0.25 * mesh.points[v as usize][k];
                }
            }
            c
        });
    }
    push_int(&mut out, seeds.len());
    out.push(b'\n');
    for (i, (tag, c)) in seeds.iter().enumerate() {
        push_int(&mut out, i + 1);
        for x in c {
            out.push(b' ');
            push_f64(&mut out, *x);
        }
        out.push(b' ');
        push_int(&mut out, *tag);
        out.extend_from_slice(b" -1\n");
    }
    out
}

pub(super) fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let main = match &opts.main_name {
        Some(name) => {
            let ext = Path::new(name).extension().and_then(|e| e.to_str()).unwrap_or("");
            Kind::from_ext(ext).ok_or_else(|| {
                Error::new(ErrorKind::CannotWrite {
                    format: "TetGen",
                    reason: format!("cannot tell which file of the set `{name}` is: name it .node, .ele, .face, .edge, .smesh or .poly"),
                })
            })?
        }
        None => Kind::Node,
    };
    if mesh.points.iter().flatten().any(|c| !c.is_finite()) {
        return Err(crate::io::refused(crate::Format::TetGen, mesh));
    }
    let mut report = WriteReport::default();
    let plc = matches!(main, Kind::Smesh | Kind::Poly);
    // One .ele holds one node count: 10-node tetrahedra when there are no 4-node ones.
    let ntet = mesh.num_cells_of(CellKind::Tetra);
    let tet = if ntet == 0 && mesh.num_cells_of(CellKind::Tetra10) > 0 {
        CellKind::Tetra10
    } else {
        CellKind::Tetra
    };
    let set_kinds = [tet, CellKind::Triangle, CellKind::Line];
    let kept: &[CellKind] = if plc { &PLC_KINDS } else { &set_kinds };
    let mut lost: BTreeMap<CellKind, usize> = BTreeMap::new();
    let mut geo_differs = 0;
    for b in &mesh.blocks {
        let held = kept.contains(&b.kind) || (plc && b.kind == CellKind::Tetra);
        if !held {
            *lost.entry(b.kind).or_default() += b.len();
        }
        geo_differs += b.tags_differ();
    }
    for (kind, n) in lost.into_iter().filter(|&(_, n)| n > 0) {
        report.drop(format!(
            "{n} {} cells: TetGen {} holds {}",
            kind.name(),
            if plc { "PLCs" } else { "meshes" },
            if plc {
                "points, segments, triangles and quadrilaterals as facets"
            } else {
                "tetrahedra of one node count (4, or 10 when there are no 4-node ones), triangles (.face) and segments (.edge)"
            }
        ));
    }
    if plc && ntet > 0 {
        report.drop(format!(
            "{ntet} tetra cells: a PLC holds the boundary and one region seed per tag, which TetGen (-pA) fills again"
        ));
    }
    if geo_differs > 0 {
        report.drop(format!("geometrical tags of {geo_differs} cells differ from the physical ones: TetGen keeps one marker (the physical tag)"));
    }
    let (markers, attrs) = point_arrays(mesh);
    for (name, a) in &mesh.point_data {
        let written = (name == MARKER && markers.is_some())
            || name
                .strip_prefix(ATTRIBUTE_PREFIX)
                .and_then(|k| k.parse::<usize>().ok())
                .is_some_and(|k| k >= 1 && k <= attrs.len());
        if !written {
            report.drop(format!("point data `{name}` ({}): TetGen keeps `{MARKER}` and `{ATTRIBUTE_PREFIX}<k>` only", crate::words::components(a.components)));
        }
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({}): TetGen's region attribute is the tetrahedra's tag",
            crate::words::components(a.components)
        ));
    }
    if !mesh.tag_names.is_empty() {
        report.drop(format!("{} tag names: TetGen markers have no names", mesh.tag_names.len()));
    }
    if !mesh.entities.is_empty() {
        report.drop(format!("{} Gmsh entities: TetGen has none", mesh.entities.len()));
    }
    for (name, s) in &mesh.point_sets {
        report.drop(format!("point set `{name}` ({} points): TetGen has no point sets", s.len()));
    }
    for (name, s) in &mesh.cell_sets {
        report.drop(format!("cell set `{name}` ({} cells): TetGen has no cell sets", s.len()));
    }
    if !mesh.holes.is_empty() || !mesh.regions.is_empty() {
        report.drop(format!(
            "{} planar holes and {} planar regions: TetGen's seeds are 3D",
            mesh.holes.len(),
            mesh.regions.len()
        ));
    }

    if plc {
        let main_bytes = plc_file(mesh, main == Kind::Poly, &markers, &attrs);
        return Ok(Written { main: main_bytes, siblings: Vec::new(), report });
    }
    let mut files: Vec<(Kind, Vec<u8>)> = vec![(Kind::Node, node_file(mesh, &markers, &attrs))];
    let tagged = |k: CellKind| mesh.cells().any(|c| c.0 == k && c.2 != 0);
    if mesh.num_cells_of(tet) > 0 || main == Kind::Ele {
        let k: &[u8] = if tet == CellKind::Tetra10 { b" 10" } else { b" 4" };
        files.push((Kind::Ele, cells_file(mesh, tet, k, tagged(tet))));
    }
    if mesh.num_cells_of(CellKind::Triangle) > 0 || main == Kind::Face {
        files.push((Kind::Face, cells_file(mesh, CellKind::Triangle, b"", true)));
    }
    if mesh.num_cells_of(CellKind::Line) > 0 || main == Kind::Edge {
        files.push((Kind::Edge, cells_file(mesh, CellKind::Line, b"", true)));
    }
    let pos = files.iter().position(|(k, _)| *k == main).unwrap_or(0);
    let (_, main_bytes) = files.remove(pos);
    let siblings = files.into_iter().map(|(k, b)| (k.ext().to_string(), b)).collect();
    Ok(Written { main: main_bytes, siblings, report })
}
