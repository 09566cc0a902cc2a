//! The frame of a vertex with respect to its closest point on a source (thesis
//! 4.3.7.1): the normal and tangent there, the junctions where segment ends of a
//! source meet, and a size tensor from a normal and two sizes.
//!
//! On the source. A vertex whose distance to the source is at most [`ON_SOURCE`] times
//! the length of its closest segment counts as on the source: the direction from its foot
//! point is rounding noise there, so the frame comes from the source's tangent instead
//! (thesis 4.3.7.1, first case).

use super::Failure;
use crate::geometry::Point2;
use crate::metric::SizeTensor;
use crate::sizing::propagation::{ClosestPoint, Source};

/// Relative distance under which a vertex counts as lying on its source.
pub const ON_SOURCE: f64 = 1e-12;

/// A tensor with `h_normal` along `normal` and `h_tangent` across it; with no normal (a
/// point source seen from the point itself) the isotropic tensor of the smaller size,
/// the only one that respects both sizes in every orientation.
#[inline]
pub(crate) fn tensor(
    vertex: usize,
    normal: Option<Point2>,
    h_normal: f64,
    h_tangent: f64,
) -> Result<SizeTensor, Failure> {
    let sizes_ok = (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&h_normal)
        && (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&h_tangent);
    match normal {
        // `unit` gave a finite unit vector: no second normalisation.
        Some(n) if sizes_ok && n[0].is_finite() && n[1].is_finite() => {
            Ok(SizeTensor::from_parts(n, [h_normal, h_tangent]))
        }
        None if sizes_ok => {
            let h = h_normal.min(h_tangent);
            Ok(SizeTensor::from_parts([1.0, 0.0], [h, h]))
        }
        _ => Err(Failure::Degenerate { vertex }),
    }
}

/// The unit vector along `v`, if it has a length.
#[inline]
pub(crate) fn unit(v: Point2) -> Option<Point2> {
    // A plain square root, not `hypot`: coordinates of a mesh are far from overflow,
    // and this runs once per vertex.
    let n = (v[0] * v[0] + v[1] * v[1]).sqrt();
    (n > 0.0 && n.is_finite()).then(|| [v[0] / n, v[1] / n])
}

/// The points where segment ends of a source meet, so that a foot point on a polyline
/// vertex sees every segment that ends there: the previous and next segment of its own
/// polyline, and the ends of other polylines of the source at the same point (two
/// curves meeting at a topological point). Ends meet when their coordinates are equal
/// bit for bit, which is the case for curves sharing a mesh vertex.
#[derive(Debug, Clone)]
pub(crate) struct Junctions {
    /// Node of each segment's start and end.
    node_of_end: Vec<[u32; 2]>,
    /// CSR offsets into `sides`, one run per node.
    offsets: Vec<u32>,
    /// (segment, end: 0 start, 1 end) of every segment end, grouped by node.
    sides: Vec<(u32, u8)>,
}

impl Junctions {
    /// The junctions of the non-degenerate segments of `source`.
    pub(crate) fn new(source: &Source) -> Junctions {
        let segs = source.segments();
        let key = |p: Point2| (p[0].to_bits(), p[1].to_bits());
        let mut ends: Vec<((u64, u64), u32, u8)> = Vec::with_capacity(2 * segs.len());
        for (i, s) in segs.iter().enumerate() {
            if s.length > 0.0 {
                ends.push((key(s.a), i as u32, 0));
                ends.push((key(s.b), i as u32, 1));
            }
        }
        ends.sort_unstable();
        let mut node_of_end = vec![[u32::MAX; 2]; segs.len()];
        let mut offsets = vec![0u32];
        let mut sides = Vec::with_capacity(ends.len());
        for (k, &(p, seg, end)) in ends.iter().enumerate() {
            if k > 0 && ends[k - 1].0 != p {
                offsets.push(sides.len() as u32);
            }
            node_of_end[seg as usize][end as usize] = (offsets.len() - 1) as u32;
            sides.push((seg, end));
        }
        offsets.push(sides.len() as u32);
        Junctions { node_of_end, offsets, sides }
    }

    /// The node of closest point `c` when its foot is an end of its segment: `t` is 0 or
    /// 1, or the foot equals an end point bit for bit (a projection of a polyline vertex
    /// on the segment it ends may round `t` to just below 1).
    pub(crate) fn node(&self, source: &Source, c: &ClosestPoint) -> Option<usize> {
        let s = source.segments().get(c.segment as usize)?;
        let end = if c.parameter == 0.0 || c.foot == s.a {
            0
        } else if c.parameter == 1.0 || c.foot == s.b {
            1
        } else {
            return None;
        };
        let n = *self.node_of_end.get(c.segment as usize)?.get(end)?;
        (n != u32::MAX).then_some(n as usize)
    }

    /// The segment ends meeting at `node`.
    pub(crate) fn sides(&self, node: usize) -> &[(u32, u8)] {
        &self.sides[self.offsets[node] as usize..self.offsets[node + 1] as usize]
    }
}

/// The unit direction of segment `s` of `source`, if it has a length.
pub(crate) fn direction(source: &Source, s: u32) -> Option<Point2> {
    let seg = &source.segments()[s as usize];
    unit([seg.b[0] - seg.a[0], seg.b[1] - seg.a[1]])
}

/// The unit tangent of the source at a foot point lying on it: the segment's direction
/// inside a segment; at a polyline vertex the normalised sum of the unit directions of
/// the segments meeting there (thesis 4.3.7.1's "orientation of the mesh edge", averaged
/// over the neighbour segments), or the segment's own direction when they cancel.
/// `None` for a point source.
pub(crate) fn tangent_at(
    source: &Source,
    junctions: &Junctions,
    c: &ClosestPoint,
) -> Option<Point2> {
    let own = direction(source, c.segment)?;
    let Some(node) = junctions.node(source, c) else { return Some(own) };
    let mut sum = [0.0, 0.0];
    for &(s, _) in junctions.sides(node) {
        if let Some(d) = direction(source, s) {
            sum[0] += d[0];
            sum[1] += d[1];
        }
    }
    let n = sum[0].hypot(sum[1]);
    Some(if n > 1e-9 { [sum[0] / n, sum[1] / n] } else { own })
}

/// Whether a closest point counts as on the source (see [`ON_SOURCE`]).
#[inline]
pub(crate) fn on_source(source: &Source, c: &ClosestPoint) -> bool {
    let len = source.segments()[c.segment as usize].length;
    c.distance == 0.0 || c.distance <= ON_SOURCE * len
}

/// The unit normal of the frame of `p` with respect to its closest point `c`: from the
/// foot point to `p` off the source (thesis 4.3.7.1, second case; at a foot on a polyline
/// vertex this is the direction the vertex is seen from the corner), the source's normal
/// on it. `None` for a point source seen from the point itself.
#[inline]
pub(crate) fn normal_at(
    source: &Source,
    junctions: &Junctions,
    p: Point2,
    c: &ClosestPoint,
) -> Option<Point2> {
    if on_source(source, c) {
        return tangent_at(source, junctions, c).map(|t| [-t[1], t[0]]);
    }
    unit([p[0] - c.foot[0], p[1] - c.foot[1]])
        .or_else(|| tangent_at(source, junctions, c).map(|t| [-t[1], t[0]]))
}
