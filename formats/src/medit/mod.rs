//! Medit / MMG meshes: `.mesh` (ASCII) and `.meshb` (binary), with their solution files
//! `.sol` / `.solb`.
//!
//! Sources: the libMeshb keyword table and reader (LoicMarechal/libMeshb
//! `sources/libmeshb7.c`, `Documentation/libMeshb7.tex`) and MMG's readers
//! (MmgTools/mmg `src/mmg2d/inout_2d.c`, `src/common/inout.c`); meshio's
//! `src/meshio/medit/_medit.py` for comparison.
//!
//! # Files
//! A file is a sequence of keywords, each followed by its data. ASCII files write the
//! keyword's name; binary files start with the endianness code (the 32-bit integer 1, read
//! as 16777216 in the other byte order) and the version, then give each keyword as its code
//! and the byte offset of the next keyword. The version sets the binary sizes: 1 = 32-bit
//! reals, 2 = 64-bit reals, 3 = 64-bit offsets, 4 = 64-bit integers too. Every keyword of
//! libMeshb's table is known (its name, whether a count follows, the layout of an item),
//! so keywords smartmesh does not use are skipped, in ASCII by their layout and in binary
//! by the next-keyword offset. A name that is not in the table is an error.
//!
//! # Reading
//! - `MeshVersionFormatted` 1 to 4, `Dimension` 2 or 3 (z is kept, `coordinate_dim` 3).
//! - `Vertices` with their references (point data `medit:ref`, present only when some
//!   reference is not 0); `Edges`, `Triangles`, `Quadrilaterals`, `Tetrahedra`,
//!   `Prisms`, `Hexahedra`, `Pyramids`: the reference is the physical and geometrical
//!   tag. Their nodes are in Gmsh's order (a prism's bottom triangle then its top, a
//!   pyramid's base then its apex; MMG's tetrahedra have Gmsh's positive orientation).
//! - Second order: `EdgesP2` (ends, then middle, as libMeshb documents it),
//!   `TrianglesP2`, `QuadrilateralsQ2`, `TetrahedraP2`, `PrismsP2` (18 nodes),
//!   `HexahedraQ2` (27), `PyramidsP2` (14). libMeshb fixes no order for their nodes
//!   (it leaves it to optional `...Ordering` keywords, which smartmesh does not read).
//!   `TetrahedraP2` follows Gmsh's Medit writer, the one tool seen writing them: Gmsh's
//!   order with its last two edge nodes swapped (edges 0-1, 1-2, 2-0, 0-3, 1-3, 2-3; a
//!   test compares the `.mesh` Gmsh writes with the nodes its API gives). No tool was found
//!   that writes the others (Gmsh 4.15 writes 27-node hexahedra under `Hexahedra`),
//!   so their nodes are taken in Gmsh's order as they are, as for `QuadrilateralsQ2`.
//!   Blocks come out in the order lines, triangles, quadrilaterals, tetrahedra, prisms,
//!   hexahedra, pyramids, then second order, whatever the order in the file.
//! - `Corners`, `RequiredVertices` become point sets of those names (0-based point
//!   indices); `Ridges`, `RequiredEdges` (edge numbers), `RequiredTriangles`,
//!   `RequiredQuadrilaterals` become cell sets of those names (global cell indices).
//! - Polyhedra and third- or fourth-order elements are refused with their keyword.
//! - After a solution (`SolAtVertices`), keywords libMeshb's table does not define (a
//!   solver's own, as `CFL`, `Model`, `Residu` in MMG's `naca-multiSols.sol`) are
//!   skipped with what follows them up to the next keyword of the table, as MMG skips
//!   them; the read report names them. Before a solution such a keyword is an error.
//! - `SolAtVertices`, in the mesh file or in the `.sol`/`.solb` beside it (for `x.mesh`,
//!   `x.sol` then `x.solb`; for `x.meshb`, `x.solb` then `x.sol`), with any number of
//!   solutions per vertex: type 1 (scalar) becomes point data `size`, type 2 (vector)
//!   `vector` (3 components, z = 0 in 2D), type 3 (symmetric tensor, written m11 m12 m22 in
//!   2D and m11 m12 m22 m13 m23 m33 in 3D, not VTK's order) `metric` (in 2D packed as the
//!   file has it, `Layout::Symmetric2`: m11 m12 m22, standing for the 9-component tensor
//!   with zz = 1; in 3D 9 components, row-major), type 4 (full matrix) `matrix`; a second
//!   solution of the same type gets `_2`, and so on. The 3D order is the file's, not
//!   MMG's C API's (m11 m12 m13 m22 m23 m33): MMG's reader swaps the third and fourth
//!   values. `mmg3d_O3` adapting to an oblique constant metric written so makes edges of
//!   unit metric length (tests/medit3d.rs).
//!
//! # Writing
//! `x.meshb` writes binary, `x.mesh` ASCII; other names (or stdout) follow
//! `MeditWrite::binary`. The extension wins over the option because MMG and
//! libMeshb choose how to read a file from its extension. The mesh is written with
//! `MeshVersionFormatted 2` (64-bit reals; 3 when a binary file passes 2 GiB), `Dimension 2`
//! unless a z coordinate is not 0 or the mesh has volume elements. The physical tag is
//! the reference. The solution file
//! beside it (`.sol` or `.solb`) holds point data `metric` as a type-3 tensor, or `size` as
//! a scalar when there is no metric: MMG reads one solution. (The `mmg2d_O3` command looks
//! for `x.sol` beside `x.meshb` unless told `-sol x.solb`; it writes `.sol` itself.)
//! Everything else is reported as dropped: other point and cell data, geometrical tags
//! that differ from the physical ones, tag names, Gmsh entities, the tags of point
//! cells, serendipity elements (8-node quadrilaterals, 20-node hexahedra, 15-node prisms,
//! 13-node pyramids), holes and regions, and point or cell sets other than
//! the six above. Point cells (topological points) are written as `Corners` and
//! `RequiredVertices` entries (joined with those point sets, sorted), so that MMG keeps
//! them where they are, as the mmg2d adapter does.
//!
//! [`read_sol`] and [`write_sol`] read and write a solution file alone, for the sizing
//! engine that writes metrics.
//!
//! # Code
//! `ascii` and `binary` read a file into `Parsed` and serialise `write::Out`; this file
//! holds the keyword tables and builds the mesh; `sol` turns a `SolAtVertices` into
//! named arrays; `write` makes the writer's choices and reports what it drops.

mod ascii;
mod binary;
mod keywords;
mod sol;
mod write;

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::{Error, ErrorKind, Position, Result};
use crate::io::refused;
use crate::{
    tensor9_to_sym2, CellBlock, CellKind, DataArray, Format, Layout, NodeIndex, ReadContext,
    ReadReport, TaggedMesh, WriteOptions, WriteReport, Written, MAX_POINTS,
};

use keywords::KEYWORDS;
use sol::{identity_layout, sol_arrays};
pub use sol::{read_sol, read_sol_alone};
pub(crate) use write::write_into;
pub use write::{write, write_sol, MeditWrite};
use write::{Out, Single, SolOut};

/// The Medit reader checks coordinates, node numbers, set items and solution lengths as
/// it reads them; its writer checks coordinates and node numbers in the passes that
/// write them, with the error of [`crate::io::refused`].
pub(crate) const CHECKS: crate::Checks =
    crate::Checks { reader_validates: true, writer_validates: true };

/// Point data holding the reference of each vertex.
pub const REF: &str = "medit:ref";

// Keyword codes smartmesh reads or writes (positions in libMeshb's table).
const KW_VERSION: usize = 1;
const KW_DIMENSION: usize = 3;
const KW_VERTICES: usize = 4;
const KW_EDGES: usize = 5;
const KW_TRIANGLES: usize = 6;
const KW_QUADRILATERALS: usize = 7;
const KW_TETRAHEDRA: usize = 8;
const KW_PRISMS: usize = 9;
const KW_HEXAHEDRA: usize = 10;
const KW_CORNERS: usize = 13;
const KW_RIDGES: usize = 14;
const KW_REQUIRED_VERTICES: usize = 15;
const KW_REQUIRED_EDGES: usize = 16;
const KW_REQUIRED_TRIANGLES: usize = 17;
const KW_REQUIRED_QUADRILATERALS: usize = 18;
const KW_TRIANGLES_P2: usize = 24;
const KW_EDGES_P2: usize = 25;
const KW_QUADRILATERALS_Q2: usize = 27;
const KW_TETRAHEDRA_P2: usize = 30;
const KW_HEXAHEDRA_Q2: usize = 33;
const KW_PYRAMIDS: usize = 49;
const KW_PRISMS_P2: usize = 86;
const KW_PYRAMIDS_P2: usize = 87;
const KW_END: usize = 54;
const KW_SOL_AT_VERTICES: usize = 62;
const KW_FLOAT_PRECISION: usize = 155;

/// Element keywords smartmesh keeps, and their cell kinds (in the order blocks come out).
const ELEMENTS: [(usize, CellKind); 14] = [
    (KW_EDGES, CellKind::Line),
    (KW_TRIANGLES, CellKind::Triangle),
    (KW_QUADRILATERALS, CellKind::Quad),
    (KW_TETRAHEDRA, CellKind::Tetra),
    (KW_PRISMS, CellKind::Wedge),
    (KW_HEXAHEDRA, CellKind::Hexa),
    (KW_PYRAMIDS, CellKind::Pyramid),
    (KW_EDGES_P2, CellKind::Line3),
    (KW_TRIANGLES_P2, CellKind::Triangle6),
    (KW_QUADRILATERALS_Q2, CellKind::Quad9),
    (KW_TETRAHEDRA_P2, CellKind::Tetra10),
    (KW_PRISMS_P2, CellKind::Wedge18),
    (KW_HEXAHEDRA_Q2, CellKind::Hexa27),
    (KW_PYRAMIDS_P2, CellKind::Pyramid14),
];

/// The most nodes an element of [`ELEMENTS`] has (`HexahedraQ2`).
const MAX_NODES: usize = 27;

/// Where each node of a Medit element is in Gmsh's order, for the kinds whose orders
/// differ: Medit's node `j` is Gmsh's node `order[j]` (see the module documentation).
fn gmsh_positions(kind: CellKind) -> Option<&'static [usize]> {
    match kind {
        CellKind::Tetra10 => Some(&[0, 1, 2, 3, 4, 5, 6, 7, 9, 8]),
        _ => None,
    }
}

/// Element keywords smartmesh cannot hold: refused with their count.
const UNSUPPORTED: [&str; 9] = [
    "Polyhedra",
    "TetrahedraP3",
    "TetrahedraP4",
    "HexahedraQ3",
    "HexahedraQ4",
    "PyramidsP3",
    "PyramidsP4",
    "PrismsP3",
    "PrismsP4",
];

/// Why [`UNSUPPORTED`] elements are refused.
const UNSUPPORTED_WHY: &str =
    "smartmesh reads first- and second-order elements (no polyhedra, no third or fourth order)";

/// Sets of vertices (point sets) and of elements (cell sets): keyword, and the element
/// kind the numbers refer to (`None` for vertices).
const SETS: [(usize, Option<CellKind>); 6] = [
    (KW_CORNERS, None),
    (KW_REQUIRED_VERTICES, None),
    (KW_RIDGES, Some(CellKind::Line)),
    (KW_REQUIRED_EDGES, Some(CellKind::Line)),
    (KW_REQUIRED_TRIANGLES, Some(CellKind::Triangle)),
    (KW_REQUIRED_QUADRILATERALS, Some(CellKind::Quad)),
];

fn element_kind(code: usize) -> Option<CellKind> {
    ELEMENTS.iter().find(|(c, _)| *c == code).map(|&(_, k)| k)
}

fn set_target(code: usize) -> Option<Option<CellKind>> {
    SETS.iter().find(|(c, _)| *c == code).map(|&(_, k)| k)
}

fn is_unsupported(code: usize) -> bool {
    UNSUPPORTED.contains(&KEYWORDS[code].name)
}

/// The code of a keyword name.
fn lookup(name: &[u8]) -> Option<usize> {
    KEYWORDS.iter().position(|k| k.name.as_bytes() == name && k.name != "Reserved")
}

/// Number of reals of one solution of `typ` (1 scalar, 2 vector, 3 symmetric, 4 matrix).
fn sol_size(typ: u32, dim: u8) -> Option<usize> {
    let d = dim as usize;
    match typ {
        1 => Some(1),
        2 => Some(d),
        3 => Some(d * (d + 1) / 2),
        4 => Some(d * d),
        _ => None,
    }
}

// ---------------------------------------------------------------------------------------
// What the two readers produce
// ---------------------------------------------------------------------------------------

/// Elements of one kind, 0-based node numbers (at least 0; the upper bound is checked
/// once every keyword is read, when `unchecked`).
#[derive(Debug)]
struct Elements {
    kind: CellKind,
    nodes: Vec<NodeIndex>,
    refs: Vec<i32>,
    /// Where each element is, for errors found after reading.
    at: Locator,
    /// Whether the node numbers are still to be checked against the vertex count.
    unchecked: bool,
}

/// Where item `i` of a keyword is in the file.
#[derive(Debug, Clone, Copy)]
enum Locator {
    /// An ASCII keyword at this line (items are not located more precisely).
    Line(u64),
    /// A binary block: first item at `start`, `size` bytes each.
    Bytes { start: u64, size: u64 },
}

impl Locator {
    fn at(self, i: usize) -> Position {
        match self {
            Locator::Line(l) => Position::Line(l),
            Locator::Bytes { start, size } => Position::Byte(start + size * i as u64),
        }
    }
}

/// Numbers of a set keyword, 0-based.
#[derive(Debug)]
struct Set {
    code: usize,
    items: Vec<usize>,
    at: Vec<Position>,
}

/// Solutions at vertices.
#[derive(Debug, Default)]
struct Sol {
    n: usize,
    types: Vec<u32>,
    /// `n * Σ sol_size(type)` values, vertex-major (empty when `raw` is given).
    values: Vec<f64>,
    /// Binary little-endian 8-byte values, checked finite but left in the file: where they
    /// start. They are decoded straight into the arrays.
    raw: Option<usize>,
    at: Option<Position>,
}

/// A file as read, before indices are resolved.
#[derive(Debug, Default)]
struct Parsed {
    dim: u8,
    points: Vec<[f64; 3]>,
    /// The vertices' references; empty when the binary reader found them all 0.
    refs: Vec<i32>,
    vertices_read: bool,
    elements: Vec<Elements>,
    sets: Vec<Set>,
    sol: Option<Sol>,
    /// Unknown keywords skipped after the solution, with their lines (ASCII).
    skipped: Vec<(String, u64)>,
}

/// The read note for the unknown keywords `skipped` after the solution of `file` (the
/// solution file beside the mesh; `None`: the mesh file itself).
fn skipped_note(file: Option<&str>, skipped: &[(String, u64)]) -> Option<String> {
    let (_, first) = skipped.first()?;
    let names: Vec<&str> = skipped.iter().map(|(n, _)| n.as_str()).collect();
    Some(format!(
        "{}keywords after the solution that libMeshb does not define, skipped from line {first} (as MMG skips them): {}",
        file.map(|f| format!("{f}: ")).unwrap_or_default(),
        names.join(", ")
    ))
}

/// The error for a vertex or item number that names nothing: below 1 (Medit numbers from
/// 1, which the message says), or past the `available` items (the vertices read so far).
fn bad_number(what: String, v: i64, available: usize) -> ErrorKind {
    let what = if v < 1 { format!("{what}, numbered from 1,") } else { what };
    ErrorKind::IndexOutOfRange { what, index: v, available }
}

fn error_at(at: Position, kind: ErrorKind) -> Error {
    Error { path: None, at: Some(at), kind }
}

fn is_binary(bytes: &[u8]) -> bool {
    bytes.len() >= 4 && matches!(bytes[..4], [1, 0, 0, 0] | [0, 0, 0, 1])
}

fn parse(bytes: &[u8], binary: bool) -> Result<Parsed> {
    if binary {
        binary::read(bytes)
    } else {
        ascii::read(bytes)
    }
}

// ---------------------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------------------

/// Reads a Medit mesh (ASCII or binary, told by its first bytes) and the solution file
/// beside it (see the module documentation).
pub fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read_reported(bytes, ctx).map(|(mesh, _)| mesh)
}

/// [`read`], with what the reader could not keep (unknown keywords after a solution).
pub fn read_reported(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<(TaggedMesh, ReadReport)> {
    let mut report = ReadReport::default();
    // The first bytes tell (an ASCII file starts with a letter, a comment or a space); a
    // `.meshb` that is neither gets the binary reader's error about its endianness code.
    let binary = is_binary(bytes) || ctx.extension == "meshb";
    let p = parse(bytes, binary)?;
    // A mesh has vertices: an empty file (or one of comments) is not a mesh of 0 points.
    if !p.vertices_read {
        let missing =
            if p.dim == 0 { "Dimension and Vertices keywords" } else { "a Vertices keyword" };
        return Err(Error::new(ErrorKind::Expected {
            expected: format!("{missing} (a Medit mesh lists its vertices)"),
            found: if bytes.is_empty() { "an empty file".into() } else { "none".into() },
        }));
    }
    report.notes.extend(skipped_note(None, &p.skipped));
    let mut mesh = assemble(p, bytes)?;
    let order: [&str; 2] = if ctx.extension == "meshb" { ["solb", "sol"] } else { ["sol", "solb"] };
    for ext in order {
        if let Some(sol_bytes) = ctx.siblings.sibling_bytes(ext)? {
            let in_sol = |e: Error| e.with_path(ctx.siblings.describe(ext));
            // A solution file of 0 bytes is a write that failed, not "no solution".
            if sol_bytes.is_empty() {
                return Err(in_sol(Error::new(ErrorKind::Expected {
                    expected: "a solution file beside the mesh (SolAtVertices)".into(),
                    found: "an empty file; write it again or remove it".into(),
                })));
            }
            let p = parse(&sol_bytes, is_binary(&sol_bytes)).map_err(in_sol)?;
            report.notes.extend(skipped_note(Some(&ctx.siblings.describe(ext)), &p.skipped));
            let sol = p.sol.unwrap_or_default();
            if sol.types.is_empty() {
                break;
            }
            if p.dim != 0 && p.dim != mesh.coordinate_dim {
                return Err(in_sol(Error::new(ErrorKind::Inconsistent(format!(
                    "the solution is {}D but the mesh is {}D",
                    p.dim, mesh.coordinate_dim
                )))));
            }
            for (name, a) in
                sol_arrays(sol, p.dim, mesh.points.len(), &sol_bytes).map_err(in_sol)?
            {
                mesh.point_data.insert(name, a);
            }
            break;
        }
    }
    Ok((mesh, report))
}

/// Resolves indices and builds the mesh (`bytes`: the file it was read from).
fn assemble(p: Parsed, bytes: &[u8]) -> Result<TaggedMesh> {
    let nv = p.points.len();
    if p.dim == 0 && (!p.points.is_empty() || !p.elements.is_empty()) {
        return Err(Error::new(ErrorKind::Expected {
            expected: "a Dimension keyword".into(),
            found: "none".into(),
        }));
    }
    let mut mesh = TaggedMesh::new();
    mesh.coordinate_dim = if p.dim == 3 { 3 } else { 2 };
    mesh.points = p.points;
    if p.refs.iter().any(|&r| r != 0) {
        mesh.point_data
            .insert(REF.into(), DataArray::new(1, p.refs.iter().map(|&r| r as f64).collect()));
    }
    for e in &p.elements {
        if !e.unchecked || e.nodes.is_empty() {
            continue;
        }
        let k = e.kind.nodes_per_cell();
        if let Some(pos) = e.nodes.iter().position(|&v| v as usize >= nv) {
            return Err(error_at(
                e.at.at(pos / k),
                ErrorKind::IndexOutOfRange {
                    what: format!(
                        "{} {} ({})",
                        e.kind.name(),
                        pos / k + 1,
                        KEYWORDS[element_code(e.kind)].name
                    ),
                    index: e.nodes[pos] as i64 + 1,
                    available: nv,
                },
            ));
        }
    }
    // Blocks in a fixed order; several keywords of one kind are joined (the first one
    // moved, not copied).
    let mut offsets = BTreeMap::new();
    let mut total = 0;
    let mut elements = p.elements;
    for &(_, kind) in &ELEMENTS {
        let mut block = CellBlock::new(kind);
        for e in elements.iter_mut().filter(|e| e.kind == kind) {
            if block.nodes.is_empty() {
                block.nodes = std::mem::take(&mut e.nodes);
                block.physical = std::mem::take(&mut e.refs);
            } else {
                block.nodes.extend_from_slice(&e.nodes);
                block.physical.extend_from_slice(&e.refs);
            }
        }
        if let Some(order) = gmsh_positions(kind) {
            let mut medit = [0 as NodeIndex; MAX_NODES];
            for cell in block.nodes.chunks_exact_mut(order.len()) {
                medit[..order.len()].copy_from_slice(cell);
                for (j, &g) in order.iter().enumerate() {
                    cell[g] = medit[j];
                }
            }
        }
        offsets.insert(kind, (total, block.len()));
        total += block.len();
        if !block.is_empty() {
            block.geometrical = block.physical.clone();
            mesh.blocks.push(block);
        }
    }
    for s in p.sets {
        let name = KEYWORDS[s.code].name.to_string();
        let target = set_target(s.code).flatten();
        let (offset, available) = match target {
            None => (0, nv),
            Some(kind) => offsets.get(&kind).copied().unwrap_or((0, 0)),
        };
        if let Some(i) = s.items.iter().position(|&v| v >= available) {
            return Err(error_at(
                s.at[i],
                ErrorKind::IndexOutOfRange {
                    what: format!("{name} entry {}", i + 1),
                    index: s.items[i] as i64 + 1,
                    available,
                },
            ));
        }
        let indices = s.items.iter().map(|&v| v + offset);
        match target {
            None => mesh.point_sets.entry(name).or_default().extend(indices),
            Some(_) => mesh.cell_sets.entry(name).or_default().extend(indices),
        }
    }
    if let Some(sol) = p.sol {
        for (name, a) in sol_arrays(sol, p.dim, nv, bytes)? {
            mesh.point_data.insert(name, a);
        }
    }
    Ok(mesh)
}

fn element_code(kind: CellKind) -> usize {
    ELEMENTS.iter().find(|(_, k)| *k == kind).map_or(0, |&(c, _)| c)
}
