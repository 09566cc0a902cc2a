//! The loop's skeleton, one for both dimensions: measure the starting mesh, then remesh
//! the current mesh to its field, measure the new one, keep the best, and stop by the
//! rules of [`super::rules`] — interrupted, a vertex limit, a failing phase, converged or
//! the iteration limit — handing every record and every new best mesh to the
//! [`Observer`] as it goes.
//!
//! What differs between the planar loop ([`super::run_with_solver`]) and the loop in
//! space ([`super::space`]) is behind [`Stepper`]: how a mesh is sized and measured (a
//! 2D field, the solver, the budget; a 3D field and the UGAWG measures), how it is
//! remeshed (`Adapter::adapt` with its topology; `Adapter::adapt_space`), the dimension
//! the complexity scales with, and what is kept of the best iteration. The decisions —
//! which mesh is best, when the loop has converged, how far one remeshing may grow the
//! mesh, when it is refused — are taken here once.

use std::time::Instant;

use smartmesh_formats::TaggedMesh;

use super::{rules, AdaptError, Observer, Phase, PhaseError, INTERRUPTED, RUNNING};
use crate::adapters::{Adapted, AdapterError};
use crate::history::{History, IterationRecord, RemeshingRecord};
use crate::metric::complexity::exceeds;

/// One dimension's half of the loop: sizing, measuring and remeshing a mesh.
pub(crate) trait Stepper {
    /// A mesh sized and measured: the current one, and the next.
    type State;
    /// What is kept of the best iteration besides its mesh (the 2D field, for the LAYER
    /// step).
    type Best;

    /// The dimension of the metric: a uniform scaling s of the metric scales the
    /// complexity by s^(d/2).
    fn dimension(&self) -> u8;

    /// Sizes and measures `mesh` as iteration `iteration`; `seconds` is the time spent
    /// remeshing it, `remeshing` what that remeshing was asked for.
    fn measure(
        &mut self,
        iteration: usize,
        mesh: TaggedMesh,
        seconds: f64,
        remeshing: Option<RemeshingRecord>,
        observer: &mut dyn Observer,
    ) -> Result<Self::State, (Phase, PhaseError)>;

    /// Remeshes the mesh of `state` to its field, scaled by `scale` when given.
    fn remesh(&self, state: &Self::State, scale: Option<f64>) -> Result<Adapted, AdapterError>;

    /// The vertex count the field of `state` asks for (its complexity).
    fn expected(&self, state: &Self::State) -> f64;

    /// The record of `state`.
    fn record<'a>(&self, state: &'a Self::State) -> &'a IterationRecord;

    /// The mesh of `state`.
    fn mesh<'a>(&self, state: &'a Self::State) -> &'a TaggedMesh;

    /// The sizing warnings on `state`'s mesh.
    fn warnings<'a>(&self, state: &'a Self::State) -> &'a [String];

    /// What is kept of `state` when it becomes the best.
    fn best(&self, state: &Self::State) -> Self::Best;

    /// A remeshing of iteration `iteration` made `made` vertices of the `expected` asked,
    /// the field scaled when `scaled`; `history` may note it.
    fn remeshed(
        &mut self,
        _iteration: usize,
        _made: usize,
        _expected: f64,
        _scaled: bool,
        _history: &mut History,
    ) {
    }

    /// Whether the mesh of `record` is on the vertex budget; `None`: no budget.
    fn on_budget(&self, _record: &IterationRecord) -> Option<bool> {
        None
    }
}

/// What the loop left: the history as last handed on, the best mesh and what was kept of
/// it, the failure that stopped it early, and the sizing warnings.
pub(crate) struct Driven<B> {
    pub history: History,
    pub best: TaggedMesh,
    pub best_kept: B,
    pub failure: Option<AdaptError>,
    pub warnings: Vec<String>,
}

/// The factor on the metric that brings a field of complexity `expected` down to
/// `max_growth` times `vertices` in dimension `d`, or `None` when it asks for no more
/// ([`rules::growth_scale`] gives the factor on the complexity).
fn metric_scale(expected: f64, vertices: usize, max_growth: Option<f64>, d: u8) -> Option<f64> {
    rules::growth_scale(expected, vertices, max_growth).map(|s| s.powf(2.0 / f64::from(d)))
}

/// Runs the loop from `start` with `stepper`; `history` names the input, the recipe and
/// the adapter (its iterations are filled here).
pub(crate) fn drive<S: Stepper>(
    stepper: &mut S,
    start: TaggedMesh,
    mut history: History,
    options: &super::AdaptOptions,
    observer: &mut dyn Observer,
) -> Result<Driven<S::Best>, AdaptError> {
    let first = stepper.measure(0, start, 0.0, None, observer).map_err(|(phase, source)| {
        if source.is_interrupted() || (phase == Phase::Solve && observer.interrupted()) {
            AdaptError::Interrupted { phase }
        } else {
            AdaptError::Start { phase, source }
        }
    })?;
    history.converged = false;
    history.best_iteration = 0;
    history.stopped = RUNNING.to_string();
    history.iterations = vec![stepper.record(&first).clone()];
    observer.record(&history, Some(stepper.mesh(&first)))?;
    let mut warnings = Vec::new();
    note_warnings(&mut warnings, stepper.record(&first).iteration, stepper.warnings(&first));
    let mut best = stepper.mesh(&first).clone();
    let mut best_kept = stepper.best(&first);
    let mut current = first;
    let mut failure = None;
    let mut stopped = format!("iteration limit ({}) reached", options.max_iterations);

    for k in 1..=options.max_iterations {
        if observer.interrupted() {
            stopped = INTERRUPTED.to_string();
            break;
        }
        let expected = stepper.expected(&current);
        if let Some(limit) = options.max_vertices {
            if exceeds(expected, limit) {
                let e = AdaptError::TooManyVertices { iteration: k, estimate: expected, limit };
                stopped = e.to_string();
                failure = Some(e);
                break;
            }
        }
        let vertices = stepper.mesh(&current).points.len();
        let complexity_scale = rules::growth_scale(expected, vertices, options.max_growth);
        let scale = metric_scale(expected, vertices, options.max_growth, stepper.dimension());
        observer.phase(k, Phase::Remesh);
        let t = Instant::now();
        let remeshed = stepper.remesh(&current, scale);
        if observer.interrupted() {
            stopped = INTERRUPTED.to_string();
            break;
        }
        let next = remeshed.map_err(|e| (Phase::Remesh, PhaseError::from(e))).and_then(|adapted| {
            let remeshing = RemeshingRecord {
                expected_vertices: expected,
                growth_limited_to: complexity_scale.map(|s| s * expected),
                remesher: adapted.stats,
            };
            let seconds = t.elapsed().as_secs_f64();
            let made = adapted.mesh.points.len();
            stepper.remeshed(k, made, expected, scale.is_some(), &mut history);
            stepper.measure(k, adapted.mesh, seconds, Some(remeshing), observer)
        });
        let next = match next {
            Ok(n) => n,
            // A solver stopped by the interruption (or failing under it) is no failure of
            // the run: the iteration is discarded, as a remeshing under way is. A sizing
            // error is the input's, and is said whatever the user pressed.
            Err((phase, source))
                if source.is_interrupted() || (phase == Phase::Solve && observer.interrupted()) =>
            {
                stopped = INTERRUPTED.to_string();
                break;
            }
            Err((phase, source)) => {
                let e = AdaptError::Iteration { iteration: k, phase, source };
                stopped = e.to_string();
                failure = Some(e);
                break;
            }
        };
        let record = stepper.record(&next).clone();
        note_warnings(&mut warnings, record.iteration, stepper.warnings(&next));
        history.iterations.push(record.clone());
        // With a budget a mesh on it beats one off it; otherwise the more conforming wins.
        let best_so_far = &history.iterations[history.best_iteration];
        let new_best = match (stepper.on_budget(&record), stepper.on_budget(best_so_far)) {
            (Some(a), Some(b)) if a != b => a,
            _ => rules::is_better(&record, best_so_far),
        };
        if new_best {
            history.best_iteration = k;
            best = stepper.mesh(&next).clone();
            best_kept = stepper.best(&next);
        }
        observer.record(&history, new_best.then_some(stepper.mesh(&next)))?;
        // With a budget the loop has not converged while the mesh is off it: the next
        // field, corrected by the remesher's ratio, brings it there. An iteration
        // remeshed to a scaled field answered another field: never the one stopped at.
        let previous = stepper.record(&current);
        if scale.is_none()
            && stepper.on_budget(&record) != Some(false)
            && rules::converged(previous, &record, &options.tolerances)
        {
            let (dv, dc) = rules::changes(previous, &record);
            history.converged = true;
            stopped = format!(
                "converged at iteration {k}: vertex count changed by {:.2}% (tolerance {:.2}%), conforming share by {:.4} (tolerance {:.4})",
                100.0 * dv,
                100.0 * options.tolerances.vertices,
                dc,
                options.tolerances.conformity
            );
            break;
        }
        current = next;
    }
    history.stopped = stopped;
    observer.record(&history, None)?;
    Ok(Driven { history, best, best_kept, failure, warnings })
}

/// Adds the sizing warnings `new` of iteration `iteration` that `all` does not hold yet.
fn note_warnings(all: &mut Vec<String>, iteration: usize, new: &[String]) {
    for w in new {
        if !all.iter().any(|a| a.ends_with(w.as_str())) {
            all.push(format!("iteration {iteration}: {w}"));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_metric_scale_gives_the_growth_in_each_dimension() {
        // 2D: the complexity is linear in s; 3D: it goes as s^(3/2).
        assert_eq!(metric_scale(8000.0, 1000, Some(4.0), 2), Some(0.5));
        let s = metric_scale(8000.0, 1000, Some(4.0), 3).unwrap();
        assert!((s.powf(1.5) - 0.5).abs() < 1e-15, "{s}");
        assert_eq!(metric_scale(4000.0, 1000, Some(4.0), 3), None);
    }
}
