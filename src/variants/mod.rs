//! Geometry variants for design studies (thesis 6.3.1): families of planar straight-line
//! graphs that share their topology and tags, written as Triangle `.poly` files with a
//! manifest for `smartmesh batch`, so that one recipe adapts every member.
//!
//! A family is one file here: [`naca`] (NACA 4-digit airfoils in a circular far field,
//! parametrised by thickness, camber and camber position, with the tags of the bundled
//! NACA 0012 example) and [`distributor`] (the three turbine distributors of
//! `examples/distributor`). Each builds a [`Pslg`]: vertices in insertion order, tagged
//! points, curves as chains of segments, holes and one face.
//!
//! Invariants of a written `.poly` ([`Pslg::write_poly`], which checks them first):
//! - every vertex where curves of different tags meet is a tagged point, so that the
//!   topology of any mesh of it recovers the point as a curve junction;
//! - no two segments cross or touch but at a shared end (exact orientation predicate);
//! - coordinates are rounded to 10 significant digits when a vertex is added, as
//!   `examples/make_examples.py` rounds them for the bundled examples, and written by the
//!   formats crate's Triangle writer (one `.poly` writer in smartmesh). The records are
//!   those of the bundled examples, value for value; only the spelling of the numbers
//!   differs: the shortest that reads back exactly (`0.0`, `0.00003531094955`, the
//!   region's `100.0 -1.0`) where Python's `%.10g` writes `0`, `3.531094955e-05`, `100 -1`;
//! - tag names travel in the comment header (`#   curve 1 = Upper`): Triangle's format
//!   has no names, and a recipe names regions by tag.

pub mod distributor;
pub mod naca;

use std::collections::BTreeMap;
use std::fmt::Write as _;

use smartmesh_formats::{
    triangle, CellBlock, CellKind, DataArray, Format, RegionSeed, TaggedMesh, WriteOptions,
};

use crate::geometry::segment::{orient, Point2};

/// A planar straight-line graph with tagged points, curves and one face.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Pslg {
    /// First comment line.
    pub title: String,
    /// Comment lines after the title and the line naming the writer.
    pub notes: Vec<String>,
    /// Vertices, rounded to 10 significant digits.
    pub vertices: Vec<Point2>,
    /// Point tag of each vertex (0: not a topological point).
    pub markers: Vec<i64>,
    /// Segments (vertex indices from 0) with their curve tag.
    pub segments: Vec<(usize, usize, i64)>,
    /// One point inside each hole.
    pub holes: Vec<Point2>,
    /// A point of the face and its tag.
    pub region: Option<(Point2, i64)>,
    /// `(dimension, tag)` → name.
    pub names: BTreeMap<(u8, i64), String>,
}

/// A `.poly` that would not be a valid geometry of its family.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryError {
    /// Curves of different tags meet at a vertex that is no tagged point.
    #[error(
        "{title}: vertex {vertex} at ({x}, {y}) joins curves {curves:?} but is no tagged point"
    )]
    UntaggedJunction {
        /// The geometry's title.
        title: String,
        /// The vertex, from 1.
        vertex: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
        /// The curve tags meeting there.
        curves: Vec<i64>,
    },
    /// Two segments cross or touch away from a shared end.
    #[error("{title}: segment {a} (curve {tag_a}) and segment {b} (curve {tag_b}) cross; the parameters give a self-intersecting boundary")]
    SegmentsCross {
        /// The geometry's title.
        title: String,
        /// First segment, from 1.
        a: usize,
        /// Its curve.
        tag_a: i64,
        /// Second segment, from 1.
        b: usize,
        /// Its curve.
        tag_b: i64,
    },
    /// No face was set.
    #[error("{0}: no face")]
    NoFace(String),
    /// The Triangle writer could not hold the graph whole (a tag past 32 bits).
    #[error("{title}: cannot be written as a .poly: {reason}")]
    Unwritable {
        /// The geometry's title.
        title: String,
        /// What could not be written.
        reason: String,
    },
}

impl Pslg {
    /// An empty graph titled `title`.
    pub fn new(title: impl Into<String>) -> Pslg {
        Pslg { title: title.into(), ..Pslg::default() }
    }

    /// Adds a vertex (rounded to 10 significant digits) with point tag `tag` (0: none);
    /// returns its index.
    pub fn add_vertex(&mut self, p: Point2, tag: i64) -> usize {
        self.vertices.push([round10(p[0]), round10(p[1])]);
        self.markers.push(tag);
        self.vertices.len() - 1
    }

    /// Adds a topological point named `name`.
    pub fn add_point(&mut self, p: Point2, tag: i64, name: &str) -> usize {
        self.names.insert((0, tag), name.to_string());
        self.add_vertex(p, tag)
    }

    /// A curve from vertex `start` through the points `inner` to vertex `end`.
    pub fn add_curve(&mut self, tag: i64, name: &str, start: usize, inner: &[Point2], end: usize) {
        self.names.insert((1, tag), name.to_string());
        let mut ids = vec![start];
        ids.extend(inner.iter().map(|&p| self.add_vertex(p, 0)));
        ids.push(end);
        for w in ids.windows(2) {
            self.segments.push((w[0], w[1], tag));
        }
    }

    /// A closed curve through `points`.
    pub fn add_closed_curve(&mut self, tag: i64, name: &str, points: &[Point2]) {
        self.names.insert((1, tag), name.to_string());
        let ids: Vec<usize> = points.iter().map(|&p| self.add_vertex(p, 0)).collect();
        for k in 0..ids.len() {
            self.segments.push((ids[k], ids[(k + 1) % ids.len()], tag));
        }
    }

    /// Adds a hole point (rounded).
    pub fn add_hole(&mut self, p: Point2) {
        self.holes.push([round10(p[0]), round10(p[1])]);
    }

    /// Sets the face: a point inside it, its tag and name.
    pub fn set_face(&mut self, p: Point2, tag: i64, name: &str) {
        self.region = Some(([round10(p[0]), round10(p[1])], tag));
        self.names.insert((2, tag), name.to_string());
    }

    /// Checks the invariants of the module header.
    pub fn check(&self) -> Result<(), GeometryError> {
        let mut curves: BTreeMap<usize, Vec<i64>> = BTreeMap::new();
        for &(a, b, tag) in &self.segments {
            for v in [a, b] {
                let c = curves.entry(v).or_default();
                if !c.contains(&tag) {
                    c.push(tag);
                }
            }
        }
        for (&v, tags) in &curves {
            if tags.len() > 1 && self.markers[v] == 0 {
                let mut tags = tags.clone();
                tags.sort_unstable();
                return Err(GeometryError::UntaggedJunction {
                    title: self.title.clone(),
                    vertex: v + 1,
                    x: self.vertices[v][0],
                    y: self.vertices[v][1],
                    curves: tags,
                });
            }
        }
        if let Some((i, j)) = first_crossing(&self.vertices, &self.segments) {
            return Err(GeometryError::SegmentsCross {
                title: self.title.clone(),
                a: i + 1,
                tag_a: self.segments[i].2,
                b: j + 1,
                tag_b: self.segments[j].2,
            });
        }
        if self.region.is_none() {
            return Err(GeometryError::NoFace(self.title.clone()));
        }
        Ok(())
    }

    /// The untagged vertex where the boundary turns most, with the turn in degrees: where
    /// it exceeds `smartmesh mesh`'s corner angle (30° by default), meshing makes a corner
    /// point there, a point with a tag of its own.
    pub fn sharpest_turn(&self) -> Option<(usize, f64)> {
        let mut ends: Vec<Vec<usize>> = vec![Vec::new(); self.vertices.len()];
        for &(a, b, _) in &self.segments {
            ends[a].push(b);
            ends[b].push(a);
        }
        let mut best: Option<(usize, f64)> = None;
        for (v, e) in ends.iter().enumerate() {
            if self.markers[v] != 0 || e.len() != 2 {
                continue;
            }
            let (p, q, r) = (self.vertices[e[0]], self.vertices[v], self.vertices[e[1]]);
            let (u, w) = ([q[0] - p[0], q[1] - p[1]], [r[0] - q[0], r[1] - q[1]]);
            let turn =
                (u[0] * w[1] - u[1] * w[0]).atan2(u[0] * w[0] + u[1] * w[1]).abs().to_degrees();
            if best.map_or(true, |(_, t)| turn > t) {
                best = Some((v, turn));
            }
        }
        best
    }

    /// The `.poly` text, after [`Pslg::check`]: a comment header (title, `writer`, notes,
    /// tag names), then the graph as the formats crate's Triangle writer writes a
    /// self-contained `.poly`: vertices with their point tags as markers, segments with
    /// their curve tags, holes and the one region whose attribute is the face tag (no
    /// area bound, -1).
    pub fn write_poly(&self, writer: &str) -> Result<String, GeometryError> {
        self.check()?;
        let mut s = String::new();
        let _ = writeln!(s, "# {}", self.title);
        let _ = writeln!(s, "# {writer}");
        for n in &self.notes {
            let _ = writeln!(s, "# {n}");
        }
        s.push_str("# Tags (topological entity: tag = name):\n");
        for ((dim, tag), name) in &self.names {
            let kind = ["point", "curve", "face"][usize::from(*dim).min(2)];
            let _ = writeln!(s, "#   {kind} {tag} = {name}");
        }
        s.push_str(
            "# Vertex markers are point tags (0: not a topological point); segment markers\n",
        );
        s.push_str("# are curve tags; the region's attribute is the face tag.\n");
        let written = smartmesh_formats::write_bytes(
            Format::Triangle,
            &self.to_mesh()?,
            &WriteOptions { main_name: Some("geometry.poly".into()), ..WriteOptions::default() },
        )
        .map_err(|e| self.unwritable(e.to_string()))?;
        // Everything of the graph has its place in a `.poly`: a line of the writer's
        // report would be something lost.
        if let Some(lost) = written.report.dropped.first() {
            return Err(self.unwritable(lost.clone()));
        }
        s.push_str(&String::from_utf8_lossy(&written.main));
        Ok(s)
    }

    /// The graph as a mesh the Triangle writer writes as a self-contained `.poly`: Line
    /// cells tagged with their curve, vertex markers as point data `triangle:marker`, the
    /// holes and the face's region seed.
    fn to_mesh(&self) -> Result<TaggedMesh, GeometryError> {
        let tag = |t: i64| {
            i32::try_from(t)
                .map_err(|_| self.unwritable(format!("tag {t} does not fit in 32 bits")))
        };
        let (face_point, face_tag) =
            self.region.ok_or_else(|| GeometryError::NoFace(self.title.clone()))?;
        let mut mesh = TaggedMesh::new();
        mesh.points = self.vertices.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let mut lines = CellBlock::new(CellKind::Line);
        for &(a, b, t) in &self.segments {
            let t = tag(t)?;
            lines.push(&[a, b], t, t);
        }
        mesh.blocks.push(lines);
        let markers =
            self.markers.iter().map(|&m| tag(m).map(f64::from)).collect::<Result<_, _>>()?;
        mesh.point_data.insert(triangle::MARKER.to_string(), DataArray::new(1, markers));
        mesh.holes.clone_from(&self.holes);
        mesh.regions.push(RegionSeed {
            point: face_point,
            attribute: f64::from(tag(face_tag)?),
            max_area: -1.0,
        });
        Ok(mesh)
    }

    fn unwritable(&self, reason: String) -> GeometryError {
        GeometryError::Unwritable { title: self.title.clone(), reason }
    }
}

/// The first pair of segments (indices, in order) that share a point other than a
/// common end, with the exact orientation predicate. A sweep along x tests only the pairs
/// whose closed boxes meet (two segments sharing a point have boxes sharing it), so a
/// graph of 200 000 segments is checked in a moment; the lowest pair of all those found
/// is the one the all-pairs twin ([`first_crossing_brute`]) finds first.
fn first_crossing(v: &[Point2], segments: &[(usize, usize, i64)]) -> Option<(usize, usize)> {
    let bounds = |k: usize| {
        let (p, q) = (v[segments[k].0], v[segments[k].1]);
        ([p[0].min(q[0]), p[1].min(q[1])], [p[0].max(q[0]), p[1].max(q[1])])
    };
    let boxes: Vec<([f64; 2], [f64; 2])> = (0..segments.len()).map(bounds).collect();
    let mut order: Vec<usize> = (0..segments.len()).collect();
    order.sort_by(|&i, &j| boxes[i].0[0].total_cmp(&boxes[j].0[0]).then(i.cmp(&j)));
    let mut active: Vec<usize> = Vec::new();
    let mut first: Option<(usize, usize)> = None;
    for &k in &order {
        let (lo, hi) = boxes[k];
        active.retain(|&a| boxes[a].1[0] >= lo[0]);
        for &a in &active {
            let (alo, ahi) = boxes[a];
            if alo[1] > hi[1] || ahi[1] < lo[1] {
                continue;
            }
            let pair = (a.min(k), a.max(k));
            if first.map_or(true, |f| pair < f) && pair_meets(v, segments, pair.0, pair.1) {
                first = Some(pair);
            }
        }
        active.push(k);
    }
    first
}

/// The all-pairs twin of [`first_crossing`].
#[cfg(test)]
fn first_crossing_brute(v: &[Point2], segments: &[(usize, usize, i64)]) -> Option<(usize, usize)> {
    (0..segments.len())
        .flat_map(|i| (i + 1..segments.len()).map(move |j| (i, j)))
        .find(|&(i, j)| pair_meets(v, segments, i, j))
}

/// Whether segments `i` and `j` share a point other than a common end.
fn pair_meets(v: &[Point2], segments: &[(usize, usize, i64)], i: usize, j: usize) -> bool {
    let on_segment = |a: Point2, b: Point2, c: Point2| {
        orient(a, b, c) == 0.0
            && c[0] >= a[0].min(b[0])
            && c[0] <= a[0].max(b[0])
            && c[1] >= a[1].min(b[1])
            && c[1] <= a[1].max(b[1])
    };
    let ((a, b, _), (c, d, _)) = (segments[i], segments[j]);
    let shared = [a, b].iter().filter(|x| **x == c || **x == d).count();
    let (p, q, r, s) = (v[a], v[b], v[c], v[d]);
    if shared == 2 {
        return true;
    }
    if shared == 1 {
        // Touching at the shared end is what a chain does; overlapping beyond it
        // (collinear and folding back) is not.
        let (far1, far2) = if a == c || a == d {
            (q, if a == c { s } else { r })
        } else {
            (p, if b == c { s } else { r })
        };
        let common = if a == c || a == d { p } else { q };
        return on_segment(common, far1, far2) || on_segment(common, far2, far1);
    }
    let (o1, o2, o3, o4) = (orient(p, q, r), orient(p, q, s), orient(r, s, p), orient(r, s, q));
    let proper = o1 * o2 < 0.0 && o3 * o4 < 0.0;
    proper
        || on_segment(p, q, r)
        || on_segment(p, q, s)
        || on_segment(r, s, p)
        || on_segment(r, s, q)
}

/// `v` rounded to 10 significant digits (what the files hold).
pub(crate) fn round10(v: f64) -> f64 {
    format_g(v, 10).parse().unwrap_or(v)
}

/// `v` as C's `printf("%.{precision}g")` (and Python's `%g`) writes it: `precision`
/// significant digits, trailing zeros dropped, exponent form (`1e-05`, `1.5e+20`) when
/// the exponent is below -4 or at least `precision`. Rust's formatting is exact, so
/// the digits are those of the correctly rounded value, as glibc's.
pub(crate) fn format_g(v: f64, precision: usize) -> String {
    let p = precision.max(1);
    if !v.is_finite() {
        return if v.is_nan() {
            "nan".into()
        } else if v > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    if v == 0.0 {
        return if v.is_sign_negative() { "-0".into() } else { "0".into() };
    }
    let e = format!("{:.*e}", p - 1, v);
    let (mantissa, exponent) = e.split_once('e').unwrap_or((&e, "0"));
    let x: i32 = exponent.parse().unwrap_or(0);
    let trim = |s: &str| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if x < -4 || x >= p as i32 {
        let sign = if x < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim(mantissa), x.abs())
    } else {
        let decimals = (p as i32 - 1 - x).max(0) as usize;
        trim(&format!("{v:.decimals$}"))
    }
}

/// A list of values from the command line: `A` (one), `A,B,C` (these) or `A:B:N` (N
/// values evenly from A to B, both included).
pub fn parse_values(text: &str) -> Result<Vec<f64>, String> {
    let number = |s: &str| -> Result<f64, String> {
        let v: f64 = s.trim().parse().map_err(|_| {
            format!("`{s}` is not a number (expected A, A,B,C or A:B:N, as 0.08:0.16:5)")
        })?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("`{s}` is not a finite number"))
        }
    };
    let parts: Vec<&str> = text.split(':').collect();
    match parts.as_slice() {
        [a, b, n] => {
            let (a, b) = (number(a)?, number(b)?);
            let n: usize = n.trim().parse().map_err(|_| {
                format!("`{n}` is not a count: expected A:B:N with N a whole number >= 1")
            })?;
            match n {
                0 => Err("A:B:N with N = 0 gives no value".into()),
                1 if a != b => Err(format!(
                    "{text}: one value between two different ends; write one value, or N >= 2"
                )),
                1 => Ok(vec![a]),
                _ if n > 100_000 => Err(format!("{text}: {n} values; at most 100000")),
                _ => Ok((0..n)
                    .map(|k| if k + 1 == n { b } else { a + (b - a) * k as f64 / (n - 1) as f64 })
                    .collect()),
            }
        }
        [one] => one.split(',').map(number).collect(),
        _ => Err(format!("`{text}`: expected A, A,B,C or A:B:N (as 0.08:0.16:5)")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_g_writes_as_c_does() {
        // Values checked with Python's "%.10g" and "%g" (which call the C rules).
        for (v, p, s) in [
            (0.0, 10, "0"),
            (-0.0, 10, "-0"),
            (1.008930411, 10, "1.008930411"),
            (0.0002489231266, 10, "0.0002489231266"),
            (0.00002489231266, 10, "2.489231266e-05"),
            (-100.0, 10, "-100"),
            (12345678901.0, 10, "1.23456789e+10"),
            (1234567890.0, 10, "1234567890"),
            (0.5044652053, 10, "0.5044652053"),
            (-13.5, 6, "-13.5"),
            (0.1 + 0.2, 10, "0.3"),
            (9.99999999999, 10, "10"),
            (1e20, 6, "1e+20"),
            (0.0001, 6, "0.0001"),
        ] {
            assert_eq!(format_g(v, p), s, "{v:e}");
        }
    }

    #[test]
    fn value_lists() {
        assert_eq!(parse_values("0.12").unwrap(), vec![0.12]);
        assert_eq!(parse_values("0.1,0.2").unwrap(), vec![0.1, 0.2]);
        let v = parse_values("0.08:0.16:5").unwrap();
        assert_eq!(v.len(), 5);
        assert_eq!((v[0], v[4]), (0.08, 0.16));
        assert!((v[2] - 0.12).abs() < 1e-15);
        assert_eq!(parse_values("0.3:0.3:1").unwrap(), vec![0.3]);
        for bad in ["", "a", "0:1:0", "0:1:1", "0:1", "0:1:x", "0:1:2:3", "inf", "1,,2"] {
            assert!(parse_values(bad).is_err(), "{bad}");
        }
    }

    fn square() -> Pslg {
        let mut g = Pslg::new("square");
        let a = g.add_point([0.0, 0.0], 1, "A");
        let b = g.add_point([1.0, 0.0], 2, "B");
        g.add_curve(10, "Bottom", a, &[[0.5, 0.0]], b);
        g.add_curve(11, "Rest", b, &[[1.0, 1.0], [0.0, 1.0]], a);
        g.set_face([0.5, 0.5], 100, "Inside");
        g
    }

    #[test]
    fn a_valid_graph_is_written_and_bad_ones_refused() {
        let g = square();
        let text = g.write_poly("test").unwrap();
        assert!(text.contains("#   curve 10 = Bottom\n"), "{text}");
        assert!(text.contains("\n5 2 0 1\n1 0.0 0.0 1\n"), "{text}");
        assert!(text.ends_with("0\n1\n1 0.5 0.5 100.0 -1.0\n"), "{text}");
        // A junction of two curves that is no tagged point.
        let mut j = square();
        j.markers[1] = 0;
        assert!(matches!(j.check(), Err(GeometryError::UntaggedJunction { vertex: 2, .. })));
        // A bow tie: the top edge moved below the bottom one.
        let mut x = square();
        x.vertices[3] = [1.0, -1.0];
        x.vertices[4] = [0.0, 1.0];
        x.vertices[2] = [0.5, 0.0];
        assert!(matches!(x.check(), Err(GeometryError::SegmentsCross { .. })), "{:?}", x.check());
        // A vertex touching another segment.
        let mut t = square();
        t.vertices[4] = [0.5, 0.0];
        assert!(t.check().is_err());
    }

    /// Closed segments with integer ends share a point: Cramer's rule in integers, and
    /// overlapping intervals on the collinear line (another algorithm than the
    /// orientation tests of [`first_crossing`]).
    fn share_a_point(p: [i64; 2], q: [i64; 2], r: [i64; 2], s: [i64; 2]) -> bool {
        let d = [q[0] - p[0], q[1] - p[1]];
        let e = [s[0] - r[0], s[1] - r[1]];
        let w = [r[0] - p[0], r[1] - p[1]];
        let den = d[0] * e[1] - d[1] * e[0];
        if den != 0 {
            // p + t d = r + u e: t = (w x e) / den, u = (w x d) / den, both in [0, 1].
            let (tn, un) = (w[0] * e[1] - w[1] * e[0], w[0] * d[1] - w[1] * d[0]);
            let within = |n: i64| if den > 0 { 0 <= n && n <= den } else { den <= n && n <= 0 };
            return within(tn) && within(un);
        }
        if w[0] * d[1] - w[1] * d[0] != 0 {
            return false; // parallel, not on one line
        }
        // On one line (or points): overlap of the intervals on both axes.
        (0..2).all(|k| p[k].min(q[k]).max(r[k].min(s[k])) <= p[k].max(q[k]).min(r[k].max(s[k])))
    }

    /// The sweep and the all-pairs twin find the same first pair on random graphs on a
    /// small grid (shared ends, collinear overlaps, T junctions), and the sweep checks a
    /// valid ring of 200 000 segments at once.
    #[test]
    fn the_sweep_and_the_all_pairs_twin_find_the_same_first_crossing() {
        use smartmesh_test_support::Generator;
        let mut rng = smartmesh_test_support::SplitMix64(11);
        let mut found = 0;
        for _ in 0..2000 {
            let n = rng.int(3, 12);
            let v: Vec<Point2> =
                (0..n).map(|_| [rng.int(0, 6) as f64, rng.int(0, 6) as f64]).collect();
            let segs: Vec<(usize, usize, i64)> = (0..rng.int(1, 10))
                .map(|_| (rng.int(0, n - 1), rng.int(0, n - 1), 1))
                .filter(|&(a, b, _)| a != b)
                .collect();
            let fast = first_crossing(&v, &segs);
            assert_eq!(fast, first_crossing_brute(&v, &segs), "{v:?} {segs:?}");
            found += usize::from(fast.is_some());
        }
        assert!(found > 200, "{found}");
        let n = 200_000;
        let ring: Vec<Point2> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                [a.cos(), a.sin()]
            })
            .collect();
        let segs: Vec<(usize, usize, i64)> = (0..n).map(|k| (k, (k + 1) % n, 1)).collect();
        let start = std::time::Instant::now();
        assert_eq!(first_crossing(&ring, &segs), None);
        assert!(start.elapsed().as_secs_f64() < 5.0, "{:?}", start.elapsed());
    }

    #[test]
    fn crossings_agree_with_an_integer_twin() {
        // Ends on a 5x5 grid: collinear overlaps, touching ends and T junctions are
        // frequent, the hard cases.
        use smartmesh_test_support::Generator;
        let mut rng = smartmesh_test_support::SplitMix64(7);
        let mut hits = 0;
        for _ in 0..20_000 {
            let mut g = || [rng.int(0, 4) as i64, rng.int(0, 4) as i64];
            let (p, q, r, s) = (g(), g(), g(), g());
            if p == q || r == s {
                continue;
            }
            let f = |a: [i64; 2]| [a[0] as f64, a[1] as f64];
            let v = vec![f(p), f(q), f(r), f(s)];
            let exact = first_crossing(&v, &[(0, 1, 1), (2, 3, 2)]).is_some();
            assert_eq!(exact, share_a_point(p, q, r, s), "{p:?}-{q:?} and {r:?}-{s:?}");
            hits += usize::from(exact);
        }
        assert!(hits > 1000, "{hits}");
    }
}
