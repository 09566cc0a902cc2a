//! TetGen's file family: `.node`, `.ele`, `.face`, `.edge` (a tetrahedral mesh) and
//! `.smesh`, `.poly` (a piecewise linear complex, TetGen's input), the 3D counterpart of
//! Triangle's.
//!
//! Source: H. Si's TetGen 1.6 user manual, section 5 ("File formats"), checked against
//! `tetgenio::load_node`, `load_tet`, `load_face`, `load_edge`, `load_poly` of
//! `tetgen.cxx` 1.6. The line records are read with Triangle's record reader
//! (`triangle::record`): the two families share it (`#` comments, one record a line,
//! missing optional fields defaulted, extra fields ignored).
//!
//! # Which files are TetGen's
//! `.smesh` and `.face` are TetGen's alone. `.node`, `.ele`, `.poly` and `.edge` are
//! Triangle's extensions too; a file of these is read as TetGen's when `--from tetgen`
//! says so, or when its header says it is 3D: a `.node` or `.poly` of dimension 3, an
//! `.ele` of 4 or 10 nodes per element (Triangle's have 3 or 6) unless the `.node` beside
//! it is 2D, an `.edge` whose `.node` beside it is of dimension 3. Writing chooses by the format, not the data: `--to
//! tetgen` (or a `.smesh` or `.face` name) writes TetGen; a `.node`/`.ele` name alone
//! means Triangle, whose writer refuses volume cells and says to write TetGen.
//!
//! # Reading
//! - The main file may be any of the set; the other files with the same base name are
//!   read from beside it when they exist (`box.1.ele` reads `box.1.node`, and
//!   `box.1.face` and `box.1.edge` when TetGen wrote them). The number of the first
//!   vertex (0 or 1) sets the numbering of the set, as in TetGen.
//! - Vertices: markers go to point data `tetgen:marker`, attributes to
//!   `tetgen:attribute1`, ... .
//! - `.ele`: 4-node tetrahedra, or 10-node ones (`-o2`), whose edge nodes TetGen 1.6
//!   lists for edges 2-3, 0-3, 0-1, 1-2, 1-3, 0-2 (read from the PyPI `tetgen` wheel's
//!   `-o2` output, checked in the tests), put in Gmsh's order. The first region attribute (`-A`) is the physical and
//!   geometrical tag of each tetrahedron when every one is an integer; otherwise (or
//!   when there are more) the attributes are cell data `tetgen:attribute<k>` (0 on the
//!   other cells).
//! - `.face` (triangles) and `.edge` (segments): the boundary marker is the tag.
//! - `.poly` and `.smesh`: each facet polygon becomes a cell of its corner count (1 a
//!   point cell, 2 a segment, 3 a triangle, 4 a quadrilateral) tagged with the facet's
//!   marker; a polygon of more corners is refused (no polygon cells). Facet holes,
//!   volume holes and region seeds are 3D points the mesh has no place for: they are
//!   dropped and the read report says so.
//! - A stream (`--from tetgen` on stdin) is a `.node` list, optionally followed by the
//!   rest of a `.smesh` (facets, holes, regions).
//!
//! # Writing
//! The main file's extension chooses the files:
//! - `.node`, `.ele`, `.face`, `.edge` (or stdout, where the `.node` is the main file):
//!   `.node` (markers from point data `tetgen:marker`, attributes from
//!   `tetgen:attribute<k>`), `.ele` for the tetrahedra (4-node ones, or 10-node ones in
//!   TetGen's order when there are no 4-node ones; region attribute = physical tag
//!   when a tetrahedron has a tag that is not 0), `.face` for the triangles and `.edge`
//!   for the segments (marker = physical tag); the named file is written even when empty.
//! - `.smesh` or `.poly`: one self-contained PLC: the vertices, every point, segment,
//!   triangle and quadrilateral as a facet polygon with its tag as marker, no holes, and
//!   one region seed per tetrahedron tag (the centroid of one of its tetrahedra, inside
//!   that region), so that `tetgen -pA` meshes the same domain with the same tags. The
//!   tetrahedra themselves are reported as not written.
//!
//! Numbering is 1-based. Everything TetGen cannot hold is listed in the report: other
//! cell kinds (hexahedra, prisms, pyramids, second order), geometrical tags that differ
//! from the physical ones, tag names, Gmsh entities, point and cell sets, planar holes and
//! regions, and every array that is not one of the `tetgen:` arrays above.

mod read;
mod write;

use crate::{ReadContext, ReadReport, Result, TaggedMesh, WriteOptions, Written};

/// Point data holding the boundary marker of each vertex.
pub const MARKER: &str = "tetgen:marker";
/// Prefix of the attribute arrays (`tetgen:attribute1`, ...), point or cell data.
pub const ATTRIBUTE_PREFIX: &str = "tetgen:attribute";

/// Where each node of a 10-node TetGen tetrahedron is in Gmsh's order: TetGen's node
/// `j` is Gmsh's node `TETGEN_TO_GMSH[j]` (Gmsh's edge nodes: 0-1, 1-2, 2-0, 3-0, 3-2,
/// 3-1; TetGen's: 2-3, 0-3, 0-1, 1-2, 1-3, 0-2).
const TETGEN_TO_GMSH: [usize; 10] = [0, 1, 2, 3, 8, 7, 4, 5, 9, 6];

/// The name of attribute array `k` (1-based).
pub fn attribute_name(k: usize) -> String {
    format!("{ATTRIBUTE_PREFIX}{k}")
}

/// Which file of the set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Node,
    Ele,
    Face,
    Edge,
    Poly,
    Smesh,
}

impl Kind {
    const ALL: [Kind; 6] = [Kind::Node, Kind::Ele, Kind::Face, Kind::Edge, Kind::Poly, Kind::Smesh];

    fn ext(self) -> &'static str {
        match self {
            Kind::Node => "node",
            Kind::Ele => "ele",
            Kind::Face => "face",
            Kind::Edge => "edge",
            Kind::Poly => "poly",
            Kind::Smesh => "smesh",
        }
    }

    fn from_ext(ext: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.ext().eq_ignore_ascii_case(ext))
    }
}

/// The TetGen reader leaves data lengths and the node numbers of nothing to `validate`:
/// it checks every index it reads, but lets `read_bytes` validate the rest.
pub(crate) const CHECKS: crate::Checks = crate::Checks::NONE;

/// The numbers of the first record (the header) of `bytes`, comments skipped.
fn header(bytes: &[u8]) -> Vec<i64> {
    let text = bytes.split(|&b| b == b'\n').map(|l| l.split(|&b| b == b'#').next().unwrap_or(l));
    let line = text.into_iter().find(|l| l.iter().any(|b| !b.is_ascii_whitespace()));
    line.map(|l| {
        l.split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty())
            .map_while(|t| std::str::from_utf8(t).ok()?.parse().ok())
            .collect()
    })
    .unwrap_or_default()
}

/// Whether a file the extension gave to Triangle is TetGen's (see the module
/// documentation): its header, or for an `.edge` the `.node` beside it, says 3D.
pub(crate) fn claims(bytes: &[u8], ctx: &ReadContext<'_>) -> bool {
    match Kind::from_ext(&ctx.extension) {
        Some(Kind::Node | Kind::Poly) => header(bytes).get(1) == Some(&3),
        // A 4-node .ele beside a 2D .node is a Triangle file gone wrong: Triangle's
        // reader says why.
        Some(Kind::Ele) => {
            matches!(header(bytes).get(1), Some(4 | 10))
                && !matches!(
                    ctx.siblings.sibling_bytes("node"),
                    Ok(Some(node)) if header(&node).get(1) == Some(&2)
                )
        }
        Some(Kind::Edge) => matches!(
            ctx.siblings.sibling_bytes("node"),
            Ok(Some(node)) if header(&node).get(1) == Some(&3)
        ),
        Some(Kind::Face | Kind::Smesh) => true,
        None => false,
    }
}

/// Reads a TetGen file and the files of its set beside it (see the module documentation).
pub fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read_reported(bytes, ctx).map(|(m, _)| m)
}

/// [`read`], with what the mesh could not keep (the seeds of a PLC).
pub fn read_reported(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<(TaggedMesh, ReadReport)> {
    read::read(bytes, ctx)
}

/// Writes a mesh as a TetGen file set or PLC (see the module documentation).
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    write::write(mesh, opts)
}
