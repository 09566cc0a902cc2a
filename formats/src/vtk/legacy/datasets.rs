//! The legacy datasets other than `UNSTRUCTURED_GRID`, read as the grid VTK makes of
//! them (`vtkDataSet::GetCell`):
//!
//! - `POLYDATA`: `VERTICES`, `LINES`, `POLYGONS` and `TRIANGLE_STRIPS` cell lists (4.2
//!   or 5.1 layout, as `CELLS`); cells numbered as VTK numbers them, vertices first,
//!   then lines, polygons, strips, whatever their order in the file. A one-point vertex
//!   cell is a vertex, a two-point line a line, a polygon of 3 or 4 points a triangle or
//!   quad; longer ones are split (`vtk/cells.rs`, with a note);
//! - `STRUCTURED_GRID` (`DIMENSIONS`, `POINTS`), `RECTILINEAR_GRID` (`DIMENSIONS`,
//!   `X_COORDINATES`, `Y_COORDINATES`, `Z_COORDINATES`) and `STRUCTURED_POINTS`
//!   (`DIMENSIONS`, `ORIGIN`, `SPACING` or `ASPECT_RATIO`): point `i + nx (j + ny k)`,
//!   one cell per step of the dimensions of more than one point, `i` fastest (VTK's
//!   order, so that cell data keeps its meaning): hexahedra when all three are, quads
//!   when two are, lines when one is, a vertex for a single point.
//!
//! A structured dataset's points are not in the file for `STRUCTURED_POINTS` and
//! `RECTILINEAR_GRID`: nothing bounds their count but the dimensions, so more than
//! [`MAX_GENERATED`] points are refused before anything is allocated.

use crate::error::Position;
use crate::{Error, ErrorKind, NodeIndex, Result};

use super::read::Reader;

/// Most points made from the dimensions alone (2^27: 3 GB of coordinates).
pub(super) const MAX_GENERATED: usize = 1 << 27;

/// The dataset types.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Dataset {
    Unstructured,
    Poly,
    StructuredGrid,
    Rectilinear,
    StructuredPoints,
}

impl Dataset {
    pub(super) fn from_name(name: &[u8]) -> Option<Dataset> {
        let n = name.to_ascii_uppercase();
        Some(match n.as_slice() {
            b"UNSTRUCTURED_GRID" => Dataset::Unstructured,
            b"POLYDATA" => Dataset::Poly,
            b"STRUCTURED_GRID" => Dataset::StructuredGrid,
            b"RECTILINEAR_GRID" => Dataset::Rectilinear,
            b"STRUCTURED_POINTS" => Dataset::StructuredPoints,
            _ => return None,
        })
    }
}

/// What a dataset other than an unstructured grid gathers before its grid is built.
#[derive(Default)]
pub(super) struct Shape {
    dims: Option<([usize; 3], Position)>,
    origin: [f64; 3],
    spacing: Option<[f64; 3]>,
    coords: [Option<Vec<f64>>; 3],
    /// POLYDATA's cell lists: vertices, lines, polygons, strips.
    poly: [Option<(Vec<usize>, Vec<NodeIndex>)>; 4],
}

/// The number of cells of a structured dataset of dimensions `d`.
fn structured_cells(d: [usize; 3]) -> usize {
    let steps: Vec<usize> = d.iter().filter(|&&n| n > 1).map(|&n| n - 1).collect();
    if d.contains(&0) {
        0
    } else {
        steps.iter().product()
    }
}

impl<'a> Reader<'a> {
    /// Reads a keyword of the current dataset other than an unstructured grid;
    /// `false` when the keyword is none of its own.
    pub(super) fn dataset_keyword(&mut self, key: &[u8]) -> Result<bool> {
        let k = key.to_ascii_uppercase();
        let ds = self.dataset;
        let structured = matches!(
            ds,
            Dataset::StructuredGrid | Dataset::Rectilinear | Dataset::StructuredPoints
        );
        match k.as_slice() {
            b"DIMENSIONS" if structured => self.dimensions()?,
            b"ORIGIN" if ds == Dataset::StructuredPoints => {
                self.shape.origin = self.three("an origin coordinate")?;
            }
            b"SPACING" | b"ASPECT_RATIO" if ds == Dataset::StructuredPoints => {
                self.shape.spacing = Some(self.three("a spacing")?);
            }
            b"X_COORDINATES" | b"Y_COORDINATES" | b"Z_COORDINATES"
                if ds == Dataset::Rectilinear =>
            {
                let axis = (k[0] - b'X') as usize;
                let n = self.count("coordinates", 2, 4)?;
                let ty = self.scalar()?;
                self.end_header();
                let mut v = Vec::new();
                self.floats(n, ty, "a coordinate", &mut v)?;
                if let Some((d, _)) = self.shape.dims {
                    if d[axis] != n {
                        return Err(self.err(ErrorKind::Inconsistent(format!(
                            "{} values, but DIMENSIONS gives {} along that axis",
                            n, d[axis]
                        ))));
                    }
                }
                self.shape.coords[axis] = Some(v);
            }
            b"VERTICES" | b"LINES" | b"POLYGONS" | b"TRIANGLE_STRIPS" if ds == Dataset::Poly => {
                let slot = match k.as_slice() {
                    b"VERTICES" => 0,
                    b"LINES" => 1,
                    b"POLYGONS" => 2,
                    _ => 3,
                };
                let at = self.here();
                let list = self.read_cell_list()?;
                self.grid.cells_at.get_or_insert(at);
                self.shape.poly[slot] = Some(list);
                let n = self.shape.poly.iter().flatten().map(|(o, _)| o.len() - 1).sum();
                self.ncells = Some(n);
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    fn three(&mut self, what: &str) -> Result<[f64; 3]> {
        let mut v = [0.0; 3];
        for x in &mut v {
            *x = self.t.f64(what).map_err(|e| self.fix(e))?;
            if !x.is_finite() {
                return Err(
                    self.err(ErrorKind::NonFinite { what: what.into(), value: x.to_string() })
                );
            }
        }
        Ok(v)
    }

    fn dimensions(&mut self) -> Result<()> {
        let at = self.here();
        let mut d = [0usize; 3];
        for x in &mut d {
            *x = self.usize("a dimension")?;
        }
        let np = d.iter().try_fold(1usize, |a, &n| a.checked_mul(n));
        let limit =
            if self.dataset == Dataset::StructuredGrid { crate::MAX_POINTS } else { MAX_GENERATED };
        let np = match np {
            Some(n) if n <= limit => n,
            _ => {
                return Err(self.err(ErrorKind::ImplausibleCount {
                    what: "points of DIMENSIONS".into(),
                    count: d.iter().map(|&n| n as u64).fold(1u64, |a, n| a.saturating_mul(n)),
                    limit: format!("{limit} points for a dataset whose points are not in the file"),
                }))
            }
        };
        match self.npoints {
            Some(p) if p != np => {
                return Err(self.err(ErrorKind::Inconsistent(format!(
                    "DIMENSIONS {} {} {} make {np} points, POINTS gives {p}",
                    d[0], d[1], d[2]
                ))))
            }
            _ => {}
        }
        if self.dataset != Dataset::StructuredGrid {
            self.npoints = Some(np);
        }
        self.ncells = Some(structured_cells(d));
        self.shape.dims = Some((d, at));
        Ok(())
    }

    /// Builds the points and cells of a dataset other than an unstructured grid, once
    /// the whole file is read.
    pub(super) fn finish_dataset(&mut self) -> Result<()> {
        match self.dataset {
            Dataset::Unstructured => Ok(()),
            Dataset::Poly => {
                let mut types = Vec::new();
                let mut offsets = vec![0usize];
                let mut conn = Vec::new();
                for (slot, list) in self.shape.poly.iter_mut().enumerate() {
                    let Some((offs, c)) = list.take() else { continue };
                    for w in offs.windows(2) {
                        let k = w[1] - w[0];
                        types.push(match (slot, k) {
                            (0, 1) => 1,
                            (0, _) => 2,
                            (1, 2) => 3,
                            (1, _) => 4,
                            (2, _) => 7,
                            _ => 6,
                        });
                        offsets.push(conn.len() + w[1]);
                    }
                    conn.extend_from_slice(&c);
                }
                // Cell lists before POINTS were read without a point count to check.
                let np = self.grid.points.len();
                if let Some(&v) = conn.iter().find(|&&v| v as usize >= np) {
                    return Err(Error {
                        path: None,
                        at: self.grid.cells_at,
                        kind: ErrorKind::IndexOutOfRange {
                            what: "a POLYDATA cell".into(),
                            index: v as i64,
                            available: np,
                        },
                    });
                }
                self.grid.types = types;
                self.grid.types_at = self.grid.cells_at;
                self.grid.offsets = offsets;
                self.grid.connectivity = conn;
                Ok(())
            }
            _ => self.structured(),
        }
    }

    fn structured(&mut self) -> Result<()> {
        let Some((d, at)) = self.shape.dims else {
            return Err(self.err(ErrorKind::UnexpectedEof {
                context: "expected DIMENSIONS in a structured dataset".into(),
            }));
        };
        let err = |kind| Error { path: None, at: Some(at), kind };
        let np = d[0] * d[1] * d[2];
        match self.dataset {
            Dataset::StructuredPoints => {
                let s = self.shape.spacing.unwrap_or([1.0; 3]);
                let o = self.shape.origin;
                self.grid.points = grid_points(d, |a, i| o[a] + s[a] * i as f64);
            }
            Dataset::Rectilinear => {
                let c = &self.shape.coords;
                for (a, axis) in c.iter().enumerate() {
                    if axis.as_ref().map_or(0, Vec::len) != d[a] {
                        return Err(err(ErrorKind::Expected {
                            expected: format!("{} {}_COORDINATES", d[a], ["X", "Y", "Z"][a]),
                            found: axis.as_ref().map_or(0, Vec::len).to_string(),
                        }));
                    }
                }
                let c: Vec<&Vec<f64>> = c.iter().flatten().collect();
                self.grid.points = grid_points(d, |a, i| c[a][i]);
            }
            _ => {
                if self.grid.points.len() != np {
                    return Err(err(ErrorKind::Inconsistent(format!(
                        "DIMENSIONS {} {} {} make {np} points, POINTS gives {}",
                        d[0],
                        d[1],
                        d[2],
                        self.grid.points.len()
                    ))));
                }
            }
        }
        let (types, offsets, conn) = structured_cells_of(d);
        self.grid.types = types;
        self.grid.offsets = offsets;
        self.grid.connectivity = conn;
        self.grid.cells_at = Some(at);
        self.grid.types_at = Some(at);
        Ok(())
    }
}

/// The points of a structured dataset, `coord(axis, index)` each coordinate.
fn grid_points(d: [usize; 3], coord: impl Fn(usize, usize) -> f64) -> Vec<[f64; 3]> {
    let mut p = Vec::with_capacity(d[0] * d[1] * d[2]);
    for k in 0..d[2] {
        for j in 0..d[1] {
            for i in 0..d[0] {
                p.push([coord(0, i), coord(1, j), coord(2, k)]);
            }
        }
    }
    p
}

/// Types, offsets and connectivity of a structured dataset's cells, in VTK's order.
fn structured_cells_of(d: [usize; 3]) -> (Vec<u8>, Vec<usize>, Vec<NodeIndex>) {
    let id = |i: usize, j: usize, k: usize| (i + d[0] * (j + d[1] * k)) as NodeIndex;
    let axes: Vec<usize> = (0..3).filter(|&a| d[a] > 1).collect();
    let n = structured_cells(d);
    let (ty, k) = match axes.len() {
        0 => (1u8, 1usize),
        1 => (3, 2),
        2 => (9, 4),
        _ => (12, 8),
    };
    let mut conn = Vec::with_capacity(n * k);
    let step = |a: usize| [usize::from(a == 0), usize::from(a == 1), usize::from(a == 2)];
    // The cells' origins: every point whose index along each cell axis is not the last.
    let last = |a: usize| if axes.contains(&a) { d[a] - 1 } else { d[a].min(1) };
    for kk in 0..last(2) {
        for jj in 0..last(1) {
            for ii in 0..last(0) {
                let at = |e: [usize; 3]| id(ii + e[0], jj + e[1], kk + e[2]);
                match axes.len() {
                    0 => conn.push(at([0, 0, 0])),
                    1 => {
                        let u = step(axes[0]);
                        conn.extend([at([0, 0, 0]), at(u)]);
                    }
                    2 => {
                        let (u, v) = (step(axes[0]), step(axes[1]));
                        let uv = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
                        conn.extend([at([0, 0, 0]), at(u), at(uv), at(v)]);
                    }
                    _ => {
                        for z in 0..2 {
                            conn.extend([[0, 0, z], [1, 0, z], [1, 1, z], [0, 1, z]].map(&at));
                        }
                    }
                }
            }
        }
    }
    let offsets = (0..=n).map(|c| c * k).collect();
    (vec![ty; n], offsets, conn)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_cells_follow_vtk_s_numbering() {
        // 3 x 2 points in the plane: two quads, counter-clockwise.
        let (t, o, c) = structured_cells_of([3, 2, 1]);
        assert_eq!(t, vec![9, 9]);
        assert_eq!(o, vec![0, 4, 8]);
        assert_eq!(c, vec![0, 1, 4, 3, 1, 2, 5, 4]);
        // A column along z: lines.
        let (t, _, c) = structured_cells_of([1, 1, 3]);
        assert_eq!((t, c), (vec![3, 3], vec![0, 1, 1, 2]));
        // 2 x 2 x 2: one hexahedron.
        let (t, _, c) = structured_cells_of([2, 2, 2]);
        assert_eq!((t, c), (vec![12], vec![0, 1, 3, 2, 4, 5, 7, 6]));
        // A single point: a vertex; an empty dimension: nothing.
        assert_eq!(structured_cells_of([1, 1, 1]).2, vec![0]);
        assert_eq!(structured_cells_of([0, 4, 4]).0, Vec::<u8>::new());
    }
}
