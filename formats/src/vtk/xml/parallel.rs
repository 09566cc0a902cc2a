//! Parallel XML files (`.pvtu`, `.pvtp`): `<PUnstructuredGrid>` or `<PPolyData>`
//! naming the files of its pieces (`<Piece Source="...">`, relative to the parallel
//! file's folder, as ParaView writes them). Each piece file is read as a serial file of
//! the same dataset and the pieces merged ([`super::pieces::merge`]: points appended,
//! not merged). The parallel file's own `<PPointData>`/`<PCellData>` only repeat the
//! pieces' array types and are not read.

use crate::{Error, ErrorKind, ReadContext, Result};

use super::{err, Ev, Scan, Tag};
use crate::vtk::Grid;

/// Reads the pieces a parallel file names, after its root element `root`.
pub(super) fn read(s: &mut Scan<'_>, root: &Tag<'_>, ctx: &ReadContext<'_>) -> Result<Grid> {
    let mut sources = Vec::new();
    loop {
        match s.next()? {
            Ev::Start(t) if t.name == b"Piece" => {
                let Some(src) = t.attr_str("Source") else {
                    return Err(err(
                        t.at,
                        ErrorKind::Expected {
                            expected: "a Source= attribute naming the piece's file".into(),
                            found: "none".into(),
                        },
                    ));
                };
                sources.push((src, t.at));
                s.skip_subtree(&t)?;
            }
            Ev::Start(t) if t.name == b"PUnstructuredGrid" || t.name == b"PPolyData" => {}
            Ev::Start(t) => s.skip_subtree(&t)?,
            Ev::End(b"VTKFile", _) | Ev::Eof => break,
            Ev::End(..) => {}
        }
    }
    if sources.is_empty() {
        return Err(err(
            root.at,
            ErrorKind::Expected {
                expected: "a <Piece Source=...> in the parallel file".into(),
                found: "none".into(),
            },
        ));
    }
    let mut grids = Vec::with_capacity(sources.len());
    for (src, at) in sources {
        let where_ = ctx.siblings.describe_beside(&src);
        let bytes = ctx.siblings.read_beside(&src)?.ok_or_else(|| {
            err(
                at,
                ErrorKind::Expected {
                    expected: format!(
                        "the piece file {where_} (a relative path beside the parallel file)"
                    ),
                    found: "no such file".into(),
                },
            )
        })?;
        // A piece is a serial file: one that is itself parallel is refused rather
        // than followed (a file naming itself would recurse).
        let g = super::read::read_piece(&bytes).map_err(|e: Error| e.with_path(&where_))?;
        grids.push((g, at));
    }
    super::pieces::merge(grids)
}
