//! Structured test meshes: the jittered grids the sizing and propagation tests build
//! their randomised cases on, the tagged unit square of the file and report tests, and
//! the independent oracle that finds the triangles a polyline crosses.
//!
//! Invariants the seeded cases rely on: vertex `(i, j)` has index `j * nx + i`; a
//! jittered grid draws its points first (interior coordinates only, row by row) and then
//! one diagonal per quad (row by row) from the same generator, so a seed names one mesh.

use smartmesh_formats::{CellBlock, CellKind, TaggedMesh};

use crate::{Generator, SplitMix64};

/// A point of the plane.
pub type Point2 = [f64; 2];

/// A jittered structured triangulation: `nx × ny` vertices from `origin` with spacing
/// `h`, each moved by up to `jitter` times the spacing along each axis it is not on the
/// boundary of (boundary vertices stay on the rectangle), each quad split along a random
/// diagonal.
#[derive(Debug, Clone)]
pub struct JitteredGrid {
    /// Vertices per row.
    pub nx: usize,
    /// The vertices, row by row.
    pub coords: Vec<Point2>,
    /// The triangles, two per quad, counter-clockwise.
    pub triangles: Vec<[usize; 3]>,
}

impl JitteredGrid {
    /// The grid of seed `seed` (splitmix64).
    pub fn new(nx: usize, ny: usize, origin: Point2, h: f64, jitter: f64, seed: u64) -> Self {
        let mut rng = SplitMix64(seed);
        let coords = jittered_points(nx, ny, origin, h, jitter, &mut rng);
        let triangles = split_quads(nx, ny, false, &mut rng);
        JitteredGrid { nx, coords, triangles }
    }

    /// The index of vertex `(i, j)`.
    pub fn vertex(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }

    /// Vertices along grid row `j` from column `i0` to `i1` (either direction): a path
    /// of mesh edges.
    pub fn row(&self, j: usize, i0: usize, i1: usize) -> Vec<usize> {
        if i0 <= i1 {
            (i0..=i1).map(|i| self.vertex(i, j)).collect()
        } else {
            (i1..=i0).rev().map(|i| self.vertex(i, j)).collect()
        }
    }

    /// Vertices along grid column `i` from row `j0` to `j1`.
    pub fn column(&self, i: usize, j0: usize, j1: usize) -> Vec<usize> {
        if j0 <= j1 {
            (j0..=j1).map(|j| self.vertex(i, j)).collect()
        } else {
            (j1..=j0).rev().map(|j| self.vertex(i, j)).collect()
        }
    }
}

/// `nx × ny` points from `origin` with spacing `h`, row by row; each coordinate of an
/// interior row or column moved by a uniform amount in `[-jitter, jitter) · h`.
pub fn jittered_points(
    nx: usize,
    ny: usize,
    origin: Point2,
    h: f64,
    jitter: f64,
    rng: &mut impl Generator,
) -> Vec<Point2> {
    let mut coords = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let mut p = [origin[0] + i as f64 * h, origin[1] + j as f64 * h];
            if i > 0 && i + 1 < nx {
                p[0] += (2.0 * rng.unit() - 1.0) * jitter * h;
            }
            if j > 0 && j + 1 < ny {
                p[1] += (2.0 * rng.unit() - 1.0) * jitter * h;
            }
            coords.push(p);
        }
    }
    coords
}

/// Splits the quads of an `nx × ny` array of points (index `j * nx + i`) along random
/// diagonals (one draw per quad, its lowest bit); `wrap` joins the last column to the
/// first.
pub fn split_quads(nx: usize, ny: usize, wrap: bool, rng: &mut impl Generator) -> Vec<[usize; 3]> {
    let cols = if wrap { nx } else { nx - 1 };
    let mut tris = Vec::with_capacity(2 * cols * ny.saturating_sub(1));
    for j in 0..ny - 1 {
        for i in 0..cols {
            let i1 = (i + 1) % nx;
            let (a, b, c, d) = (j * nx + i, j * nx + i1, (j + 1) * nx + i1, (j + 1) * nx + i);
            if rng.next_u64() & 1 == 0 {
                tris.extend([[a, b, c], [a, c, d]]);
            } else {
                tris.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    tris
}

/// A structured triangulation of the unit square, `n` cells a side, and how it is
/// tagged; [`SquareGrid::build`] makes it.
#[derive(Debug, Clone, Copy)]
pub struct SquareGrid {
    /// Cells a side.
    pub n: usize,
    /// The line tags of the sides: bottom (left to right), right (upwards), top (right to
    /// left), left (downwards).
    pub sides: [i32; 4],
    /// The face tags of the cells left of x = 1/2 and of the others (cell column `i` is
    /// on the right when `2 i >= n`); equal for one face.
    pub faces: [i32; 2],
    /// A line of this tag along column `n / 2` (the interface between the two faces).
    pub interface: Option<i32>,
    /// Diagonals alternating like a chessboard (cell `(i, j)` split from its lower left
    /// corner when `i + j` is even, from its lower right one otherwise) rather than all
    /// from the lower left corner.
    pub alternate: bool,
}

impl SquareGrid {
    /// The mesh: vertex `(i, j)` at `(i / n, j / n)` with index `j (n + 1) + i`; a
    /// triangle block (cell by cell, row by row), then a line block (for each `k`, the
    /// `k`-th segment of bottom, right, top, left, then of the interface).
    pub fn build(&self) -> TaggedMesh {
        let n = self.n;
        let mut m = TaggedMesh::new();
        for j in 0..=n {
            for i in 0..=n {
                m.points.push([i as f64 / n as f64, j as f64 / n as f64, 0.0]);
            }
        }
        let id = |i: usize, j: usize| j * (n + 1) + i;
        let mut tri = CellBlock::new(CellKind::Triangle);
        for j in 0..n {
            for i in 0..n {
                let tag = self.faces[usize::from(2 * i >= n)];
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                if !self.alternate || (i + j) % 2 == 0 {
                    tri.push(&[a, b, c], tag, tag);
                    tri.push(&[a, c, d], tag, tag);
                } else {
                    tri.push(&[a, b, d], tag, tag);
                    tri.push(&[b, c, d], tag, tag);
                }
            }
        }
        let [bottom, right, top, left] = self.sides;
        let mut lines = CellBlock::new(CellKind::Line);
        for k in 0..n {
            lines.push(&[id(k, 0), id(k + 1, 0)], bottom, bottom);
            lines.push(&[id(n, k), id(n, k + 1)], right, right);
            lines.push(&[id(k + 1, n), id(k, n)], top, top);
            lines.push(&[id(0, k + 1), id(0, k)], left, left);
            if let Some(tag) = self.interface {
                lines.push(&[id(n / 2, k), id(n / 2, k + 1)], tag, tag);
            }
        }
        m.blocks.push(tri);
        m.blocks.push(lines);
        m
    }
}

/// The unit square, `n` cells a side, each split along the diagonal from its lower left
/// corner: face 1; the sides as lines 11 (bottom, left to right), 12 (right, upwards),
/// 13 (top, right to left), 14 (left, downwards); a triangle block, then a line block.
pub fn unit_square(n: usize) -> TaggedMesh {
    SquareGrid { n, sides: [11, 12, 13, 14], faces: [1, 1], interface: None, alternate: false }
        .build()
}

/// The triangles (indices into `triangles`) that contain a point of `polyline` sampled
/// every 1/1000 of each segment, boundary included: an oracle that knows nothing of
/// walking or clipping.
pub fn triangles_crossed_by(
    coords: &[Point2],
    triangles: &[[usize; 3]],
    polyline: &[Point2],
) -> Vec<usize> {
    let inside = |t: &[usize; 3], p: Point2| {
        let c =
            |a: Point2, b: Point2| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let [a, b, cc] = t.map(|v| coords[v]);
        let (s1, s2, s3) = (c(a, b), c(b, cc), c(cc, a));
        (s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0) || (s1 <= 0.0 && s2 <= 0.0 && s3 <= 0.0)
    };
    (0..triangles.len())
        .filter(|&t| {
            polyline.windows(2).any(|w| {
                (0..=1000).any(|k| {
                    let s = k as f64 / 1000.0;
                    let p = [w[0][0] + s * (w[1][0] - w[0][0]), w[0][1] + s * (w[1][1] - w[0][1])];
                    inside(&triangles[t], p)
                })
            })
        })
        .collect()
}

/// The box [0, size[0]] × [0, size[1]] × [0, size[2]], `n` cubes a side, each cut into
/// the six Kuhn tetrahedra around its diagonal from the lower corner, every tetrahedron
/// positive (Gmsh's orientation): volume 1; its boundary as triangles, tag 10 + the side
/// (x = 0, x = max, y = 0, y = max, z = 0, z = max: 11 to 16). Vertex (i, j, k) has
/// index (k (n + 1) + j) (n + 1) + i.
pub fn kuhn_box(n: usize, size: [f64; 3]) -> TaggedMesh {
    let m = n + 1;
    let id = |i: usize, j: usize, k: usize| ((k * m + j) * m + i) as u32;
    let mut mesh = TaggedMesh::new();
    mesh.coordinate_dim = 3;
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                mesh.points.push([
                    size[0] * i as f64 / n as f64,
                    size[1] * j as f64 / n as f64,
                    size[2] * k as f64 / n as f64,
                ]);
            }
        }
    }
    let mut tets = CellBlock::new(CellKind::Tetra);
    let mut tris = CellBlock::new(CellKind::Triangle);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = |b: usize| id(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2));
                for path in [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]] {
                    let mut t = [c(0), c(path[0]), c(path[1]), c(7)];
                    let p = t.map(|v| mesh.points[v as usize]);
                    let e = |a: usize| [0, 1, 2].map(|x| p[a][x] - p[0][x]);
                    let (a, b, d) = (e(1), e(2), e(3));
                    let det = a[0] * (b[1] * d[2] - b[2] * d[1])
                        - a[1] * (b[0] * d[2] - b[2] * d[0])
                        + a[2] * (b[0] * d[1] - b[1] * d[0]);
                    if det < 0.0 {
                        t.swap(2, 3);
                    }
                    tets.push(&t, 1, 1);
                }
            }
        }
    }
    // Each side: two triangles per square, split along the diagonal through the corner
    // nearest the origin's, as the tetrahedra's faces are.
    for side in 0..6 {
        let (axis, high) = (side / 2, side % 2 == 1);
        for a in 0..n {
            for b in 0..n {
                let at = |da: usize, db: usize| {
                    let fixed = if high { n } else { 0 };
                    let (u, v) = (a + da, b + db);
                    match axis {
                        0 => id(fixed, u, v),
                        1 => id(u, fixed, v),
                        _ => id(u, v, fixed),
                    }
                };
                let tag = 11 + side;
                tris.push(&[at(0, 0), at(1, 0), at(1, 1)], tag, tag);
                tris.push(&[at(0, 0), at(1, 1), at(0, 1)], tag, tag);
            }
        }
    }
    mesh.blocks.push(tets);
    mesh.blocks.push(tris);
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle of a jittered grid is counter-clockwise and the triangles tile the
    /// rectangle (their areas add up to it): the jitter never folds a cell.
    #[test]
    fn jittered_grids_tile_their_rectangle() {
        for seed in 0..20 {
            let g = JitteredGrid::new(9, 7, [1.0, -2.0], 0.5, 0.3, seed);
            let mut total = 0.0;
            for t in &g.triangles {
                let [a, b, c] = t.map(|v| g.coords[v]);
                let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
                assert!(area > 0.0, "seed {seed}: {t:?}");
                total += area;
            }
            assert!((total - 4.0 * 3.0).abs() < 1e-12, "seed {seed}: {total}");
        }
    }

    /// Cell counts, the two faces split at x = 1/2, the interface on it, and every
    /// triangle counter-clockwise with either diagonal rule.
    #[test]
    fn square_grids_have_their_cells_faces_and_sides() {
        let m = unit_square(3);
        assert_eq!(m.points.len(), 16);
        assert_eq!(m.num_cells_of(CellKind::Triangle), 18);
        assert_eq!(m.num_cells_of(CellKind::Line), 12);
        let g = SquareGrid {
            n: 4,
            sides: [1, 2, 3, 4],
            faces: [10, 11],
            interface: Some(5),
            alternate: true,
        };
        let m = g.build();
        assert_eq!(m.num_cells_of(CellKind::Line), 20);
        for (kind, c, tag, _) in m.cells() {
            let p: Vec<[f64; 3]> = c.iter().map(|&v| m.points[v as usize]).collect();
            match kind {
                CellKind::Triangle => {
                    let area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                        - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
                    assert!(area > 0.0);
                    let right = p.iter().all(|q| q[0] >= 0.5);
                    assert_eq!(tag, if right { 11 } else { 10 }, "{p:?}");
                }
                _ if tag == 5 => assert!(p.iter().all(|q| q[0] == 0.5)),
                _ => {}
            }
        }
    }

    /// A segment along the diagonal of a 1 × 1 grid's only quad crosses both triangles
    /// (it lies on their shared edge); one inside the lower right triangle crosses one.
    #[test]
    fn crossed_triangles_by_hand() {
        let coords = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
        let tris = [[0, 1, 3], [0, 3, 2]];
        assert_eq!(triangles_crossed_by(&coords, &tris, &[[0.1, 0.1], [0.9, 0.9]]), [0, 1]);
        assert_eq!(triangles_crossed_by(&coords, &tris, &[[0.5, 0.1], [0.9, 0.2]]), [0]);
    }
}
