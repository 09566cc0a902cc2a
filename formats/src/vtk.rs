//! VTK legacy and XML (being written).

#[allow(unused_imports)]
use crate::{Error, ErrorKind, ReadContext, Result, TaggedMesh, WriteOptions, Written};

/// Reads a legacy .vtk file.
pub fn read_legacy(_bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    Err(Error::new(ErrorKind::Unsupported("this reader is not written yet".into())))
}

/// Reads a .vtu file.
pub fn read_vtu(_bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    Err(Error::new(ErrorKind::Unsupported("this reader is not written yet".into())))
}

/// Writes a legacy .vtk file.
pub fn write_legacy(_mesh: &TaggedMesh, _opts: &WriteOptions) -> Result<Written> {
    Err(Error::new(ErrorKind::Unsupported("this writer is not written yet".into())))
}

/// Writes a .vtu file.
pub fn write_vtu(_mesh: &TaggedMesh, _opts: &WriteOptions) -> Result<Written> {
    Err(Error::new(ErrorKind::Unsupported("this writer is not written yet".into())))
}
