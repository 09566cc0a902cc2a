//! Periodic sides: two sets of boundary curves, a *master* and a *slave*, that a solver
//! glues because a transform (a translation, or a rotation about a centre) maps the
//! master onto the slave (thesis 6.3.2.4, the distributor's periodic pitch).
//!
//! [`check`] measures one pair on a mesh, by brute force over the curves' vertices and
//! edges (curves hold thousands of vertices at most, so O(master × slave) is cheap):
//!
//! - the shapes: every master vertex mapped by the transform lies on a slave edge and
//!   every slave vertex mapped back lies on a master edge, within [`SHAPE_TOLERANCE`]
//!   times the diagonal of the mesh's bounding box; otherwise the pair is refused
//!   ([`PeriodicError::NotImages`]) naming both sides and the distance found;
//! - the vertices: the largest distance between a master vertex's image and the nearest
//!   slave vertex, and between a slave vertex's preimage and the nearest master vertex
//!   ([`PairMatch::max_distance`]). A solver can glue the sides vertex to vertex when it
//!   is at rounding level ([`PairMatch::matched`]).
//!
//! Invariant kept by the remesher: the vertices and edges of the curves of a periodic pair
//! are frozen ([`crate::remesh::RemeshOptions::frozen_curves`]), so a mesh whose sides
//! match keeps them matching, bit for bit, through `remesh` and `adapt`.

use crate::topology::Topology;

/// Largest distance, relative to the diagonal of the mesh's bounding box, between a side
/// and the image of the other for the two to count as images of each other.
pub const SHAPE_TOLERANCE: f64 = 1e-6;

/// Largest distance, relative to the diagonal of the mesh's bounding box, between a
/// vertex's image and its partner for the two to count as one glued vertex.
pub const MATCH_TOLERANCE: f64 = 1e-12;

/// The map from the master side to the slave side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transform {
    /// p ↦ p + vector.
    Translation([f64; 2]),
    /// p ↦ centre + R(angle) (p − centre), the angle in degrees, counter-clockwise.
    Rotation {
        /// The centre.
        centre: [f64; 2],
        /// The angle, degrees.
        angle_degrees: f64,
    },
}

impl Transform {
    /// The image of `p`.
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        match *self {
            Transform::Translation(t) => [p[0] + t[0], p[1] + t[1]],
            Transform::Rotation { centre: c, angle_degrees } => {
                let (s, co) = angle_degrees.to_radians().sin_cos();
                let (x, y) = (p[0] - c[0], p[1] - c[1]);
                [c[0] + co * x - s * y, c[1] + s * x + co * y]
            }
        }
    }

    /// The inverse map.
    pub fn inverse(&self) -> Transform {
        match *self {
            Transform::Translation(t) => Transform::Translation([-t[0], -t[1]]),
            Transform::Rotation { centre, angle_degrees } => {
                Transform::Rotation { centre, angle_degrees: -angle_degrees }
            }
        }
    }

    /// Whether every number is finite.
    pub fn is_finite(&self) -> bool {
        match *self {
            Transform::Translation(t) => t.iter().all(|x| x.is_finite()),
            Transform::Rotation { centre, angle_degrees } => {
                centre.iter().all(|x| x.is_finite()) && angle_degrees.is_finite()
            }
        }
    }
}

/// One periodic pair: the curves (tags or names) of each side, and the map.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicPair {
    /// The master side's curves.
    pub master: Vec<String>,
    /// The slave side's curves.
    pub slave: Vec<String>,
    /// Master to slave.
    pub transform: Transform,
}

impl PeriodicPair {
    /// "master 302, 303 and slave 306, 307" as messages name the pair.
    pub fn label(&self) -> String {
        format!("master {} and slave {}", self.master.join(", "), self.slave.join(", "))
    }
}

/// How well one pair matches on a mesh.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PairMatch {
    /// The pair, as [`PeriodicPair::label`] names it.
    pub label: String,
    /// Vertices on the master side.
    pub master_vertices: usize,
    /// Vertices on the slave side.
    pub slave_vertices: usize,
    /// The largest distance between a vertex's image and the nearest vertex of the other
    /// side (both ways).
    pub max_distance: f64,
    /// Whether the sides can be glued vertex to vertex: as many vertices on each, every
    /// one within [`MATCH_TOLERANCE`] of the diagonal of its partner.
    pub matched: bool,
    /// The curve tags of both sides (the remesher freezes them).
    pub curve_tags: Vec<i32>,
}

/// Why a pair is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PeriodicError {
    /// A side names no curve of the mesh, or a curve without a tag.
    #[error("periodic pair {pair}: {why}")]
    Curve {
        /// The pair.
        pair: String,
        /// What is wrong.
        why: String,
    },
    /// The sides are not images of each other.
    #[error("periodic pair {pair}: the sides are not images of each other by the transform: a vertex of the {side} side at ({x}, {y}) is {distance:.3e} from the other side's image (tolerance {tolerance:.3e}, {SHAPE_TOLERANCE:e} of the domain's diagonal)")]
    NotImages {
        /// The pair.
        pair: String,
        /// "master" or "slave".
        side: &'static str,
        /// The vertex farthest off.
        x: f64,
        /// Its y.
        y: f64,
        /// How far.
        distance: f64,
        /// The tolerance.
        tolerance: f64,
    },
}

/// One side of a pair on a mesh: its vertices (sorted), its edges, its curves' tags.
type Side = (Vec<usize>, Vec<[usize; 2]>, Vec<i32>);

/// The vertices and edges of the curves `names` (tags or names) of `topology`, and the
/// curves' tags.
fn side(topology: &Topology, names: &[String], pair: &str) -> Result<Side, PeriodicError> {
    let bad = |why: String| PeriodicError::Curve { pair: pair.to_string(), why };
    if names.is_empty() {
        return Err(bad("a side lists no curve".into()));
    }
    let mut vertices = std::collections::BTreeSet::new();
    let mut edges = Vec::new();
    let mut tags = Vec::new();
    for name in names {
        let found = crate::layer::resolve_curve(topology, name).map_err(|e| bad(e.to_string()))?;
        for c in found {
            let curve = &topology.curves[c];
            tags.extend(curve.tag);
            for p in &curve.polylines {
                vertices.extend(p.vertices.iter().copied());
                edges.extend(p.edges());
            }
        }
    }
    if edges.is_empty() {
        return Err(bad(format!("curves {} have no edge", names.join(", "))));
    }
    Ok((vertices.into_iter().collect(), edges, tags))
}

/// Distance from `p` to segment `a`–`b`.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// Measures `pair` on the mesh of `points` whose topology is `topology`.
pub fn check(
    points: &[[f64; 3]],
    topology: &Topology,
    pair: &PeriodicPair,
) -> Result<PairMatch, PeriodicError> {
    let label = pair.label();
    let (mv, me, mut tags) = side(topology, &pair.master, &label)?;
    let (sv, se, slave_tags) = side(topology, &pair.slave, &label)?;
    tags.extend(slave_tags);
    let xy = |v: usize| [points[v][0], points[v][1]];
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let diagonal = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let tolerance = SHAPE_TOLERANCE * diagonal;
    let inverse = pair.transform.inverse();
    // Shapes: each side's vertices mapped onto the other side's edges.
    for (name, verts, map, edges) in
        [("master", &mv, pair.transform, &se), ("slave", &sv, inverse, &me)]
    {
        for &v in verts {
            let q = map.apply(xy(v));
            let d = edges
                .iter()
                .map(|e| to_segment(q, xy(e[0]), xy(e[1])))
                .fold(f64::INFINITY, f64::min);
            if d.is_nan() || d > tolerance {
                let [x, y] = xy(v);
                return Err(PeriodicError::NotImages {
                    pair: label,
                    side: name,
                    x,
                    y,
                    distance: d,
                    tolerance,
                });
            }
        }
    }
    // Vertices: each image to the nearest vertex of the other side.
    let mut max_distance = 0.0f64;
    for (verts, map, other) in [(&mv, pair.transform, &sv), (&sv, inverse, &mv)] {
        for &v in verts {
            let q = map.apply(xy(v));
            let d = other
                .iter()
                .map(|&w| {
                    let p = xy(w);
                    (p[0] - q[0]).hypot(p[1] - q[1])
                })
                .fold(f64::INFINITY, f64::min);
            max_distance = max_distance.max(d);
        }
    }
    tags.sort_unstable();
    tags.dedup();
    Ok(PairMatch {
        label,
        master_vertices: mv.len(),
        slave_vertices: sv.len(),
        max_distance,
        matched: mv.len() == sv.len() && max_distance <= MATCH_TOLERANCE * diagonal,
        curve_tags: tags,
    })
}

/// Measures every pair of `pairs` on `mesh`.
pub fn check_all(
    mesh: &crate::formats::TaggedMesh,
    pairs: &[PeriodicPair],
) -> Result<Vec<PairMatch>, PeriodicError> {
    if pairs.is_empty() {
        return Ok(Vec::new());
    }
    let topology = Topology::from_mesh(mesh);
    pairs.iter().map(|p| check(&mesh.points, &topology, p)).collect()
}

impl std::fmt::Display for PairMatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "periodic {}: {} and {} vertices, largest distance between a vertex's image and its partner {:.3e} ({})",
            self.label,
            self.master_vertices,
            self.slave_vertices,
            self.max_distance,
            if self.matched { "matched" } else { "NOT matched vertex to vertex" }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_transform_and_its_inverse_cancel() {
        for t in [
            Transform::Translation([3.5, -88.0]),
            Transform::Rotation { centre: [1.0, -2.0], angle_degrees: 36.0 },
        ] {
            for p in [[0.0, 0.0], [10.0, -7.5], [-1e3, 2e2]] {
                let q = t.inverse().apply(t.apply(p));
                assert!((q[0] - p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12, "{q:?}");
            }
        }
        // A quarter turn about (1, 1) takes (2, 1) to (1, 2).
        let q = Transform::Rotation { centre: [1.0, 1.0], angle_degrees: 90.0 }.apply([2.0, 1.0]);
        assert!((q[0] - 1.0).abs() < 1e-15 && (q[1] - 2.0).abs() < 1e-15, "{q:?}");
    }

    #[test]
    fn the_distance_to_a_segment_is_the_analytic_one() {
        assert_eq!(to_segment([0.5, 2.0], [0.0, 0.0], [1.0, 0.0]), 2.0);
        assert_eq!(to_segment([-3.0, 4.0], [0.0, 0.0], [1.0, 0.0]), 5.0);
        assert_eq!(to_segment([4.0, 4.0], [0.0, 0.0], [1.0, 0.0]), 5.0);
        assert_eq!(to_segment([4.0, 4.0], [1.0, 0.0], [1.0, 0.0]), 5.0);
    }
}
