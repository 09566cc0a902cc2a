//! Whether a mixed triangle/quad mesh is valid: every cell positive (a triangle's area, a
//! quad's Jacobian at each of its four corners), no two cells overlapping, no vertex
//! hanging inside another cell's edge, no edge shared by more than two cells or twice in
//! the same direction, and the sum of the cell areas (its brute-force twin: it must equal
//! the area of the domain the caller knows).
//!
//! Overlaps and hanging vertices are found through a uniform grid of the cells' boxes;
//! tests also run the all-pairs twin on small meshes ([`check_cells_brute`]).
//! Cost: O(cells) with the grid when cells are of similar size.

use smartmesh_formats::{CellKind, TaggedMesh};

use super::geom::{convex_overlap, norm, orient, segment_distance, sub, Bbox, Grid, P};

/// What [`check_mesh`] found. Lists hold at most [`Validity::LIMIT`] items each.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct Validity {
    /// Triangles checked.
    pub triangles: usize,
    /// Quads checked.
    pub quads: usize,
    /// Cells (index among the surface cells, in block order) with a corner whose
    /// Jacobian is not positive.
    pub inverted: Vec<usize>,
    /// Pairs of cells that overlap.
    pub overlaps: Vec<(usize, usize)>,
    /// Vertices lying inside an edge of a cell they are not a corner of.
    pub hanging: Vec<usize>,
    /// Edges shared by more than two cells or twice in the same direction.
    pub bad_edges: Vec<[usize; 2]>,
    /// Sum of the cell areas.
    pub area: f64,
}

impl Validity {
    /// Most items each list keeps.
    pub const LIMIT: usize = 100;

    /// Whether no problem was found.
    pub fn is_valid(&self) -> bool {
        self.inverted.is_empty()
            && self.overlaps.is_empty()
            && self.hanging.is_empty()
            && self.bad_edges.is_empty()
    }

    /// One line per kind of problem, empty when valid.
    pub fn problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        if !self.inverted.is_empty() {
            out.push(format!(
                "{} cells not positive (first: cell {})",
                self.inverted.len(),
                self.inverted[0]
            ));
        }
        if !self.overlaps.is_empty() {
            let (a, b) = self.overlaps[0];
            out.push(format!(
                "{} overlapping cell pairs (first: cells {a} and {b})",
                self.overlaps.len()
            ));
        }
        if !self.hanging.is_empty() {
            out.push(format!(
                "{} hanging vertices (first: vertex {})",
                self.hanging.len(),
                self.hanging[0]
            ));
        }
        if !self.bad_edges.is_empty() {
            let [a, b] = self.bad_edges[0];
            out.push(format!(
                "{} edges shared by more than two cells or twice the same way (first: {a}-{b})",
                self.bad_edges.len()
            ));
        }
        out
    }
}

/// The corners of every first-order surface cell of `mesh` (second-order cells by their
/// corners), in block order.
pub fn surface_cells(mesh: &TaggedMesh) -> Vec<Vec<usize>> {
    mesh.cells()
        .filter(|c| c.0.dim() == 2)
        .map(|(kind, nodes, _, _)| {
            let k = match kind {
                CellKind::Triangle | CellKind::Triangle6 => 3,
                _ => 4,
            };
            nodes[..k].iter().map(|&v| v as usize).collect()
        })
        .collect()
}

/// Checks the surface cells of `mesh`.
pub fn check_mesh(mesh: &TaggedMesh) -> Validity {
    let pts: Vec<P> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    check_cells(&pts, &surface_cells(mesh))
}

fn corners(pts: &[P], c: &[usize]) -> Vec<P> {
    c.iter().map(|&v| pts[v]).collect()
}

/// Signed area of a polygon.
pub fn polygon_area(poly: &[P]) -> f64 {
    let mut a = 0.0;
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        a += p[0] * q[1] - p[1] * q[0];
    }
    0.5 * a
}

/// Whether every corner of the cell has a positive Jacobian (the cross product of its two
/// edges, counter-clockwise), relative to the cell's size.
pub fn positive_corners(poly: &[P]) -> bool {
    let n = poly.len();
    let size: f64 = (0..n).map(|i| norm(sub(poly[(i + 1) % n], poly[i]))).fold(0.0, f64::max);
    (0..n).all(|i| orient(poly[(i + n - 1) % n], poly[i], poly[(i + 1) % n]) > 1e-14 * size * size)
}

fn edge_checks(cells: &[Vec<usize>], v: &mut Validity) -> Vec<[usize; 2]> {
    let mut edges: Vec<([usize; 2], bool)> = Vec::new();
    for c in cells {
        for i in 0..c.len() {
            let (a, b) = (c[i], c[(i + 1) % c.len()]);
            edges.push(([a.min(b), a.max(b)], a < b));
        }
    }
    edges.sort_unstable();
    let mut unique = Vec::new();
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 {
            j += 1;
        }
        let bad = j - i > 2 || (j - i == 2 && edges[i].1 == edges[i + 1].1);
        if bad && v.bad_edges.len() < Validity::LIMIT {
            v.bad_edges.push(edges[i].0);
        }
        unique.push(edges[i].0);
        i = j;
    }
    unique
}

fn cell_checks(pts: &[P], cells: &[Vec<usize>], v: &mut Validity) {
    for (i, c) in cells.iter().enumerate() {
        let poly = corners(pts, c);
        if c.len() == 3 {
            v.triangles += 1;
        } else {
            v.quads += 1;
        }
        v.area += polygon_area(&poly).abs();
        if !positive_corners(&poly) && v.inverted.len() < Validity::LIMIT {
            v.inverted.push(i);
        }
    }
}

fn overlap(pts: &[P], a: &[usize], b: &[usize]) -> bool {
    let (pa, pb) = (corners(pts, a), corners(pts, b));
    let size = Bbox::of(&pa).union(Bbox::of(&pb));
    let tol = 1e-9 * (size.hi[0] - size.lo[0]).max(size.hi[1] - size.lo[1]);
    // Only positive cells are convex; an inverted one is reported already.
    positive_corners(&pa) && positive_corners(&pb) && convex_overlap(&pa, &pb, -tol)
}

fn hangs(pts: &[P], v: usize, e: [usize; 2]) -> bool {
    if v == e[0] || v == e[1] {
        return false;
    }
    let len = norm(sub(pts[e[1]], pts[e[0]]));
    segment_distance(pts[v], pts[e[0]], pts[e[1]]) <= 1e-9 * len
        && norm(sub(pts[v], pts[e[0]])) > 1e-9 * len
        && norm(sub(pts[v], pts[e[1]])) > 1e-9 * len
}

/// Checks cells given by their counter-clockwise corners (3 or 4 each).
pub fn check_cells(pts: &[P], cells: &[Vec<usize>]) -> Validity {
    let mut v = Validity::default();
    cell_checks(pts, cells, &mut v);
    let edges = edge_checks(cells, &mut v);
    let boxes: Vec<Bbox> = cells.iter().map(|c| Bbox::of(&corners(pts, c))).collect();
    if !boxes.is_empty() {
        let mut grid = Grid::new(&boxes);
        for (i, c) in cells.iter().enumerate() {
            for j in grid.query(boxes[i]) {
                let j = j as usize;
                if j > i && overlap(pts, c, &cells[j]) && v.overlaps.len() < Validity::LIMIT {
                    v.overlaps.push((i, j));
                }
            }
        }
    }
    let eboxes: Vec<Bbox> = edges.iter().map(|e| Bbox::of(&[pts[e[0]], pts[e[1]]])).collect();
    if !eboxes.is_empty() {
        let mut grid = Grid::new(&eboxes);
        let mut used: Vec<usize> = cells.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        for &p in &used {
            let b = Bbox::of(&[pts[p]]);
            if grid.query(b).into_iter().any(|e| hangs(pts, p, edges[e as usize]))
                && v.hanging.len() < Validity::LIMIT
            {
                v.hanging.push(p);
            }
        }
    }
    v
}

/// The all-pairs twin of [`check_cells`] (for small meshes in tests).
pub fn check_cells_brute(pts: &[P], cells: &[Vec<usize>]) -> Validity {
    let mut v = Validity::default();
    cell_checks(pts, cells, &mut v);
    let edges = edge_checks(cells, &mut v);
    for i in 0..cells.len() {
        for j in i + 1..cells.len() {
            if overlap(pts, &cells[i], &cells[j]) && v.overlaps.len() < Validity::LIMIT {
                v.overlaps.push((i, j));
            }
        }
    }
    let mut used: Vec<usize> = cells.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    for &p in &used {
        if edges.iter().any(|&e| hangs(pts, p, e)) && v.hanging.len() < Validity::LIMIT {
            v.hanging.push(p);
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2x1 strip of unit quads, then variations that break it.
    fn strip() -> (Vec<P>, Vec<Vec<usize>>) {
        let pts = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, 1.0], [2.0, 1.0]];
        (pts, vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]])
    }

    fn both(pts: &[P], cells: &[Vec<usize>]) -> Validity {
        let a = check_cells(pts, cells);
        let b = check_cells_brute(pts, cells);
        assert_eq!(a, b, "grid and brute force disagree");
        a
    }

    #[test]
    fn a_valid_strip_passes_and_its_area_is_exact() {
        let (pts, cells) = strip();
        let v = both(&pts, &cells);
        assert!(v.is_valid(), "{v:?}");
        assert_eq!(v.area, 2.0);
        assert_eq!((v.quads, v.triangles), (2, 0));
    }

    #[test]
    fn inverted_overlapping_and_hanging_are_found() {
        // A non-convex (arrow) quad: one corner negative.
        let (mut pts, mut cells) = strip();
        pts[4] = [0.4, 0.2];
        let v = both(&pts, &cells);
        assert!(!v.inverted.is_empty());
        // Overlap: a third quad on top of the first.
        let (pts, _) = strip();
        cells = vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4], vec![0, 1, 5, 3]];
        let v = both(&pts, &cells);
        assert!(v.overlaps.contains(&(0, 2)), "{v:?}");
        assert!(v.area > 2.0);
        // Hanging node: the right cell split in two triangles and a vertex on the shared
        // edge of the left one.
        let mut pts = strip().0;
        pts.push([1.0, 0.5]);
        let cells = vec![vec![0, 1, 4, 3], vec![1, 2, 6], vec![2, 5, 6], vec![6, 5, 4]];
        let v = both(&pts, &cells);
        assert_eq!(v.hanging, vec![6]);
        assert!(v.overlaps.is_empty() && v.inverted.is_empty());
        // An edge shared three times.
        let (pts, _) = strip();
        let cells = vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4], vec![1, 4, 3]];
        assert!(!both(&pts, &cells).bad_edges.is_empty());
    }
}
