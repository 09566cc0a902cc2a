//! A recipe written to another folder (`recipe convert`): every relative `FILE` path (the
//! sheet of DISTANCE_TO_IMAGINARY_SURFACE) is read relative to the recipe file that wrote
//! it (`crate::recipe`'s sheet reader), so a copy in another folder must name the same
//! file from there. [`Recipe::rebase_files`] rewrites each one relative to the new
//! recipe's folder; to an absolute path when the recipe has no folder (standard output)
//! or when no relative path leads there (another drive on Windows). Absolute paths, and
//! paths of a recipe written back into the folder of the file that wrote the key, are
//! kept as written.
//!
//! Paths are data: the folders are made absolute and their symbolic links resolved by
//! the file system (`std::fs::canonicalize`, the sheet's own folder when it exists, so
//! that `..` means what the system means by it), then compared component by component;
//! nothing is given to a shell or a program. A folder that does not exist is made
//! absolute and cleaned of `.` and `..` by its text alone.

use std::path::{Component, Path, PathBuf};

use super::Recipe;

/// `path` without `.` components and with each `..` taking off the component before it
/// (at the root, `..` stays the root), by the text alone.
fn normalize(path: &Path) -> PathBuf {
    let mut out: Vec<Component<'_>> = Vec::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => match out.last() {
                Some(Component::Normal(_)) => {
                    out.pop();
                }
                Some(Component::RootDir | Component::Prefix(_)) => {}
                _ => out.push(c),
            },
            _ => out.push(c),
        }
    }
    out.iter().collect()
}

/// The folder `dir` (empty: the current one) absolute, with its links resolved when it
/// exists.
fn real_dir(dir: &Path) -> PathBuf {
    let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
    std::fs::canonicalize(dir).unwrap_or_else(|_| {
        normalize(&std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf()))
    })
}

/// The file `written` names from the absolute folder `from`, absolute.
fn locate(from: &Path, written: &Path) -> PathBuf {
    let joined = from.join(written);
    match (joined.parent(), joined.file_name()) {
        (Some(parent), Some(name)) => match std::fs::canonicalize(parent) {
            Ok(p) => p.join(name),
            Err(_) => normalize(&joined),
        },
        _ => normalize(&joined),
    }
}

/// The path of `target` from the folder `from`, both absolute and normalised: `..` for
/// each component of `from` past their common start, then the rest of `target`. `None`
/// when they start differently (another drive or share).
pub(crate) fn relative(from: &Path, target: &Path) -> Option<PathBuf> {
    let (a, b): (Vec<Component<'_>>, Vec<Component<'_>>) =
        (from.components().collect(), target.components().collect());
    let root = |c: &[Component<'_>]| {
        c.iter().take_while(|x| matches!(x, Component::Prefix(_) | Component::RootDir)).count()
    };
    let (ra, rb) = (root(&a), root(&b));
    if ra == 0 || a[..ra] != b[..rb] {
        return None;
    }
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..a.len() {
        out.push("..");
    }
    for c in &b[common..] {
        out.push(c);
    }
    if out.as_os_str().is_empty() {
        out.push(".");
    }
    Some(out)
}

/// `written` (read from a recipe in folder `from`) as a recipe in folder `to` must write
/// it (`None`: no folder, an absolute path).
fn rebase(written: &str, from: &Path, to: Option<&Path>) -> Result<String, String> {
    let given = Path::new(written);
    if written.is_empty() || given.is_absolute() {
        return Ok(written.to_string());
    }
    let from = real_dir(from);
    let target = locate(&from, given);
    let path = match to.map(real_dir) {
        Some(to) if to == from => return Ok(written.to_string()),
        Some(to) => relative(&to, &target).unwrap_or(target),
        None => target,
    };
    path.to_str()
        .map(str::to_string)
        .ok_or_else(|| format!("FILE \"{written}\": its path {} is not UTF-8 text", path.display()))
}

impl Recipe {
    /// Rewrites every relative `FILE` path so that it names the same file from a recipe
    /// written at `to` (`None`: written where it has no folder, as standard output; the
    /// paths become absolute). See the module header. An error names a path that is not
    /// UTF-8 text once rewritten.
    pub fn rebase_files(&mut self, to: Option<&Path>) -> Result<(), String> {
        let to_dir = to.map(|p| p.parent().unwrap_or(Path::new("")).to_path_buf());
        let mut bases: Vec<PathBuf> = Vec::new();
        for (i, a) in self.algorithms.iter_mut().enumerate() {
            for (field, _) in a.files_mut() {
                let at = format!("algorithms[{i}].{field}");
                let from = self.places.file_of(&at).and_then(Path::parent);
                bases.push(from.unwrap_or(Path::new("")).to_path_buf());
            }
        }
        let mut bases = bases.into_iter();
        for a in &mut self.algorithms {
            for (_, path) in a.files_mut() {
                let from = bases.next().unwrap_or_default();
                *path = rebase(path, &from, to_dir.as_deref())?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_climb_to_the_common_folder() {
        let r = |a: &str, b: &str| relative(Path::new(a), Path::new(b));
        assert_eq!(r("/w/b/c", "/w/a/wake.stl"), Some("../../a/wake.stl".into()));
        assert_eq!(r("/w/a", "/w/a/s/wake.stl"), Some("s/wake.stl".into()));
        assert_eq!(r("/", "/wake.stl"), Some("wake.stl".into()));
        assert_eq!(r("/w/a/s", "/w/a"), Some("..".into()));
        assert_eq!(r("/w", "/w"), Some(".".into()));
        assert_eq!(r("w", "/w"), None);
    }

    #[test]
    fn normalizing_is_by_the_text() {
        let n = |a: &str| normalize(Path::new(a));
        assert_eq!(n("/w/./a/../b/wake.stl"), PathBuf::from("/w/b/wake.stl"));
        assert_eq!(n("/../w"), PathBuf::from("/w"));
        assert_eq!(n("../w/.."), PathBuf::from(".."));
    }
}
