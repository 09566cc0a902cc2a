//! glTF 2.0 writer (being written).

#[allow(unused_imports)]
use crate::{Error, ErrorKind, ReadContext, Result, TaggedMesh, WriteOptions, Written};

/// Writes a mesh.
pub fn write(_mesh: &TaggedMesh, _opts: &WriteOptions) -> Result<Written> {
    Err(Error::new(ErrorKind::Unsupported("this writer is not written yet".into())))
}
