//! Euclidean element quality: the figures `info` prints and the remesher will compare.
//!
//! Triangle quality is the normalised ratio q = 4√3·A / (l₁² + l₂² + l₃²), 1 for an
//! equilateral triangle and 0 for a degenerate one (the measure MMG and Gmsh report as
//! "gamma"-like shape quality). Areas are signed: a triangle whose corners run
//! clockwise has negative area and counts as inverted.

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

/// Summary of the shape of the triangles of a mesh (quads are split along their
/// first diagonal for this purpose).
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
    /// Smallest and largest edge length.
    pub edge_length_range: [f64; 2],
    /// Counts of triangles whose quality falls in [0,0.1), [0.1,0.2), ... [0.9,1].
    pub histogram: [usize; 10],
}

impl QualitySummary {
    /// Measures the surface cells of `topo` on `points`. `None` without surface cells.
    pub fn of(points: &[[f64; 3]], topo: &Topology) -> Option<QualitySummary> {
        let p = |i: usize| [points[i][0], points[i][1]];
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
        let mut add = |a: usize, b: usize, c: usize, s: &mut QualitySummary| {
            let (pa, pb, pc) = (p(a), p(b), p(c));
            let area = signed_area(pa, pb, pc);
            let q = triangle_quality(pa, pb, pc);
            s.triangles += 1;
            if area <= 0.0 {
                s.inverted_or_flat += 1;
            }
            s.min_quality = s.min_quality.min(q);
            sum += q;
            s.min_angle_deg = s.min_angle_deg.min(min_angle_deg(pa, pb, pc));
            s.area_range[0] = s.area_range[0].min(area.abs());
            s.area_range[1] = s.area_range[1].max(area.abs());
            s.histogram[((q.max(0.0) * 10.0) as usize).min(9)] += 1;
        };
        for c in &topo.surface_cells {
            let v = c.vertices();
            add(v[0], v[1], v[2], &mut s);
            if v.len() == 4 {
                add(v[0], v[2], v[3], &mut s);
            }
        }
        if s.triangles == 0 {
            return None;
        }
        for (e, _) in &topo.edges {
            let (a, b) = (p(e[0]), p(e[1]));
            let l = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
            s.edge_length_range[0] = s.edge_length_range[0].min(l);
            s.edge_length_range[1] = s.edge_length_range[1].max(l);
        }
        s.mean_quality = sum / s.triangles as f64;
        Some(s)
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

    #[test]
    fn clockwise_is_negative() {
        assert!(triangle_quality([0.0, 0.0], [0.0, 1.0], [1.0, 0.0]) < 0.0);
        assert_eq!(signed_area([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 0.5);
    }
}
