//! The decisions of the loop, kept apart so that they are stated once and tested on
//! their own: which iteration's mesh is the best so far, when the loop has converged, and
//! how much one remeshing may grow the mesh.

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

/// The growth limit of one remeshing: the factor by which to scale the field's
/// complexity so that it asks for at most `max_growth` times the current `vertices`, or
/// `None` when the field asks for no more than that.
///
/// On a coarse mesh the recipe's field is sampled at few vertices and interpolated across
/// large triangles: a boundary layer or a shock smeared over them asks for far more
/// vertices than the field resolved on a fine mesh (GAMM A7: 92 000 on the 618-vertex
/// start, 17 000 at convergence). Remeshing to the field scaled down to `max_growth`
/// times the mesh keeps its shape — directions, ratios and relative sizes — at a
/// vertex count the next sizing resolves better; the loop grows the mesh by at most
/// `max_growth` per iteration until the field's own count is within reach. In dimension
/// d the complexity ∫√det M goes as s^(d/2) under a uniform scaling s·M (linear in 2D),
/// so the metric is multiplied by this factor to the power 2/d (the loop's driver does
/// it) and the scaled field asks for exactly `max_growth · vertices`.
pub fn growth_scale(expected: f64, vertices: usize, max_growth: Option<f64>) -> Option<f64> {
    let g = max_growth?;
    let limit = g * vertices.max(1) as f64;
    (expected.is_finite() && expected > limit).then(|| limit / expected)
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
            space: None,
        }
    }

    #[test]
    fn growth_is_limited_only_above_the_factor() {
        assert_eq!(growth_scale(4000.0, 1000, Some(4.0)), None);
        assert_eq!(growth_scale(8000.0, 1000, Some(4.0)), Some(0.5));
        assert_eq!(growth_scale(8000.0, 1000, None), None);
        assert_eq!(growth_scale(f64::NAN, 1000, Some(4.0)), None);
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
