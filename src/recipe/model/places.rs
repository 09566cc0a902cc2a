//! Where each item and key of a recipe was written, so that later errors point into the
//! file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::recipe::error::RecipeError;

/// Where an item or a key of the model was written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Place {
    /// Index into [`Places::files`].
    pub file: usize,
    /// 1-based line (0 when unknown).
    pub line: usize,
    /// The key as the file spells it (`MAXDISTANCE`, `max_distance`).
    pub key: String,
    /// The enclosing item as the file names it (`CREATE_ALGORITHMS entry 3`).
    pub context: String,
}

/// The places of a recipe's items and keys, by model path: `global.hmin`,
/// `regions.NAME`, `regions.NAME[i]`, `polylines.NAME`, `functions.NAME`,
/// `functions.NAME.FIELD`, `algorithms[i]`, `algorithms[i].FIELD`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Places {
    pub files: Vec<PathBuf>,
    pub by_path: BTreeMap<String, Place>,
}

impl Places {
    pub(crate) fn new(origin: &Path) -> Places {
        Places { files: vec![origin.to_path_buf()], by_path: BTreeMap::new() }
    }

    pub(crate) fn file_index(&mut self, path: &Path) -> usize {
        match self.files.iter().position(|p| p == path) {
            Some(i) => i,
            None => {
                self.files.push(path.to_path_buf());
                self.files.len() - 1
            }
        }
    }

    pub(crate) fn insert(
        &mut self,
        path: String,
        file: &Path,
        line: usize,
        key: &str,
        context: &str,
    ) {
        let file = self.file_index(file);
        self.by_path
            .insert(path, Place { file, line, key: key.to_string(), context: context.to_string() });
    }

    /// The place of `path`, or of its nearest enclosing item.
    pub(crate) fn find(&self, path: &str) -> Option<&Place> {
        let mut p = path;
        loop {
            if let Some(place) = self.by_path.get(p) {
                return Some(place);
            }
            let cut = p.rfind(['.', '['])?;
            p = &p[..cut];
        }
    }

    /// The file `path` was written in (or its nearest enclosing item), else the recipe's
    /// own file.
    pub(crate) fn file_of(&self, path: &str) -> Option<&Path> {
        match self.find(path) {
            Some(place) => self.files.get(place.file).map(PathBuf::as_path),
            None => self.files.first().map(PathBuf::as_path),
        }
    }

    /// The key as written at `path`, or `default`.
    pub(crate) fn key<'a>(&'a self, path: &str, default: &'a str) -> &'a str {
        self.by_path.get(path).map(|p| p.key.as_str()).unwrap_or(default)
    }

    /// `error`, placed at `path`.
    pub(crate) fn locate(&self, error: RecipeError, path: &str) -> RecipeError {
        match self.find(path) {
            Some(place) => {
                let e = error.at(&self.files[place.file], place.line);
                if place.context.is_empty() {
                    e
                } else {
                    e.within(place.context.clone())
                }
            }
            None => match self.files.first() {
                Some(f) => error.in_file(f),
                None => error,
            },
        }
    }
}
