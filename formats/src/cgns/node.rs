//! CGNS nodes on HDF5 (the File Mapping Manual's HDF5 mapping): a node is a group with
//! the attributes `name`, `label`, `type` and `flags`, its data in the dataset
//! `" data"`, HDF5 dimensions the CGNS ones reversed. Writing makes nodes; reading
//! checks each node's label, type and sizes, every error naming the node's HDF5 path.

use hdf5_metno as hdf5;
use hdf5_metno::plist::file_create::LinkCreationOrder;
use hdf5_metno::types::FixedAscii;
use hdf5_metno::{Dataset, Group, IndexType, IterationOrder};

use crate::{Error, ErrorKind, Result};

/// A node's data, as written.
pub(super) enum Data<'a> {
    /// No data (`MT`).
    Empty,
    /// 32-bit integers with their CGNS dimensions (Fortran order).
    I4(&'a [i32], &'a [usize]),
    /// 64-bit integers with their CGNS dimensions.
    I8(&'a [i64], &'a [usize]),
    /// Doubles, one dimension.
    R8(&'a [f64]),
    /// Single precision, one dimension (the library version node).
    R4(&'a [f32]),
    /// Characters.
    C1(&'a str),
}

impl Data<'_> {
    fn code(&self) -> &'static str {
        match self {
            Data::Empty => "MT",
            Data::I4(..) => "I4",
            Data::I8(..) => "I8",
            Data::R8(_) => "R8",
            Data::R4(_) => "R4",
            Data::C1(_) => "C1",
        }
    }
}

/// The error for an HDF5 failure while writing.
pub(super) fn h5_write(e: hdf5::Error) -> Error {
    Error::new(ErrorKind::CannotWrite { format: "CGNS", reason: format!("HDF5: {e}") })
}

/// A malformed node: `what` was expected at `path`, `found` is there.
pub(super) fn bad(path: &str, expected: impl std::fmt::Display, found: impl Into<String>) -> Error {
    Error::new(ErrorKind::Expected {
        expected: format!("{expected} at node {path}"),
        found: found.into(),
    })
}

fn fixed<const N: usize>(s: &str) -> hdf5::Result<FixedAscii<N>> {
    FixedAscii::<N>::from_ascii(s.as_bytes()).map_err(|e| hdf5::Error::from(e.to_string()))
}

/// Writes the string attributes of a node (or the root) on `g`.
fn attrs(g: &hdf5::Location, name: &str, label: &str, code: &str) -> hdf5::Result<()> {
    g.new_attr::<FixedAscii<33>>().create("name")?.write_scalar(&fixed::<33>(name)?)?;
    g.new_attr::<FixedAscii<33>>().create("label")?.write_scalar(&fixed::<33>(label)?)?;
    g.new_attr::<FixedAscii<3>>().create("type")?.write_scalar(&fixed::<3>(code)?)
}

/// Creates the HDF5 file's root as the CGNS library does: the root attributes, the
/// `" format"` and `" hdf5version"` datasets.
pub(super) fn root(file: &hdf5::File) -> hdf5::Result<()> {
    attrs(file, "HDF5 MotherNode", "Root Node of HDF5 File", "MT")?;
    let mut format: Vec<i8> = b"IEEE_LITTLE_32\0".iter().map(|&b| b as i8).collect();
    file.new_dataset_builder().with_data(&format).create(" format")?;
    let (a, b, c) = hdf5::library_version();
    format = format!("HDF5 Version {a}.{b}.{c}").bytes().map(|b| b as i8).collect();
    format.resize(33, 0);
    file.new_dataset_builder().with_data(&format).create(" hdf5version")?;
    Ok(())
}

/// Creates the child `name` of `parent`, of SIDS type `label`, holding `data`.
pub(super) fn create(parent: &Group, name: &str, label: &str, data: Data) -> hdf5::Result<Group> {
    let g = parent
        .create_group_builder()
        .with_gcpl(|p| p.link_creation_order(LinkCreationOrder::Indexed))
        .create(name)?;
    attrs(&g, name, label, data.code())?;
    g.new_attr::<i32>().shape(1).create("flags")?.write_raw(&[1i32])?;
    match data {
        Data::Empty => {}
        Data::I4(v, dims) => {
            let shape: Vec<usize> = dims.iter().rev().copied().collect();
            g.new_dataset::<i32>().shape(shape).create(" data")?.write_raw(v)?;
        }
        Data::I8(v, dims) => {
            let shape: Vec<usize> = dims.iter().rev().copied().collect();
            g.new_dataset::<i64>().shape(shape).create(" data")?.write_raw(v)?;
        }
        Data::R8(v) => {
            g.new_dataset_builder().with_data(v).create(" data")?;
        }
        Data::R4(v) => {
            g.new_dataset_builder().with_data(v).create(" data")?;
        }
        Data::C1(s) => {
            let chars: Vec<i8> = s.bytes().map(|b| b as i8).collect();
            g.new_dataset_builder().with_data(&chars).create(" data")?;
        }
    }
    Ok(g)
}

/// Integers of CGNS dimensions `dims` as `I4` when they fit, else `I8` (what a 64-bit
/// CGNS library writes).
pub(super) fn create_ints(
    parent: &Group,
    name: &str,
    label: &str,
    v: &[i64],
    dims: &[usize],
) -> hdf5::Result<Group> {
    if v.iter().all(|&x| i32::try_from(x).is_ok()) {
        let small: Vec<i32> = v.iter().map(|&x| x as i32).collect();
        create(parent, name, label, Data::I4(&small, dims))
    } else {
        create(parent, name, label, Data::I8(v, dims))
    }
}

// ---------------------------------------------------------------------------------
// Reading

/// A node read back: its group, its HDF5 path (for messages), label and data type.
pub(super) struct Node {
    pub group: Group,
    pub path: String,
    pub name: String,
    pub label: String,
    pub code: String,
}

/// A string attribute, NUL padding cut.
fn attr_string(g: &Group, path: &str, attr: &str) -> Result<String> {
    let a = g.attr(attr).map_err(|_| bad(path, format!("a `{attr}` attribute"), "none"))?;
    let s: FixedAscii<33> = a
        .read_scalar()
        .map_err(|e| bad(path, format!("a string `{attr}` attribute"), e.to_string()))?;
    Ok(s.as_bytes().iter().take_while(|&&b| b != 0).map(|&b| b as char).collect())
}

/// Opens the node at `name` under `parent` (whose path is `parent_path`).
pub(super) fn open(parent: &Group, parent_path: &str, name: &str) -> Result<Node> {
    let path =
        if parent_path == "/" { format!("/{name}") } else { format!("{parent_path}/{name}") };
    let group =
        parent.group(name).map_err(|e| bad(&path, "a CGNS node (an HDF5 group)", e.to_string()))?;
    let label = attr_string(&group, &path, "label")?;
    let code = attr_string(&group, &path, "type")?;
    let name = attr_string(&group, &path, "name").unwrap_or_else(|_| name.to_string());
    Ok(Node { group, path, name, label, code })
}

/// The child nodes of `node` (HDF5 groups; the `" data"` dataset and others left),
/// in creation order where the file tracks it, else by name.
pub(super) fn children(node: &Node) -> Result<Vec<Node>> {
    let names = node
        .group
        .member_names_by(IndexType::CreationOrder, IterationOrder::Increasing)
        .or_else(|_| node.group.member_names())
        .map_err(|e| bad(&node.path, "a readable list of children", e.to_string()))?;
    let mut out = Vec::new();
    for n in names {
        if n.starts_with(' ') || node.group.group(&n).is_err() {
            continue;
        }
        out.push(open(&node.group, &node.path, &n)?);
    }
    Ok(out)
}

/// The children of `node` with SIDS label `label`.
pub(super) fn children_labelled(node: &Node, label: &str) -> Result<Vec<Node>> {
    Ok(children(node)?.into_iter().filter(|c| c.label == label).collect())
}

/// The child of `node` with SIDS label `label`, if any (the first).
pub(super) fn child_labelled(node: &Node, label: &str) -> Result<Option<Node>> {
    Ok(children_labelled(node, label)?.into_iter().next())
}

/// The `" data"` dataset of a node, with its element count, refused when its announced
/// size cannot come from the file: more values than `limit`, or more bytes than its
/// storage could expand to (deflate, the best HDF5 compressor in common use, expands at
/// most ~1032 times; contiguous data not at all).
fn dataset(node: &Node, limit: usize) -> Result<(Dataset, usize)> {
    let ds = node.group.dataset(" data").map_err(|_| {
        bad(&node.path, format!("data ({} node of type {})", node.label, node.code), "none")
    })?;
    let n = ds.size();
    let bytes = (n as u64).saturating_mul(ds.dtype().map(|t| t.size() as u64).unwrap_or(8));
    let storage = ds.storage_size();
    if n > limit || bytes > storage.saturating_mul(1100).saturating_add(4096) {
        return Err(Error::new(ErrorKind::ImplausibleCount {
            what: format!("the data of node {}", node.path),
            count: n as u64,
            limit: format!("at most {limit} values, {storage} bytes stored"),
        }));
    }
    Ok((ds, n))
}

/// The node's data as integers (`I4` or `I8`), at most `limit` of them.
pub(super) fn ints(node: &Node, limit: usize) -> Result<Vec<i64>> {
    if node.code != "I4" && node.code != "I8" {
        return Err(bad(&node.path, "integer data (I4 or I8)", node.code.clone()));
    }
    let (ds, _) = dataset(node, limit)?;
    ds.read_raw::<i64>().map_err(|e| bad(&node.path, "readable integer data", e.to_string()))
}

/// The node's data as doubles (`R4` or `R8`), at most `limit` values.
pub(super) fn reals(node: &Node, limit: usize) -> Result<Vec<f64>> {
    if node.code != "R4" && node.code != "R8" {
        return Err(bad(&node.path, "real data (R4 or R8)", node.code.clone()));
    }
    let (ds, _) = dataset(node, limit)?;
    ds.read_raw::<f64>().map_err(|e| bad(&node.path, "readable real data", e.to_string()))
}

/// The node's data as text (`C1`), trailing NULs and blanks cut.
pub(super) fn text(node: &Node) -> Result<String> {
    if node.code != "C1" {
        return Err(bad(&node.path, "character data (C1)", node.code.clone()));
    }
    let (ds, _) = dataset(node, 1 << 20)?;
    let raw =
        ds.read_raw::<i8>().map_err(|e| bad(&node.path, "readable characters", e.to_string()))?;
    let s: String = raw.iter().take_while(|&&c| c != 0).map(|&c| c as u8 as char).collect();
    Ok(s.trim_end().to_string())
}
