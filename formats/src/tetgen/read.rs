//! Reading TetGen's files: one parser per file on Triangle's line records, then the mesh
//! (see the module documentation of `tetgen` for the rules).

use std::borrow::Cow;

use crate::error::{Error, ErrorKind, Result};
use crate::text::{check_count, Tokens};
use crate::triangle::parse::tokens;
use crate::triangle::record::{start, Rec};
use crate::{
    CellBlock, CellKind, DataArray, NodeIndex, ReadContext, ReadReport, TaggedMesh, MAX_POINTS,
};

use super::{attribute_name, Kind, MARKER, TETGEN_TO_GMSH};

/// A vertex list (`.node`, or the first part of a `.poly`/`.smesh`).
struct Nodes {
    xyz: Vec<[f64; 3]>,
    nattr: usize,
    attrs: Vec<f64>,
    markers: Option<Vec<i32>>,
    /// Number of the first vertex (0 or 1), which numbers the whole set.
    base: i64,
}

fn parse_nodes(t: &mut Tokens<'_>, file: &str) -> Result<Nodes> {
    let line = start(t, || {
        format!(
            "the header of the {file} file (number of vertices, dimension 3, attributes, markers)"
        )
    })?;
    let mut r = Rec::new(t, line, "header", 0);
    // A vertex record is at least "1 0 0 0\n".
    let n = r.count("number of vertices", 8)?;
    if n > MAX_POINTS {
        return Err(Error::at_line(line, crate::mesh::past_max_points("vertices", n)));
    }
    let dim = r.opt_int("dimension", 3)?;
    // A PLC's list may be empty with dimension 0 (its vertices are in the .node).
    if dim != 3 && !(n == 0 && dim == 0) {
        return Err(Error::expected(line, "dimension 3 (a TetGen file is 3D)", dim.to_string()));
    }
    let nattr = r.opt_int("number of attributes", 0)?;
    let nattr = r.check_count("number of attributes", nattr, 1)?;
    check_count(n.saturating_mul(nattr), r.t.remaining().len(), 1, "vertex attributes")
        .map_err(|k| Error::at_line(line, k))?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    if !(0..=1).contains(&nmarkers) {
        return Err(Error::expected(line, "0 or 1 boundary markers", nmarkers.to_string()));
    }
    r.end();
    let mut list = Nodes {
        xyz: Vec::with_capacity(n),
        nattr,
        attrs: Vec::with_capacity(n * nattr),
        markers: (nmarkers == 1).then(|| Vec::with_capacity(n)),
        base: 1,
    };
    for i in 0..n {
        let line = start(t, || format!("vertex {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "vertex", i + 1);
        let num = r.number()?;
        if i == 0 {
            list.base = if num == 0 { 0 } else { 1 };
        }
        let p = [r.f64("x")?, r.f64("y")?, r.f64("z")?];
        list.xyz.push(p);
        for _ in 0..nattr {
            list.attrs.push(r.opt_f64("attribute", 0.0)?);
        }
        if let Some(m) = &mut list.markers {
            m.push(r.opt_marker()?);
        }
        r.end();
    }
    Ok(list)
}

/// Elements of one kind with their numbers read: `k` nodes and `nattr` reals each.
struct Items {
    /// Nodes per tetrahedron: 4, or 10 (`-o2`, in Gmsh's order once read).
    k: usize,
    nodes: Vec<NodeIndex>,
    attrs: Vec<f64>,
    nattr: usize,
}

/// `.ele`: `<n> <nodes per tetrahedron> <attributes>`, then the tetrahedra.
fn parse_ele(t: &mut Tokens<'_>, nv: usize, base: i64) -> Result<Items> {
    let line = start(t, || {
        "the header of the .ele file (number of tetrahedra, nodes per tetrahedron, attributes)"
            .to_string()
    })?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count("number of tetrahedra", 10)?;
    let k = r.opt_int("nodes per tetrahedron", 4)?;
    if k != 4 && k != 10 {
        return Err(Error::expected(line, "4 or 10 nodes per tetrahedron", k.to_string()));
    }
    let k = k as usize;
    let nattr = r.opt_int("number of attributes", 0)?;
    let nattr = r.check_count("number of attributes", nattr, 1)?;
    r.end();
    let mut items =
        Items { k, nodes: Vec::with_capacity(k * n), attrs: Vec::with_capacity(n * nattr), nattr };
    for i in 0..n {
        let line = start(t, || format!("tetrahedron {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "tetrahedron", i + 1);
        r.number()?;
        let mut cell = [0 as NodeIndex; 10];
        for v in cell.iter_mut().take(k) {
            *v = r.index("vertex", base, nv)?;
        }
        if k == 10 {
            let mut gmsh = [0 as NodeIndex; 10];
            for (j, &g) in TETGEN_TO_GMSH.iter().enumerate() {
                gmsh[g] = cell[j];
            }
            cell = gmsh;
        }
        items.nodes.extend_from_slice(&cell[..k]);
        for _ in 0..nattr {
            items.attrs.push(r.opt_f64("attribute", 0.0)?);
        }
        r.end();
    }
    Ok(items)
}

/// `.face` or `.edge`: `<n> <markers>`, then items of `k` vertices and a marker.
fn parse_marked(
    t: &mut Tokens<'_>,
    k: usize,
    item: &'static str,
    nv: usize,
    base: i64,
) -> Result<(Vec<NodeIndex>, Vec<i32>)> {
    let line = start(t, || format!("the header of the {item} list (number, boundary markers)"))?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count(&format!("number of {item}s"), 2 * k + 2)?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    r.end();
    let (mut nodes, mut markers) = (Vec::with_capacity(k * n), Vec::with_capacity(n));
    for i in 0..n {
        let line = start(t, || format!("{item} {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, item, i + 1);
        r.number()?;
        for _ in 0..k {
            nodes.push(r.index("vertex", base, nv)?);
        }
        markers.push(if nmarkers == 1 { r.opt_marker()? } else { 0 });
        r.end();
    }
    Ok((nodes, markers))
}

/// Cells of a PLC's facets, by corner count (index 0: point cells, ... 3: quads).
#[derive(Default)]
struct Facets {
    cells: [(Vec<NodeIndex>, Vec<i32>); 4],
    facet_holes: usize,
}

impl Facets {
    /// Reads `<corners> <c1> ... <cn>` into its block; returns the block's index, where
    /// the caller puts the facet's marker.
    fn polygon(&mut self, r: &mut Rec<'_, '_>, nv: usize, base: i64) -> Result<usize> {
        let nc = r.int("number of corners")?;
        if !(1..=4).contains(&nc) {
            return Err(Error::at_line(
                r.line,
                ErrorKind::Unsupported(format!(
                    "a facet polygon of {nc} corners: smartmesh holds polygons of 1 to 4 corners (points, segments, triangles, quadrilaterals)"
                )),
            ));
        }
        let slot = nc as usize - 1;
        for _ in 0..nc {
            let v = r.index("corner", base, nv)?;
            self.cells[slot].0.push(v);
        }
        Ok(slot)
    }
}

/// The facets of a `.smesh` (one polygon a line, marker last) or a `.poly` (a facet
/// header, its polygons, its holes).
fn parse_facets(t: &mut Tokens<'_>, nv: usize, base: i64, poly: bool) -> Result<Facets> {
    let line = start(t, || "the facet list header (number of facets, boundary markers)".into())?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count("number of facets", 4)?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    r.end();
    let mut f = Facets::default();
    for i in 0..n {
        let line = start(t, || format!("facet {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "facet", i + 1);
        if !poly {
            // `<corners> <c1> ... <cn> [marker]`: the marker follows the corners.
            let slot = f.polygon(&mut r, nv, base)?;
            let marker = if nmarkers == 1 { r.opt_marker()? } else { 0 };
            f.cells[slot].1.push(marker);
            r.end();
            continue;
        }
        let npoly = r.count("number of polygons", 2)?;
        let nholes = r.opt_int("number of holes", 0)?;
        let nholes = r.check_count("number of holes", nholes, 6)?;
        let marker = if nmarkers == 1 { r.opt_marker()? } else { 0 };
        r.end();
        for j in 0..npoly {
            let line = start(t, || format!("polygon {} of facet {}", j + 1, i + 1))?;
            let mut r = Rec::new(t, line, "polygon", j + 1);
            let slot = f.polygon(&mut r, nv, base)?;
            f.cells[slot].1.push(marker);
            r.end();
        }
        for j in 0..nholes {
            let line = start(t, || format!("hole {} of facet {}", j + 1, i + 1))?;
            let mut r = Rec::new(t, line, "facet hole", j + 1);
            r.number()?;
            r.f64("x")?;
            r.f64("y")?;
            r.f64("z")?;
            r.end();
        }
        f.facet_holes += nholes;
    }
    Ok(f)
}

/// The volume holes, then the regions, of a PLC: how many of each (their points are
/// checked and dropped). Both lists are optional at the end of the file.
fn parse_seeds(t: &mut Tokens<'_>) -> Result<(usize, usize)> {
    let mut counts = [0usize; 2];
    for (s, (what, fields)) in [("hole", 3), ("region", 4)].into_iter().enumerate() {
        t.skip_space();
        if t.remaining().is_empty() {
            break;
        }
        let line = t.line();
        let mut r = Rec::new(t, line, "header", 0);
        let n = r.count(&format!("number of {what}s"), 8)?;
        r.end();
        for i in 0..n {
            let line = start(t, || format!("{what} {} of {n}", i + 1))?;
            let mut r = Rec::new(t, line, what, i + 1);
            r.number()?;
            for c in ["x", "y", "z", "region attribute"].into_iter().take(fields) {
                r.f64(c)?;
            }
            r.end();
        }
        counts[s] = n;
    }
    Ok((counts[0], counts[1]))
}

/// What was read, before the mesh is built.
#[derive(Default)]
struct Set {
    tets: Option<Items>,
    faces: Option<(Vec<NodeIndex>, Vec<i32>)>,
    edges: Option<(Vec<NodeIndex>, Vec<i32>)>,
    facets: Option<Facets>,
    holes: usize,
    regions: usize,
}

pub(super) fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<(TaggedMesh, ReadReport)> {
    let bytes = &*crate::text::lone_cr_as_newline(bytes);
    let main = Kind::from_ext(&ctx.extension);
    let load = |k: Kind| -> Result<Option<Cow<'_, [u8]>>> {
        if Some(k) == main {
            return Ok(Some(Cow::Borrowed(bytes)));
        }
        Ok(ctx
            .siblings
            .read_sibling(k.ext())?
            .map(|b| Cow::Owned(crate::text::lone_cr_as_newline(&b).into_owned())))
    };
    let in_file = |k: Kind| {
        move |e: Error| {
            if Some(k) == main {
                e
            } else {
                e.with_path(ctx.siblings.describe(k.ext()))
            }
        }
    };
    let mut set = Set::default();
    let nodes = match main {
        Some(k @ (Kind::Poly | Kind::Smesh)) => {
            let mut t = tokens(bytes);
            let own = parse_nodes(&mut t, &format!(".{}", k.ext())).map_err(in_file(k))?;
            let nodes = if own.xyz.is_empty() {
                let node = load(Kind::Node)?.ok_or_else(|| {
                    Error::new(ErrorKind::Inconsistent(format!(
                        "the .{} lists 0 vertices, which means that they are in {}, but there is no such file",
                        k.ext(),
                        ctx.siblings.describe("node")
                    )))
                })?;
                parse_nodes(&mut tokens(&node), ".node").map_err(in_file(Kind::Node))?
            } else {
                own
            };
            let (nv, base) = (nodes.xyz.len(), nodes.base);
            let facets = parse_facets(&mut t, nv, base, k == Kind::Poly).map_err(in_file(k))?;
            (set.holes, set.regions) = parse_seeds(&mut t).map_err(in_file(k))?;
            set.facets = Some(facets);
            nodes
        }
        None => {
            // A stream: a .node list, then maybe the rest of a .smesh.
            let mut t = tokens(bytes);
            let nodes = parse_nodes(&mut t, "TetGen")?;
            t.skip_space();
            if !t.remaining().is_empty() {
                let (nv, base) = (nodes.xyz.len(), nodes.base);
                set.facets = Some(parse_facets(&mut t, nv, base, false)?);
                (set.holes, set.regions) = parse_seeds(&mut t)?;
            }
            nodes
        }
        Some(_) => {
            let node = load(Kind::Node)?.ok_or_else(|| {
                Error::new(ErrorKind::Inconsistent(format!(
                    "a TetGen mesh needs its vertices: there is no {}",
                    ctx.siblings.describe("node")
                )))
            })?;
            let nodes = parse_nodes(&mut tokens(&node), ".node").map_err(in_file(Kind::Node))?;
            let (nv, base) = (nodes.xyz.len(), nodes.base);
            if let Some(b) = load(Kind::Ele)? {
                set.tets = Some(parse_ele(&mut tokens(&b), nv, base).map_err(in_file(Kind::Ele))?);
            }
            if let Some(b) = load(Kind::Face)? {
                let f = parse_marked(&mut tokens(&b), 3, "face", nv, base);
                set.faces = Some(f.map_err(in_file(Kind::Face))?);
            }
            if let Some(b) = load(Kind::Edge)? {
                let e = parse_marked(&mut tokens(&b), 2, "edge", nv, base);
                set.edges = Some(e.map_err(in_file(Kind::Edge))?);
            }
            nodes
        }
    };
    Ok(assemble(nodes, set))
}

fn block(kind: CellKind, nodes: Vec<NodeIndex>, tags: Vec<i32>) -> CellBlock {
    let mut b = CellBlock::new(kind);
    b.nodes = nodes;
    b.geometrical = tags.clone();
    b.physical = tags;
    b
}

fn assemble(nodes: Nodes, set: Set) -> (TaggedMesh, ReadReport) {
    let mut report = ReadReport::default();
    let mut mesh = TaggedMesh::new();
    mesh.coordinate_dim = 3;
    let n = nodes.xyz.len();
    mesh.points = nodes.xyz;
    if let Some(m) = nodes.markers {
        mesh.point_data
            .insert(MARKER.into(), DataArray::new(1, m.into_iter().map(f64::from).collect()));
    }
    for k in 0..nodes.nattr {
        let a = (0..n).map(|i| nodes.attrs[i * nodes.nattr + k]).collect();
        mesh.point_data.insert(attribute_name(k + 1), DataArray::new(1, a));
    }
    // Blocks: facet points, segments, triangles, quadrilaterals, then tetrahedra.
    if let Some(f) = set.facets {
        let kinds = [CellKind::Vertex, CellKind::Line, CellKind::Triangle, CellKind::Quad];
        for (kind, (nodes, tags)) in kinds.into_iter().zip(f.cells) {
            if !tags.is_empty() {
                mesh.blocks.push(block(kind, nodes, tags));
            }
        }
        if f.facet_holes > 0 {
            report.note(format!(
                "{} facet holes dropped: a mesh has no place for them",
                f.facet_holes
            ));
        }
    }
    if let Some((nodes, tags)) = set.edges {
        mesh.blocks.push(block(CellKind::Line, nodes, tags));
    }
    if let Some((nodes, tags)) = set.faces {
        mesh.blocks.push(block(CellKind::Triangle, nodes, tags));
    }
    if set.holes > 0 || set.regions > 0 {
        report.note(format!(
            "{} volume holes and {} region seeds dropped: smartmesh keeps no 3D seeds (a tetrahedral mesh's regions are its tags)",
            set.holes, set.regions
        ));
    }
    if let Some(tets) = set.tets {
        let kind = if tets.k == 10 { CellKind::Tetra10 } else { CellKind::Tetra };
        let nt = tets.nodes.len() / tets.k;
        let first: Vec<f64> =
            (0..nt).map(|i| tets.attrs.get(i * tets.nattr).copied().unwrap_or(0.0)).collect();
        let integral = first.iter().all(|&a| a.fract() == 0.0 && a.abs() <= i32::MAX as f64);
        let offset = mesh.num_cells();
        let total = offset + nt;
        if tets.nattr == 1 && integral {
            mesh.blocks.push(block(
                CellKind::Tetra,
                tets.nodes,
                first.iter().map(|&a| a as i32).collect(),
            ));
        } else {
            mesh.blocks.push(block(kind, tets.nodes, vec![0; nt]));
            for k in 0..tets.nattr {
                let mut a = vec![0.0; total];
                for i in 0..nt {
                    a[offset + i] = tets.attrs[i * tets.nattr + k];
                }
                mesh.cell_data.insert(attribute_name(k + 1), DataArray::new(1, a));
            }
        }
    }
    (mesh, report)
}
