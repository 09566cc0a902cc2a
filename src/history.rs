//! The convergence history of an adaptation run (`history.json`): what `smartmesh adapt`
//! writes after every iteration and `smartmesh report --history` draws.
//!
//! One record per iteration, in order; iteration 0 is the starting mesh measured against
//! the recipe's first field. The file is rewritten whole (atomically) after each
//! iteration, so that a run stopped half-way still leaves a readable history. Each record
//! after the first also says what the remeshing that made its mesh was asked for and did
//! ([`RemeshingRecord`]).

use serde::{Deserialize, Serialize};

use crate::remesh::RemeshCounts;

/// Seconds spent in each phase of one iteration.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PhaseTimes {
    /// Computing the size field of the recipe on the current mesh.
    pub size: f64,
    /// Remeshing (native remesher or external adapter).
    pub remesh: f64,
    /// Measuring conformity and quality.
    pub measure: f64,
}

/// The state of the mesh after one iteration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IterationRecord {
    /// 0 for the starting mesh, then 1, 2, …
    pub iteration: usize,
    /// Mesh vertices.
    pub vertices: usize,
    /// Mesh triangles.
    pub triangles: usize,
    /// Share of edges with metric length in [1/√2, √2] against the field the recipe gives
    /// on this mesh.
    pub conforming_share: f64,
    /// Mean metric edge length.
    pub mean_edge_length: f64,
    /// Mean metric triangle quality.
    pub mean_quality: f64,
    /// Smallest metric triangle quality.
    pub min_quality: f64,
    /// Time per phase.
    pub seconds: PhaseTimes,
    /// The remeshing that made this mesh (none for iteration 0, the starting mesh).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub remeshing: Option<RemeshingRecord>,
    /// The solver run on this mesh (`adapt --solver`), and the metric made from its
    /// solution.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<SolverRecord>,
    /// For a mesh in space (tetrahedra, or a surface through mmgs): the UGAWG measures of
    /// its cells against the 3D field ([`crate::conformity::Ugawg`]); absent for a planar
    /// mesh. `triangles` then counts the boundary (or surface) triangles, and
    /// `conforming_share`, `mean_edge_length`, `mean_quality` and `min_quality` are these
    /// cells' (the mean ratio of each tetrahedron in the Log-Euclidean mean of its
    /// corners' metrics).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub space: Option<SpaceRecord>,
}

/// The UGAWG measures of a mesh in space against its 3D field, as published in the
/// UGAWG's tables: what `info --metric` prints for a 3D mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpaceRecord {
    /// The cells measured: `tetrahedron`, or `triangle` for a surface in space.
    pub cell: String,
    /// Cells measured.
    pub cells: usize,
    /// Edges measured (each undirected edge of the cells once).
    pub edges: usize,
    /// Shortest and longest metric edge length.
    pub edge_length_range: [f64; 2],
    /// Geometric mean of the positive metric edge lengths (refine's "mean").
    pub geometric_mean_edge_length: f64,
    /// Geometric mean of the positive qualities (refine's "mean").
    pub geometric_mean_quality: f64,
    /// Cells of quality 0 or less (flat or inverted).
    pub non_positive: usize,
}

/// What the solver of the loop did on one mesh, and what its solution's metric asked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolverRecord {
    /// The solver's wall-clock seconds.
    pub seconds: f64,
    /// The solution fields taken, comma-separated (as `--field` takes them).
    pub field: String,
    /// The solution fields, in the order their metrics were intersected.
    #[serde(default)]
    pub fields: Vec<String>,
    /// The vertex count asked of the solution's metric at this iteration (the schedule's
    /// value; absent for an error target).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub complexity_asked: Option<f64>,
    /// The vertex count the whole field on this mesh (recipe and solution, clamped and
    /// graded) asks for: what the next remeshing is asked to make.
    pub complexity_obtained: f64,
}

/// What one remeshing of the loop was asked for and did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RemeshingRecord {
    /// The vertices the previous iteration's field asked for, its complexity
    /// ([`crate::metric_field::expected_vertices`]), checked against the vertex limit before the
    /// remesher ran.
    pub expected_vertices: f64,
    /// The vertices the remesher was asked for when the field was scaled down to limit the
    /// growth of one iteration ([`crate::adapt::rules::growth_scale`]); absent when the
    /// field was given as it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub growth_limited_to: Option<f64>,
    /// The remesher's passes and per-pass counts of splits, collapses, swaps and moves
    /// (the native remesher; external tools report none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub remesher: Option<RemeshCounts>,
}

/// The whole history of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct History {
    /// The input (a `.poly` or a mesh), as given on the command line.
    pub input: String,
    /// The recipe, as given on the command line.
    pub recipe: String,
    /// The remesher: `native`, `mmg2d` or `gmsh`.
    pub adapter: String,
    /// Whether the stopping tolerances were met (false when the run stopped at the
    /// iteration limit or on an error).
    pub converged: bool,
    /// The iteration whose mesh was written as the result.
    pub best_iteration: usize,
    /// Why the run stopped, in words.
    pub stopped: String,
    /// One record per iteration, in order.
    pub iterations: Vec<IterationRecord>,
    /// The files of the mesh of `best_iteration` as they were written (name, size,
    /// CRC-32): the history and the mesh are two files renamed one after the other, and a
    /// run killed between the two renames leaves a new mesh beside the previous history.
    /// With these a reader tells whether the mesh it has is the one described
    /// ([`History::mismatch`]). Empty when the mesh went to stdout.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub best_mesh: Vec<WrittenFile>,
    /// The recipe's LAYER skin, inserted into the best mesh once the loop stopped: the
    /// mesh written (and `best_mesh`) is then the skinned one, whose counts are here
    /// (the best iteration's record keeps the loop's mesh). Absent without a skin.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<LayerRecord>,
    /// The vertex budget the field was normalised to on every mesh (`--complexity`, or
    /// the recipe's own complexity with a solver); absent without one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub budget: Option<BudgetRecord>,
}

/// The vertex budget of a run ([`crate::adapt::budget`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BudgetRecord {
    /// The vertex count asked of the final mesh.
    pub vertices: f64,
    /// Where it came from, in words.
    pub from: String,
    /// Per iteration: the vertex count the field on that mesh was normalised to (the
    /// schedule's value, corrected by the ratio of vertices made to vertices asked of the
    /// previous remeshing).
    pub normalised_to: Vec<f64>,
}

/// The skin inserted into the best mesh, and the counts of the mesh written with it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct LayerRecord {
    /// Layers of quads.
    pub layers: usize,
    /// Columns of the skin.
    pub columns: usize,
    /// Columns thinned below their nominal thickness.
    pub thinned_columns: usize,
    /// Points of the mesh written.
    pub vertices: usize,
    /// Its triangles.
    pub triangles: usize,
    /// Its quads.
    pub quads: usize,
}

/// One file as it was written: enough to recognise it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct WrittenFile {
    /// Its file name (no directory: the mesh may be read from elsewhere).
    pub name: String,
    /// Its size in bytes.
    pub bytes: u64,
    /// The CRC-32 (IEEE) of its bytes, 8 hexadecimal digits.
    pub crc32: String,
}

impl WrittenFile {
    /// The record of `bytes` written as the file `name`.
    pub fn of(name: &str, bytes: &[u8]) -> WrittenFile {
        WrittenFile {
            name: name.to_string(),
            bytes: bytes.len() as u64,
            crc32: format!("{:08x}", crc32fast::hash(bytes)),
        }
    }
}

impl History {
    /// Reads a history from JSON text; the error says what serde found and where.
    pub fn from_json(text: &str) -> Result<History, serde_json::Error> {
        serde_json::from_str(text)
    }

    /// Why the mesh file at `mesh` is not the mesh of the best iteration this history
    /// describes, or `None` when it is. The file is recognised by its size and CRC-32,
    /// whatever its name (a result copied or renamed is still the one described, and
    /// another run's history does not pass for this mesh's because its file had the same
    /// name). `None` also when the history has no record to compare with (its mesh went to
    /// stdout, or it predates the record) or the file cannot be read.
    pub fn mismatch(&self, mesh: &std::path::Path) -> Option<String> {
        if self.best_mesh.is_empty() {
            return None;
        }
        let bytes = std::fs::read(mesh).ok()?;
        let found = WrittenFile::of("", &bytes);
        let same = |f: &WrittenFile| f.bytes == found.bytes && f.crc32 == found.crc32;
        if self.best_mesh.iter().any(same) {
            return None;
        }
        let name = mesh.file_name().map(|n| n.to_string_lossy()).unwrap_or_default();
        let recorded = self.best_mesh.iter().find(|f| f.name == name).unwrap_or(&self.best_mesh[0]);
        let why = if recorded.name == name {
            "the run was stopped between writing the two, or the file was changed since"
        } else {
            "another run's history, or a file changed since"
        };
        Some(format!(
            "{} is not the mesh this history describes as iteration {} ({}: {} bytes, CRC-32 {}; the file has {} bytes, CRC-32 {}): {why}",
            mesh.display(),
            self.best_iteration,
            recorded.name,
            recorded.bytes,
            recorded.crc32,
            found.bytes,
            found.crc32
        ))
    }

    /// The vertices and triangles of the mesh written: the skinned mesh's when a skin was
    /// inserted, else the best iteration's.
    pub fn written_counts(&self) -> Option<(usize, usize)> {
        if let Some(l) = &self.layer {
            return Some((l.vertices, l.triangles));
        }
        let best =
            self.iterations.get(self.best_iteration.min(self.iterations.len().checked_sub(1)?))?;
        Some((best.vertices, best.triangles))
    }

    /// The history as pretty-printed JSON with a final newline.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a History always serialises");
        s.push('\n');
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_through_json() {
        let h = History {
            input: "a.poly".into(),
            recipe: "r.toml".into(),
            adapter: "native".into(),
            converged: true,
            best_iteration: 1,
            stopped: "vertex count and conformity stable".into(),
            layer: None,
            budget: None,
            iterations: vec![IterationRecord {
                iteration: 0,
                vertices: 10,
                triangles: 12,
                conforming_share: 0.5,
                mean_edge_length: 1.3,
                mean_quality: 0.7,
                min_quality: 0.1,
                seconds: PhaseTimes { size: 0.01, remesh: 0.0, measure: 0.001 },
                remeshing: Some(RemeshingRecord {
                    expected_vertices: 11.5,
                    growth_limited_to: None,
                    remesher: Some(RemeshCounts { passes: 2, splits: 3, ..Default::default() }),
                }),
                solver: Some(SolverRecord {
                    seconds: 0.25,
                    field: "u".into(),
                    fields: vec!["u".into()],
                    complexity_asked: Some(500.0),
                    complexity_obtained: 612.5,
                }),
                space: Some(SpaceRecord {
                    cell: "tetrahedron".into(),
                    cells: 30,
                    edges: 50,
                    edge_length_range: [0.4, 1.9],
                    geometric_mean_edge_length: 0.95,
                    geometric_mean_quality: 0.6,
                    non_positive: 0,
                }),
            }],
            best_mesh: vec![WrittenFile::of("a.msh", b"123456789")],
        };
        assert_eq!(History::from_json(&h.to_json()).unwrap(), h);
        // The CRC-32 check value of the IEEE polynomial.
        assert_eq!(h.best_mesh[0].crc32, "cbf43926");
        assert!(History::from_json("{\"input\": 3}").is_err());
        // Seconds are arbitrary floats: each must come back exactly (serde_json's default
        // parser read 1.3374001039999999 back as 1.337400104).
        let mut odd = h.clone();
        odd.iterations[0].seconds.size = 1.3374001039999999;
        assert_eq!(History::from_json(&odd.to_json()).unwrap(), odd);
    }

    #[test]
    fn a_mesh_is_recognised_by_its_bytes_whatever_its_name() {
        let dir = tempfile::tempdir().unwrap();
        let h = |name: &str, bytes: &[u8]| History {
            input: "a.poly".into(),
            recipe: "r.toml".into(),
            adapter: "native".into(),
            converged: true,
            best_iteration: 2,
            stopped: String::new(),
            iterations: Vec::new(),
            best_mesh: vec![WrittenFile::of(name, bytes)],
            layer: None,
            budget: None,
        };
        let mesh = dir.path().join("b.msh");
        std::fs::write(&mesh, b"this mesh").unwrap();
        // The history of this very file, under its name or another (a renamed copy).
        assert_eq!(h("b.msh", b"this mesh").mismatch(&mesh), None);
        assert_eq!(h("a.msh", b"this mesh").mismatch(&mesh), None);
        // Another run's history, whatever the name it records.
        let m = h("a.msh", b"another mesh").mismatch(&mesh).expect("another run's history");
        assert!(m.contains("a.msh: 12 bytes") && m.contains("the file has 9 bytes"), "{m}");
        assert!(h("b.msh", b"another mesh").mismatch(&mesh).is_some());
        // Nothing recorded: nothing to compare with.
        let mut none = h("b.msh", b"");
        none.best_mesh.clear();
        assert_eq!(none.mismatch(&mesh), None);
    }
}
