//! Neighbour propagation from a source (thesis 2.2.5, 2.2.10.4–5, 4.3.6–4.3.7): every
//! mesh vertex near a source gets its closest point on the source — distance, segment,
//! foot point, parameter, curvilinear abscissa and side — starting at the source and
//! stopping past a maximum distance. This is the engine of distance to border, distance
//! to a vertex, distance between two boundaries and distance to an imaginary polyline.
//!
//! The parts, one concept each:
//!
//! - `source` and `builder`: a [`Source`] is a set of segments — polylines along mesh
//!   edges (topological curves), free polylines that may cross cells (a wake), single
//!   points — with the seed vertices a propagation starts from (for free pieces, the
//!   corners of every cell they touch, so that a coarse mesh is still marked);
//! - `window`: the polyline geometry of a closest point. A guess steps along the
//!   polyline while its foot is a segment end and the next segment is closer, then moves
//!   to the best segment of its *window* (thesis 4.3.6.3's march); the answer is then
//!   *certified* by the clearance of that segment or vertex (`Clearance`: how far out
//!   the window alone decides the closest point), or else found by an exact search — near
//!   the medial axis of a non-convex source, past a sharp corner, where another curve
//!   comes close;
//! - `breadth_first`: [`propagate`], by levels from the seeds, each vertex from its
//!   first evaluated neighbour's segment, stopping past the maximum distance;
//! - `vertex_order`: the same closest points in vertex order, for a step whose reach
//!   covers the whole mesh (no levels, no list of reached vertices).
//!
//! Invariants. Every closest point is the exact closest point on the discretised source
//! (ties: smaller segment id), equal bit for bit to [`closest_point_brute_force`],
//! whatever the order of evaluation, the guess or the number of threads: a guess and a
//! certificate change the work, never the answer. Reported are the seeds and the
//! vertices within the maximum distance, in breadth-first order.
//!
//! Cost: O(1) segment projections per vertex for the guess and the window, and O(1) for
//! a clearance certificate; a vertex beyond its clearance costs a box search, O(log m)
//! boxes for m segments. The clearances cost one bounded search per segment side
//! asked (O(m log m)); a polyline vertex's clearance comes from its two segments', with
//! a search of its own only where that falls short. Seeding free pieces scans the cells
//! once (O(cells), with a box test against the source first).

mod breadth_first;
mod builder;
mod source;
mod vertex_order;
mod window;

#[cfg(test)]
mod tests;

pub use breadth_first::{propagate, PropagationOptions, PropagationReport, Reach};
pub use builder::{SourceBuilder, SourceError};
pub use source::{
    closest_point_brute_force, ClosestPoint, PieceKind, Source, SourcePolyline, SourceSegment,
};
pub(crate) use vertex_order::{reach_covers_mesh, VertexOrder, VERTEX_RUN};
