//! Reading Triangle's file set. Each file is parsed on its own into a small record of
//! what it lists (`parse`, one parser per file, on the line records of `record`);
//! `read` then chooses the vertex list, resolves indices and builds the mesh (see the
//! module documentation of `triangle` for the rules).

use std::borrow::Cow;

use crate::error::{Error, ErrorKind, Result};
use crate::{CellBlock, CellKind, DataArray, ReadContext, RegionSeed, TaggedMesh};

use super::parse::{
    parse_area, parse_edges, parse_ele, parse_nodes, parse_poly_rest, tokens, Ele, Lines, NodeList,
};
use super::{attribute_name, Kind, AREA, MARKER, RAY_DIRECTION};

/// Reads the main file and the set beside it.
pub(super) fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    // Records are lines: a lone carriage return ends one too.
    let bytes = &*crate::text::lone_cr_as_newline(bytes);
    let Some(main) = Kind::from_ext(&ctx.extension) else {
        return read_stream(bytes);
    };
    // Siblings are read only when the rules below need them.
    let load = |k: Kind| -> Result<Option<Cow<'_, [u8]>>> {
        if k == main {
            Ok(Some(Cow::Borrowed(bytes)))
        } else {
            Ok(ctx.siblings.read_sibling(k.ext())?.map(|b| {
                match crate::text::lone_cr_as_newline(&b) {
                    Cow::Owned(fixed) => Cow::Owned(fixed),
                    Cow::Borrowed(_) => Cow::Owned(b),
                }
            }))
        }
    };
    // Errors in a sibling name the sibling; those in the main file get its path from the
    // caller.
    let in_file = |k: Kind| {
        move |e: Error| if k == main { e } else { e.with_path(ctx.siblings.describe(k.ext())) }
    };

    let node_bytes = load(Kind::Node)?;
    let node = match &node_bytes {
        Some(b) => Some(parse_nodes(&mut tokens(b), ".node").map_err(in_file(Kind::Node))?),
        None => None,
    };

    // The .poly: its own vertex list, or 0 vertices and the .node's.
    let poly_bytes = load(Kind::Poly)?;
    let mut poly_nodes = None;
    let mut poly_rest = None;
    if let Some(b) = &poly_bytes {
        let mut t = tokens(b);
        let own = parse_nodes(&mut t, ".poly").map_err(in_file(Kind::Poly))?;
        let (nv, base) = if !own.xy.is_empty() {
            if let Some(node) = &node {
                if node.xy.len() != own.xy.len()
                    || node.xy.iter().zip(&own.xy).any(|(a, b)| {
                        a[0].to_bits() != b[0].to_bits() || a[1].to_bits() != b[1].to_bits()
                    })
                {
                    return Err(Error::new(ErrorKind::Inconsistent(format!(
                        "{} lists its own {} vertices, which differ from the {} of {}; read one of the two files without the other",
                        ctx.siblings.describe("poly"),
                        own.xy.len(),
                        node.xy.len(),
                        ctx.siblings.describe("node"),
                    ))));
                }
            }
            (own.xy.len(), own.base)
        } else if let Some(node) = &node {
            (node.xy.len(), node.base)
        } else {
            return Err(Error::new(ErrorKind::Inconsistent(format!(
                "{} lists 0 vertices, which means that they are in {}, but there is no such file",
                ctx.siblings.describe("poly"),
                ctx.siblings.describe("node")
            ))));
        };
        poly_rest = Some(parse_poly_rest(&mut t, nv, base).map_err(in_file(Kind::Poly))?);
        if !own.xy.is_empty() {
            poly_nodes = Some(own);
        }
    }

    // The vertex list of the set: the main file's when it has one, else the .node's.
    let verts = match (node, poly_nodes) {
        (Some(_), Some(p)) if main == Kind::Poly => p,
        (Some(n), _) => n,
        (None, Some(p)) => p,
        (None, None) => {
            return Err(Error::new(ErrorKind::Inconsistent(format!(
                "the vertices of this {} file are in {}, which does not exist",
                main.ext(),
                ctx.siblings.describe("node")
            ))))
        }
    };
    let nv = verts.xy.len();

    let ele = match load(Kind::Ele)? {
        Some(b) => Some(parse_ele(&mut tokens(&b), nv, verts.base).map_err(in_file(Kind::Ele))?),
        None => None,
    };

    // Line cells: from the main file when it is a .poly or .edge, else the .poly, else
    // the .edge.
    let use_edge = main == Kind::Edge || poly_rest.is_none();
    let mut lines = None;
    if use_edge {
        if let Some(b) = load(Kind::Edge)? {
            lines =
                Some(parse_edges(&mut tokens(&b), nv, verts.base).map_err(in_file(Kind::Edge))?);
        }
    }
    let (segments, holes, regions) = match poly_rest {
        Some(p) => (Some(p.segments), p.holes, p.regions),
        None => (None, Vec::new(), Vec::new()),
    };
    if !use_edge {
        lines = segments;
    }

    let area = match load(Kind::Area)? {
        Some(b) => {
            let Some(ele) = &ele else {
                return Err(Error::new(ErrorKind::Inconsistent(format!(
                    "{} bounds the areas of the triangles of {}, which does not exist",
                    ctx.siblings.describe("area"),
                    ctx.siblings.describe("ele")
                ))));
            };
            Some(parse_area(&mut tokens(&b), ele.len()).map_err(in_file(Kind::Area))?)
        }
        None => None,
    };

    Ok(assemble(verts, ele, lines, holes, regions, area))
}

/// A stream: a `.node`, or a `.poly` with its own vertices.
fn read_stream(bytes: &[u8]) -> Result<TaggedMesh> {
    let mut t = tokens(bytes);
    let verts = parse_nodes(&mut t, ".node or .poly")?;
    t.skip_space();
    if t.remaining().is_empty() {
        return Ok(assemble(verts, None, None, Vec::new(), Vec::new(), None));
    }
    if verts.xy.is_empty() {
        return Err(t.error(ErrorKind::Inconsistent(
            "this .poly lists 0 vertices, which means that they are in a .node file beside it; a stream has none (read the file by its path)".into(),
        )));
    }
    let rest = parse_poly_rest(&mut t, verts.xy.len(), verts.base)?;
    Ok(assemble(verts, None, Some(rest.segments), rest.holes, rest.regions, None))
}

/// Builds the mesh: blocks in the order rays (Vertex), lines, triangles; cell data over
/// all of them.
fn assemble(
    verts: NodeList,
    ele: Option<Ele>,
    lines: Option<Lines>,
    holes: Vec<[f64; 2]>,
    regions: Vec<RegionSeed>,
    area: Option<Vec<f64>>,
) -> TaggedMesh {
    let mut mesh = TaggedMesh::new();
    let nv = verts.xy.len();
    mesh.points = verts.xy.iter().map(|&[x, y]| [x, y, 0.0]).collect();
    if let Some(m) = &verts.markers {
        mesh.point_data
            .insert(MARKER.into(), DataArray::new(1, m.iter().map(|&v| v as f64).collect()));
    }
    for k in 0..verts.nattr {
        let values = (0..nv).map(|i| verts.attrs[i * verts.nattr + k]).collect();
        mesh.point_data.insert(attribute_name(k + 1), DataArray::new(1, values));
    }

    let lines = lines.unwrap_or_default();
    let nrays = lines.rays.len();
    let nlines = lines.tags.len();
    if nrays > 0 {
        let mut b = CellBlock::new(CellKind::Vertex);
        for &(origin, m, _) in &lines.rays {
            b.push(&[origin], m, m);
        }
        mesh.blocks.push(b);
    }
    if nlines > 0 {
        mesh.blocks.push(CellBlock {
            kind: CellKind::Line,
            nodes: lines.nodes,
            physical: lines.tags.clone(),
            geometrical: lines.tags,
        });
    }
    let before = nrays + nlines;
    let ntri = ele.as_ref().map_or(0, Ele::len);
    let total = before + ntri;

    if nrays > 0 {
        let mut dir = vec![0.0; 3 * total];
        for (i, &(_, _, [dx, dy])) in lines.rays.iter().enumerate() {
            dir[3 * i] = dx;
            dir[3 * i + 1] = dy;
        }
        mesh.cell_data.insert(RAY_DIRECTION.into(), DataArray::new(3, dir));
    }

    if let Some(ele) = ele {
        // The first attribute is the tag when every triangle's is an integer.
        let first_is_tag = ele.nattr > 0
            && (0..ntri).all(|i| {
                let a = ele.attrs[i * ele.nattr];
                a.fract() == 0.0 && a >= i32::MIN as f64 && a <= i32::MAX as f64
            });
        let tags: Vec<i32> = if first_is_tag {
            (0..ntri).map(|i| ele.attrs[i * ele.nattr] as i32).collect()
        } else {
            vec![0; ntri]
        };
        for k in 0..ele.nattr {
            let mut values = vec![0.0; total];
            for i in 0..ntri {
                values[before + i] = ele.attrs[i * ele.nattr + k];
            }
            mesh.cell_data.insert(attribute_name(k + 1), DataArray::new(1, values));
        }
        if let Some(area) = area {
            let mut values = vec![-1.0; total];
            values[before..].copy_from_slice(&area);
            mesh.cell_data.insert(AREA.into(), DataArray::new(1, values));
        }
        if ntri > 0 {
            mesh.blocks.push(CellBlock {
                kind: ele.kind,
                nodes: ele.nodes,
                physical: tags.clone(),
                geometrical: tags,
            });
        }
    }
    mesh.holes = holes;
    mesh.regions = regions;
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MemorySiblings, NoSiblings};

    fn ctx<'a>(sib: &'a MemorySiblings, ext: &str) -> ReadContext<'a> {
        ReadContext { siblings: sib, extension: ext.into() }
    }

    fn set(files: &[(&str, &str)]) -> MemorySiblings {
        MemorySiblings {
            files: files.iter().map(|(e, s)| (e.to_string(), s.as_bytes().to_vec())).collect(),
        }
    }

    #[test]
    fn missing_fields_take_triangle_defaults() {
        let sib = set(&[]);
        let m = read(b"3 2 2 1\n1 0 0\n2 1 0 7\n3 0 1 7 8 9\n", &ctx(&sib, "node")).unwrap();
        assert_eq!(m.point_data["triangle:attribute1"].values, vec![0.0, 7.0, 7.0]);
        assert_eq!(m.point_data["triangle:attribute2"].values, vec![0.0, 0.0, 8.0]);
        assert_eq!(m.point_data[MARKER].values, vec![0.0, 0.0, 9.0]);
    }

    #[test]
    fn region_without_area_takes_its_attribute() {
        let sib = set(&[]);
        let m = read(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n0\n1\n1 0.2 0.2 5\n", &ctx(&sib, "poly"))
            .unwrap();
        assert_eq!(
            m.regions,
            vec![RegionSeed { point: [0.2, 0.2], attribute: 5.0, max_area: 5.0 }]
        );
    }

    #[test]
    fn second_order_triangles_are_reordered() {
        let sib = set(&[("node", "6 2 0 0\n0 0 0\n1 2 0\n2 0 2\n3 1 1\n4 0 1\n5 1 0\n")]);
        let m = read(b"1 6 0\n0 0 1 2 3 4 5\n", &ctx(&sib, "ele")).unwrap();
        assert_eq!(m.blocks[0].kind, CellKind::Triangle6);
        // Triangle: 3 opposite corner 0 (edge 1-2), 4 opposite 1 (edge 2-0), 5 opposite 2 (edge 0-1).
        assert_eq!(m.blocks[0].nodes, vec![0, 1, 2, 5, 3, 4]);
    }

    #[test]
    fn stream_is_node_or_poly() {
        let c = ReadContext { siblings: &NoSiblings, extension: String::new() };
        let m = read(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", &c).unwrap();
        assert_eq!(m.points.len(), 3);
        let m = read(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 1\n1 1 2 4\n0\n", &c).unwrap();
        assert_eq!(m.blocks[0].physical, vec![4]);
    }
}
