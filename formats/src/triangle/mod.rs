//! Triangle's file family: `.node`, `.ele`, `.poly`, `.edge`, `.area`.
//!
//! Source: J. R. Shewchuk's format pages, <https://www.cs.cmu.edu/~quake/triangle.node.html>
//! (and `triangle.ele.html`, `.poly.html`, `.edge.html`, `.area.html`, `.highorder.html`),
//! checked against the reading code of `triangle.c` 1.6.
//!
//! # Reading
//! The main file may have any of the five extensions; the other files of the set (same base
//! name) are read from beside it when they exist, so `box.1.ele`, `box.1.node` and
//! `box.1.poly` all give the same mesh. A stream without an extension is read as a `.node`
//! or a self-contained `.poly` (whatever follows the vertex list).
//! - Records are read line by line, as Triangle does: `#` starts a comment, blank lines are
//!   skipped, missing trailing fields take Triangle's defaults (attributes 0, markers 0,
//!   a region's area = its attribute, a triangle's area constraint -1) and extra fields
//!   are ignored. The number of the first vertex (0 or 1) sets the numbering of the whole
//!   set; later item numbers are not checked, as Triangle does not check them.
//! - Vertices (`.node`, or the vertex list of a `.poly`): a `.poly` with 0 vertices uses the
//!   `.node`; when both list vertices, the lists must agree.
//!   Boundary markers go to point data `triangle:marker`, attributes to point data
//!   `triangle:attribute1`, `triangle:attribute2`, ... (one scalar each).
//! - `.ele`: 3-node triangles ([`CellKind::Triangle`](crate::CellKind::Triangle)) or 6-node ones
//!   ([`CellKind::Triangle6`](crate::CellKind::Triangle6); Triangle puts the mid-edge nodes opposite corners 1, 2, 3,
//!   they are reordered to edges 1-2, 2-3, 3-1). Every attribute is kept as cell data
//!   `triangle:attribute<k>`; when all first attributes are integers, they are also the
//!   physical and geometrical tags of the triangles.
//! - Segments of the `.poly` become [`CellKind::Line`](crate::CellKind::Line) cells tagged with their boundary
//!   marker; holes go to [`TaggedMesh::holes`], regional attributes and area bounds to
//!   [`TaggedMesh::regions`]. Without a `.poly` (or when the main file is the `.edge`),
//!   the `.edge` file gives the Line cells; the infinite rays of a Voronoi `.v.edge` become
//!   [`CellKind::Vertex`](crate::CellKind::Vertex) cells at their origin, with cell data `triangle:ray_direction`.
//! - `.area`: per-triangle area bounds, cell data `triangle:area`.
//! - Cell data covers every cell: non-triangles get 0 as attributes, -1 as area, and
//!   non-rays a zero direction.
//!
//! # Writing
//! The main file's extension (`WriteOptions::main_name`) chooses the files:
//! - `.node`, `.ele` or `.area`: `.node` (markers from point data `triangle:marker` when
//!   present), `.ele` when there are triangles (or when the main file is the `.ele` or
//!   `.area`), `.poly` with 0 vertices when there are segments, holes or regions (as
//!   Triangle's own output `.poly` files are), `.area` when there is cell data
//!   `triangle:area` (or when it is the main file; -1, no bound, for every triangle).
//! - `.poly`: with triangles, the same set with the `.poly` as main file; without
//!   triangles, one self-contained PSLG (vertices, segments, holes, regions).
//! - `.edge`: `.edge` (Line cells and Voronoi rays) beside `.node` and `.ele`; holes and
//!   regions are reported as dropped, since a `.poly` beside it would take precedence.
//! - no name (stdout): a self-contained `.poly` when there are no triangles but segments,
//!   holes or regions, otherwise the `.node` as main file and its siblings (which stdout
//!   cannot hold: the caller says so).
//!
//! The first triangle attribute is the physical tag (when any triangle has one), followed
//! by cell data `triangle:attribute2`...; without tags, the `triangle:attribute<k>`
//! arrays are written as they are. Numbering is 1-based, as Triangle writes by default.
//! Everything Triangle cannot hold is listed in the report: z coordinates, quadrilaterals,
//! second-order lines, point cells, geometrical tags that differ from the physical ones,
//! tag names, Gmsh entities, point and cell sets, and every point or cell array that is
//! not one of the `triangle:` arrays above.

mod read;
mod write;

use crate::{ReadContext, Result, TaggedMesh, WriteOptions, Written};

/// Point data holding the boundary marker of each vertex.
pub const MARKER: &str = "triangle:marker";
/// Prefix of the attribute arrays (`triangle:attribute1`, ...), point or cell data.
pub const ATTRIBUTE_PREFIX: &str = "triangle:attribute";
/// Cell data holding the area bound of each triangle (`.area`), -1 for none.
pub const AREA: &str = "triangle:area";
/// Cell data holding the direction of each Voronoi ray (3 components, z = 0).
pub const RAY_DIRECTION: &str = "triangle:ray_direction";

/// The name of attribute array `k` (1-based).
pub fn attribute_name(k: usize) -> String {
    format!("{ATTRIBUTE_PREFIX}{k}")
}

/// Which file of the set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Node,
    Ele,
    Poly,
    Edge,
    Area,
}

impl Kind {
    const ALL: [Kind; 5] = [Kind::Node, Kind::Ele, Kind::Poly, Kind::Edge, Kind::Area];

    fn ext(self) -> &'static str {
        match self {
            Kind::Node => "node",
            Kind::Ele => "ele",
            Kind::Poly => "poly",
            Kind::Edge => "edge",
            Kind::Area => "area",
        }
    }

    fn from_ext(ext: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.ext().eq_ignore_ascii_case(ext))
    }
}

/// Reads a Triangle file and the files of its set beside it (see the module documentation).
pub fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read::read(bytes, ctx)
}

/// Writes a mesh as a Triangle file set (see the module documentation).
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    write::write(mesh, opts)
}
