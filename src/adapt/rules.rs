//! The two decisions of the loop, kept apart so that they are stated once and tested on
//! their own: which iteration's mesh is the best so far, and when the loop has converged.

use crate::history::IterationRecord;

/// Stopping tolerances (thesis 5.5 runs a fixed number of iterations; smartmesh stops
/// earlier when the mesh no longer changes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Largest relative change of the vertex count, |ΔV| / V, between two iterations.
    pub vertices: f64,
    /// Largest change of the share of conforming edges between two iterations.
    pub conformity: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances { vertices: 0.05, conformity: 0.02 }
    }
}

/// The changes between two records: relative vertex count, conforming share.
pub fn changes(previous: &IterationRecord, current: &IterationRecord) -> (f64, f64) {
    let dv = (current.vertices as f64 - previous.vertices as f64).abs()
        / (current.vertices.max(1) as f64);
    let dc = (current.conforming_share - previous.conforming_share).abs();
    (dv, dc)
}

/// Whether `current` is within the tolerances of `previous`.
pub fn converged(previous: &IterationRecord, current: &IterationRecord, tol: &Tolerances) -> bool {
    let (dv, dc) = changes(previous, current);
    dv <= tol.vertices && dc <= tol.conformity
}

/// The best mesh is the one with the highest share of conforming edges (measured against
/// the recipe's field on that mesh); a tie goes to the later iteration, which has been
/// through more adaptation. Returns whether `candidate` replaces `best`.
pub fn is_better(candidate: &IterationRecord, best: &IterationRecord) -> bool {
    candidate.conforming_share >= best.conforming_share
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::history::PhaseTimes;

    fn rec(iteration: usize, vertices: usize, share: f64) -> IterationRecord {
        IterationRecord {
            iteration,
            vertices,
            triangles: 2 * vertices,
            conforming_share: share,
            mean_edge_length: 1.0,
            mean_quality: 0.8,
            min_quality: 0.1,
            seconds: PhaseTimes::default(),
            remeshing: None,
            solver: None,
        }
    }

    #[test]
    fn ties_go_to_the_later_iteration() {
        assert!(is_better(&rec(2, 100, 0.5), &rec(1, 90, 0.5)));
        assert!(is_better(&rec(2, 100, 0.6), &rec(1, 90, 0.5)));
        assert!(!is_better(&rec(2, 100, 0.49), &rec(1, 90, 0.5)));
    }

    #[test]
    fn convergence_needs_both_figures_stable() {
        let t = Tolerances { vertices: 0.05, conformity: 0.02 };
        assert!(converged(&rec(1, 1000, 0.70), &rec(2, 1040, 0.71), &t));
        assert!(!converged(&rec(1, 1000, 0.70), &rec(2, 1100, 0.71), &t), "10% more vertices");
        assert!(
            !converged(&rec(1, 1000, 0.70), &rec(2, 1000, 0.75), &t),
            "conformity moved by 0.05"
        );
        // Relative to the current count: 1000 → 950 is 5.3%.
        assert!(!converged(&rec(1, 1000, 0.70), &rec(2, 950, 0.70), &t));
    }
}
