//! The loop's results on disk: the best mesh, rewritten whenever a better one comes, and
//! `history.json`, rewritten after every iteration. A new best mesh and the history that
//! names it are one set: every file is written whole to a temporary name first, and the
//! renames follow one another only once all are complete, so that a failed write leaves
//! the previous files and the history on disk names the best iteration of the mesh on disk. (Only a
//! kill between two of those renames, SIGKILL or a power cut, can separate them; a
//! Ctrl-C is handled by the caller between iterations, never during a write.) The history
//! records the size and CRC-32 of every file of the mesh it describes
//! ([`History::best_mesh`]), so that even then a reader tells a mesh the history does not
//! describe ([`History::mismatch`]) instead of taking one for the other.

use std::path::{Path, PathBuf};

use smartmesh_formats::{
    sync_files, write_all_atomically_synced, write_bytes, Error, ErrorKind, Format, PathSiblings,
    TaggedMesh, WriteOptions,
};

use super::Observer;
use crate::history::{History, WrittenFile};

/// Writes the best mesh to `mesh` and the history to `history`.
#[derive(Debug, Clone)]
pub struct ResultFiles {
    /// The output mesh (any writable format, chosen by its extension).
    pub mesh: PathBuf,
    /// The history file.
    pub history: PathBuf,
    /// The mesh's format (`--to`); `None`: chosen by the mesh's extension.
    pub format: Option<Format>,
    /// Options of the mesh writer.
    pub options: WriteOptions,
    /// What the mesh format could not hold, once per message.
    pub dropped: Vec<String>,
    /// The files of the best mesh as last written, which every history names.
    written: Vec<WrittenFile>,
    /// The paths of the best mesh's files as last written, synced once the loop stops.
    best_paths: Vec<PathBuf>,
}

impl ResultFiles {
    /// Results written to `mesh`, with the history at `history` or, when `None`, beside
    /// the mesh ([`default_history_path`]).
    pub fn new(mesh: &Path, history: Option<&Path>, options: WriteOptions) -> ResultFiles {
        ResultFiles {
            mesh: mesh.to_path_buf(),
            history: history.map_or_else(|| default_history_path(mesh), Path::to_path_buf),
            format: None,
            options,
            dropped: Vec::new(),
            written: Vec::new(),
            best_paths: Vec::new(),
        }
    }
}

impl ResultFiles {
    /// The same, the mesh written in `format` whatever its extension (`--to`).
    pub fn with_format(mut self, format: Format) -> ResultFiles {
        self.format = Some(format);
        self
    }
}

/// `DIR/NAME.history.json` for the output `DIR/NAME.EXT`: beside the mesh, and one per
/// output, so that runs on several geometry variants in one directory keep theirs.
pub fn default_history_path(mesh: &Path) -> PathBuf {
    let stem =
        mesh.file_stem().map_or_else(|| "adapt".to_string(), |s| s.to_string_lossy().into_owned());
    mesh.with_file_name(format!("{stem}.history.json"))
}

impl ResultFiles {
    /// The files of the case directory `self.mesh` for `mesh` (each polyMesh file, and
    /// the `system/` files it lacks), added to `targets` so that they are renamed into
    /// place with the history as one set, file by file as every other output; returns
    /// what the case could not hold. The directories are made first (empty ones are all
    /// a failed set can leave).
    fn case_targets(
        &self,
        mesh: &TaggedMesh,
        targets: &mut Vec<(PathBuf, Vec<u8>)>,
    ) -> Result<Vec<String>, Error> {
        let (files, report) =
            smartmesh_formats::openfoam::poly_mesh_files(mesh, &self.options.openfoam)
                .map_err(|e| e.with_path(&self.mesh))?;
        if self.mesh.exists() && !self.mesh.is_dir() {
            return Err(Error::new(ErrorKind::CannotWrite {
                format: Format::OpenFoam.name(),
                reason: "an OpenFOAM case is a directory, and this path is a file".into(),
            })
            .with_path(&self.mesh));
        }
        let poly = self.mesh.join("constant").join("polyMesh");
        let system = self.mesh.join("system");
        for dir in [&poly, &system] {
            std::fs::create_dir_all(dir)
                .map_err(|e| Error::new(ErrorKind::Unwritable(e)).with_path(dir))?;
        }
        for (name, bytes) in files {
            targets.push((poly.join(name), bytes));
        }
        for (name, bytes) in smartmesh_formats::openfoam::missing_system_files(&system) {
            targets.push((system.join(name), bytes));
        }
        Ok(report.dropped)
    }
}

impl Observer for ResultFiles {
    fn record(
        &mut self,
        history: &History,
        new_best: Option<&TaggedMesh>,
    ) -> Result<(), smartmesh_formats::Error> {
        let mut targets = Vec::new();
        if let Some(mesh) = new_best {
            let format =
                self.format.or_else(|| Format::from_path(&self.mesh)).ok_or_else(|| {
                    Error::new(ErrorKind::UnknownFormat(self.mesh.display().to_string()))
                })?;
            let dropped = if format == Format::OpenFoam {
                self.case_targets(mesh, &mut targets)?
            } else {
                let mut options = self.options.clone();
                options.main_name =
                    self.mesh.file_name().and_then(|n| n.to_str()).map(str::to_owned);
                let written =
                    write_bytes(format, mesh, &options).map_err(|e| e.with_path(&self.mesh))?;
                let siblings = PathSiblings::new(&self.mesh);
                targets.push((self.mesh.clone(), written.main));
                for (ext, bytes) in written.siblings {
                    targets.push((siblings.path(&ext), bytes));
                }
                written.report.dropped
            };
            for d in dropped {
                if !self.dropped.contains(&d) {
                    self.dropped.push(d);
                }
            }
        }
        let written: Vec<WrittenFile> = if new_best.is_some() {
            targets
                .iter()
                .map(|(path, bytes)| {
                    let name = path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default();
                    WrittenFile::of(&name, bytes)
                })
                .collect()
        } else {
            self.written.clone()
        };
        let mut described = history.clone();
        described.best_mesh = written.clone();
        // The history last: renamed after the mesh it names.
        targets.push((self.history.clone(), described.to_json().into_bytes()));
        // Rewritten after every iteration: only the last set, once the loop has stopped,
        // is synced to disk (the renames keep every set whole for readers and a kill).
        let last = history.stopped != crate::adapt::RUNNING;
        write_all_atomically_synced(&targets, false)?;
        if last {
            let mut paths: Vec<PathBuf> = if new_best.is_some() {
                targets.iter().map(|(p, _)| p.clone()).collect()
            } else {
                self.best_paths.clone()
            };
            paths.push(self.history.clone());
            sync_files(&paths)?;
        }
        // A set that failed left the previous files, which the previous record names.
        if new_best.is_some() {
            self.best_paths =
                targets.iter().map(|(p, _)| p.clone()).filter(|p| *p != self.history).collect();
        }
        self.written = written;
        Ok(())
    }
}
