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
//!   A mesh with triangles and segments but no holes and regions of its own (one read
//!   from another format) gets them from its triangles in that `.poly` (a point in each
//!   hole, a seed with its tag in each part the segments separate; `seeds`), so that
//!   Triangle `-pA` on the `.poly` meshes the same domain with the same attributes.
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
//! Quads are written as two triangles each (said in the report). Everything Triangle
//! cannot hold is listed in the report: z coordinates, second-order quadrilaterals and
//! lines, point cells, geometrical tags that differ from the physical ones,
//! tag names, Gmsh entities, point and cell sets, and every point or cell array that is
//! not one of the `triangle:` arrays above.

pub(crate) mod parse;
mod read;
pub(crate) mod record;
mod seeds;
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

/// The 1-based line of each record of a self-contained `.poly`, section by section, for
/// a caller that finds something wrong with an item after reading (the mesher reports
/// "segment 7 crosses segment 2"; this says on which line segment 7 is). Records are
/// lines, as Triangle reads them: `#` starts a comment, blank lines are skipped. A `.poly`
/// with 0 vertices lists none (they are in the `.node`). Stops at the first header it
/// cannot read, keeping what it found.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PolyLines {
    /// Line of vertex `i` (0-based, in file order).
    pub vertices: Vec<u64>,
    /// Line of segment `i`.
    pub segments: Vec<u64>,
    /// Line of hole `i`.
    pub holes: Vec<u64>,
    /// Line of region `i`.
    pub regions: Vec<u64>,
}

/// Finds the line of every record of a `.poly` (see [`PolyLines`]).
pub fn poly_lines(bytes: &[u8]) -> PolyLines {
    let mut records = bytes.split(|&b| b == b'\n').enumerate().filter_map(|(i, line)| {
        let line = line.split(|&b| b == b'#').next().unwrap_or_default();
        let first = line.split(|b| b.is_ascii_whitespace()).find(|t| !t.is_empty())?;
        Some((i as u64 + 1, first))
    });
    let mut out = PolyLines::default();
    // A header (its first number is the count), then that many records.
    fn section<'a>(
        records: &mut impl Iterator<Item = (u64, &'a [u8])>,
        into: &mut Vec<u64>,
    ) -> bool {
        let Some(n) =
            records.next().and_then(|(_, t)| std::str::from_utf8(t).ok()?.parse::<usize>().ok())
        else {
            return false;
        };
        into.extend(records.take(n).map(|(l, _)| l));
        true
    }
    let _ = section(&mut records, &mut out.vertices)
        && section(&mut records, &mut out.segments)
        && section(&mut records, &mut out.holes)
        && section(&mut records, &mut out.regions);
    out
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

/// Triangle's reader leaves node numbers of lines and data lengths to `validate`.
pub(crate) const CHECKS: crate::Checks = crate::Checks::NONE;

/// Reads a Triangle file and the files of its set beside it (see the module documentation).
pub fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read::read(bytes, ctx)
}

/// Writes a mesh as a Triangle file set (see the module documentation).
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    write::write(mesh, opts)
}

#[cfg(test)]
mod poly_lines_tests {
    use super::*;

    #[test]
    fn lines_of_records_skip_comments_and_blanks() {
        let text = "# a square\n4 2 0 1\n1 0 0\n2 1 0\n\n3 1 1 # top\n4 0 1\n4 1\n1 1 2 5\n2 2 3 5\n3 3 4 5\n4 4 1 5\n# holes\n1\n1 0.5 0.5\n0\n";
        let l = poly_lines(text.as_bytes());
        assert_eq!(l.vertices, vec![3, 4, 6, 7]);
        assert_eq!(l.segments, vec![9, 10, 11, 12]);
        assert_eq!(l.holes, vec![15]);
        assert!(l.regions.is_empty());
    }
}
