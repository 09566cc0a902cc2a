//! Size gradation on a mesh in space: the 2D pass's fixed point
//! ([`crate::sizing::gradation`], Alauzet's anisotropic gradation with the exponential
//! law) over the edges of a [`SpaceMesh`], each edge bounded by
//! [`gradate_edge3`]: T_q ⊆ g^ℓ T_p by intersection, so the anisotropy is kept.
//!
//! A FIFO worklist holding every vertex once, in index order; a vertex whose tensor
//! shrinks queues again. Sequential, so deterministic; stops after
//! [`MAX_UPDATES_PER_VERTEX`] × n updates and says so.

use std::collections::VecDeque;

use crate::metric::{gradate_edge3, SizeTensor3};
use crate::sizing::gradation::{GradationReport, MAX_UPDATES_PER_VERTEX};
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
    let mut report = GradationReport { converged: true, ..GradationReport::default() };
    let mut queued = vec![true; n];
    let mut changed = vec![false; n];
    let mut queue: VecDeque<u32> = (0..n as u32).collect();
    let max_updates = MAX_UPDATES_PER_VERTEX.saturating_mul(n).saturating_add(1024);
    while let Some(p) = queue.pop_front() {
        let p = p as usize;
        queued[p] = false;
        report.visits += 1;
        let tp = tensors[p];
        let xp = points[p];
        for &q in mesh.neighbours(p) {
            let q = q as usize;
            if q >= n {
                continue;
            }
            let xq = points[q];
            let edge = [xq[0] - xp[0], xq[1] - xp[1], xq[2] - xp[2]];
            let Some(t) = gradate_edge3(&tp, &tensors[q], edge, gradation) else { continue };
            tensors[q] = t;
            report.updates += 1;
            if !changed[q] {
                changed[q] = true;
                report.vertices_changed += 1;
            }
            if report.updates >= max_updates {
                report.converged = false;
                return report;
            }
            if !queued[q] {
                queued[q] = true;
                queue.push_back(q as u32);
            }
        }
    }
    report
}
