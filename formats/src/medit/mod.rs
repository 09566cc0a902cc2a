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
//!   reference is not 0); `Edges`, `Triangles`, `Quadrilaterals`: the reference is the
//!   physical and geometrical tag. `EdgesP2` (ends, then middle, as libMeshb documents
//!   it), `TrianglesP2` and `QuadrilateralsQ2` are read and written with their nodes as
//!   they are, taken to be in smartmesh's (Gmsh's) order: libMeshb leaves that order to
//!   optional `...Ordering` keywords, which smartmesh does not read. Blocks come out in the order lines,
//!   triangles, quadrilaterals, then second order, whatever the order in the file.
//! - `Corners`, `RequiredVertices` become point sets of those names (0-based point
//!   indices); `Ridges`, `RequiredEdges` (edge numbers), `RequiredTriangles`,
//!   `RequiredQuadrilaterals` become cell sets of those names (global cell indices).
//! - Volume elements (tetrahedra, prisms, ...) are refused: smartmesh meshes are 2D.
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
//!   with zz = 1; in 3D 9 components), type 4 (full matrix) `matrix`; a second solution of the same type gets `_2`,
//!   and so on.
//!
//! # Writing
//! `x.meshb` writes binary, `x.mesh` ASCII; other names (or stdout) follow
//! `MeditWrite::binary`. The extension wins over the option because MMG and
//! libMeshb choose how to read a file from its extension. The mesh is written with
//! `MeshVersionFormatted 2` (64-bit reals; 3 when a binary file passes 2 GiB), `Dimension 2`
//! unless a z coordinate is not 0. The physical tag is the reference. The solution file
//! beside it (`.sol` or `.solb`) holds point data `metric` as a type-3 tensor, or `size` as
//! a scalar when there is no metric: MMG reads one solution. (The `mmg2d_O3` command looks
//! for `x.sol` beside `x.meshb` unless told `-sol x.solb`; it writes `.sol` itself.)
//! Everything else is reported as dropped: other point and cell data, geometrical tags
//! that differ from the physical ones, tag names, Gmsh entities, the tags of point
//! cells, 8-node quadrilaterals, holes and regions, and point or cell sets other than
//! the six above. Point cells (topological points) are written as `Corners` and
//! `RequiredVertices` entries (joined with those point sets, sorted), so that MMG keeps
//! them where they are, as the mmg2d adapter does.
//!
//! [`read_sol`] and [`write_sol`] read and write a solution file alone, for the sizing
//! engine that writes metrics.

mod ascii;
mod binary;
mod keywords;

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::{Error, ErrorKind, Position, Result};
use crate::io::refused;
use crate::{
    tensor9_to_sym2, CellBlock, CellKind, DataArray, Format, Layout, NodeIndex, ReadContext,
    ReadReport, TaggedMesh, WriteOptions, WriteReport, Written, MAX_POINTS,
};

use keywords::KEYWORDS;

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
const KW_CORNERS: usize = 13;
const KW_RIDGES: usize = 14;
const KW_REQUIRED_VERTICES: usize = 15;
const KW_REQUIRED_EDGES: usize = 16;
const KW_REQUIRED_TRIANGLES: usize = 17;
const KW_REQUIRED_QUADRILATERALS: usize = 18;
const KW_TRIANGLES_P2: usize = 24;
const KW_EDGES_P2: usize = 25;
const KW_QUADRILATERALS_Q2: usize = 27;
const KW_END: usize = 54;
const KW_SOL_AT_VERTICES: usize = 62;
const KW_FLOAT_PRECISION: usize = 155;

/// Element keywords smartmesh keeps, and their cell kinds (in the order blocks come out).
const ELEMENTS: [(usize, CellKind); 6] = [
    (KW_EDGES, CellKind::Line),
    (KW_TRIANGLES, CellKind::Triangle),
    (KW_QUADRILATERALS, CellKind::Quad),
    (KW_EDGES_P2, CellKind::Line3),
    (KW_TRIANGLES_P2, CellKind::Triangle6),
    (KW_QUADRILATERALS_Q2, CellKind::Quad9),
];

/// Volume elements: a 2D toolchain cannot hold them.
const VOLUMES: [&str; 16] = [
    "Tetrahedra",
    "Prisms",
    "Hexahedra",
    "TetrahedraP2",
    "HexahedraQ2",
    "Polyhedra",
    "Pyramids",
    "PrismsP2",
    "PyramidsP2",
    "TetrahedraP3",
    "TetrahedraP4",
    "HexahedraQ3",
    "HexahedraQ4",
    "PyramidsP3",
    "PyramidsP4",
    "PrismsP3",
];

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

fn is_volume(code: usize) -> bool {
    VOLUMES.contains(&KEYWORDS[code].name)
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

/// Reads a solution file (`.sol` when `binary` is false, `.solb` when true) whose
/// `SolAtVertices` must cover `n_vertices` vertices. Returns the arrays named as in the
/// module documentation (`size`, `vector`, `metric`, `matrix`); an empty map when the
/// file has no solution at vertices.
pub fn read_sol(
    bytes: &[u8],
    n_vertices: usize,
    binary: bool,
) -> Result<BTreeMap<String, DataArray>> {
    let p = parse(bytes, binary)?;
    match p.sol {
        Some(sol) => sol_arrays(sol, p.dim, n_vertices, bytes),
        None => Ok(BTreeMap::new()),
    }
}

/// Reads a solution file given without its mesh (ASCII or binary, told by its first
/// bytes, as [`read`] tells a sibling's): the number of vertices its `SolAtVertices`
/// covers and the arrays of [`read_sol`] for that number, `None` when the file has no
/// solution at vertices. The caller compares the count with its mesh's.
pub fn read_sol_alone(bytes: &[u8]) -> Result<Option<(usize, BTreeMap<String, DataArray>)>> {
    let p = parse(bytes, is_binary(bytes))?;
    match p.sol {
        Some(sol) if !sol.types.is_empty() => {
            let n = sol.n;
            Ok(Some((n, sol_arrays(sol, p.dim, n, bytes)?)))
        }
        _ => Ok(None),
    }
}

/// Names and converts the solutions of a `SolAtVertices` read from `bytes`.
fn sol_arrays(
    mut sol: Sol,
    dim: u8,
    n_vertices: usize,
    bytes: &[u8],
) -> Result<BTreeMap<String, DataArray>> {
    let at = sol.at.unwrap_or(Position::Line(1));
    if sol.n != n_vertices {
        return Err(error_at(
            at,
            ErrorKind::Inconsistent(format!(
                "SolAtVertices gives {} vertices, the mesh has {n_vertices}",
                sol.n
            )),
        ));
    }
    let sizes: Vec<usize> = sol.types.iter().map(|&t| sol_size(t, dim).unwrap_or(0)).collect();
    let stride: usize = sizes.iter().sum();
    let n_values = if sol.raw.is_some() { sol.n * stride } else { sol.values.len() };
    if sizes.contains(&0) || n_values != sol.n * stride {
        return Err(error_at(
            at,
            ErrorKind::Inconsistent(format!(
                "SolAtVertices holds {} values, expected {} vertices of {stride}",
                sol.values.len(),
                sol.n
            )),
        ));
    }
    let mut out = BTreeMap::new();
    let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
    let mut offset = 0;
    for (&typ, &size) in sol.types.iter().zip(&sizes) {
        let base = match typ {
            1 => "size",
            2 => "vector",
            3 => "metric",
            _ => "matrix",
        };
        let k = seen.entry(base).or_insert(0);
        *k += 1;
        let name = if *k == 1 { base.to_string() } else { format!("{base}_{k}") };
        let d = dim as usize;
        // A 2D symmetric tensor stays packed as the file has it (m11 m12 m22).
        let packed = typ == 3 && d == 2;
        let comps = if typ == 1 {
            1
        } else if typ == 2 || packed {
            3
        } else {
            9
        };
        // The layout is decided once per field, then each vertex's values are written
        // in place (one pass over the solution, no per-value growth check), decoded
        // from the file's bytes when they were left there.
        let values = match sol.raw {
            Some(start) => {
                let mut values = vec![0.0; comps * sol.n];
                let rows = bytes[start..start + sol.n * stride * 8]
                    .chunks_exact(stride * 8)
                    .map(|r| &r[offset * 8..(offset + size) * 8]);
                convert(
                    &mut values,
                    comps,
                    rows,
                    |r: &&[u8], j| {
                        f64::from_le_bytes(r[8 * j..8 * j + 8].try_into().unwrap_or([0; 8]))
                    },
                    typ,
                    d,
                );
                values
            }
            // Decoded already in the file's order, alone in its rows (the binary reader
            // does so for one such field): the array itself.
            None if stride == size && size == comps && identity_layout(typ, d) => {
                std::mem::take(&mut sol.values)
            }
            None => {
                let mut values = vec![0.0; comps * sol.n];
                convert(
                    &mut values,
                    comps,
                    sol.values.chunks_exact(stride).map(|r| &r[offset..offset + size]),
                    |r: &&[f64], j| r[j],
                    typ,
                    d,
                );
                values
            }
        };
        out.insert(
            name,
            if packed { DataArray::symmetric2(values) } else { DataArray::new(comps, values) },
        );
        offset += size;
    }
    Ok(out)
}

/// Whether a solution of `typ` in dimension `d` is kept with the file's values in the
/// file's order (see [`convert`]).
fn identity_layout(typ: u32, d: usize) -> bool {
    matches!((typ, d), (1, _) | (3, 2) | (2, 3) | (4, 3))
}

/// One field's values, vertex by vertex (`rows`, value `j` of a row by `get`), in the
/// layout of its array: `comps` values per vertex.
#[inline(always)]
fn convert<T>(
    out: &mut [f64],
    comps: usize,
    rows: impl Iterator<Item = T>,
    get: impl Fn(&T, usize) -> f64,
    typ: u32,
    d: usize,
) {
    let items = out.chunks_exact_mut(comps).zip(rows);
    // Values are stored one by one: `copy_from_slice` of a small array is a call to
    // `memcpy` per vertex.
    let put = |o: &mut [f64], v: &[f64]| o.iter_mut().zip(v).for_each(|(o, &v)| *o = v);
    match (typ, d) {
        (1, _) => items.for_each(|(o, s)| o[0] = get(&s, 0)),
        (2, 2) => items.for_each(|(o, s)| put(o, &[get(&s, 0), get(&s, 1), 0.0])),
        (2, _) | (3, 2) => items.for_each(|(o, s)| put(o, &[get(&s, 0), get(&s, 1), get(&s, 2)])),
        // libMeshb's 3D order: m11 m12 m22 m13 m23 m33.
        (3, _) => items.for_each(|(o, s)| {
            let m: [f64; 6] = std::array::from_fn(|j| get(&s, j));
            put(o, &[m[0], m[1], m[3], m[1], m[2], m[4], m[3], m[4], m[5]])
        }),
        (_, 2) => items.for_each(|(o, s)| {
            put(o, &[get(&s, 0), get(&s, 1), 0.0, get(&s, 2), get(&s, 3), 0.0, 0.0, 0.0, 1.0])
        }),
        (_, _) => items.for_each(|(o, s)| {
            for (j, v) in o.iter_mut().enumerate() {
                *v = get(&s, j);
            }
        }),
    }
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

// ---------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------

/// What the writers serialise: the mesh with its choices made.
struct Out<'m> {
    dim: u8,
    points: &'m [[f64; 3]],
    refs: Option<Vec<i32>>,
    /// Element keyword and the blocks written under it.
    elements: Vec<(usize, Vec<&'m CellBlock>)>,
    /// Set keyword and its 1-based numbers.
    sets: Vec<(usize, Vec<usize>)>,
}

impl Out<'_> {
    fn count(&self, code: usize) -> usize {
        self.elements
            .iter()
            .filter(|(c, _)| *c == code)
            .flat_map(|(_, b)| b.iter())
            .map(|b| b.len())
            .sum()
    }
}

fn integral_i32(v: f64) -> Option<i32> {
    (v.fract() == 0.0 && v >= i32::MIN as f64 && v <= i32::MAX as f64).then_some(v as i32)
}

/// How to write Medit files (the `medit` group of [`WriteOptions`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MeditWrite {
    /// `.meshb`/`.solb` rather than ASCII when the main file name does not tell.
    pub binary: bool,
}

/// Writes a mesh as Medit, with its solution file beside it (see the module documentation).
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let binary = match opts
        .main_name
        .as_deref()
        .and_then(|n| Path::new(n).extension())
        .and_then(|e| e.to_str())
    {
        Some(e) if e.eq_ignore_ascii_case("meshb") => true,
        Some(e) if e.eq_ignore_ascii_case("mesh") => false,
        _ => opts.medit.binary,
    };
    let mut report = WriteReport::default();
    // One pass over the points for the dimension and for what `validate` checks of
    // them; the node numbers are checked where the elements are written.
    let (has_z, finite) = mesh.points.iter().fold((false, true), |(z, f), p| {
        (z | (p[2] != 0.0), f & p[0].is_finite() & p[1].is_finite() & p[2].is_finite())
    });
    if !finite || !mesh.lengths_agree() {
        return Err(refused(Format::Medit, mesh));
    }
    let dim = if has_z { 3 } else { 2 };

    let refs = match mesh.point_data.get(REF) {
        Some(a) if a.components == 1 => {
            let r: Option<Vec<i32>> = a.values.iter().map(|&v| integral_i32(v)).collect();
            if r.is_none() {
                report.drop(format!("point data `{REF}`: not integers, so not vertex references"));
            }
            r
        }
        Some(a) => {
            report.drop(format!(
                "point data `{REF}` ({}): a vertex has one reference",
                crate::words::components(a.components)
            ));
            None
        }
        None => None,
    };

    // Elements, and the global index → element number maps the sets need.
    let mut elements = Vec::new();
    let mut number: BTreeMap<CellKind, Vec<(usize, usize)>> = BTreeMap::new(); // kind → [(first global, len)]
    let mut offset = 0;
    let mut geo_differs = 0;
    let mut topological: Vec<usize> = Vec::new();
    let mut point_tags = 0;
    for b in &mesh.blocks {
        if let Some(&(code, _)) = ELEMENTS.iter().find(|(_, k)| *k == b.kind) {
            match elements.iter_mut().find(|(c, _): &&mut (usize, Vec<&CellBlock>)| *c == code) {
                Some((_, list)) => list.push(b),
                None => elements.push((code, vec![b])),
            }
            number.entry(b.kind).or_default().push((offset, b.len()));
            geo_differs += b.physical.iter().zip(&b.geometrical).filter(|(p, g)| p != g).count();
        } else if b.kind == CellKind::Vertex {
            // Topological points: MMG keeps them where they are as corners and required
            // vertices (what the mmg2d adapter writes too).
            topological.extend(b.nodes.iter().map(|&v| v as usize));
            point_tags += b.physical.iter().filter(|&&t| t != 0).count();
        } else if !b.is_empty() {
            report.drop(format!(
                "{} {} cells: Medit has no 8-node quadrilaterals",
                b.len(),
                b.kind.name()
            ));
        }
        offset += b.len();
    }
    // File order as MMG writes it: edges, then triangles, then quadrilaterals.
    elements.sort_by_key(|(code, _)| ELEMENTS.iter().position(|(c, _)| c == code));
    if geo_differs > 0 {
        report.drop(format!(
            "geometrical tags of {geo_differs} cells differ from the physical ones: Medit keeps one reference (the physical tag)"
        ));
    }

    if !topological.is_empty() {
        report.drop(format!(
            "{} point cells: written as Corners and RequiredVertices entries, which are not cells (the file has {0} cells fewer)",
            topological.len()
        ));
    }
    if point_tags > 0 {
        report.drop(format!(
            "the tags of {point_tags} point cells: written as Corners and RequiredVertices, which have no references"
        ));
    }

    // Sets; the Vertex cells' points join Corners and RequiredVertices.
    let mut sets = Vec::new();
    let mut point_sets: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    if !topological.is_empty() {
        for name in ["Corners", "RequiredVertices"] {
            point_sets.insert(name, topological.clone());
        }
    }
    for (name, items) in &mesh.point_sets {
        point_sets.entry(name.as_str()).or_default().extend(items);
    }
    for (name, mut items) in point_sets {
        match lookup(name.as_bytes()).filter(|&c| set_target(c) == Some(None)) {
            Some(code) => {
                if !topological.is_empty() {
                    items.sort_unstable();
                    items.dedup();
                }
                sets.push((code, items.iter().map(|&v| v + 1).collect()))
            }
            None => report
                .drop(format!("point set `{name}`: Medit keeps only Corners and RequiredVertices")),
        }
    }
    for (name, items) in &mesh.cell_sets {
        let Some((code, kind)) =
            lookup(name.as_bytes()).and_then(|c| set_target(c).flatten().map(|k| (c, k)))
        else {
            report.drop(format!("cell set `{name}`: Medit keeps only Ridges, RequiredEdges, RequiredTriangles and RequiredQuadrilaterals"));
            continue;
        };
        // Global cell index → number among the elements of `kind`, in writing order.
        let ranges = number.get(&kind).map(Vec::as_slice).unwrap_or(&[]);
        let mut numbers = Vec::with_capacity(items.len());
        let mut lost = 0;
        for &g in items {
            let mut before = 0;
            let mut found = None;
            for &(first, len) in ranges {
                if g >= first && g < first + len {
                    found = Some(before + g - first + 1);
                    break;
                }
                before += len;
            }
            match found {
                Some(n) => numbers.push(n),
                None => lost += 1,
            }
        }
        if lost > 0 {
            report.drop(format!(
                "{lost} entries of cell set `{name}`: they are not {} cells",
                kind.name()
            ));
        }
        sets.push((code, numbers));
    }
    sets.sort_by_key(|(code, _)| SETS.iter().position(|(c, _)| c == code));

    if !mesh.tag_names.is_empty() {
        report.drop(format!("{} tag names: Medit references have no names", mesh.tag_names.len()));
    }
    if !mesh.entities.is_empty() {
        report.drop(format!("{} Gmsh entities: Medit has none", mesh.entities.len()));
    }
    if !mesh.holes.is_empty() || !mesh.regions.is_empty() {
        report.drop(format!(
            "{} holes and {} regions: Medit meshes have no PSLG seeds",
            mesh.holes.len(),
            mesh.regions.len()
        ));
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({}): the Medit writer keeps point data only (SolAtVertices)",
            crate::words::components(a.components)
        ));
    }

    // The solution MMG reads: the metric, else the size.
    let metric = mesh.point_data.get("metric").filter(|a| a.is_tensor());
    let size = mesh.point_data.get("size").filter(|a| a.components == 1);
    let chosen = match (metric, size) {
        (Some(m), _) => Some(("metric", m)),
        (None, Some(s)) => Some(("size", s)),
        _ => None,
    };
    for (name, a) in &mesh.point_data {
        if name == REF || chosen.is_some_and(|(c, _)| c == name) {
            continue;
        }
        let why = if name == "metric" {
            "a metric needs 9 components".to_string()
        } else if chosen.is_some() {
            format!("MMG reads one solution, `{}` was written", chosen.map_or("", |c| c.0))
        } else {
            "only `metric` (tensor) or `size` (scalar) go to the solution file".into()
        };
        report.drop(format!(
            "point data `{name}` ({}): {why}",
            crate::words::components(a.expanded_components())
        ));
    }

    let out = Out { dim, points: &mesh.points, refs, elements, sets };
    // Node numbers: checked in the pass that writes the binary elements; in a pass of
    // their own for ASCII and for the blocks Medit does not hold.
    let bound = |b: &CellBlock| b.nodes.iter().fold(0, |m, &v| m.max(v as usize + 1));
    let (main, written_bound) =
        if binary { binary::write_mesh(&out) } else { (ascii::write_mesh(&out), 0) };
    let held = |b: &CellBlock| ELEMENTS.iter().any(|(_, k)| *k == b.kind);
    let rest_bound =
        mesh.blocks.iter().filter(|b| !binary || !held(b)).map(bound).max().unwrap_or(0);
    if written_bound.max(rest_bound) > mesh.points.len() {
        return Err(refused(Format::Medit, mesh));
    }
    let mut written = Written { main, siblings: Vec::new(), report };
    if let Some((name, a)) = chosen {
        let sol = write_sol(&[(name, a)], dim, binary)?;
        written.siblings.push((if binary { "solb" } else { "sol" }.to_string(), sol));
    }
    Ok(written)
}

/// Writes a solution file (`.solb` when `binary`, else `.sol`) with one `SolAtVertices`
/// holding every array in order: 1 component → scalar (type 1), 2 or 3 → vector (type 2),
/// 9 or packed symmetric 2D → symmetric tensor (type 3, m11 m12 m22 in 2D; off-diagonal
/// terms of 9-component ones averaged).
/// `dim` is 2 or 3; every array must cover the same number of vertices.
pub fn write_sol(arrays: &[(&str, &DataArray)], dim: u8, binary: bool) -> Result<Vec<u8>> {
    let cannot =
        |reason: String| Error::new(ErrorKind::CannotWrite { format: "Medit solution", reason });
    if dim != 2 && dim != 3 {
        return Err(cannot(format!("dimension {dim}: Medit solutions are 2D or 3D")));
    }
    let Some(&(_, first)) = arrays.first() else {
        return Err(cannot("no array to write".into()));
    };
    let n = first.len();
    let mut types = Vec::with_capacity(arrays.len());
    for &(name, a) in arrays {
        if a.len() != n {
            return Err(cannot(format!(
                "array `{name}` covers {} vertices, `{}` {n}",
                a.len(),
                arrays[0].0
            )));
        }
        types.push(match a.components {
            _ if a.is_tensor() => 3,
            1 => 1u32,
            2 | 3 => 2,
            c => {
                return Err(cannot(format!("array `{name}` has {c} components; a solution is a scalar, a vector or a 9-component tensor")))
            }
        });
    }
    let stride: usize = types.iter().map(|&t| sol_size(t, dim).unwrap_or(0)).sum();
    let sol = SolOut { dim, n, types: &types, stride, arrays };
    Ok(if binary { binary::write_sol(&sol) } else { ascii::write_sol(&sol) })
}

/// A `SolAtVertices` to serialise: `n` vertices of `stride` reals, taken from `arrays`
/// one vertex row at a time (no intermediate copy of the whole solution).
struct SolOut<'a> {
    dim: u8,
    n: usize,
    types: &'a [u32],
    stride: usize,
    arrays: &'a [(&'a str, &'a DataArray)],
}

/// A solution file's single array, in a layout with a fixed-size record.
enum Single<'a> {
    /// A scalar.
    Scalar(&'a DataArray),
    /// A 2D symmetric tensor kept packed (`m11 m12 m22`).
    Packed(&'a DataArray),
    /// A 2D metric as a full 9-component tensor (its symmetric part is written).
    Tensor2(&'a DataArray),
}

impl<'a> SolOut<'a> {
    /// The one array of a 2D solution file, when its record has a fixed layout
    /// ([`SolOut::row`] writes the same reals).
    fn single(&self) -> Option<Single<'a>> {
        match self.arrays {
            [(_, a)] if self.dim == 2 => match (a.layout, a.components) {
                (Layout::Symmetric2, _) => Some(Single::Packed(a)),
                (_, 1) => Some(Single::Scalar(a)),
                (_, 9) => Some(Single::Tensor2(a)),
                _ => None,
            },
            _ => None,
        }
    }

    /// The file's reals for vertex `v`, in `row` (cleared first).
    #[inline]
    fn row(&self, v: usize, row: &mut Vec<f64>) {
        row.clear();
        let d = self.dim as usize;
        for &(_, a) in self.arrays {
            let s = a.item(v);
            if a.layout == Layout::Symmetric2 {
                row.extend_from_slice(s);
                if d == 3 {
                    row.extend_from_slice(&[0.0, 0.0, 1.0]);
                }
                continue;
            }
            match (a.components, d) {
                (1, _) => row.push(s[0]),
                (2, 2) | (3, 2) => row.extend_from_slice(&s[..2]),
                (2, _) => row.extend_from_slice(&[s[0], s[1], 0.0]),
                (3, _) => row.extend_from_slice(s),
                (_, 2) => {
                    let (m11, m12, m22) = tensor9_to_sym2(s);
                    row.extend_from_slice(&[m11, m12, m22]);
                }
                (_, _) => row.extend_from_slice(&[
                    s[0],
                    0.5 * (s[1] + s[3]),
                    s[4],
                    0.5 * (s[2] + s[6]),
                    0.5 * (s[5] + s[7]),
                    s[8],
                ]),
            }
        }
    }
}
