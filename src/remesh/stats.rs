//! What a run did: per-pass counts of each operator, seconds per phase, the sizes and the
//! conformity of input and output. [`RemeshCounts`] is the part the adaptation loop keeps
//! in `history.json` for every iteration.

use serde::{Deserialize, Serialize};

use crate::conformity::Conformity;

/// What one pass did.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PassStats {
    /// Edges split.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
    /// Diagonals flipped.
    pub swaps: usize,
    /// Vertices moved.
    pub moves: usize,
    /// Triangles at the end of the pass.
    pub triangles: usize,
}

/// Seconds spent in each phase.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PhaseSeconds {
    /// Reading the input: constraints, pieces, background index.
    pub setup: f64,
    /// Splitting.
    pub split: f64,
    /// Collapsing.
    pub collapse: f64,
    /// Swapping.
    pub swap: f64,
    /// Smoothing.
    pub smooth: f64,
    /// Building the output mesh and measuring it.
    pub output: f64,
}

/// What a run did and how the result conforms.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RemeshStats {
    /// Passes run.
    pub passes: usize,
    /// Edges split, in all.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
    /// Diagonals flipped.
    pub swaps: usize,
    /// Vertices moved.
    pub moves: usize,
    /// Each pass.
    pub per_pass: Vec<PassStats>,
    /// Seconds per phase.
    pub seconds: PhaseSeconds,
    /// Input vertices and triangles.
    pub input: [usize; 2],
    /// Output vertices and triangles.
    pub output: [usize; 2],
    /// Conformity of the input mesh to the metric.
    pub initial: Option<Conformity>,
    /// Conformity of the output mesh to its metric.
    pub conformity: Option<Conformity>,
    /// What the output does not carry.
    pub warnings: Vec<String>,
    /// When the mesh was remeshed part by part (`super::parallel`): each pass's parts
    /// and times. Empty for the serial remesher.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub partitioned: Vec<PartitionedPass>,
}

/// One pass of the partitioned remesher: how long each part took and how long the
/// driver's own work (cutting, gluing) took, in wall seconds, so that a run can tell how
/// much of it ran in parallel.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct PartitionedPass {
    /// Wall seconds of each part's remeshing, in part order.
    pub part_seconds: Vec<f64>,
    /// Wall seconds of the pass outside the parts (one thread).
    pub driver_seconds: f64,
    /// Wall seconds of the whole pass.
    pub seconds: f64,
}

/// What the operators did in a run, without the measures: what `history.json` records
/// for each remeshing (the external tools report none).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RemeshCounts {
    /// Passes run.
    pub passes: usize,
    /// Edges split, in all.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
    /// Diagonals flipped.
    pub swaps: usize,
    /// Vertices moved.
    pub moves: usize,
    /// Each pass.
    pub per_pass: Vec<PassStats>,
    /// Seconds per phase.
    pub seconds: PhaseSeconds,
}

impl RemeshStats {
    /// The record of a run about to start on `input` vertices and triangles: no pass,
    /// no operation, no output yet.
    pub(crate) fn starting(
        input: [usize; 2],
        initial: Option<Conformity>,
        warnings: Vec<String>,
    ) -> Self {
        RemeshStats {
            passes: 0,
            splits: 0,
            collapses: 0,
            swaps: 0,
            moves: 0,
            per_pass: Vec::new(),
            seconds: PhaseSeconds::default(),
            input,
            output: [0, 0],
            initial,
            conformity: None,
            warnings,
            partitioned: Vec::new(),
        }
    }

    /// The operators' counts and times.
    pub fn counts(&self) -> RemeshCounts {
        RemeshCounts {
            passes: self.passes,
            splits: self.splits,
            collapses: self.collapses,
            swaps: self.swaps,
            moves: self.moves,
            per_pass: self.per_pass.clone(),
            seconds: self.seconds.clone(),
        }
    }
}
