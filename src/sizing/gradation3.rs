//! Size gradation on a mesh in space: the fixed point of the 2D pass
//! ([`crate::sizing::gradation::propagate_bounds`], Alauzet's anisotropic gradation with
//! the exponential law) over the edges of a [`SpaceMesh`], each edge bounded by
//! [`gradate_edge3`]: T_q ⊆ g^ℓ T_p by intersection, so the anisotropy is kept.
//!
//! Only what differs from 2D lives here: the points in space and the 3D edge rule. The
//! worklist, its order (hence determinism) and its update guard are the shared driver's.

use crate::metric::{gradate_edge3, SizeTensor3};
use crate::sizing::gradation::{propagate_bounds, GradationReport};
use crate::sizing::space::SpaceMesh;

/// Runs the gradation pass on `tensors` (one per vertex of `mesh`) with gradation
/// `gradation` (>= 1).
pub(crate) fn apply_gradation3(
    mesh: &SpaceMesh<'_>,
    tensors: &mut [SizeTensor3],
    gradation: f64,
) -> GradationReport {
    let n = mesh.num_vertices().min(tensors.len());
    let points = mesh.points();
    propagate_bounds(
        n,
        |p| mesh.neighbours(p),
        tensors,
        |p, q, tp, tq| {
            let (xp, xq) = (points[p], points[q]);
            let edge = [xq[0] - xp[0], xq[1] - xp[1], xq[2] - xp[2]];
            gradate_edge3(tp, tq, edge, gradation)
        },
    )
}
