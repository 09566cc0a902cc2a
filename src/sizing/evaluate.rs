//! How the driver evaluates an algorithm's [`Work`]: the vertices it reaches and their
//! tensors handed to a [`Sink`], which keeps them as a [`Contribution`] ([`Collect`]) or
//! merges them into a field (the driver's sink in [`crate::sizing::field`]), in the order
//! of the reach or in vertex order.
//!
//! Determinism: tensors are built on the rayon pool for large reaches, each from its own
//! closest point, and committed in a fixed order; where a tensor fails, the error of the
//! first vertex in that order is returned, whatever the thread count.

use rayon::prelude::*;

use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use crate::sizing::algorithms::{
    Algorithm, Contribution, Failure, SizingAlgorithm, Tensor, Visit, Work,
};
use crate::sizing::propagation::{
    propagate, ClosestPoint, PropagationOptions, Reach, Source, VertexOrder, VERTEX_RUN,
};
use crate::topology::Topology;

/// Reaches smaller than this build their tensors on the calling thread.
const PARALLEL_MIN: usize = 4096;

/// Runs one algorithm of a plan on a mesh (thesis 4.3.6–4.3.7), handing its tensors to
/// `sink`.
pub(crate) fn run<S: Sink>(
    graph: &MeshGraph,
    topology: &Topology,
    algorithm: &Algorithm,
    sink: S,
) -> Result<S::Output, Failure> {
    algorithm.visit(Run { graph, topology, sink })
}

struct Run<'g, S> {
    graph: &'g MeshGraph,
    topology: &'g Topology,
    sink: S,
}

impl<S: Sink> Visit for Run<'_, S> {
    type Output = Result<S::Output, Failure>;

    fn visit<A: SizingAlgorithm>(self, algorithm: &A) -> Self::Output {
        let work = algorithm.work(self.graph, self.topology)?;
        evaluate(self.graph, work, &PropagationOptions::new(), self.sink)
    }
}

/// Evaluates `work` on `graph` into `sink`: a list as it is; one source by the sink's
/// choice ([`Sink::take_source`]); two sources by propagating from each, the vertices of
/// the first reach that the second reaches too.
pub(crate) fn evaluate<T: Tensor, S: Sink>(
    graph: &MeshGraph,
    work: Work<T>,
    options: &PropagationOptions,
    sink: S,
) -> Result<S::Output, Failure> {
    match work {
        Work::Listed(contribution) => sink.take_list(contribution),
        Work::FromSource { source, reach, tensor } => {
            let sources = std::slice::from_ref(&source);
            sink.take_source(graph, &source, reach, options, |v, c| {
                tensor.tensor(sources, v, std::slice::from_ref(c))
            })
        }
        Work::FromTwoSources { sources, reach, tensor } => {
            let first = propagate(graph, &sources[0], reach, options);
            let second = propagate(graph, &sources[1], reach, options);
            sink.take_reach(first, |v, c1| {
                let Some(c2) = second.get(v) else { return Ok(None) };
                tensor.tensor(&sources, v, &[*c1, c2])
            })
        }
    }
}

/// Where an algorithm's tensors go: one tensor per vertex it reaches, from the vertex's
/// closest point ([`Sink::take_reach`]), or one tensor on a list of vertices (UNIFORM,
/// [`Sink::take_list`]); the sink decides whether they are kept as a [`Contribution`]
/// or merged into a field at once.
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
