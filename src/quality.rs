//! Euclidean element quality: the figures `info` prints and the remesher will compare.
//!
//! Triangle quality is the normalised ratio q = 4√3·A / (l₁² + l₂² + l₃²), 1 for an
//! equilateral triangle and 0 for a degenerate one (the measure MMG and Gmsh report as
//! "gamma"-like shape quality). In a planar mesh areas are signed: a triangle whose
//! corners run clockwise has negative area and counts as inverted. A surface in space is
//! measured in each triangle's own plane.

use serde::Serialize;

use crate::topology::Topology;

/// Signed area of triangle `(a, b, c)`: positive when counter-clockwise.
#[inline]
pub(crate) fn signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// Shape quality of a triangle in [0, 1] (negative for an inverted one).
#[inline]
pub(crate) fn triangle_quality(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    let l2 = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let s = l2(a, b) + l2(b, c) + l2(c, a);
    if s == 0.0 {
        return 0.0;
    }
    4.0 * 3f64.sqrt() * signed_area(a, b, c) / s
}

/// Smallest interior angle of a triangle, in degrees.
pub(crate) fn min_angle_deg(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    let ang = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        let u = [q[0] - p[0], q[1] - p[1]];
        let v = [r[0] - p[0], r[1] - p[1]];
        let cross = u[0] * v[1] - u[1] * v[0];
        let dot = u[0] * v[0] + u[1] * v[1];
        cross.abs().atan2(dot).to_degrees()
    };
    ang(a, b, c).min(ang(b, c, a)).min(ang(c, a, b))
}

/// Shape quality, absolute area and smallest angle (degrees) of triangle `(a, b, c)`
/// measured in its own plane: the quality is never negative (a triangle in space has no
/// side to be inverted from).
fn in_own_plane(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> (f64, f64, f64) {
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    };
    let (ab, bc, ca) = (sub(b, a), sub(c, b), sub(a, c));
    let area = 0.5 * dot(cross(ab, bc), cross(ab, bc)).sqrt();
    let s = dot(ab, ab) + dot(bc, bc) + dot(ca, ca);
    let q = if s == 0.0 { 0.0 } else { 4.0 * 3f64.sqrt() * area / s };
    // The angle at a corner between the edges leaving it.
    let ang = |u: [f64; 3], v: [f64; 3]| {
        let w = cross(u, v);
        dot(w, w).sqrt().atan2(dot(u, v)).to_degrees()
    };
    let neg = |u: [f64; 3]| [-u[0], -u[1], -u[2]];
    let angle = ang(ab, neg(ca)).min(ang(bc, neg(ab))).min(ang(ca, neg(bc)));
    (q, area, angle)
}

/// Summary of the shape of the triangles of a mesh (quads have figures of their own,
/// [`crate::layer::stats::quad_quality`]: the halves of a quad are not triangles of the
/// mesh). A planar mesh (every z equal) is measured in the xy-plane, where a clockwise
/// triangle is inverted; a surface in space is measured triangle by triangle in the
/// triangle's own plane, where only a flat triangle counts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QualitySummary {
    /// Number of triangles measured.
    pub triangles: usize,
    /// Triangles with zero or negative area.
    pub inverted_or_flat: usize,
    /// Smallest shape quality.
    pub min_quality: f64,
    /// Mean shape quality.
    pub mean_quality: f64,
    /// Smallest interior angle over all triangles, degrees.
    pub min_angle_deg: f64,
    /// Smallest and largest absolute area.
    pub area_range: [f64; 2],
    /// Smallest and largest edge length (of every surface cell's edges).
    pub edge_length_range: [f64; 2],
    /// Counts of triangles whose quality falls in [0,0.1), [0.1,0.2), ... [0.9,1].
    pub histogram: [usize; 10],
}

/// Whether every point of `points` has the same z: the mesh lies in a plane z = const.
pub(crate) fn is_planar(points: &[[f64; 3]]) -> bool {
    points.first().map_or(true, |p0| points.iter().all(|p| p[2] == p0[2]))
}

/// Area of triangle `(a, b, c)` in its own plane (never negative).
pub(crate) fn area_in_space(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    in_own_plane(a, b, c).1
}

/// Distance between `a` and `b`, in space.
pub(crate) fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

impl QualitySummary {
    /// Measures the triangles of `topo` on `points`. `None` without triangles.
    pub fn of(points: &[[f64; 3]], topo: &Topology) -> Option<QualitySummary> {
        let planar = is_planar(points);
        let xy = |i: usize| [points[i][0], points[i][1]];
        let mut s = QualitySummary {
            triangles: 0,
            inverted_or_flat: 0,
            min_quality: f64::INFINITY,
            mean_quality: 0.0,
            min_angle_deg: f64::INFINITY,
            area_range: [f64::INFINITY, 0.0],
            edge_length_range: [f64::INFINITY, 0.0],
            histogram: [0; 10],
        };
        let mut sum = 0.0;
        for c in topo.surface_cells.iter().filter(|c| c.vertices().len() == 3) {
            let v = c.vertices();
            let (q, area, angle) = if planar {
                let (a, b, c) = (xy(v[0]), xy(v[1]), xy(v[2]));
                (triangle_quality(a, b, c), signed_area(a, b, c), min_angle_deg(a, b, c))
            } else {
                in_own_plane(points[v[0]], points[v[1]], points[v[2]])
            };
            s.triangles += 1;
            if area <= 0.0 {
                s.inverted_or_flat += 1;
            }
            s.min_quality = s.min_quality.min(q);
            sum += q;
            s.min_angle_deg = s.min_angle_deg.min(angle);
            s.area_range[0] = s.area_range[0].min(area.abs());
            s.area_range[1] = s.area_range[1].max(area.abs());
            s.histogram[((q.max(0.0) * 10.0) as usize).min(9)] += 1;
        }
        if s.triangles == 0 {
            return None;
        }
        for (e, _) in &topo.edges {
            let l = distance(points[e[0]], points[e[1]]);
            s.edge_length_range[0] = s.edge_length_range[0].min(l);
            s.edge_length_range[1] = s.edge_length_range[1].max(l);
        }
        s.mean_quality = sum / s.triangles as f64;
        Some(s)
    }

    /// The smallest angle (degrees) of the first-order Triangle cells of `mesh`, as
    /// [`QualitySummary::of`] measures it on a mesh whose surface cells are those
    /// triangles, without the topology `of` needs (a tenth of `smartmesh mesh`'s time at
    /// 10⁶ triangles went to the topology and the full summary of a one-line report).
    /// `None` without triangles.
    pub fn smallest_angle_deg(mesh: &smartmesh_formats::TaggedMesh) -> Option<f64> {
        let points = &mesh.points;
        let planar = is_planar(points);
        let xy = |i: u32| [points[i as usize][0], points[i as usize][1]];
        mesh.cells()
            .filter(|c| c.0 == smartmesh_formats::CellKind::Triangle)
            .map(|(_, v, _, _)| {
                if planar {
                    min_angle_deg(xy(v[0]), xy(v[1]), xy(v[2]))
                } else {
                    let p = |i: u32| points[i as usize];
                    in_own_plane(p(v[0]), p(v[1]), p(v[2])).2
                }
            })
            .reduce(f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equilateral_has_quality_one() {
        let q = triangle_quality([0.0, 0.0], [1.0, 0.0], [0.5, 3f64.sqrt() / 2.0]);
        assert!((q - 1.0).abs() < 1e-12);
        assert!(
            (min_angle_deg([0.0, 0.0], [1.0, 0.0], [0.5, 3f64.sqrt() / 2.0]) - 60.0).abs() < 1e-9
        );
    }

    /// The same equilateral triangle, tilted out of the xy-plane, has quality 1 and
    /// angles of 60° in its own plane (in the xy-plane it would be squashed).
    #[test]
    fn a_triangle_in_space_is_measured_in_its_own_plane() {
        let h = 3f64.sqrt() / 2.0;
        let (c, s) = (80f64.to_radians().cos(), 80f64.to_radians().sin());
        let (q, area, angle) = in_own_plane([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, h * c, h * s]);
        assert!((q - 1.0).abs() < 1e-12, "{q}");
        assert!((area - h / 2.0).abs() < 1e-12, "{area}");
        assert!((angle - 60.0).abs() < 1e-9, "{angle}");
        assert!(triangle_quality([0.0, 0.0], [1.0, 0.0], [0.5, h * c]) < 0.5);
    }

    /// The shortcut agrees with the full summary, in the plane and in space.
    #[test]
    fn smallest_angle_is_the_summarys() {
        use smartmesh_formats::{CellKind, TaggedMesh};
        for z in [[0.0; 4], [0.0, 0.3, 0.1, 0.7]] {
            let mut m = TaggedMesh::new();
            m.points = vec![[0.0, 0.0, z[0]], [1.0, 0.0, z[1]], [0.9, 0.2, z[2]], [0.0, 1.0, z[3]]];
            let b = m.block_mut(CellKind::Triangle);
            b.push(&[0, 1, 2], 1, 1);
            b.push(&[0, 2, 3], 1, 1);
            m.block_mut(CellKind::Line).push(&[0, 1], 2, 2);
            let full = QualitySummary::of(&m.points, &Topology::from_mesh(&m)).unwrap();
            assert_eq!(QualitySummary::smallest_angle_deg(&m), Some(full.min_angle_deg));
        }
        assert_eq!(QualitySummary::smallest_angle_deg(&smartmesh_formats::TaggedMesh::new()), None);
    }

    #[test]
    fn clockwise_is_negative() {
        assert!(triangle_quality([0.0, 0.0], [0.0, 1.0], [1.0, 0.0]) < 0.0);
        assert_eq!(signed_area([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 0.5);
    }
}
