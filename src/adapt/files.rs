//! The loop's results on disk: the best mesh, rewritten whenever a better one comes, and
//! `history.json`, rewritten after every iteration. Both are written to a temporary file
//! and renamed, the mesh before the history, so that the history never names a best
//! iteration whose mesh is not on disk, and a stopped run leaves whole files.

use std::path::{Path, PathBuf};

use smartmesh_formats::{write_all_atomically, write_path, Format, TaggedMesh, WriteOptions};

use super::Observer;
use crate::history::History;

/// Writes the best mesh to `mesh` and the history to `history`.
#[derive(Debug, Clone)]
pub struct ResultFiles {
    /// The output mesh (any writable format, chosen by its extension).
    pub mesh: PathBuf,
    /// The history file.
    pub history: PathBuf,
    /// Options of the mesh writer.
    pub options: WriteOptions,
    /// What the mesh format could not hold, once per message.
    pub dropped: Vec<String>,
}

impl ResultFiles {
    /// Results written to `mesh`, with the history at `history` or, when `None`, beside
    /// the mesh ([`default_history_path`]).
    pub fn new(mesh: &Path, history: Option<&Path>, options: WriteOptions) -> ResultFiles {
        ResultFiles {
            mesh: mesh.to_path_buf(),
            history: history.map_or_else(|| default_history_path(mesh), Path::to_path_buf),
            options,
            dropped: Vec::new(),
        }
    }
}

/// `DIR/NAME.history.json` for the output `DIR/NAME.EXT`: beside the mesh, and one per
/// output, so that runs on several geometry variants in one directory keep theirs.
pub fn default_history_path(mesh: &Path) -> PathBuf {
    let stem =
        mesh.file_stem().map_or_else(|| "adapt".to_string(), |s| s.to_string_lossy().into_owned());
    mesh.with_file_name(format!("{stem}.history.json"))
}

impl Observer for ResultFiles {
    fn record(
        &mut self,
        history: &History,
        new_best: Option<&TaggedMesh>,
    ) -> Result<(), smartmesh_formats::Error> {
        if let Some(mesh) = new_best {
            let report =
                write_path(&self.mesh, mesh, Format::from_path(&self.mesh), &self.options)?;
            for d in report.dropped {
                if !self.dropped.contains(&d) {
                    self.dropped.push(d);
                }
            }
        }
        write_all_atomically(&[(self.history.clone(), history.to_json().into_bytes())])
    }
}
