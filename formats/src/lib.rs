//! Read and write 2D tagged meshes and their fields in the formats of the meshing world.
//!
//! Features:
//! - one in-memory [`TaggedMesh`]: points, cell blocks, physical and geometrical tags,
//!   tag names, Gmsh entities, named point and cell data (scalars, vectors, tensors);
//! - one module per format, each with the same two entry points
//!   `read(&[u8], &ReadContext) -> Result<TaggedMesh>` and
//!   `write(&TaggedMesh, &WriteOptions) -> Result<Written>`, the writer reading its own
//!   group of [`WriteOptions`]:
//!   [`triangle`] (.node/.ele/.poly/.edge/.area), [`gmsh`] (MSH 2.2 and 4.1, ASCII and
//!   binary), [`vtk`] (legacy .vtk 4.2/5.1 and XML .vtu), [`obj`], [`medit`]
//!   (.mesh/.meshb with .sol/.solb), [`gltf`] (.gltf + .bin, .glb; write only), [`su2`],
//!   [`openfoam`] (a case directory), [`stl`] (ASCII and binary), [`tetgen`], [`fluent`]
//!   (ASCII `.fluent.msh` written; ASCII and binary read), [`cgns`] (`.cgns`, HDF5; with the `cgns`
//!   feature, which needs libhdf5);
//! - [`Format::from_path`], a static extension table;
//! - [`read_path`] / [`write_path`]: files or `-` for stdin/stdout, sibling files
//!   (Triangle's .node beside .ele, Medit's .sol beside .mesh), and outputs written as a
//!   set, all or nothing ([`write_all_atomically`]: temporaries, then renames; links
//!   written through, read-only files refused);
//! - errors that name the file, the line or byte offset, and what was expected.
//!
//! This crate sizes nothing and knows no topology: those are the `smartmesh` crate's.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod error;
mod io;
mod linear;
mod mesh;
mod output;
mod point_sets;
mod scan;
mod skin;
pub mod text;
pub mod words;

pub mod cgns;
pub mod fluent;
pub mod gltf;
pub mod gmsh;
pub mod medit;
pub mod obj;
pub mod openfoam;
pub mod stl;
pub mod su2;
pub mod tetgen;
pub mod triangle;
pub mod vtk;

#[cfg(feature = "proptest")]
pub mod arbitrary;

pub use error::{Error, ErrorKind, Position, Result};
pub use gltf::GltfWrite;
pub use gmsh::{GmshVersion, GmshWrite};
pub use io::{
    read_bytes, read_bytes_reported, read_path, read_path_keeping_bytes, read_path_reported,
    read_path_reported_without, write_bytes, write_path, write_path_reusing, MemorySiblings,
    NoSiblings, PathSiblings, SiblingSource,
};
pub use medit::MeditWrite;
pub use mesh::{
    sym2_to_tensor9, tensor9_to_sym2, CellBlock, CellKind, DataArray, DataShape, Layout,
    MeshProblem, NodeIndex, RegionSeed, TaggedMesh, MAX_POINTS,
};
pub use openfoam::{CyclicPair, CyclicTransform, OpenFoamWrite};
pub use output::{sync_files, write_all_atomically, write_all_atomically_synced};
pub use stl::StlWrite;
pub use vtk::{VtkWrite, VtuEncoding};

use std::path::Path;

/// A file format smartmesh reads or writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// Triangle's .node/.ele/.poly/.edge/.area family.
    Triangle,
    /// Gmsh MSH 2.2 or 4.1, ASCII or binary.
    Gmsh,
    /// VTK legacy `.vtk`.
    VtkLegacy,
    /// VTK XML unstructured grid `.vtu`.
    Vtu,
    /// Wavefront OBJ.
    Obj,
    /// Medit `.mesh` (ASCII) or `.meshb` (binary), with `.sol`/`.solb` beside it.
    Medit,
    /// glTF 2.0: `.gltf` with a `.bin` beside it, or a single `.glb`.
    Gltf,
    /// SU2 native mesh `.su2` (ASCII).
    Su2,
    /// STL, ASCII or binary: triangles in space, a solid per tag.
    Stl,
    /// TetGen's .node/.ele/.face/.edge set, or a `.smesh`/`.poly` PLC (3D).
    TetGen,
    /// An OpenFOAM case directory (`constant/polyMesh`): the path is the directory
    /// (`case.foam`, or any name with `--from`/`--to openfoam`).
    OpenFoam,
    /// CGNS (`.cgns`, HDF5): unstructured zones; needs the `cgns` feature and libhdf5.
    Cgns,
    /// Fluent mesh: written ASCII to a name ending in `.fluent.msh` or with `--to
    /// fluent` (a plain `.msh` is Gmsh's); read ASCII or binary from those, or from a
    /// `.msh` whose first non-blank byte is `(`.
    Fluent,
}

/// The extension table, as meshio's `_helpers.py` keeps one: last suffix, lower case.
const EXTENSIONS: &[(&str, Format)] = &[
    ("node", Format::Triangle),
    ("ele", Format::Triangle),
    ("poly", Format::Triangle),
    ("edge", Format::Triangle),
    ("area", Format::Triangle),
    ("msh", Format::Gmsh),
    ("vtk", Format::VtkLegacy),
    ("vtu", Format::Vtu),
    ("vtp", Format::Vtu),
    ("pvtu", Format::Vtu),
    ("pvtp", Format::Vtu),
    ("obj", Format::Obj),
    ("mesh", Format::Medit),
    ("meshb", Format::Medit),
    ("gltf", Format::Gltf),
    ("glb", Format::Gltf),
    ("su2", Format::Su2),
    ("smesh", Format::TetGen),
    ("face", Format::TetGen),
    ("foam", Format::OpenFoam),
    ("stl", Format::Stl),
    ("cgns", Format::Cgns),
];

impl Format {
    /// The format of a path, from its last extension (`naca.1.ele` is Triangle,
    /// `test.0.mesh` is Medit).
    pub fn from_path(path: impl AsRef<Path>) -> Option<Format> {
        let name = path.as_ref().file_name()?.to_str()?.to_ascii_lowercase();
        if name.ends_with(".fluent.msh") {
            return Some(Format::Fluent);
        }
        let ext = path.as_ref().extension()?.to_str()?.to_ascii_lowercase();
        Format::from_extension(&ext)
    }

    /// The format of an extension without its dot.
    pub fn from_extension(ext: &str) -> Option<Format> {
        EXTENSIONS.iter().find(|(e, _)| e.eq_ignore_ascii_case(ext)).map(|&(_, f)| f)
    }

    /// The format of a `--from`/`--to` name: an extension or a format name
    /// (`gmsh`, `msh`, `vtk`, `vtu`, `triangle`, `obj`, `medit`, `mesh`, `gltf`, `glb`).
    pub fn from_name(name: &str) -> Option<Format> {
        let n = name.to_ascii_lowercase();
        Format::from_extension(&n).or(match n.as_str() {
            "triangle" => Some(Format::Triangle),
            "gmsh" => Some(Format::Gmsh),
            "vtk-legacy" | "legacy" => Some(Format::VtkLegacy),
            "medit" | "mmg" => Some(Format::Medit),
            "tetgen" => Some(Format::TetGen),
            "openfoam" | "polymesh" => Some(Format::OpenFoam),
            "fluent" => Some(Format::Fluent),
            _ => None,
        })
    }

    /// A human name.
    pub fn name(self) -> &'static str {
        match self {
            Format::Triangle => "Triangle",
            Format::Gmsh => "Gmsh MSH",
            Format::VtkLegacy => "VTK legacy",
            Format::Vtu => "VTK XML (.vtu)",
            Format::Obj => "OBJ",
            Format::Medit => "Medit",
            Format::Gltf => "glTF",
            Format::Su2 => "SU2",
            Format::TetGen => "TetGen",
            Format::OpenFoam => "OpenFOAM",
            Format::Stl => "STL",
            Format::Fluent => "Fluent",
            Format::Cgns => "CGNS",
        }
    }

    /// Every extension of the table, for messages: `.node, .ele, …, .glb`.
    pub fn known_extensions() -> String {
        EXTENSIONS.iter().map(|(e, _)| format!(".{e}")).collect::<Vec<_>>().join(", ")
    }

    /// Whether smartmesh reads this format.
    pub fn can_read(self) -> bool {
        !matches!(self, Format::Gltf)
    }

    /// The names accepted by [`Format::from_name`], for help texts.
    pub const NAMES: &'static str =
        "triangle (node, ele, poly), tetgen (smesh, face; node, ele, poly when 3D), gmsh (msh), vtk, vtu, obj, medit (mesh, meshb), gltf, glb, su2, openfoam (foam), stl, fluent (.fluent.msh), cgns";
}

/// Which of [`TaggedMesh::validate`]'s checks a format's reader and writer make
/// themselves, declared by each format module (`CHECKS`), so that reading and writing
/// validate only where they do not: finite coordinates, every cell's points, every
/// data array's length, every set's items, each fault named by its byte or line.
/// Validating again would cost one more pass over the largest arrays (a tenth of a
/// binary Medit read).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Checks {
    /// The reader refuses every mesh `validate` would refuse. Debug builds (the tests)
    /// validate anyway and stop on a mesh such a reader let through; the fuzz targets
    /// validate every mesh they are given.
    pub reader_validates: bool,
    /// The writer refuses, with [`io::refused`]'s error, every mesh `validate` would
    /// refuse, in the passes that write it.
    pub writer_validates: bool,
}

impl Checks {
    /// Neither reader nor writer checks: `read_bytes`/`write_bytes` validate.
    pub(crate) const NONE: Checks = Checks { reader_validates: false, writer_validates: false };
}

impl Format {
    /// What the format's own code checks (see [`Checks`]).
    pub(crate) fn checks(self) -> Checks {
        match self {
            Format::Triangle => triangle::CHECKS,
            // Not declared by the Gmsh module: its meshes are validated here.
            Format::Gmsh => Checks::NONE,
            Format::VtkLegacy | Format::Vtu => vtk::CHECKS,
            Format::Obj => obj::CHECKS,
            Format::Medit => medit::CHECKS,
            Format::Gltf => gltf::CHECKS,
            Format::Su2 => su2::CHECKS,
            Format::Stl => stl::CHECKS,
            Format::TetGen => tetgen::CHECKS,
            Format::Fluent => fluent::CHECKS,
            Format::Cgns => cgns::CHECKS,
            // Validated by `openfoam::poly_mesh_files` itself.
            Format::OpenFoam => Checks { reader_validates: false, writer_validates: true },
        }
    }
}

/// How to write, grouped by the format each knob concerns: a writer reads its own
/// group, and [`WriteOptions::main_name`], which [`write_path`] sets. A new format with
/// options adds one group here and its type in its module.
#[derive(Debug, Clone, Default)]
pub struct WriteOptions {
    /// Gmsh MSH: version and encoding.
    pub gmsh: GmshWrite,
    /// VTK: legacy version and encoding, XML encoding and compression.
    pub vtk: VtkWrite,
    /// Medit: binary when the file name does not tell.
    pub medit: MeditWrite,
    /// glTF: the colouring field, `.glb` or `.gltf` + `.bin`.
    pub gltf: GltfWrite,
    /// OpenFOAM: the extrusion thickness, patch types.
    pub openfoam: OpenFoamWrite,
    /// STL: binary or ASCII.
    pub stl: StlWrite,
    /// File name (no directory) of the main output, for formats whose main file names
    /// its siblings (glTF's `.bin` URI) or whose extension chooses what is written
    /// (Triangle's files, Medit's encoding, `.glb`). `None` when writing to stdout.
    pub main_name: Option<String>,
}

/// What a reader may consult besides the main file's bytes.
pub struct ReadContext<'a> {
    /// Sibling files (same base name, another extension).
    pub siblings: &'a dyn SiblingSource,
    /// Lower-case extension of the main file (`ele`, `poly`, `meshb`...), empty for a
    /// stream with an explicit `--from`.
    pub extension: String,
}

impl<'a> ReadContext<'a> {
    /// A context with no siblings, for a main file with extension `ext`.
    pub fn alone(ext: &str) -> ReadContext<'static> {
        ReadContext { siblings: &NoSiblings, extension: ext.to_ascii_lowercase() }
    }
}

/// What a writer produced: the main file and the siblings it needs beside it.
#[derive(Debug, Default)]
pub struct Written {
    /// Bytes of the main file.
    pub main: Vec<u8>,
    /// `(extension, bytes)` of each sibling file, written beside the main one with the
    /// main file's base name (`out.sol` beside `out.mesh`).
    pub siblings: Vec<(String, Vec<u8>)>,
    /// What the format could not hold.
    pub report: WriteReport,
}

/// What a writer dropped because the format cannot hold it, one line each, for the
/// user to read (`convert` prints them on stderr and in `--json`).
#[derive(Debug, Default, Clone, PartialEq, Eq, serde::Serialize)]
pub struct WriteReport {
    /// One human-readable line per dropped item.
    pub dropped: Vec<String>,
}

impl WriteReport {
    /// Records a dropped item.
    pub fn drop(&mut self, what: impl Into<String>) {
        self.dropped.push(what.into());
    }
}

/// What a reader changed in what it read so that the mesh fits the model (a
/// second-order Gmsh mesh read as linear), one line each, for the user to read: the CLI
/// prints them as notes on stderr. Empty when the mesh is the file's as it stands.
#[derive(Debug, Default, Clone, PartialEq, Eq, serde::Serialize)]
pub struct ReadReport {
    /// One human-readable line per change.
    pub notes: Vec<String>,
}

impl ReadReport {
    /// Records a change.
    pub fn note(&mut self, what: impl Into<String>) {
        self.notes.push(what.into());
    }
}
