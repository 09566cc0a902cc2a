//! VTK cells of no fixed node count, and VTK's axis-aligned ones, turned into the
//! kinds smartmesh holds before the grid becomes a mesh:
//!
//! - poly-vertex (2) → one vertex per point; poly-line (4) → one line per segment;
//! - triangle strip (6) → its triangles, every other one turned so that all keep the
//!   strip's orientation (VTK's `vtkTriangleStrip` decomposition);
//! - polygon (7): three points → a triangle, four → a quad, more → triangles by ear
//!   clipping in the polygon's plane (Newell's normal), which is exact for any simple
//!   polygon (a convex one is cut as a fan at once); a polygon that has no ear
//!   (self-intersecting or degenerate), or a non-convex one of more than 256 points
//!   (clipping costs up to n^3), is cut as a fan from its first point, and the notes
//!   say how many were;
//! - pixel (8) → quad (0, 1, 3, 2); voxel (11) → hexahedron (0, 1, 3, 2, 4, 5, 7, 6).
//!
//! Each new cell takes the tags and cell data of the cell it came from. Splits are
//! listed in the read notes; pixels and voxels are the same elements renumbered and
//! need no note.

use crate::{Error, ErrorKind, NodeIndex, Result};

use super::Grid;

/// Whether a VTK type is one [`normalize`] rewrites.
fn special(t: u8) -> bool {
    matches!(t, 2 | 4 | 6 | 7 | 8 | 11)
}

/// Counts of what was split, for the notes.
#[derive(Default)]
struct Counts {
    poly_vertices: (usize, usize),
    poly_lines: (usize, usize),
    strips: (usize, usize),
    polygons: (usize, usize),
    fans: usize,
}

/// Rewrites the special cells of `g` (see the module header) and returns the notes.
/// Cells must already be checked against the points (every reader does).
pub(crate) fn normalize(g: &mut Grid) -> Result<Vec<String>> {
    let points = std::mem::take(&mut g.points);
    let r = rewrite(g, &points);
    g.points = points;
    r
}

fn rewrite(g: &mut Grid, points: &[[f64; 3]]) -> Result<Vec<String>> {
    let n = g.types.len();
    if !g.types.iter().any(|&t| special(t)) || g.offsets.len() != n + 1 {
        return Ok(Vec::new());
    }
    if g.offsets.last().is_some_and(|&e| e > g.connectivity.len()) {
        return Ok(Vec::new()); // into_mesh reports it
    }
    let mut types = Vec::with_capacity(n);
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0usize);
    let mut conn: Vec<NodeIndex> = Vec::with_capacity(g.connectivity.len());
    let mut parent = Vec::with_capacity(n);
    let mut c = Counts::default();
    let at = g.cells_at.or(g.types_at);
    for i in 0..n {
        let cell = &g.connectivity[g.offsets[i]..g.offsets[i + 1]];
        let t = g.types[i];
        let mut emit = |ty: u8, nodes: &[NodeIndex]| {
            types.push(ty);
            conn.extend_from_slice(nodes);
            offsets.push(conn.len());
            parent.push(i);
        };
        let too_few = |min: usize, what: &str| Error {
            path: None,
            at,
            kind: ErrorKind::Expected {
                expected: format!("at least {min} points in cell {i} (a {what})"),
                found: cell.len().to_string(),
            },
        };
        match t {
            2 => {
                c.poly_vertices.0 += 1;
                c.poly_vertices.1 += cell.len();
                cell.iter().for_each(|&v| emit(1, &[v]));
            }
            4 => {
                if cell.len() < 2 {
                    return Err(too_few(2, "poly-line"));
                }
                c.poly_lines.0 += 1;
                c.poly_lines.1 += cell.len() - 1;
                cell.windows(2).for_each(|w| emit(3, w));
            }
            6 => {
                if cell.len() < 3 {
                    return Err(too_few(3, "triangle strip"));
                }
                c.strips.0 += 1;
                c.strips.1 += cell.len() - 2;
                for (j, w) in cell.windows(3).enumerate() {
                    if j % 2 == 0 {
                        emit(5, w);
                    } else {
                        emit(5, &[w[1], w[0], w[2]]);
                    }
                }
            }
            7 => match cell.len() {
                0..=2 => return Err(too_few(3, "polygon")),
                3 => emit(5, cell),
                4 => emit(9, cell),
                k => {
                    c.polygons.0 += 1;
                    c.polygons.1 += k - 2;
                    let (tris, fan) = triangulate(cell, points);
                    c.fans += fan as usize;
                    tris.iter().for_each(|t| emit(5, t));
                }
            },
            8 if cell.len() == 4 => emit(9, &[cell[0], cell[1], cell[3], cell[2]]),
            11 if cell.len() == 8 => {
                emit(12, &[cell[0], cell[1], cell[3], cell[2], cell[4], cell[5], cell[7], cell[6]])
            }
            // A pixel or voxel of the wrong size, or any other type: as it is, for
            // `into_mesh` to check.
            _ => emit(
                if t == 8 {
                    9
                } else if t == 11 {
                    12
                } else {
                    t
                },
                cell,
            ),
        }
    }
    // The data of each new cell is its parent's.
    for a in &mut g.cell_arrays {
        let k = a.components;
        if a.values.len() == n * k {
            a.values = parent.iter().flat_map(|&p| a.values[p * k..(p + 1) * k].to_vec()).collect();
        }
    }
    for (_, tags, _) in &mut g.cell_tags {
        if tags.len() == n {
            *tags = parent.iter().map(|&p| tags[p]).collect();
        }
    }
    g.types = types;
    g.offsets = offsets;
    g.connectivity = conn;
    Ok(notes(&c))
}

fn notes(c: &Counts) -> Vec<String> {
    let mut out = Vec::new();
    let mut say = |(cells, parts): (usize, usize), what: &str, into: &str| {
        if cells > 0 {
            out.push(format!("{cells} {what} split into {parts} {into}"));
        }
    };
    say(c.poly_vertices, "VTK poly-vertices", "vertices");
    say(c.poly_lines, "VTK poly-lines", "lines");
    say(c.strips, "VTK triangle strips", "triangles");
    say(c.polygons, "VTK polygons of more than 4 points", "triangles");
    if c.fans > 0 {
        out.push(format!(
            "{} of those polygons are not simple (no ear to clip in their plane) or are non-convex with more than {MAX_CLIPPED} points, and were cut as a fan from their first point",
            c.fans
        ));
    }
    out
}

/// The most points of a non-convex polygon cut by ear clipping.
const MAX_CLIPPED: usize = 256;

/// Triangles of a polygon of more than 4 points, by ear clipping in its plane;
/// `true` when it had to fall back on a fan.
fn triangulate(cell: &[NodeIndex], points: &[[f64; 3]]) -> (Vec<[NodeIndex; 3]>, bool) {
    let p = |v: NodeIndex| points[v as usize];
    // Newell's normal; the polygon is projected on the plane of the two other axes,
    // keeping its orientation.
    let mut nrm = [0.0f64; 3];
    for (j, &a) in cell.iter().enumerate() {
        let (a, b) = (p(a), p(cell[(j + 1) % cell.len()]));
        nrm[0] += (a[1] - b[1]) * (a[2] + b[2]);
        nrm[1] += (a[2] - b[2]) * (a[0] + b[0]);
        nrm[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let drop = (0..3).max_by(|&i, &j| nrm[i].abs().total_cmp(&nrm[j].abs())).unwrap_or(2);
    let (u, w) = match drop {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    };
    let sign = if nrm[drop] < 0.0 { -1.0 } else { 1.0 };
    let q: Vec<[f64; 2]> = cell.iter().map(|&v| [p(v)[u], p(v)[w]]).collect();
    let cross = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        sign * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    };
    let n = cell.len();
    let fan = || (1..n - 1).map(|j| [cell[0], cell[j], cell[j + 1]]).collect::<Vec<_>>();
    // A convex polygon (the usual one) is its fan, in one pass. Ear clipping costs up
    // to n^3 steps: a non-convex polygon of more than `MAX_CLIPPED` points is cut as a
    // fan too, and counted with the polygons that have no ear.
    if (0..n).all(|j| cross(q[(j + n - 1) % n], q[j], q[(j + 1) % n]) >= 0.0) {
        return (fan(), false);
    }
    if n > MAX_CLIPPED {
        return (fan(), true);
    }
    let mut left: Vec<usize> = (0..n).collect();
    let mut tris = Vec::with_capacity(cell.len() - 2);
    while left.len() > 3 {
        let m = left.len();
        let ear = (0..m).find(|&j| {
            let (a, b, c) = (left[(j + m - 1) % m], left[j], left[(j + 1) % m]);
            if cross(q[a], q[b], q[c]) <= 0.0 {
                return false;
            }
            // No other remaining point inside or on the candidate triangle.
            left.iter().all(|&o| {
                o == a
                    || o == b
                    || o == c
                    || q[o] == q[a]
                    || q[o] == q[b]
                    || q[o] == q[c]
                    || cross(q[a], q[b], q[o]) < 0.0
                    || cross(q[b], q[c], q[o]) < 0.0
                    || cross(q[c], q[a], q[o]) < 0.0
            })
        });
        let Some(j) = ear else {
            return (fan(), true);
        };
        let (a, b, c) = (left[(j + m - 1) % m], left[j], left[(j + 1) % m]);
        tris.push([cell[a], cell[b], cell[c]]);
        left.remove(j);
    }
    tris.push([cell[left[0]], cell[left[1]], cell[left[2]]]);
    (tris, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(tris: &[[NodeIndex; 3]], pts: &[[f64; 3]]) -> f64 {
        tris.iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| pts[v as usize]);
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
            })
            .sum()
    }

    #[test]
    fn a_non_convex_polygon_is_cut_into_its_own_area() {
        // An L of area 3, counter-clockwise, whose fan from point 0 would cover the notch.
        let pts = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
        ];
        let cell: Vec<NodeIndex> = vec![1, 2, 3, 4, 5, 0];
        let (tris, fan) = triangulate(&cell, &pts);
        assert!(!fan);
        assert_eq!(tris.len(), 4);
        assert_eq!(area(&tris, &pts), 3.0);
        assert!(tris.iter().all(|t| area(&[*t], &pts) > 0.0));
        // Clockwise: the same cut, every triangle clockwise.
        let rev: Vec<NodeIndex> = cell.iter().rev().copied().collect();
        let (tris, fan) = triangulate(&rev, &pts);
        assert!(!fan);
        assert_eq!(area(&tris, &pts), -3.0);
    }
}
