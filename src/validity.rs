//! Whether a mixed triangle/quad mesh is valid: every cell positive (a triangle's area, a
//! quad's Jacobian at each of its four corners), no two cells overlapping, no vertex
//! hanging inside another cell's edge, no edge shared by more than two cells or twice in
//! the same direction, and the sum of the cell areas (its brute-force twin: it must equal
//! the area of the domain the caller knows).
//!
//! A corner is positive when its exact orientation (Shewchuk's predicate,
//! `geometry::segment::orient`, the one the remesher's operators use) exceeds 1e-14 of
//! the square of the cell's longest edge: slivers flatter than that are refused as
//! inverted. The boundary-layer skin builds only cells that pass this test, and the
//! remesher checks a mesh with frozen cells, given and returned, with [`check_mesh`].
//!
//! Overlaps and hanging vertices are found through a quadtree of the cells' and edges'
//! boxes (`geometry::near_pairs`, which sweeps each leaf across its items so that a
//! skin's stacked, slanted cells are not all tested against each other), whose leaves
//! follow the grading: an airfoil's cells 50 chords inside a far field do not share a
//! few buckets, as they did in a uniform grid (10 s on the GAMM A7 example's 20 000
//! cells). A pair of cells is tested only when their boxes meet, which overlapping
//! cells' boxes must (overlap means a penetration of more than the tolerance along every
//! separating axis); an edge's box is grown by twice the distance a hanging vertex may
//! be off it. Each cell's corners and positivity are computed once. Tests run the
//! all-pairs twin ([`check_cells_brute`]) and require the same answer, lists in the same
//! order, on hard cases.
//! Cost: O(cells · log) when cells of similar size are near each other.

use smartmesh_formats::{CellKind, TaggedMesh};

use crate::geometry::near_pairs::near_pairs;
use crate::geometry::plane::{convex_overlap, norm, segment_distance, sub, Bbox, P};
use crate::geometry::segment::orient;

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
pub(crate) fn polygon_area(poly: &[P]) -> f64 {
    let mut a = 0.0;
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        a += p[0] * q[1] - p[1] * q[0];
    }
    0.5 * a
}

/// Whether every corner of the cell has a positive Jacobian (the exact orientation of the
/// corner and its two neighbours, counter-clockwise) above 1e-14 of the square of the
/// cell's longest edge.
pub(crate) fn positive_corners(poly: &[P]) -> bool {
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

/// Counts, area and inverted cells of the cells of corners `polys`; returns whether each
/// is positive.
fn cell_checks(polys: &[Vec<P>], v: &mut Validity) -> Vec<bool> {
    let mut positive = Vec::with_capacity(polys.len());
    for (i, poly) in polys.iter().enumerate() {
        if poly.len() == 3 {
            v.triangles += 1;
        } else {
            v.quads += 1;
        }
        v.area += polygon_area(poly).abs();
        let ok = positive_corners(poly);
        if !ok && v.inverted.len() < Validity::LIMIT {
            v.inverted.push(i);
        }
        positive.push(ok);
    }
    positive
}

fn overlap(pts: &[P], a: &[usize], b: &[usize]) -> bool {
    let (pa, pb) = (corners(pts, a), corners(pts, b));
    // Only positive cells are convex; an inverted one is reported already.
    positive_corners(&pa) && positive_corners(&pb) && overlap_of(&pa, &pb)
}

/// Whether two positive cells of corners `pa` and `pb` overlap by more than 1e-9 of the
/// size of their boxes' union.
fn overlap_of(pa: &[P], pb: &[P]) -> bool {
    let size = Bbox::of(pa).union(Bbox::of(pb));
    let tol = 1e-9 * (size.hi[0] - size.lo[0]).max(size.hi[1] - size.lo[1]);
    convex_overlap(pa, pb, -tol)
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
    // Each cell's corners gathered once, for every test below.
    let polys: Vec<Vec<P>> = cells.iter().map(|c| corners(pts, c)).collect();
    let positive = cell_checks(&polys, &mut v);
    let edges = edge_checks(cells, &mut v);
    // Candidate pairs in (i, j) order, so that the first LIMIT found are the twin's.
    let items: Vec<(&[P], f64)> = polys.iter().map(|p| (&p[..], 0.0)).collect();
    for (i, j) in near_pairs(&items) {
        if v.overlaps.len() >= Validity::LIMIT {
            break;
        }
        let (i, j) = (i as usize, j as usize);
        if positive[i] && positive[j] && overlap_of(&polys[i], &polys[j]) {
            v.overlaps.push((i, j));
        }
    }
    // A hanging vertex is within 1e-9 of the edge's length of it: inside its hull grown
    // by twice that. Items: the edges, then the vertices used.
    let mut used: Vec<usize> = cells.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    let ends: Vec<[P; 2]> = edges.iter().map(|e| [pts[e[0]], pts[e[1]]]).collect();
    let spots: Vec<[P; 1]> = used.iter().map(|&p| [pts[p]]).collect();
    let items: Vec<(&[P], f64)> = ends
        .iter()
        .map(|e| (&e[..], 2e-9 * norm(sub(e[1], e[0]))))
        .chain(spots.iter().map(|s| (&s[..], 0.0)))
        .collect();
    let mut hanging = vec![false; used.len()];
    for (e, p) in near_pairs(&items) {
        let (e, p) = (e as usize, p as usize);
        if e < ends.len() && p >= ends.len() && hangs(pts, used[p - ends.len()], edges[e]) {
            hanging[p - ends.len()] = true;
        }
    }
    v.hanging = used
        .iter()
        .zip(&hanging)
        .filter(|(_, &h)| h)
        .map(|(&p, _)| p)
        .take(Validity::LIMIT)
        .collect();
    v
}

/// The all-pairs twin of [`check_cells`] (for small meshes in tests).
pub fn check_cells_brute(pts: &[P], cells: &[Vec<usize>]) -> Validity {
    let mut v = Validity::default();
    let polys: Vec<Vec<P>> = cells.iter().map(|c| corners(pts, c)).collect();
    cell_checks(&polys, &mut v);
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

    /// A graded polar mesh as an airfoil's in a far field: rings from radius 1e-3 to 50
    /// (growth 1.35), quads inside, each outer quad split into two triangles, and an
    /// axis-aligned square block at the centre with a vertex that hangs on its bottom
    /// edge 1e-13 off it (outside the edge's flat box).
    fn graded() -> (Vec<P>, Vec<Vec<usize>>) {
        let (rings, sectors): (usize, usize) = (36, 32);
        let mut pts = Vec::new();
        for r in 0..rings {
            let rad = 1e-3 * 1.35f64.powi(r as i32);
            for s in 0..sectors {
                let a = s as f64 * std::f64::consts::TAU / sectors as f64;
                pts.push([rad * a.cos(), rad * a.sin()]);
            }
        }
        let id = |r: usize, s: usize| r * sectors + s % sectors;
        let mut cells = Vec::new();
        for r in 0..rings - 1 {
            for s in 0..sectors {
                let q = [id(r, s), id(r + 1, s), id(r + 1, s + 1), id(r, s + 1)];
                if r < rings / 2 {
                    cells.push(q.to_vec());
                } else {
                    cells.push(vec![q[0], q[1], q[2]]);
                    cells.push(vec![q[0], q[2], q[3]]);
                }
            }
        }
        // The block, far inside the first ring: [0, 1e-4]² with a hanging vertex.
        let base = pts.len();
        pts.extend([[0.0, 0.0], [1e-4, 0.0], [1e-4, 1e-4], [0.0, 1e-4], [5e-5, -1e-13]]);
        cells.push(vec![base, base + 1, base + 2, base + 3]);
        cells.push(vec![base, base + 4, base + 1]);
        (pts, cells)
    }

    /// The index and the all-pairs twin agree on a mesh graded over five orders of
    /// magnitude, valid and then broken in the ways a skin breaks: a vertex pushed across
    /// its neighbours (inverted cells and overlaps), a cell laid over others, a vertex on
    /// another cell's axis-aligned edge, cells that only touch.
    #[test]
    fn the_index_and_the_all_pairs_twin_agree_on_a_graded_mesh() {
        let (pts, cells) = graded();
        let v = both(&pts, &cells);
        assert_eq!(v.hanging, vec![pts.len() - 1], "{v:?}");
        assert!(v.overlaps.is_empty() && v.inverted.is_empty(), "{v:?}");

        // A ring vertex pushed outwards across the next ring.
        let mut moved = pts.clone();
        let k = 20 * 32 + 5;
        moved[k] = [moved[k][0] * 1.5, moved[k][1] * 1.5];
        let v = both(&moved, &cells);
        assert!(!v.inverted.is_empty() || !v.overlaps.is_empty(), "{v:?}");

        // A large triangle laid over the centre and three rings, and one on half a quad.
        let mut over = cells.clone();
        over.push(vec![32 * 3, 32 * 3 + 11, 32 * 3 + 22]);
        over.push(vec![32 * 10, 32 * 11 + 1, 32 * 10 + 1]);
        let v = both(&pts, &over);
        assert!(v.overlaps.len() > 50 && v.inverted.is_empty(), "{v:?}");
        let last = over.len() - 1;
        assert!(v.overlaps.iter().any(|&(a, b)| b == last && a < last), "{v:?}");

        // Two cells that share a corner or an edge only: apart.
        let (pts2, cells2) = (
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 1.0], [2.0, 2.0]],
            vec![vec![0, 1, 2, 3], vec![2, 4, 5], vec![1, 4, 2]],
        );
        assert!(both(&pts2, &cells2).is_valid());
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
