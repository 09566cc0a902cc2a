//! Gmsh MSH files, versions 2.2 and 4.1, ASCII and binary: reader and writer (the
//! parsed post-processing format, `.pos`, is [`pos`]).
//!
//! Source: the Gmsh reference manual, section "MSH file format" (4.1) and "MSH file
//! format version 2 (Legacy)" (<https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format>),
//! checked against Gmsh's own code (`src/geo/GModelIO_MSH2.cpp`, `GModelIO_MSH4.cpp`,
//! `src/post/PViewDataGModelIO_MSH.cpp`, `PViewIO.cpp`).
//!
//! Hand-written rather than built on `mshio` (the crate the design names for 4.1),
//! after measuring it (`bench_against_mshio` in `formats/tests/gmsh.rs`, release, on a
//! 4.1 file of 751,689 nodes and 1,499,912 triangles): it parses ASCII in 0.78 s where
//! this reader builds the whole mesh in 0.20 s, and binary in 0.33 s against 0.06 s;
//! its errors carry no line (a letter in a node tag reads "An invalid entity tag value
//! was encountered" and a hex dump; here "25: expected node tag (a non-negative
//! integer), found `x`"); it
//! panics (`unimplemented!`) on a binary header whose size_t is 3 bytes; it refuses
//! parametric nodes ("not supported yet"); and it reads neither `$PhysicalNames` nor
//! `$NodeData`, nor MSH 2.2, so a second parser would have been needed beside it anyway.
//!
//! Reading:
//! - `$MeshFormat` 2.x or 4.1, ASCII (`0`) or binary (`1`); binary files must be
//!   little-endian (a byte-swapped endianness marker is an error naming its offset);
//!   4.1 binary takes `size_t` of 4 or 8 bytes;
//! - `$PhysicalNames` → [`TaggedMesh::tag_names`];
//! - 4.1 `$Entities` → [`TaggedMesh::entities`] (every entity, points to volumes, with
//!   its physical tags; its point or bounding box is checked, finite and no minimum
//!   above its maximum, and kept in [`TaggedMesh::entity_boxes`]);
//!   the physical tag of a cell is the first physical tag of its entity (0 when none
//!   or without `$Entities`, as for Gmsh: such a file has no groups), its geometrical
//!   tag the entity tag; the cells of a group named [`UNTAGGED`] are read as untagged
//!   (tag 0, see below);
//! - 4.1 `$PartitionedEntities` (a partitioned mesh, `gmsh -part N`): the cells of a
//!   partitioned entity take its first physical tag and, as geometrical tag, its
//!   parent's (the model entity it is a part of, what a 2.2 file of the same mesh gives
//!   as elementary tag); the partitions merge into one mesh, which the read report says
//!   (the partition of a cell is not kept); ghost entities are read past;
//! - `$Nodes` (and 2.x `$ParametricNodes`): parametric coordinates are read past;
//!   nodes no element uses are kept. Points are ordered by node tag (the file's order
//!   when tags ascend, as Gmsh writes them); tags may be sparse: they are looked up in
//!   a dense table when the largest tag is within 4x the node count, else in a sorted
//!   table — never a table sized by an arbitrary largest tag;
//! - `$Elements` of the kinds [`crate::CellKind::from_gmsh_type`] knows (types 1 to 19:
//!   points, lines, triangles, quadrangles, tetrahedra, hexahedra, prisms and pyramids,
//!   first and second order, in Gmsh's node order, which is smartmesh's: no permutation);
//!   any other type (a third-order triangle...) is an error that names it. Cells are
//!   ordered by element tag (file order for Gmsh's files). 2.x elements carry physical
//!   and elementary tags; further (partition) tags are read past, the partitions
//!   merged into one mesh, which the read report says as for 4.1. Gmsh 2.2 writes an
//!   element once per physical group of its entity: such consecutive copies are read
//!   as one cell, and their groups listed in `entities[(dim, elementary)]` (the only
//!   entries a 2.x file gives that table); second-order cells (`gmsh -order 2`: types
//!   8, 9, 16, 10, 11, 12, 13, 14, 17, 18, 19) are kept as they are, as the VTK and Medit
//!   readers keep them
//!   ([`TaggedMesh::linearise`] makes them linear for the commands that need it);
//! - `$NodeData`, `$ElementData` (→ point and cell data named after the view's first
//!   string tag) and `$ElementNodeData` (→ cell data with components × nodes values per
//!   cell, padded with NaN for cells with fewer nodes). When a view appears with several
//!   time steps, the last section in the file wins; sections of the same step (a
//!   partitioned view) are merged. Items a view does not cover are NaN, which the read
//!   report says; NaN and infinities in a view are kept (refused where the data is used);
//! - a file of views alone (Gmsh's data-only file: `$NodeData` before any `$Nodes` or
//!   `$Elements`) is refused by [`read`], with a hint, and read by [`read_mesh_or_data`]
//!   as [`NodeData`] (node tag t = vertex t − 1 of the mesh it goes with);
//! - `$Comments`, `$Periodic`, `$GhostElements`, `$Parametrizations`,
//!   2.x `$PartitionedEntities`, `$InterpolationScheme`, Gmsh's `$Edges`/`$Faces`, and any
//!   section the format does not define (`$Comment`, `$Foo`: Gmsh's documentation says
//!   readers ignore them, and Gmsh and meshio do) are skipped up to their `$End` line,
//!   which must be there.
//!
//! Writing ([`GmshWrite`]: its `version` and `binary`):
//! - 4.1: `$PhysicalNames`, `$Entities` (one entity per dimension and geometrical tag,
//!   with the physical tags of [`TaggedMesh::entities`] where it lists them, and the
//!   box of [`TaggedMesh::entity_boxes`] where it holds the nodes of the entity's cells
//!   (a file's boxes round trip as read), else the bounding box of those nodes (zeros
//!   for an entity with neither); cells of
//!   one entity with different physical tags are split onto new entities, which the
//!   report says), `$Nodes` in entity blocks (a node goes to the lowest-dimensional
//!   entity using it; nodes no cell uses go to the first entity of the highest
//!   dimension, so Gmsh keeps them), `$Elements` by entity and type, node and element
//!   tags = index + 1;
//! - 2.2: the same with a physical and an elementary tag on each element, written once
//!   per physical group where `entities` lists several, as Gmsh does;
//! - in both, when some cells have a physical tag, the cells of dimension `d` without
//!   one are written in a group of their own, numbered one above the largest physical
//!   tag of dimension `d` and named [`UNTAGGED`] (`untagged.rs`: Gmsh keeps only the
//!   cells of physical groups, meshio needs a group on every block); the report says so;
//! - each point array as `$NodeData`, each cell array as `$ElementData` (tensors as 9
//!   row-major components, Gmsh's layout); non-finite items are left out (read back as
//!   missing, NaN). What MSH cannot hold (point and cell sets, PSLG holes and regions,
//!   quotes in names...) is listed in the [`WriteReport`]. Same mesh, same bytes.
//!
//! Not supported: MSH 1, 3 and 4.0, big-endian binary files, elements of order 3 and
//! more, the partition of each cell (partitions are read as one mesh),
//! interpolation schemes.
//!
//! Points keep the three coordinates MSH stores; `coordinate_dim` is 3 when some z is
//! not 0, else 2.
//!
//! Cost: one pass over the bytes, O(n) but for files whose tags are out of order
//! (sorted in runs). ASCII numbers go through a small scanner for plain digits and
//! floats, with [`crate::text::Tokens`] behind it for anything else and for errors;
//! binary arrays through `chunks_exact` + `from_le_bytes`. Writing fills one pre-sized
//! buffer with `text::push_f64` / `push_int` numbers.

/// The node counts of the cell kinds, each a const generic instance of the binary
/// record code (a record then has a size known at compile time). Checked at compile time
/// against [`crate::CellKind::ALL`] below, so that [`by_nodes!`] has an arm for every kind.
const NODE_COUNTS: [usize; 15] = [1, 2, 3, 4, 5, 6, 8, 9, 10, 13, 14, 15, 18, 20, 27];

/// The most nodes a cell has (the 27-node hexahedron): the size of the stack buffers
/// the binary records are assembled in.
const MAX_NODES: usize = 27;

const _: () = {
    let mut i = 0;
    while i < crate::CellKind::ALL.len() {
        let k = crate::CellKind::ALL[i].nodes_per_cell();
        let mut found = false;
        let mut j = 0;
        while j < NODE_COUNTS.len() {
            found |= NODE_COUNTS[j] == k;
            j += 1;
        }
        assert!(found && k <= MAX_NODES, "a cell kind's node count has no arm in by_nodes!");
        i += 1;
    }
};

/// `$f::<K>(args)` with `K` the node count `$k` of a cell kind, one of [`NODE_COUNTS`]
/// (every kind's, as the assertion above checks at compile time).
macro_rules! by_nodes {
    ($k:expr, $f:ident ( $($a:expr),* $(,)? )) => {
        match $k {
            1 => $f::<1>($($a),*),
            2 => $f::<2>($($a),*),
            3 => $f::<3>($($a),*),
            4 => $f::<4>($($a),*),
            5 => $f::<5>($($a),*),
            6 => $f::<6>($($a),*),
            8 => $f::<8>($($a),*),
            9 => $f::<9>($($a),*),
            10 => $f::<10>($($a),*),
            13 => $f::<13>($($a),*),
            14 => $f::<14>($($a),*),
            15 => $f::<15>($($a),*),
            18 => $f::<18>($($a),*),
            20 => $f::<20>($($a),*),
            k => {
                debug_assert_eq!(k, 27, "no cell kind has {k} nodes");
                $f::<27>($($a),*)
            }
        }
    };
}

// Reading: `cursor` (tokens, binary arrays, the ASCII fast path), `tags` (tag maps),
// `reader` (the state and the sections both versions share), `msh2` / `msh4` (nodes,
// elements, 4.1 entities), `views` (data sections, read and written), `assembly` (the
// mesh in tag order), `untagged` (the policy above). Writing: `header`,
// then `msh2` / `msh4` and `views`.
mod assembly;
mod cursor;
mod header;
mod msh2;
mod msh4;
pub mod pos;
mod reader;
mod tags;
mod untagged;
mod views;

pub use untagged::UNTAGGED;

use crate::{
    DataArray, Error, ErrorKind, ReadContext, ReadReport, Result, TaggedMesh, WriteOptions,
    WriteReport, Written,
};
use cursor::show;
use reader::Reader;
use views::ViewKind;

/// Reads an MSH 2.x or 4.1 file, ASCII or binary.
pub fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read_reported(bytes, ctx).map(|(mesh, _)| mesh)
}

/// [`read`], with what the reader could not keep on the way.
pub fn read_reported(bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<(TaggedMesh, ReadReport)> {
    let mut r = Reader::new(bytes);
    read_sections(&mut r)?;
    r.finish()
}

/// What an MSH file holds: a mesh, or (Gmsh's data-only file) node views alone.
// Returned once per file read, never stored in bulk: the size of the mesh's table
// headers inline costs nothing, and boxing it would change the public API.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum MshContent {
    /// A mesh, with its data views as point and cell data ([`read`]).
    Mesh(TaggedMesh),
    /// Node views without a mesh.
    NodeData(NodeData),
}

/// The node views of a data-only MSH file: `$MeshFormat` and `$NodeData` sections (and
/// sections skipped, such as the `$InterpolationScheme` Gmsh writes), no `$Nodes` nor
/// `$Elements` — what `gmsh.view.write` writes with `PostProcessing.SaveMesh = 0`, or a
/// solver beside the mesh it read. Node tag t stands for vertex t − 1 of that mesh (the
/// numbering of the mesh file when its tags are 1, 2, …, as Gmsh and smartmesh write
/// them).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NodeData {
    /// Each view, named as in [`read`], with one item per node tag from 1 to the largest
    /// tag the view gives (NaN where it gives none).
    pub arrays: std::collections::BTreeMap<String, DataArray>,
    /// The number of entries each view gives.
    pub entries: std::collections::BTreeMap<String, usize>,
}

/// Reads an MSH file that is either a mesh ([`read`]) or a data-only file of node views
/// ([`NodeData`]): a `$NodeData` section before any `$Nodes` or `$Elements` makes it the
/// latter, and a mesh section after that is then an error.
pub fn read_mesh_or_data(bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<MshContent> {
    let mut r = Reader::new(bytes);
    r.allow_data_only = true;
    read_sections(&mut r)?;
    if r.data_only {
        r.finish_node_data().map(MshContent::NodeData)
    } else {
        r.finish().map(|(mesh, _)| MshContent::Mesh(mesh))
    }
}

/// `$MeshFormat`, then every section up to the end of the file.
fn read_sections(r: &mut Reader<'_>) -> Result<()> {
    r.read_mesh_format()?;
    while let Some(tok) = r.c.t.next() {
        let at = r.c.here_before(tok.len());
        if tok.first() != Some(&b'$') || tok.len() < 2 {
            return Err(Error {
                path: None,
                at: Some(at),
                kind: ErrorKind::Expected {
                    expected: "a section header such as `$Nodes`".into(),
                    found: show(tok),
                },
            });
        }
        let name = &tok[1..];
        if matches!(name, b"Nodes" | b"ParametricNodes" | b"Elements") {
            if r.data_only {
                return Err(Error {
                    path: None,
                    at: Some(at),
                    kind: ErrorKind::Inconsistent(format!(
                        "a ${} section after $NodeData that came before any mesh: a file is a mesh or a data-only file of views, not both",
                        String::from_utf8_lossy(name)
                    )),
                });
            }
            r.saw_mesh = true;
        }
        match name {
            b"PhysicalNames" => r.read_physical_names()?,
            b"Entities" if r.v4 => msh4::read_entities(r)?,
            b"PartitionedEntities" if r.v4 => msh4::read_partitioned_entities(r)?,
            b"Nodes" if r.v4 => msh4::read_nodes(r, at)?,
            b"Elements" if r.v4 => msh4::read_elements(r)?,
            b"Nodes" => msh2::read_nodes(r, at, false)?,
            b"ParametricNodes" if !r.v4 => msh2::read_nodes(r, at, true)?,
            b"Elements" => msh2::read_elements(r)?,
            b"NodeData" => r.read_view(ViewKind::Node)?,
            b"ElementData" => r.read_view(ViewKind::Element)?,
            b"ElementNodeData" => r.read_view(ViewKind::ElementNode)?,
            // Sections Gmsh defines that carry nothing a TaggedMesh holds. A 2.x file may
            // hold MSH3-style `$Entities` (Gmsh's Mesh.SaveTopology).
            b"Comments"
            | b"Periodic"
            | b"GhostElements"
            | b"Parametrizations"
            | b"PartitionedEntities"
            | b"InterpolationScheme"
            | b"Edges"
            | b"Faces"
            | b"Entities" => r.skip_section(name, at)?,
            b"MeshFormat" => {
                return Err(Error {
                    path: None,
                    at: Some(at),
                    kind: ErrorKind::Inconsistent("a second $MeshFormat section".into()),
                })
            }
            _ if name.starts_with(b"End") => {
                return Err(Error {
                    path: None,
                    at: Some(at),
                    kind: ErrorKind::Expected {
                        expected: "a section header such as `$Nodes`".into(),
                        found: format!("{}, which closes no open section", show(tok)),
                    },
                })
            }
            // Gmsh's format documentation: "any section with an unrecognized header is
            // simply ignored" (`$Comment`, a tool's own section); Gmsh and meshio skip it.
            _ => r.skip_section(name, at)?,
        }
    }
    Ok(())
}

/// Gmsh MSH file format version to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GmshVersion {
    /// MSH 2.2 (physical and elementary tags on each element).
    V22,
    /// MSH 4.1 (entities, the current default of Gmsh).
    #[default]
    V41,
}

/// How to write MSH (the `gmsh` group of [`WriteOptions`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GmshWrite {
    /// The version: 4.1 by default, as Gmsh's own.
    pub version: GmshVersion,
    /// Binary rather than ASCII.
    pub binary: bool,
}

/// Writes MSH 4.1 or 2.2 (per `opts.gmsh.version`), ASCII or binary (`opts.gmsh.binary`).
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    if let Some(p) = mesh.validate().into_iter().next() {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: "Gmsh MSH",
            reason: p.to_string(),
        }));
    }
    write_validated(mesh, opts, Vec::new())
}

/// [`write`] of a mesh that [`TaggedMesh::validate`] found without problems (as
/// `write_bytes` checks first, with the same error): not checked again.
/// `spare`: memory to write the file into (cleared first), reused rather than fresh.
pub(crate) fn write_validated(
    mesh: &TaggedMesh,
    opts: &WriteOptions,
    spare: Vec<u8>,
) -> Result<Written> {
    let mut report = WriteReport::default();
    // Tags in MSH binary data sections and 2.2 elements are C ints.
    let n_cells = mesh.num_cells();
    if mesh.points.len() >= i32::MAX as usize || n_cells >= (i32::MAX / 2) as usize {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: "Gmsh MSH",
            reason: "more nodes or elements than MSH's 32-bit tags can number".into(),
        }));
    }
    let grouped = untagged::grouped(mesh, &mut report);
    let GmshWrite { version, binary } = opts.gmsh;
    let mut out = spare;
    out.clear();
    out.reserve(estimate_size(mesh, binary));
    match version {
        GmshVersion::V41 => msh4::write(&grouped, binary, &mut out, &mut report)?,
        GmshVersion::V22 => msh2::write(&grouped, binary, &mut out, &mut report)?,
    }
    report_unheld(mesh, &mut report);
    Ok(Written { main: out, siblings: Vec::new(), report })
}

fn estimate_size(mesh: &TaggedMesh, binary: bool) -> usize {
    let nodes: usize = mesh.blocks.iter().map(|b| b.nodes.len() + b.len()).sum();
    let data: usize = mesh
        .point_data
        .values()
        .chain(mesh.cell_data.values())
        .map(|a| a.len() * (a.expanded_components() + 1))
        .sum();
    if binary {
        mesh.points.len() * 40 + nodes * 8 + data * 8 + 4096
    } else {
        mesh.points.len() * 64 + nodes * 9 + data * 22 + 4096
    }
}

/// What MSH has no place for.
fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    for (name, set) in &mesh.point_sets {
        report
            .drop(format!("point set `{name}` ({} points): Gmsh MSH has no point sets", set.len()));
    }
    for (name, set) in &mesh.cell_sets {
        report.drop(format!("cell set `{name}` ({} cells): Gmsh MSH has no cell sets", set.len()));
    }
    if !mesh.holes.is_empty() {
        report.drop(format!(
            "{} hole point(s) of the planar straight-line graph: Gmsh MSH holds none",
            mesh.holes.len()
        ));
    }
    if !mesh.regions.is_empty() {
        report.drop(format!(
            "{} region seed(s) of the planar straight-line graph: Gmsh MSH holds none",
            mesh.regions.len()
        ));
    }
}
