//! Output files written as a set, all or nothing: every file goes to a temporary file
//! beside its target, and the targets are replaced only once every temporary is written
//! and flushed to disk.
//!
//! What a user of `cp`, Gmsh or Triangle expects of an output path, and so what happens:
//! - a symbolic link is written through: the file it points to (followed to the end of
//!   a chain of links) is replaced, the link stays;
//! - an existing file keeps its permission bits (and, when allowed, its owner and group);
//!   a new file gets the usual `0666` less the umask;
//! - a read-only file (no write permission bit) is refused, and so is a directory: the
//!   user named something that should not be replaced (exit status 2 in the CLI);
//! - a target that exists and is neither a regular file nor a directory (`/dev/null`,
//!   a named pipe) is written directly, after every regular file of the set is in place:
//!   it cannot be renamed onto.
//!
//! Temporary files are created exclusively (`O_EXCL` with a random name, by the `tempfile`
//! crate), so a file or link planted under a predictable name is never followed; they
//! are synced before the renames and removed when anything fails. Their names say whose
//! they are, `.NAME.smartmesh-PID.RANDOM.tmp`: a process killed before it could remove
//! its own (SIGKILL, a power cut) leaves them behind, and the next write into that
//! directory removes those of processes that are gone — only regular files of that exact
//! pattern, owned by the writing user, whose PID no longer runs (Unix; elsewhere nothing
//! is removed).

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use tempfile::NamedTempFile;

use crate::error::{Error, ErrorKind, Result};

/// Links followed before giving up, as the kernel's `ELOOP` limit.
const MAX_LINKS: usize = 40;

/// Where a target's bytes go.
enum Destination {
    /// A regular file (existing or not), replaced by renaming a temporary onto it.
    Replace {
        /// The path renamed onto (the end of the chain of links).
        path: PathBuf,
        /// The existing file's metadata, whose permissions and owner the new file keeps.
        existing: Option<std::fs::Metadata>,
    },
    /// A device or pipe, written in place.
    Stream(PathBuf),
}

/// Follows `path` through symbolic links to the path that is finally named (which need
/// not exist: a dangling link names the file it would create).
fn follow_links(path: &Path) -> Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p).map_err(|e| unwritable(e, &p))?;
                p = match p.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(Error::new(ErrorKind::Unwritable(std::io::Error::other(format!(
        "more than {MAX_LINKS} symbolic links to follow"
    ))))
    .with_path(path))
}

/// An I/O error while writing: a path that cannot be written where it was named (a
/// missing directory, no permission, a read-only file system) is the user's to fix
/// ([`ErrorKind::Unwritable`]); anything else (a full disk, a failing device) is the
/// work failing ([`ErrorKind::Io`]).
fn write_error(e: std::io::Error) -> Error {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::NotFound
        | K::PermissionDenied
        | K::NotADirectory
        | K::ReadOnlyFilesystem
        | K::IsADirectory
        | K::InvalidFilename => Error::new(ErrorKind::Unwritable(e)),
        _ => Error::from(e),
    }
}

fn unwritable(e: std::io::Error, path: &Path) -> Error {
    Error::new(ErrorKind::Unwritable(e)).with_path(path)
}

/// Decides where `target`'s bytes go, refusing what must not be replaced.
fn destination(target: &Path) -> Result<Destination> {
    let path = follow_links(target)?;
    match std::fs::metadata(&path) {
        Ok(m) if m.is_dir() => Err(unwritable(std::io::Error::other("it is a directory"), target)),
        Ok(m) if m.is_file() => {
            if m.permissions().readonly() {
                return Err(Error::new(ErrorKind::ReadOnly).with_path(target));
            }
            Ok(Destination::Replace { path, existing: Some(m) })
        }
        Ok(_) => Ok(Destination::Stream(path)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            Ok(Destination::Replace { path, existing: None })
        }
        Err(e) => Err(unwritable(e, target)),
    }
}

/// The directory a temporary for `path` goes in (its own, so that the rename stays on
/// one file system).
fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// What follows the target's name in a temporary's: `.smartmesh-PID.RANDOM.tmp`.
const TEMP_TAG: &str = ".smartmesh-";
const TEMP_SUFFIX: &str = ".tmp";

/// The PID in the name of a temporary file of ours (`.NAME.smartmesh-PID.RANDOM.tmp`),
/// `None` for any other name.
fn temporary_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?.strip_suffix(TEMP_SUFFIX)?;
    let at = rest.rfind(TEMP_TAG)?;
    let (pid, random) = rest[at + TEMP_TAG.len()..].split_once('.')?;
    let ours = at > 0
        && !pid.is_empty()
        && pid.bytes().all(|b| b.is_ascii_digit())
        && !random.is_empty()
        && random.bytes().all(|b| b.is_ascii_alphanumeric());
    ours.then(|| pid.parse().ok()).flatten()
}

/// Whether no process `pid` runs (a process of another user runs: we may not signal it,
/// but it is there).
#[cfg(unix)]
fn is_gone(pid: u32) -> bool {
    let Some(pid) = i32::try_from(pid).ok().and_then(rustix::process::Pid::from_raw) else {
        return false;
    };
    rustix::process::test_kill_process(pid) == Err(rustix::io::Errno::SRCH)
}

/// Directories already cleaned by this process.
static CLEANED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes from `dir` the temporary files that processes now gone left behind (see the
/// module documentation), once per directory and process. Best effort: what cannot be
/// read or removed is left.
fn remove_stale_temporaries(dir: &Path) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let mut cleaned = CLEANED.lock().unwrap_or_else(|e| e.into_inner());
        if cleaned.iter().any(|d| d == dir) {
            return;
        }
        cleaned.push(dir.to_path_buf());
        let Ok(entries) = std::fs::read_dir(dir) else { return };
        let me = rustix::process::getuid().as_raw();
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(pid) = name.to_str().and_then(temporary_pid) else { continue };
            // symlink_metadata: a link is never ours, and never followed.
            let Ok(m) = std::fs::symlink_metadata(entry.path()) else { continue };
            if m.is_file() && m.uid() == me && pid != std::process::id() && is_gone(pid) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
    #[cfg(not(unix))]
    let _ = (dir, &CLEANED);
}

/// Writes `bytes` to a new temporary file beside `path`, with the permissions the
/// target must end with, synced to disk.
fn write_temporary(
    path: &Path,
    existing: Option<&std::fs::Metadata>,
    bytes: &[u8],
) -> std::io::Result<NamedTempFile> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let prefix = format!(".{name}{TEMP_TAG}{}.", std::process::id());
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(TEMP_SUFFIX);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // A new file: 0666 less the umask, as any program's output.
        if existing.is_none() {
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
    }
    let mut tmp = builder.tempfile_in(directory_of(path))?;
    if let Some(m) = existing {
        tmp.as_file().set_permissions(m.permissions())?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            // Keeping the owner needs privileges; without them the file is the
            // writer's, as with any program that replaces a file by renaming.
            let _ = std::os::unix::fs::fchown(tmp.as_file(), Some(m.uid()), Some(m.gid()));
        }
    }
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    Ok(tmp)
}

/// Writes every `(path, bytes)` (see the module documentation): all targets are checked,
/// then all temporaries written, then all renamed. On failure before the renames, no
/// target has changed and no temporary is left.
pub fn write_all_atomically(targets: &[(PathBuf, Vec<u8>)]) -> Result<()> {
    let mut plan = Vec::with_capacity(targets.len());
    for (target, bytes) in targets {
        plan.push((target, destination(target)?, bytes));
    }
    for (_, dest, _) in &plan {
        if let Destination::Replace { path, .. } = dest {
            remove_stale_temporaries(directory_of(path));
        }
    }
    // Dropping a `NamedTempFile` removes it, so an early return cleans up.
    let mut temps = Vec::new();
    for (target, dest, bytes) in &plan {
        if let Destination::Replace { path, existing } = dest {
            let tmp = write_temporary(path, existing.as_ref(), bytes)
                .map_err(|e| write_error(e).with_path(target))?;
            temps.push((tmp, *target, path));
        }
    }
    let mut dirs = Vec::new();
    for (tmp, target, path) in temps {
        tmp.persist(path).map_err(|e| write_error(e.error).with_path(target))?;
        let dir = directory_of(path);
        if !dirs.contains(&dir) {
            dirs.push(dir);
        }
    }
    // The renames themselves reach the disk with their directories (best effort: some
    // file systems cannot sync a directory).
    for dir in dirs {
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    for (target, dest, bytes) in &plan {
        if let Destination::Stream(path) = dest {
            OpenOptions::new()
                .write(true)
                .open(path)
                .and_then(|mut f| f.write_all(bytes))
                .map_err(|e| write_error(e).with_path(target))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_our_temporary_names_give_a_pid() {
        assert_eq!(temporary_pid(".out.msh.smartmesh-1234.AbC123.tmp"), Some(1234));
        assert_eq!(temporary_pid(".a.smartmesh-1.x.smartmesh-77.q1.tmp"), Some(77));
        for other in [
            "out.msh.smartmesh-1234.AbC123.tmp",
            ".out.msh.smartmesh-1234.tmp",
            ".smartmesh-1234.AbC123.tmp",
            ".out.msh.smartmesh-+12.AbC123.tmp",
            ".out.msh.smartmesh-12.Ab-C.tmp",
            ".out.msh.AbC123.smartmesh.tmp",
            ".out.msh.smartmesh-1234.AbC123.tmpx",
        ] {
            assert_eq!(temporary_pid(other), None, "{other}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn temporaries_of_gone_processes_are_removed_by_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let gone = child.id();
        child.wait().unwrap();
        assert!(is_gone(gone));
        let stale = dir.path().join(format!(".out.msh.smartmesh-{gone}.AbC123.tmp"));
        // Kept: a live process's (ours), another pattern, a link.
        let live = dir.path().join(format!(".out.msh.smartmesh-{}.XyZ789.tmp", std::process::id()));
        let other = dir.path().join(format!(".out.msh.smartmesh-{gone}.tmp"));
        let link = dir.path().join(format!(".l.smartmesh-{gone}.Lnk000.tmp"));
        for p in [&stale, &live, &other] {
            std::fs::write(p, b"partial").unwrap();
        }
        std::os::unix::fs::symlink(&other, &link).unwrap();
        write_all_atomically(&[(dir.path().join("out.msh"), b"mesh".to_vec())]).unwrap();
        assert!(!stale.exists(), "the stale temporary stays");
        assert!(live.exists() && other.exists() && link.symlink_metadata().is_ok());
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names.len(), 4, "{names:?}");
    }
}
