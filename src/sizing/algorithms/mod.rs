//! The six sizing algorithms of thesis 4.3.6–4.3.7, one file each, and what they share:
//! turning entity sets into propagation sources, the frame (normal and tangent) of a
//! vertex with respect to its closest point on a source, the junctions of a source's
//! polylines, and the assembly of a step's tensors in a fixed order.
//!
//! Every algorithm is a pure function from the mesh and its parameters to a
//! [`Contribution`]: the vertices it reaches, each with one size tensor. The driver
//! ([`crate::sizing::compute_size_field`]) intersects contributions into the field in plan
//! order. Each algorithm works by neighbour propagation
//! ([`crate::sizing::propagate`]) from its sources,
//! stopping past its maximum distance; UNIFORM needs none.
//!
//! Maximum distance. An algorithm propagates up to the largest maximum distance of the
//! functions it evaluates at a distance (perpendicular, parallel, projection; the
//! polyline's abscissa function and the curvature-to-size function take no distance).
//! Past its own maximum distance a function holds its end value (thesis 4.3.5.1 extended
//! by continuity), so every function is honoured over its whole range and none is cut
//! short by another. The perpendicular function usually has the largest reach; when it
//! does, it alone decides where the algorithm applies.
//!
//! On the source. A vertex whose distance to the source is at most [`ON_SOURCE`] times
//! the length of its closest segment counts as on the source: the direction from its foot
//! point is rounding noise there, so the frame comes from the source's tangent instead
//! (thesis 4.3.7.1, first case).

pub mod curvature_of_border;
pub mod distance_between_two_borders;
pub mod distance_to_border;
pub mod distance_to_imaginary_polyline;
pub mod distance_to_point;
pub mod uniform;

use rayon::prelude::*;

use crate::geometry::Point2;
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use crate::sizing::plan::{Algorithm, EntitySet};
use crate::sizing::propagation::{
    propagate, ClosestPoint, PropagationOptions, Reach, Source, SourceBuilder, SourceError,
    VertexOrder, VERTEX_RUN,
};
use crate::topology::Topology;

/// Relative distance under which a vertex counts as lying on its source.
pub const ON_SOURCE: f64 = 1e-12;

/// Reaches smaller than this build their tensors on the calling thread.
const PARALLEL_MIN: usize = 4096;

/// What one algorithm asks for: the vertices it reaches and one tensor each.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Contribution {
    /// Reached vertices, each once, in the algorithm's order (seeds first, then by
    /// propagation level).
    pub vertices: Vec<u32>,
    /// The tensor of each vertex of `vertices`.
    pub tensors: Vec<SizeTensor>,
    /// Vertices the propagation started from (0 for UNIFORM).
    pub seeds: usize,
}

impl Contribution {
    /// Number of vertices reached.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Whether no vertex was reached.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }
}

/// Why an algorithm could not run; the driver adds the step.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Failure {
    /// A topological entity index the topology does not have.
    EntityOutOfRange { what: &'static str, index: usize, len: usize },
    /// An entity of a kind the algorithm cannot use as a source.
    UnsupportedEntity { what: &'static str, index: usize },
    /// The sources make no segment and no point.
    NoSource,
    /// An imaginary polyline with no point.
    EmptyPolyline,
    /// A polyline point with a NaN or infinite coordinate.
    NonFinitePoint { point: usize },
    /// A size outside [MIN_SIZE, MAX_SIZE].
    InvalidSize { size: f64 },
    /// A vertex whose tensor could not be formed (non-finite coordinates).
    Degenerate { vertex: usize },
}

impl From<SourceError> for Failure {
    fn from(e: SourceError) -> Failure {
        match e {
            SourceError::VertexOutOfRange { vertex, len, .. } => {
                Failure::EntityOutOfRange { what: "mesh vertex", index: vertex, len }
            }
            SourceError::EntityOutOfRange { what, index, len, .. } => {
                Failure::EntityOutOfRange { what, index, len }
            }
            SourceError::EmptyPiece { .. } => Failure::EmptyPolyline,
            SourceError::NonFinite { point, .. } => Failure::NonFinitePoint { point },
        }
    }
}

/// Runs one algorithm of a plan on a mesh (thesis 4.3.6–4.3.7), handing its tensors to
/// `sink`: collected into a [`Contribution`] ([`Collect`]), or intersected straight into
/// a field (the driver's sink).
pub(crate) fn run<S: Sink>(
    graph: &MeshGraph,
    topology: &Topology,
    algorithm: &Algorithm,
    sink: S,
) -> Result<S::Output, Failure> {
    let options = PropagationOptions::new();
    match algorithm {
        Algorithm::Uniform { size, on } => uniform::run(graph, topology, *size, on, sink),
        Algorithm::DistanceToPoint { function, sources } => {
            distance_to_point::run(graph, topology, function, sources, &options, sink)
        }
        Algorithm::DistanceToBorder { perpendicular, parallel, borders } => {
            distance_to_border::run(
                graph,
                topology,
                perpendicular,
                parallel,
                borders,
                &options,
                sink,
            )
        }
        Algorithm::CurvatureOfBorder { perpendicular, curvature, projection, borders } => {
            curvature_of_border::run(
                graph,
                topology,
                perpendicular,
                curvature,
                projection,
                borders,
                &options,
                sink,
            )
        }
        Algorithm::DistanceBetweenTwoBorders { perpendicular, parallel, first, second } => {
            distance_between_two_borders::run(
                graph,
                topology,
                perpendicular,
                parallel,
                first,
                second,
                &options,
                sink,
            )
        }
        Algorithm::DistanceToImaginaryPolyline {
            perpendicular,
            polyline_distance,
            projection,
            polyline,
            within,
        } => distance_to_imaginary_polyline::run(
            graph,
            topology,
            perpendicular,
            polyline_distance,
            projection,
            polyline,
            within,
            &options,
            sink,
        ),
    }
}

/// Where an algorithm's tensors go. An algorithm computes one tensor per vertex that it
/// reaches, from the vertex's closest point ([`Sink::take_reach`]), or one tensor on a
/// list of vertices (UNIFORM, [`Sink::take_list`]); the sink decides whether they are
/// kept as a [`Contribution`] or merged into a field at once.
pub(crate) trait Sink {
    /// What the algorithm returns.
    type Output;

    /// The tensors `f` gives the vertices of `reach` (`Ok(None)`: the vertex is left
    /// out). When `f` fails on some vertices, the error of the first of them in the
    /// reach's order is returned, whatever the thread count.
    fn take_reach<F>(self, reach: Reach<'_>, f: F) -> Result<Self::Output, Failure>
    where
        F: Fn(usize, &ClosestPoint) -> Result<Option<SizeTensor>, Failure> + Sync;

    /// The tensors of a list of distinct vertices.
    fn take_list(self, contribution: Contribution) -> Result<Self::Output, Failure>;

    /// The tensors `f` gives the vertices that a propagation from `source` up to
    /// `max_distance` reaches: by default [`propagate`], then [`Sink::take_reach`].
    fn take_source<F>(
        self,
        graph: &MeshGraph,
        source: &Source,
        max_distance: f64,
        options: &PropagationOptions,
        f: F,
    ) -> Result<Self::Output, Failure>
    where
        Self: Sized,
        F: Fn(usize, &ClosestPoint) -> Result<Option<SizeTensor>, Failure> + Sync,
    {
        self.take_reach(propagate(graph, source, max_distance, options), f)
    }
}

/// The sink that keeps an algorithm's tensors as a [`Contribution`].
pub(crate) struct Collect;

impl Sink for Collect {
    type Output = Contribution;

    fn take_reach<F>(self, reach: Reach<'_>, f: F) -> Result<Contribution, Failure>
    where
        F: Fn(usize, &ClosestPoint) -> Result<Option<SizeTensor>, Failure> + Sync,
    {
        assemble(reach, f)
    }

    fn take_list(self, contribution: Contribution) -> Result<Contribution, Failure> {
        Ok(contribution)
    }
}

/// Checks the indices of `set` against `topology`.
pub(crate) fn check_entities(topology: &Topology, set: &EntitySet) -> Result<(), Failure> {
    let check =
        |what: &'static str, list: &[usize], len: usize| match list.iter().find(|&&i| i >= len) {
            Some(&index) => Err(Failure::EntityOutOfRange { what, index, len }),
            None => Ok(()),
        };
    check("point", &set.points, topology.points.len())?;
    check("curve", &set.curves, topology.curves.len())?;
    check("face", &set.faces, topology.faces.len())
}

/// A border source: every polyline of the curves of `set`, and its points as point
/// sources when `points_allowed`. Faces are not borders.
pub(crate) fn border_source(
    graph: &MeshGraph,
    topology: &Topology,
    set: &EntitySet,
    points_allowed: bool,
) -> Result<Source, Failure> {
    check_entities(topology, set)?;
    if let Some(&index) = set.faces.first() {
        return Err(Failure::UnsupportedEntity { what: "face", index });
    }
    if !points_allowed {
        if let Some(&index) = set.points.first() {
            return Err(Failure::UnsupportedEntity { what: "point", index });
        }
    }
    let mut b = SourceBuilder::new(graph);
    for &c in &set.curves {
        b.topology_curve(topology, c);
    }
    for &p in &set.points {
        b.topology_point(topology, p);
    }
    let source = b.build()?;
    if source.segments().is_empty() {
        return Err(Failure::NoSource);
    }
    Ok(source)
}

/// The largest of the maximum distances.
pub(crate) fn reach_of(distances: &[f64]) -> f64 {
    distances.iter().copied().fold(0.0, f64::max)
}

/// Builds one tensor per entry of `reach` that `f` keeps (`Ok(None)` skips the vertex),
/// in the reach's order, on the rayon pool for large reaches. The first error in that
/// order wins, so the result does not depend on the thread count.
///
/// The tensors are written in place into the contribution's array (no intermediate
/// array of results), and each closest point is made where its tensor is: for a reach
/// of 10^6 vertices that is 100 MB of fresh memory less than arrays of both.
pub(crate) fn assemble<F>(reach: Reach<'_>, f: F) -> Result<Contribution, Failure>
where
    F: Fn(usize, &ClosestPoint) -> Result<Option<SizeTensor>, Failure> + Sync,
{
    let n = reach.len();
    let seeds = reach.report().seeds;
    let mut tensors = vec![SizeTensor::isotropic(1.0); n];
    let mut keep = vec![true; n];
    let call = |i: usize| f(reach.vertices()[i] as usize, &reach.closest(i));
    // For each item: the index of an error, and whether it was skipped.
    let one = |i: usize, slot: &mut SizeTensor, kept: &mut bool| -> (usize, usize) {
        match call(i) {
            Ok(Some(t)) => {
                *slot = t;
                (usize::MAX, 0)
            }
            Ok(None) => {
                *kept = false;
                (usize::MAX, 1)
            }
            Err(_) => (i, 0),
        }
    };
    let (first_error, skipped) = scan_pairs(&mut tensors, &mut keep, one);
    if first_error != usize::MAX {
        // The smallest index with an error, whatever the threads; its error again.
        return Err(call(first_error)
            .err()
            .unwrap_or(Failure::Degenerate { vertex: reach.vertices()[first_error] as usize }));
    }
    let mut vertices = reach.into_vertices();
    if skipped > 0 {
        let mut k = 0;
        for i in 0..n {
            if keep[i] {
                vertices[k] = vertices[i];
                tensors[k] = tensors[i];
                k += 1;
            }
        }
        vertices.truncate(k);
        tensors.truncate(k);
    }
    Ok(Contribution { vertices, tensors, seeds })
}

/// Merges tensor `t` into a field's tensor of a vertex: intersected into it (thesis
/// 3.2.2) when the vertex has one already (`has`), taken as it is otherwise.
#[inline]
pub(crate) fn merge(slot: &mut SizeTensor, has: &mut bool, t: &SizeTensor) {
    *slot = if *has { slot.intersection(t) } else { *t };
    *has = true;
}

/// Merges the tensors `f` gives the vertices of `reach` straight into a field, in vertex
/// order: each is intersected into the vertex's tensor, or taken as it is where the
/// vertex has none yet (`reached`). Returns how many were merged. The same merge as
/// [`assemble`] followed by one per vertex, without the list of tensors in between:
/// for a reach of 10^6 vertices, 32 MB of fresh memory and a pass over it less. Every
/// mesh vertex is looked up, so this pays where the reach covers much of the mesh.
/// Errors as [`assemble`]'s: the first in the reach's order; the field is then partly
/// merged and the caller discards it.
///
/// `finish` then sees every vertex once, with whether it has a tensor: the field's last
/// pass (default size, clamp) done in the same one when this is the last step.
pub(crate) fn merge_in_vertex_order<F, G>(
    reach: &Reach<'_>,
    f: F,
    tensors: &mut [SizeTensor],
    reached: &mut [bool],
    finish: G,
) -> Result<usize, Failure>
where
    F: Fn(usize, &ClosestPoint) -> Result<Option<SizeTensor>, Failure> + Sync,
    G: Fn(&mut SizeTensor, bool) + Sync,
{
    let positions = reach.positions();
    // For each vertex: the reach position of an error, and whether it merged a tensor.
    let one = |v: usize, slot: &mut SizeTensor, has: &mut bool| -> (usize, usize) {
        let i = positions[v];
        let outcome = if i == u32::MAX {
            (usize::MAX, 0)
        } else {
            match f(v, &reach.closest(i as usize)) {
                Ok(Some(t)) => {
                    merge(slot, has, &t);
                    (usize::MAX, 1)
                }
                Ok(None) => (usize::MAX, 0),
                Err(_) => (i as usize, 0),
            }
        };
        finish(slot, *has);
        outcome
    };
    let (first_error, merged) = scan_pairs(tensors, reached, one);
    if first_error != usize::MAX {
        let v = reach.vertices()[first_error] as usize;
        return Err(f(v, &reach.closest(first_error))
            .err()
            .unwrap_or(Failure::Degenerate { vertex: v }));
    }
    Ok(merged)
}

/// Merges the tensors `f` gives every mesh vertex from its closest point on `source`
/// straight into a field, in vertex order, for a step that reaches every vertex, none
/// farther than `farthest` ([`crate::sizing::propagation::reach_covers_mesh`]): the closest points come from
/// [`VertexOrder`] in runs of [`VERTEX_RUN`] vertices, on the rayon pool when
/// `parallel`, and each tensor is merged where its closest point is found. The same
/// field as [`merge_in_vertex_order`] after [`propagate`] (the same exact closest
/// points), without the breadth-first levels, the reach's arrays and a second
/// projection per vertex. Errors: the first in vertex order. `finish` as in
/// [`merge_in_vertex_order`]. Returns how many tensors were merged.
#[allow(clippy::too_many_arguments)]
pub(crate) fn merge_closest_in_vertex_order<F, G>(
    graph: &MeshGraph,
    source: &Source,
    farthest: f64,
    f: F,
    tensors: &mut [SizeTensor],
    reached: &mut [bool],
    finish: G,
    parallel: bool,
) -> Result<usize, Failure>
where
    F: Fn(usize, &ClosestPoint) -> Result<Option<SizeTensor>, Failure> + Sync,
    G: Fn(&mut SizeTensor, bool) + Sync,
{
    let order = VertexOrder::new(graph, source, farthest);
    // One run: the vertex of its first error (or usize::MAX) and the tensors merged.
    let run = |(k, (ts, rs)): (usize, (&mut [SizeTensor], &mut [bool]))| -> (usize, usize) {
        let lo = k * VERTEX_RUN;
        let (mut error, mut merged) = (usize::MAX, 0);
        order.for_each(lo..lo + ts.len(), |v, c| {
            let (slot, has) = (&mut ts[v - lo], &mut rs[v - lo]);
            match f(v, c) {
                Ok(Some(t)) => {
                    merge(slot, has, &t);
                    merged += 1;
                }
                Ok(None) => {}
                Err(_) => error = error.min(v),
            }
            finish(slot, *has);
        });
        (error, merged)
    };
    let combine = |a: (usize, usize), b: (usize, usize)| (a.0.min(b.0), a.1 + b.1);
    let (first_error, merged) = if parallel && tensors.len() > VERTEX_RUN {
        tensors
            .par_chunks_mut(VERTEX_RUN)
            .zip(reached.par_chunks_mut(VERTEX_RUN))
            .enumerate()
            .map(run)
            .reduce(|| (usize::MAX, 0), combine)
    } else {
        tensors
            .chunks_mut(VERTEX_RUN)
            .zip(reached.chunks_mut(VERTEX_RUN))
            .enumerate()
            .map(run)
            .fold((usize::MAX, 0), combine)
    };
    if first_error != usize::MAX {
        let v = first_error;
        let c = source.closest_point(graph.point(v));
        return Err(c.and_then(|c| f(v, &c).err()).unwrap_or(Failure::Degenerate { vertex: v }));
    }
    Ok(merged)
}

/// Runs `one` on every `(index, tensor, flag)` of two parallel slices, on the rayon pool
/// when they are long, and reduces what it returns, `(error index or usize::MAX, count)`,
/// to the smallest error index and the sum of the counts: the same whatever the threads.
fn scan_pairs<F>(tensors: &mut [SizeTensor], flags: &mut [bool], one: F) -> (usize, usize)
where
    F: Fn(usize, &mut SizeTensor, &mut bool) -> (usize, usize) + Sync,
{
    let combine = |a: (usize, usize), b: (usize, usize)| (a.0.min(b.0), a.1 + b.1);
    if tensors.len() >= PARALLEL_MIN {
        tensors
            .par_iter_mut()
            .zip(flags.par_iter_mut())
            .enumerate()
            .with_min_len(1024)
            .map(|(i, (t, f))| one(i, t, f))
            .reduce(|| (usize::MAX, 0), combine)
    } else {
        tensors
            .iter_mut()
            .zip(flags.iter_mut())
            .enumerate()
            .map(|(i, (t, f))| one(i, t, f))
            .fold((usize::MAX, 0), combine)
    }
}

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
