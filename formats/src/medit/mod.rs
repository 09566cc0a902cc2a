//! Medit .mesh/.meshb and .sol/.solb (being written).

#[allow(unused_imports)]
use crate::{Error, ErrorKind, ReadContext, Result, TaggedMesh, WriteOptions, Written};

/// Reads a mesh.
pub fn read(_bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    Err(Error::new(ErrorKind::Unsupported("this reader is not written yet".into())))
}

/// Writes a mesh.
pub fn write(_mesh: &TaggedMesh, _opts: &WriteOptions) -> Result<Written> {
    Err(Error::new(ErrorKind::Unsupported("this writer is not written yet".into())))
}
