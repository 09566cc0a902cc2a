//! The reader's state, shared by MSH 2.2 and 4.1: the cursor, the nodes and element
//! blocks as read, tag maps, names and entities; and the sections both versions share
//! (`$MeshFormat`, `$PhysicalNames`, the sections skipped).

use std::collections::BTreeMap;

use super::cursor::{le_i32, show, Cursor};
use super::tags::{TagList, TagMap};
use super::views::View;
use crate::text;
use crate::{CellKind, Error, ErrorKind, NodeIndex, Position, Result, MAX_POINTS};

/// Elements of one kind as read, before they are put in tag order.
pub(super) struct RawBlock {
    pub kind: CellKind,
    pub at: Position,
    pub tags: TagList,
    /// Node positions in file order (indices into `Reader::points`).
    pub nodes: Vec<NodeIndex>,
    /// Per cell; empty for 4.1 blocks until `finish` fills them from the entity.
    pub physical: Vec<i32>,
    pub geometrical: Vec<i32>,
    /// 4.1: the `(dim, tag)` entity of the block.
    pub entity: Option<(u8, i32)>,
}

pub(super) struct Reader<'a> {
    pub c: Cursor<'a>,
    pub v4: bool,
    /// Bytes of a binary `size_t` (4.1).
    pub size_t: usize,
    pub points: Vec<[f64; 3]>,
    /// Node tags in file order: a range while they count up by one.
    pub node_tags: TagList,
    /// First node index of each node block and where the block starts.
    pub node_blocks: Vec<(usize, Position)>,
    pub(super) node_map: Option<TagMap>,
    pub raw: Vec<RawBlock>,
    pub n_raw_cells: usize,
    pub(super) elem_map: Option<TagMap>,
    /// 2.2 copies of an element for another physical group: tag → raw cell id.
    pub aliases: Vec<(u64, usize)>,
    pub tag_names: BTreeMap<(u8, i32), String>,
    pub entities: BTreeMap<(u8, i32), Vec<i32>>,
    /// 4.1 `$Entities` boxes as read (`[min, max]`; a point's coordinates twice).
    pub entity_boxes: BTreeMap<(u8, i32), [f64; 6]>,
    /// 4.1 `$PartitionedEntities`: `(dim, tag)` → (the geometrical tag its cells get,
    /// its physical tags).
    pub partitioned: BTreeMap<(u8, i32), (i32, Vec<i32>)>,
    /// The number of partitions `$PartitionedEntities` announces (0 without it).
    pub partitions: usize,
    pub(super) views: Vec<View>,
    pub(super) view_count: usize,
    /// Whether a `$NodeData` before any `$Nodes`/`$Elements` is read as a data-only
    /// file's (node tag t = vertex t − 1) rather than refused ([`super::read_mesh_or_data`]).
    pub(super) allow_data_only: bool,
    /// Whether a `$Nodes`, `$ParametricNodes` or `$Elements` section was read.
    pub(super) saw_mesh: bool,
    /// Whether node views were read as a data-only file's.
    pub(super) data_only: bool,
}

impl<'a> Reader<'a> {
    pub(super) fn new(bytes: &'a [u8]) -> Self {
        Reader {
            c: Cursor::new(bytes),
            v4: true,
            size_t: 8,
            points: Vec::new(),
            node_tags: TagList::new(),
            node_blocks: Vec::new(),
            node_map: None,
            raw: Vec::new(),
            n_raw_cells: 0,
            elem_map: None,
            aliases: Vec::new(),
            tag_names: BTreeMap::new(),
            entities: BTreeMap::new(),
            entity_boxes: BTreeMap::new(),
            partitioned: BTreeMap::new(),
            partitions: 0,
            views: Vec::new(),
            view_count: 0,
            allow_data_only: false,
            saw_mesh: false,
            data_only: false,
        }
    }

    pub(super) fn read_mesh_format(&mut self) -> Result<()> {
        let t = &mut self.c.t;
        match t.next() {
            Some(b"$MeshFormat") => {}
            Some(tok) if tok.starts_with(b"$NOD") || tok.starts_with(b"$NOE") => {
                return Err(self.c.err(ErrorKind::Unsupported("MSH version 1 (a file without $MeshFormat); save it as MSH 2.2 or 4.1 with Gmsh".into())))
            }
            // Invisible in a quote: named (Gmsh and meshio do not read such a file either).
            Some(tok) if tok.starts_with("\u{feff}".as_bytes()) => return Err(self.c.err(ErrorKind::Expected { expected: "`$MeshFormat` (a Gmsh MSH file starts with it)".into(), found: "a byte order mark (U+FEFF) before it; remove it (Gmsh does not read such a file either)".into() })),
            Some(tok) => return Err(self.c.err(ErrorKind::Expected { expected: "`$MeshFormat` (a Gmsh MSH file starts with it)".into(), found: show(tok) })),
            None => return Err(self.c.err(ErrorKind::UnexpectedEof { context: "expected `$MeshFormat`; the file is empty".into() })),
        }
        let vtok = self.c.token("the MSH version number")?;
        let version = text::parse_f64(vtok).map_err(|_| {
            self.c.err(ErrorKind::Expected {
                expected: "the MSH version number".into(),
                found: show(vtok),
            })
        })?;
        self.v4 = if (version - 4.1).abs() < 1e-9 {
            true
        } else if (2.0..3.0).contains(&version) {
            false
        } else if (4.0..4.1).contains(&version) {
            return Err(self.c.err(ErrorKind::Unsupported(format!(
                "MSH version {} (smartmesh reads 2.2 and 4.1; save it again with Gmsh: -format msh41)",
                String::from_utf8_lossy(vtok)
            ))));
        } else {
            return Err(self.c.err(ErrorKind::Unsupported(format!(
                "MSH version {} (smartmesh reads 2.2 and 4.1)",
                String::from_utf8_lossy(vtok)
            ))));
        };
        let file_type = self.c.i64("the file type (0 for ASCII, 1 for binary)")?;
        if file_type != 0 && file_type != 1 {
            return Err(self.c.err(ErrorKind::Expected {
                expected: "the file type 0 (ASCII) or 1 (binary)".into(),
                found: format!("`{file_type}`"),
            }));
        }
        let data_size = self.c.i64("the data size")?;
        if file_type == 1 {
            if self.v4 && data_size != 8 && data_size != 4 {
                return Err(self.c.err(ErrorKind::Unsupported(format!(
                    "binary MSH 4.1 with a size_t of {data_size} bytes (4 or 8 expected)"
                ))));
            }
            if !self.v4 && data_size != 8 {
                return Err(self.c.err(ErrorKind::Unsupported(format!(
                    "binary MSH 2 with data size {data_size} (only 8, sizeof(double), is defined)"
                ))));
            }
            self.size_t = data_size as usize;
            self.c.end_text_line()?;
            self.c.binary = true;
            let pos = self.c.pos();
            let b = self.c.take(4, "the endianness marker (the integer 1)")?;
            let le = le_i32(b);
            if le != 1 {
                let kind = if i32::from_be_bytes([b[0], b[1], b[2], b[3]]) == 1 {
                    ErrorKind::Unsupported("a big-endian binary file (the endianness marker, the integer 1, is byte-swapped); smartmesh reads little-endian MSH files: convert it with Gmsh on a little-endian machine".into())
                } else {
                    ErrorKind::Expected {
                        expected: "the endianness marker, the integer 1 as 4 binary bytes".into(),
                        found: format!("bytes {:02x} {:02x} {:02x} {:02x}", b[0], b[1], b[2], b[3]),
                    }
                };
                return Err(self.c.byte_err(pos, kind));
            }
        }
        self.c.expect_end("MeshFormat")
    }

    pub(super) fn read_physical_names(&mut self) -> Result<()> {
        let n = self.c.count("number of physical names", 7)?;
        for _ in 0..n {
            let dim = self.c.i32("physical group dimension")?;
            if !(0..=3).contains(&dim) {
                return Err(self.c.err(ErrorKind::Expected {
                    expected: "a physical group dimension 0 to 3".into(),
                    found: format!("`{dim}`"),
                }));
            }
            let tag = self.c.i32("physical tag")?;
            let at = self.c.here();
            let rest = self.c.t.rest_of_line();
            let name = quoted(rest).ok_or_else(|| {
                self.c.err_at(
                    at,
                    ErrorKind::Expected {
                        expected: "a name in double quotes".into(),
                        found: show(rest),
                    },
                )
            })?;
            self.tag_names.insert((dim as u8, tag), String::from_utf8_lossy(name).into_owned());
        }
        self.c.expect_end("PhysicalNames")
    }

    /// Skips a section smartmesh does not hold (or does not know), up to its `$End` line.
    pub(super) fn skip_section(&mut self, name: &[u8], at: Position) -> Result<()> {
        let mut end = b"\n$End".to_vec();
        end.extend_from_slice(name);
        let rest = self.c.remaining();
        let mut from = 0;
        loop {
            let Some(i) = memchr::memmem::find(&rest[from..], &end) else {
                let n = String::from_utf8_lossy(name);
                return Err(self.c.err_at(
                    at,
                    ErrorKind::UnexpectedEof {
                        context: format!("section `${n}` has no `$End{n}` line"),
                    },
                ));
            };
            let after = from + i + end.len();
            // The marker must be the whole token (`$EndComments`, not `$EndCommentsX`).
            if rest.get(after).map_or(true, |c| c.is_ascii_whitespace()) {
                let pos = self.c.pos() + from + i + 1;
                self.c.seek(pos);
                self.c.t.next();
                return Ok(());
            }
            from = after;
        }
    }

    /// The node tag → node position table, built when first needed after nodes change.
    pub fn take_node_map(&mut self) -> Result<TagMap> {
        // Cells address points with 32-bit indices: past that, no file is read.
        if self.points.len() > MAX_POINTS {
            let at = self.node_blocks.first().map_or(Position::Byte(0), |b| b.1);
            return Err(Error {
                path: None,
                at: Some(at),
                kind: crate::mesh::past_max_points("nodes", self.points.len()),
            });
        }
        if let Some(m) = self.node_map.take() {
            return Ok(m);
        }
        if let TagList::Range { first, len } = self.node_tags {
            if len > 0 {
                // What `build` makes of tags `first, first + 1, ...`, without the pass.
                return Ok(TagMap::Range { first, len });
            }
        }
        TagMap::build(self.node_tags.iter().zip(0..)).map_err(|dup| self.duplicate_node(dup))
    }

    pub(super) fn duplicate_node(&self, dup: u64) -> Error {
        // Where the second definition is: the block holding its last occurrence.
        let last = self.node_tags.iter().rposition(|t| t == dup).unwrap_or(0);
        let at = self
            .node_blocks
            .iter()
            .rev()
            .find(|(start, _)| *start <= last)
            .map_or(Position::Byte(0), |b| b.1);
        Error {
            path: None,
            at: Some(at),
            kind: ErrorKind::Inconsistent(format!(
                "node tag {dup} is defined twice (the second time in the node block here)"
            )),
        }
    }

    pub fn put_node_map(&mut self, m: TagMap) {
        self.node_map = Some(m);
    }

    pub fn nodes_changed(&mut self) {
        self.node_map = None;
    }

    pub fn push_raw(&mut self, b: RawBlock) {
        self.n_raw_cells += b.tags.len();
        self.elem_map = None;
        self.raw.push(b);
    }

    pub(super) fn raw_tags(&self) -> impl Iterator<Item = (u64, usize)> + Clone + '_ {
        self.raw.iter().flat_map(|b| b.tags.iter()).zip(0..).chain(self.aliases.iter().copied())
    }

    pub(super) fn take_elem_map(&mut self) -> Result<TagMap> {
        if let Some(m) = self.elem_map.take() {
            return Ok(m);
        }
        TagMap::build(self.raw_tags()).map_err(|dup| self.duplicate_element(dup))
    }

    pub(super) fn duplicate_element(&self, dup: u64) -> Error {
        let at = self
            .raw
            .iter()
            .rev()
            .find(|b| b.tags.contains(dup))
            .map_or(Position::Byte(0), |b| b.at);
        Error {
            path: None,
            at: Some(at),
            kind: ErrorKind::Inconsistent(format!(
                "element tag {dup} is used twice (the second time in the element block here)"
            )),
        }
    }
}

/// The text between the first pair of double quotes of a line.
pub(super) fn quoted(line: &[u8]) -> Option<&[u8]> {
    let a = memchr::memchr(b'"', line)?;
    let b = memchr::memchr(b'"', &line[a + 1..])?;
    Some(&line[a + 1..a + 1 + b])
}

/// The kind of a Gmsh element type, or an error that names the type.
pub(super) fn cell_kind(t: i32) -> std::result::Result<CellKind, ErrorKind> {
    CellKind::from_gmsh_type(t).ok_or_else(|| {
        let name = match t {
            20 => "9-node third-order incomplete triangle",
            21 => "10-node third-order triangle",
            22 => "12-node fourth-order incomplete triangle",
            23 => "15-node fourth-order triangle",
            24 => "15-node fifth-order incomplete triangle",
            25 => "21-node fifth-order triangle",
            26 => "4-node third-order line",
            27 => "5-node fourth-order line",
            28 => "6-node fifth-order line",
            29..=31 => "high-order tetrahedron",
            36 | 37 => "high-order quadrangle",
            92 | 93 => "high-order hexahedron",
            _ => "an element type smartmesh does not know",
        };
        ErrorKind::Unsupported(format!(
            "Gmsh element type {t} ({name}): smartmesh reads points, lines, triangles, quadrangles, tetrahedra, hexahedra, prisms and pyramids of order 1 and 2 (types 1 to 19)"
        ))
    })
}

/// An error met reading the node tags of the ASCII element record on `line`: when it is
/// on a later line, the record ended before its nodes did (a tetrahedron of 3 nodes
/// before `$EndElements`), which is said at the record's line as `expected`.
pub(super) fn short_record(e: Error, line: u64, expected: impl FnOnce() -> String) -> Error {
    match e.at {
        Some(Position::Line(l)) if l != line => Error::at_line(
            line,
            ErrorKind::Expected { expected: expected(), found: "fewer values on the line".into() },
        ),
        _ => e,
    }
}
