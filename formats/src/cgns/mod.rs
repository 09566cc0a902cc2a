//! CGNS files (`.cgns`, the HDF5 flavour), unstructured zones, read and write.
//!
//! Sources: the CGNS Standard Interface Data Structures (SIDS) and its File Mapping
//! Manual (cgns.github.io, "CGNS/SIDS" and "CGNS/FMM"), and the files the CGNS library
//! 3.4 itself writes (Debian's `cgns-convert` tools, `tetgen_to_cgns`), read with h5py.
//! Each CGNS node is an HDF5 group with the attributes `name`, `label` (the SIDS type,
//! `Zone_t`), `type` (`MT`, `I4`, `I8`, `R4`, `R8`, `C1`) and `flags`, its data in a
//! dataset named `" data"` whose HDF5 dimensions are the node's CGNS dimensions
//! reversed (CGNS speaks Fortran order). HDF5 itself comes from libhdf5 through the
//! `hdf5-metno` crate (the maintained fork of `hdf5`): the format's container is not
//! something to write by hand.
//!
//! The dependency is behind the cargo feature `cgns` (off by default, so that a machine
//! without libhdf5 builds smartmesh): without it, reading or writing a `.cgns` file is
//! refused with a message that names the feature and the library
//! ([`NEEDS_FEATURE`]).
//!
//! Write ([`write()`]): the CGNS library version node (3.4, what Debian's CGNS tools
//! read), one `CGNSBase_t` `Base` (cell dimension: the highest cell dimension of the
//! mesh, physical dimension 3) holding one unstructured `Zone_t` `Zone1` (these two
//! names are the ones meshio's reader looks for) with:
//! - `GridCoordinates`: `CoordinateX`, `CoordinateY`, `CoordinateZ`, doubles;
//! - one `Elements_t` section per (dimension, physical tag, kind), highest dimension
//!   first, element numbers consecutive from 1 across the sections (the first section
//!   is named `GridElements`, the one meshio reads); element types and node orders of
//!   the SIDS (see [`cgns_type`]), second-order kinds whose CGNS order is Gmsh's (or one
//!   swap away: the 10-node tetrahedron) kept, the others written by their corners;
//! - `ZoneBC`: one `BC_t` per tag of the boundary cells (dimension one below the
//!   zone's), its element range (`PointRange` with `GridLocation` `FaceCenter` in 3D,
//!   `EdgeCenter` in 2D, the tag's sections being consecutive), of type
//!   `FamilySpecified` with its `FamilyName`: the family's `FamilyBC` holds the type,
//!   chosen from the name as OpenFOAM patch types are (`BCWall` for wall-like names,
//!   else `UserDefined`). ParaView's reader takes no other BC type but Dirichlet and
//!   Neumann, and every CGNS reader follows a family;
//! - `ZoneSubRegion_t` nodes for the tags of the other dimensions (volume regions
//!   at `CellCenter`, edges in 3D at `EdgeCenter`, points of vertex cells at `Vertex`);
//! - `FlowSolution` at `Vertex` with every point field: a scalar as one array named as
//!   the field, a vector as `<name>X`, `Y`, `Z`, a 3x3 tensor (the metric) as `<name>XX`,
//!   `XY`, … `ZZ` (the suffixes ParaView's CGNS reader assembles), other counts as
//!   `<name>_0`, `_1`, …;
//! - a `Family_t` per tag under the base, named from the tag name (`tag<N>` for an
//!   unnamed tag N), with its `FamilyBC` for boundaries and a `Descriptor_t` for the
//!   others (ParaView's reader stumbles on a node without children).
//!
//! CGNS names are at most 32 characters without `/`: longer names are cut and made
//! unique, reported. A BC or region of an unnamed tag `N` is named `tag<N>`; a named
//! one carries its tag number in a `Descriptor_t` `smartmesh_tag`, so that tags read
//! back with their numbers. What CGNS (as written here) cannot hold is reported: cell
//! data, point and cell sets, geometrical tags that differ from the physical ones,
//! second-order nodes of the kinds written by their corners.
//!
//! Read: the first base (others noted), every unstructured zone of it (structured ones
//! refused), merged into one mesh with each zone's points apart (CGNS zones share no
//! points; a note says how many zones were merged). Sections of any SIDS element type
//! but the polyhedral `NGON_n`/`NFACE_n` (refused), `MIXED` sections included (the
//! type code before each element's nodes; CGNS 4's `ElementStartOffset` is then
//! redundant and not needed). Tags: a cell covered by a `BC_t` or `ZoneSubRegion_t`
//! (by `PointRange`/`PointList` of element numbers, or the older `ElementRange`/
//! `ElementList`) takes that node's tag, named by its `FamilyName` or, without one, by
//! the node's name; other cells of the zone's dimension take a tag per zone named after
//! the zone, and other lower-dimension cells a tag per section named after the section.
//! A BC given at `Vertex` becomes a point set of that name. `FlowSolution_t` nodes at
//! `Vertex` become point data (suffixes assembled as above); other locations are noted
//! and left. Every size is checked before anything is allocated for it (an array's
//! announced size against what its storage can hold), every index against its range;
//! a malformed file is refused naming the HDF5 path of the node and what was expected.
//! The HDF5 container itself is libhdf5's to read: a file cut short is refused, but
//! bytes flipped inside HDF5's own structures can crash libhdf5 1.10 (a class of known
//! libhdf5 faults), which no check on this side can prevent; there is no fuzz target.
//!
//! libhdf5 reads and writes files, not memory: the bytes go through a temporary file.
//! Checked by the CGNS library's `cgnscheck` (no error), read back by meshio (its
//! reader takes `Base/Zone1/GridElements` tetrahedra only) and by VTK's
//! `vtkCGNSReader` (cells in the node order of our `.vtu`, patches by name); see
//! `formats/tests/cgns.rs`.

#[cfg(feature = "cgns")]
mod fields;
#[cfg(feature = "cgns")]
mod node;
#[cfg(feature = "cgns")]
mod read;
#[cfg(feature = "cgns")]
mod write;

use crate::{CellKind, ReadContext, ReadReport, Result, TaggedMesh, WriteOptions, Written};
#[cfg(not(feature = "cgns"))]
use crate::{Error, ErrorKind};

/// Neither the reader nor the writer validates itself: `read_bytes`/`write_bytes` do.
pub(crate) const CHECKS: crate::Checks = crate::Checks::NONE;

/// What a build without the `cgns` feature says about a `.cgns` file.
pub const NEEDS_FEATURE: &str = "CGNS files need smartmesh built with the `cgns` feature and \
     the HDF5 library (Debian/Ubuntu: `apt-get install libhdf5-dev`, then \
     `cargo build --release --features cgns`)";

/// CGNS `ElementType_t` values (SIDS, "Elements_t").
pub(crate) mod etype {
    pub const NODE: i64 = 2;
    pub const BAR_2: i64 = 3;
    pub const BAR_3: i64 = 4;
    pub const TRI_3: i64 = 5;
    pub const TRI_6: i64 = 6;
    pub const QUAD_4: i64 = 7;
    pub const QUAD_8: i64 = 8;
    pub const QUAD_9: i64 = 9;
    pub const TETRA_4: i64 = 10;
    pub const TETRA_10: i64 = 11;
    pub const PYRA_5: i64 = 12;
    pub const PYRA_14: i64 = 13;
    pub const PENTA_6: i64 = 14;
    pub const PENTA_15: i64 = 15;
    pub const PENTA_18: i64 = 16;
    pub const HEXA_8: i64 = 17;
    pub const HEXA_20: i64 = 18;
    pub const HEXA_27: i64 = 19;
    pub const MIXED: i64 = 20;
    pub const PYRA_13: i64 = 21;
    pub const NGON_N: i64 = 22;
    pub const NFACE_N: i64 = 23;
}

/// The CGNS element type a kind is written as, and whether it is written by its
/// corners only (the second-order kinds whose CGNS node order is not checked here).
pub fn cgns_type(kind: CellKind) -> (i64, bool) {
    use etype::*;
    match kind {
        CellKind::Vertex => (NODE, false),
        CellKind::Line => (BAR_2, false),
        CellKind::Line3 => (BAR_3, false),
        CellKind::Triangle => (TRI_3, false),
        CellKind::Triangle6 => (TRI_6, false),
        CellKind::Quad => (QUAD_4, false),
        CellKind::Quad8 => (QUAD_8, false),
        CellKind::Quad9 => (QUAD_9, false),
        CellKind::Tetra => (TETRA_4, false),
        CellKind::Tetra10 => (TETRA_10, false),
        CellKind::Pyramid => (PYRA_5, false),
        CellKind::Wedge => (PENTA_6, false),
        CellKind::Hexa => (HEXA_8, false),
        CellKind::Pyramid13 | CellKind::Pyramid14 => (PYRA_5, true),
        CellKind::Wedge15 | CellKind::Wedge18 => (PENTA_6, true),
        CellKind::Hexa20 | CellKind::Hexa27 => (HEXA_8, true),
    }
}

/// The kind a CGNS element type is read as, and whether only its corners are kept
/// (second-order types whose node order smartmesh does not map). `None` for `MIXED`,
/// the polyhedral types and unknown numbers.
pub fn kind_of(t: i64) -> Option<(CellKind, usize, bool)> {
    use etype::*;
    // (kind kept, nodes per element in the file, corners only)
    Some(match t {
        NODE => (CellKind::Vertex, 1, false),
        BAR_2 => (CellKind::Line, 2, false),
        BAR_3 => (CellKind::Line3, 3, false),
        TRI_3 => (CellKind::Triangle, 3, false),
        TRI_6 => (CellKind::Triangle6, 6, false),
        QUAD_4 => (CellKind::Quad, 4, false),
        QUAD_8 => (CellKind::Quad8, 8, false),
        QUAD_9 => (CellKind::Quad9, 9, false),
        TETRA_4 => (CellKind::Tetra, 4, false),
        TETRA_10 => (CellKind::Tetra10, 10, false),
        PYRA_5 => (CellKind::Pyramid, 5, false),
        PYRA_13 => (CellKind::Pyramid, 13, true),
        PYRA_14 => (CellKind::Pyramid, 14, true),
        PENTA_6 => (CellKind::Wedge, 6, false),
        PENTA_15 => (CellKind::Wedge, 15, true),
        PENTA_18 => (CellKind::Wedge, 18, true),
        HEXA_8 => (CellKind::Hexa, 8, false),
        HEXA_20 => (CellKind::Hexa, 20, true),
        HEXA_27 => (CellKind::Hexa, 27, true),
        _ => return None,
    })
}

/// Which Gmsh node each CGNS position of a kind holds. The SIDS numbers the corners of
/// every linear element as Gmsh does (the tetrahedron's 0-1-2 counter-clockwise seen
/// from 3, the prism's 0-1-2 likewise seen from 3-4-5) and the mid-edge nodes of bars,
/// triangles and quadrilaterals in Gmsh's edge order; the 10-node tetrahedron's last two
/// edges come the other way round (CGNS 1-3 then 2-3, Gmsh 3-2 then 3-1). An
/// involution, so the same table converts both ways.
pub fn cgns_order(kind: CellKind) -> &'static [usize] {
    const IDENTITY: [usize; 9] = [0, 1, 2, 3, 4, 5, 6, 7, 8];
    match kind {
        CellKind::Tetra10 => &[0, 1, 2, 3, 4, 5, 6, 7, 9, 8],
        k => &IDENTITY[..k.nodes_per_cell().min(9)],
    }
}

/// The SIDS name of an element type, for messages.
pub fn type_name(t: i64) -> String {
    use etype::*;
    let n = match t {
        NODE => "NODE",
        BAR_2 => "BAR_2",
        BAR_3 => "BAR_3",
        TRI_3 => "TRI_3",
        TRI_6 => "TRI_6",
        QUAD_4 => "QUAD_4",
        QUAD_8 => "QUAD_8",
        QUAD_9 => "QUAD_9",
        TETRA_4 => "TETRA_4",
        TETRA_10 => "TETRA_10",
        PYRA_5 => "PYRA_5",
        PYRA_13 => "PYRA_13",
        PYRA_14 => "PYRA_14",
        PENTA_6 => "PENTA_6",
        PENTA_15 => "PENTA_15",
        PENTA_18 => "PENTA_18",
        HEXA_8 => "HEXA_8",
        HEXA_20 => "HEXA_20",
        HEXA_27 => "HEXA_27",
        MIXED => "MIXED",
        NGON_N => "NGON_n",
        NFACE_N => "NFACE_n",
        _ => return format!("element type {t}"),
    };
    n.to_string()
}

/// The `BCType_t` of a boundary named `name`: `BCWall` for the names a CFD user gives
/// walls (as OpenFOAM's patch types are chosen), else `UserDefined`.
pub fn bc_type(name: Option<&str>) -> &'static str {
    let lower = name.unwrap_or("").to_ascii_lowercase();
    let wall = ["wall", "airfoil", "aerofoil", "wing", "body", "blade", "cylinder", "hull"];
    if wall.iter().any(|w| lower.contains(w)) {
        "BCWall"
    } else {
        "UserDefined"
    }
}

/// Reads a CGNS file's bytes.
pub fn read_reported(bytes: &[u8], _ctx: &ReadContext) -> Result<(TaggedMesh, ReadReport)> {
    #[cfg(feature = "cgns")]
    {
        read::read(bytes)
    }
    #[cfg(not(feature = "cgns"))]
    {
        let _ = bytes;
        Err(Error::new(ErrorKind::Unsupported(NEEDS_FEATURE.into())))
    }
}

/// Writes a mesh as a CGNS/HDF5 file.
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    #[cfg(feature = "cgns")]
    {
        let _ = opts;
        write::write(mesh)
    }
    #[cfg(not(feature = "cgns"))]
    {
        let _ = (mesh, opts);
        Err(Error::new(ErrorKind::CannotWrite { format: "CGNS", reason: NEEDS_FEATURE.into() }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_written_reads_back_as_itself_or_its_corners() {
        for kind in CellKind::ALL {
            let (t, corners) = cgns_type(kind);
            let (back, n, _) = kind_of(t).expect("a type smartmesh writes, it reads");
            if corners {
                assert_eq!(back, kind.linear(), "{kind:?}");
            } else {
                assert_eq!(back, kind, "{kind:?}");
                assert_eq!(n, kind.nodes_per_cell(), "{kind:?}");
                let order = cgns_order(kind);
                assert_eq!(order.len(), n, "{kind:?}");
                // An involution: the same table converts both ways.
                for (i, &k) in order.iter().enumerate() {
                    assert_eq!(order[k], i, "{kind:?}");
                }
            }
        }
    }

    #[test]
    fn wall_like_names_are_walls() {
        assert_eq!(bc_type(Some("Airfoil")), "BCWall");
        assert_eq!(bc_type(Some("lower_wall")), "BCWall");
        assert_eq!(bc_type(Some("inlet")), "UserDefined");
        assert_eq!(bc_type(None), "UserDefined");
    }
}
