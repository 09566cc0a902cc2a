//! The pieces of an XML dataset: what the scan finds in each `<Piece>`, PolyData's
//! cell lists, and the merge of several pieces (of one file, or of the files a parallel
//! file names) into one grid.
//!
//! Pieces are appended as VTK's own readers append them (`vtkXMLPUnstructuredGridReader`,
//! `vtkAppendFilter` without merging): the points of each piece follow those of the
//! pieces before it, and a point that two pieces share (the interface of a partition)
//! stays twice, once in each piece, since nothing in the files says that two points are
//! one (coincident points are not always the same vertex). Cells keep their pieces'
//! order; each point or cell array must be in every piece, with the same components.

use crate::error::Position;
use crate::{DataArray, ErrorKind, Layout, Result, MAX_POINTS};

use super::decode::Decoder;
use super::read::Spec;
use super::{err, Tag};
use crate::vtk::{Grid, Named};

/// What the scan finds in one `<Piece>`.
pub(super) struct PieceBody {
    pub(super) np: usize,
    /// `NumberOfCells` (UnstructuredGrid).
    pub(super) nc: usize,
    /// `NumberOfVerts`, `NumberOfLines`, `NumberOfPolys`, `NumberOfStrips` (PolyData).
    pub(super) npoly: [usize; 4],
    pub(super) at: usize,
    pub(super) point: Vec<Spec>,
    pub(super) cell: Vec<Spec>,
    pub(super) pts: Vec<Spec>,
    pub(super) cells: Vec<Spec>,
    /// PolyData's `<Verts>`, `<Lines>`, `<Polys>`, `<Strips>`.
    pub(super) poly: [Vec<Spec>; 4],
}

impl PieceBody {
    pub(super) fn new(t: &Tag<'_>) -> Result<PieceBody> {
        let n = |name: &str| t.attr_usize(name).map(|v| v.unwrap_or(0));
        Ok(PieceBody {
            np: n("NumberOfPoints")?,
            nc: n("NumberOfCells")?,
            npoly: [
                n("NumberOfVerts")?,
                n("NumberOfLines")?,
                n("NumberOfPolys")?,
                n("NumberOfStrips")?,
            ],
            at: t.at,
            point: Vec::new(),
            cell: Vec::new(),
            pts: Vec::new(),
            cells: Vec::new(),
            poly: Default::default(),
        })
    }

    /// Every array specification of the piece.
    pub(super) fn specs(&self) -> impl Iterator<Item = &Spec> {
        self.point
            .iter()
            .chain(&self.cell)
            .chain(&self.pts)
            .chain(&self.cells)
            .chain(self.poly.iter().flatten())
    }

    /// The piece's cell count: `NumberOfCells`, or the sum of PolyData's four (each
    /// checked against the file's size, so that the sum cannot overflow).
    pub(super) fn cells_total(&self) -> usize {
        self.npoly.iter().fold(self.nc, |a, &n| a.saturating_add(n))
    }
}

/// PolyData's cells of a piece into `g`, in VTK's order: vertices, lines, polygons,
/// strips. A one-point vertex cell is a vertex, a two-point line a line; polygons and
/// longer cells are split later (`vtk/cells.rs`).
pub(super) fn read_poly_cells(dec: &Decoder<'_>, p: &PieceBody, g: &mut Grid) -> Result<()> {
    g.offsets = vec![0];
    for (slot, specs) in p.poly.iter().enumerate() {
        let n = p.npoly[slot];
        if n == 0 {
            continue;
        }
        let name = ["Verts", "Lines", "Polys", "Strips"][slot];
        let find = |what: &str| {
            specs.iter().find(|s| s.name == what).ok_or_else(|| {
                err(
                    p.at,
                    ErrorKind::Expected {
                        expected: format!("a `{what}` DataArray in <{name}>"),
                        found: "none".into(),
                    },
                )
            })
        };
        let off = find("offsets")?;
        let mut offs = vec![0usize];
        dec.ints_into(off, n, &mut offs, "a cell end offset (0 or more)", |e| {
            usize::try_from(e).ok()
        })?;
        if let Some(i) = offs.windows(2).position(|w| w[1] < w[0]) {
            return Err(err(
                off.at,
                ErrorKind::Inconsistent(format!(
                    "offsets of <{name}> must rise; cell {i} ends at {} after {}",
                    offs[i + 1],
                    offs[i]
                )),
            ));
        }
        let con = find("connectivity")?;
        let last = *offs.last().unwrap_or(&0);
        let conn = dec.indices(con, last, p.np, &offs)?;
        let base = g.connectivity.len();
        for w in offs.windows(2) {
            g.types.push(match (slot, w[1] - w[0]) {
                (0, 1) => 1,
                (0, _) => 2,
                (1, 2) => 3,
                (1, _) => 4,
                (2, _) => 7,
                _ => 6,
            });
            g.offsets.push(base + w[1]);
        }
        g.connectivity.extend_from_slice(&conn);
        g.cells_at.get_or_insert(Position::Byte(con.at as u64));
        g.types_at.get_or_insert(Position::Byte(off.at as u64));
    }
    Ok(())
}

/// Widens a packed tensor array to 9 plain components (when pieces disagree on it).
fn plain(a: &mut Named) {
    if a.layout == Layout::Plain {
        return;
    }
    let d = DataArray {
        components: a.components,
        values: std::mem::take(&mut a.values),
        layout: a.layout,
    };
    let d = d.expanded().into_owned();
    a.components = d.components;
    a.values = d.values;
    a.layout = Layout::Plain;
}

/// Appends the arrays of a later piece to the first piece's arrays of the same names.
fn append_arrays(into: &mut [Named], from: Vec<Named>, what: &str, at: usize) -> Result<()> {
    if from.len() != into.len() {
        return Err(err(
            at,
            ErrorKind::Inconsistent(format!(
                "this piece has {} {what} arrays, the first piece {}",
                from.len(),
                into.len()
            )),
        ));
    }
    for mut b in from {
        let Some(a) = into.iter_mut().find(|a| a.name == b.name) else {
            return Err(err(
                at,
                ErrorKind::Inconsistent(format!(
                    "{what} array `{}` of this piece is not in the first piece",
                    b.name
                )),
            ));
        };
        if a.layout != b.layout {
            plain(a);
            plain(&mut b);
        }
        if a.components != b.components {
            return Err(err(
                at,
                ErrorKind::Inconsistent(format!(
                    "{what} array `{}` has {} components here, {} in the first piece",
                    b.name, b.components, a.components
                )),
            ));
        }
        a.values.extend_from_slice(&b.values);
    }
    Ok(())
}

/// The grids of the pieces (each with the byte of its `<Piece>`), appended into one.
pub(super) fn merge(grids: Vec<(Grid, usize)>) -> Result<Grid> {
    let mut it = grids.into_iter();
    let Some((mut g, _)) = it.next() else { return Ok(Grid::default()) };
    for (p, at) in it {
        let base = g.points.len();
        if base + p.points.len() > MAX_POINTS {
            return Err(err(
                at,
                crate::mesh::past_max_points("points of the pieces", base + p.points.len()),
            ));
        }
        let conn0 = g.connectivity.len();
        g.points.extend_from_slice(&p.points);
        g.connectivity.extend(p.connectivity.iter().map(|&v| v + base as crate::NodeIndex));
        g.offsets.extend(p.offsets.iter().skip(1).map(|&o| o + conn0));
        g.types.extend_from_slice(&p.types);
        g.cells_at = g.cells_at.or(p.cells_at);
        g.types_at = g.types_at.or(p.types_at);
        append_arrays(&mut g.point_arrays, p.point_arrays, "point", at)?;
        append_arrays(&mut g.cell_arrays, p.cell_arrays, "cell", at)?;
        if p.cell_tags.len() != g.cell_tags.len() {
            return Err(err(
                at,
                ErrorKind::Inconsistent(
                    "this piece has other cell tag arrays than the first piece".into(),
                ),
            ));
        }
        for (name, tags, _) in p.cell_tags {
            match g.cell_tags.iter_mut().find(|t| t.0 == name) {
                Some(t) => t.1.extend_from_slice(&tags),
                None => {
                    return Err(err(
                        at,
                        ErrorKind::Inconsistent(format!(
                            "cell array `{name}` of this piece is not in the first piece"
                        )),
                    ))
                }
            }
        }
    }
    Ok(g)
}
