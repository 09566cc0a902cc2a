//! Output files written as a set, all or nothing: every file goes to a temporary file
//! beside its target, and the targets are replaced only once every temporary is written
//! and flushed to disk.
//!
//! What survives a crash of the system (a power cut), and what it costs: each temporary
//! is synced (`fsync`) before it is renamed, so whatever a target's name points to after
//! a crash is a whole file, the old one or the new one, never a torn one. The directory
//! is not synced after the renames: that would only make the new names themselves
//! durable at once (instead of at the file system's next commit, 5 s on ext4), and each
//! `fsync` waits for a journal commit shared with every other writer of the disk (0.1–0.5
//! ms on an idle disk, 4–10 ms on a busy one, where a whole 2 000-triangle `mesh` takes
//! 4 ms of CPU). So after a crash within seconds of a write a target may still be the old
//! file, or absent if it was new; it is never partial. [`sync_files`] still syncs the
//! directory: the files it syncs were renamed before being synced.
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
//! they are, `.NAME.smartmesh-HOST-PID.RANDOM.tmp`: a process killed before it could
//! remove its own (SIGKILL, a power cut) leaves them behind, and the next write into that
//! directory removes those of processes that are gone — only regular files of that exact
//! pattern, owned by the writing user, written on this host (the same `HOST`), whose PID
//! no longer runs (Unix; elsewhere nothing is removed).
//!
//! A PID means something only in the PID namespace of the kernel that gave it: a
//! directory shared by several nodes (NFS, Lustre) or containers holds temporaries whose
//! PIDs say nothing here, and a writer alive elsewhere must never lose its temporary.
//! `HOST` ([`host_tag`]) is 16 hex digits of a hash of the kernel's boot id and the PID
//! namespace (Linux), or of the host name (other Unix systems); a temporary of another
//! `HOST`, or of the old name without one, is never removed.

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

/// What follows the target's name in a temporary's: `.smartmesh-HOST-PID.RANDOM.tmp`.
const TEMP_TAG: &str = ".smartmesh-";
const TEMP_SUFFIX: &str = ".tmp";
/// The digits of `HOST` (hex).
const HOST_DIGITS: usize = 16;

/// The host and PID in the name of a temporary file of ours
/// (`.NAME.smartmesh-HOST-PID.RANDOM.tmp`), `None` for any other name (the old
/// `.NAME.smartmesh-PID.RANDOM.tmp` included: whose host it was is not known).
fn temporary_owner(name: &str) -> Option<(&str, u32)> {
    let rest = name.strip_prefix('.')?.strip_suffix(TEMP_SUFFIX)?;
    let at = rest.rfind(TEMP_TAG)?;
    let (owner, random) = rest[at + TEMP_TAG.len()..].split_once('.')?;
    let (host, pid) = owner.split_once('-')?;
    let ours = at > 0
        && host.len() == HOST_DIGITS
        && host.bytes().all(|b| b.is_ascii_hexdigit())
        && !pid.is_empty()
        && pid.bytes().all(|b| b.is_ascii_digit())
        && !random.is_empty()
        && random.bytes().all(|b| b.is_ascii_alphanumeric());
    ours.then(|| pid.parse().ok().map(|pid| (host, pid))).flatten()
}

/// FNV-1a, 64 bits: stable across builds and platforms (the tag is compared between
/// processes, possibly of other builds).
fn fnv1a(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for part in parts {
        for &b in part.iter().chain([0xffu8].iter()) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// What makes a PID of this process meaningful: on Linux the kernel's boot id and our PID
/// namespace (two containers on one kernel share the boot id, not the namespace); else
/// the host name. `None` when neither can be read: then nothing is ever swept.
#[cfg(unix)]
fn host_identity() -> Option<Vec<u8>> {
    let boot = std::fs::read_to_string("/proc/sys/kernel/random/boot_id").ok();
    let namespace = std::fs::read_link("/proc/self/ns/pid").ok();
    match (boot, namespace) {
        (Some(boot), Some(ns)) if !boot.trim().is_empty() => {
            Some(format!("linux {} {}", boot.trim(), ns.display()).into_bytes())
        }
        _ => {
            let uname = rustix::system::uname();
            let host = uname.nodename().to_bytes();
            (!host.is_empty()).then(|| [b"host ".as_slice(), host].concat())
        }
    }
}

/// This process's `HOST` in its temporaries' names (see the module documentation), and
/// whether it is known (an unknown host writes zeros and sweeps nothing).
fn host_tag() -> (&'static str, bool) {
    static TAG: std::sync::OnceLock<(String, bool)> = std::sync::OnceLock::new();
    let (tag, known) = TAG.get_or_init(|| {
        #[cfg(unix)]
        let identity = host_identity();
        #[cfg(not(unix))]
        let identity: Option<Vec<u8>> = None;
        match identity {
            Some(id) => (format!("{:016x}", fnv1a(&[b"smartmesh host", &id])), true),
            None => ("0".repeat(HOST_DIGITS), false),
        }
    });
    (tag.as_str(), *known)
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
        let (here, known) = host_tag();
        if !known {
            return;
        }
        let me = rustix::process::getuid().as_raw();
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some((host, pid)) = name.to_str().and_then(temporary_owner) else { continue };
            // Another host's PID says nothing here: its writer may be alive.
            if host != here {
                continue;
            }
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
/// target must end with, synced to disk when `durable`.
fn write_temporary(
    path: &Path,
    existing: Option<&std::fs::Metadata>,
    bytes: &[u8],
    durable: bool,
) -> std::io::Result<NamedTempFile> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let prefix = format!(".{name}{TEMP_TAG}{}-{}.", host_tag().0, std::process::id());
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
    if durable {
        tmp.as_file().sync_all()?;
    }
    Ok(tmp)
}

/// Writes every `(path, bytes)` (see the module documentation): all targets are checked,
/// then all temporaries written, then all renamed. On failure before the renames, no
/// target has changed and no temporary is left.
pub fn write_all_atomically(targets: &[(PathBuf, Vec<u8>)]) -> Result<()> {
    write_all_atomically_synced(targets, true)
}

/// [`write_all_atomically`], the files synced to disk before their renames only when
/// `durable`. Without it the set is still all or nothing for every reader and for a
/// killed writer (the renames are atomic), but not against a crash of the system: for
/// files rewritten many times in one run (the adaptation loop's result after every
/// iteration), whose last version alone is synced ([`sync_files`]).
pub fn write_all_atomically_synced(targets: &[(PathBuf, Vec<u8>)], durable: bool) -> Result<()> {
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
            let tmp = write_temporary(path, existing.as_ref(), bytes, durable)
                .map_err(|e| write_error(e).with_path(target))?;
            temps.push((tmp, *target, path));
        }
    }
    // The temporaries are on disk (when durable): the renames need no directory sync to
    // keep every name on a whole file (module documentation).
    for (tmp, target, path) in temps {
        tmp.persist(path).map_err(|e| write_error(e.error).with_path(target))?;
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

/// Syncs the regular files `paths` and then their directories to disk (best effort for
/// the directories): what makes files written by [`write_all_atomically_synced`] without
/// `durable` survive a crash of the system once they are final.
pub fn sync_files(paths: &[PathBuf]) -> Result<()> {
    let mut dirs = Vec::new();
    for path in paths {
        let Ok(m) = std::fs::metadata(path) else { continue };
        if !m.is_file() {
            continue;
        }
        File::open(path).and_then(|f| f.sync_all()).map_err(|e| write_error(e).with_path(path))?;
        let dir = directory_of(path);
        if !dirs.contains(&dir) {
            dirs.push(dir);
        }
    }
    for dir in dirs {
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const H: &str = "0123456789abcdef";

    #[test]
    fn only_our_temporary_names_give_a_host_and_a_pid() {
        assert_eq!(
            temporary_owner(&format!(".out.msh.smartmesh-{H}-1234.AbC123.tmp")),
            Some((H, 1234))
        );
        assert_eq!(
            temporary_owner(&format!(".a.smartmesh-{H}-1.x.smartmesh-{H}-77.q1.tmp")),
            Some((H, 77))
        );
        for other in [
            format!("out.msh.smartmesh-{H}-1234.AbC123.tmp"),
            format!(".out.msh.smartmesh-{H}-1234.tmp"),
            format!(".smartmesh-{H}-1234.AbC123.tmp"),
            format!(".out.msh.smartmesh-{H}-+12.AbC123.tmp"),
            format!(".out.msh.smartmesh-{H}-12.Ab-C.tmp"),
            format!(".out.msh.smartmesh-{H}-1234.AbC123.tmpx"),
            ".out.msh.AbC123.smartmesh.tmp".to_string(),
            // The old name, without a host: whose it was is not known.
            ".out.msh.smartmesh-1234.AbC123.tmp".to_string(),
            ".out.msh.smartmesh-0123456789abcde-1234.AbC123.tmp".to_string(),
            ".out.msh.smartmesh-0123456789abcdeg-1234.AbC123.tmp".to_string(),
        ] {
            assert_eq!(temporary_owner(&other), None, "{other}");
        }
    }

    #[test]
    fn the_host_tag_is_known_and_stable() {
        let (tag, known) = host_tag();
        assert_eq!(tag.len(), HOST_DIGITS);
        assert!(cfg!(not(unix)) || known);
        assert_eq!(host_tag().0, tag);
        assert_ne!(fnv1a(&[b"ab", b"c"]), fnv1a(&[b"a", b"bc"]));
    }

    #[cfg(unix)]
    #[test]
    fn temporaries_of_gone_processes_are_removed_by_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let gone = child.id();
        child.wait().unwrap();
        assert!(is_gone(gone));
        let here = host_tag().0;
        let elsewhere = if here == H { "fedcba9876543210" } else { H };
        let stale = dir.path().join(format!(".out.msh.smartmesh-{here}-{gone}.AbC123.tmp"));
        // Kept: a live process's (ours), another pattern, a link, the same PID on another
        // host (its writer may be alive there), the old name without a host.
        let live =
            dir.path().join(format!(".out.msh.smartmesh-{here}-{}.XyZ789.tmp", std::process::id()));
        let other = dir.path().join(format!(".out.msh.smartmesh-{here}-{gone}.tmp"));
        let link = dir.path().join(format!(".l.smartmesh-{here}-{gone}.Lnk000.tmp"));
        let remote = dir.path().join(format!(".out.msh.smartmesh-{elsewhere}-{gone}.Rem000.tmp"));
        let old = dir.path().join(format!(".out.msh.smartmesh-{gone}.Old000.tmp"));
        for p in [&stale, &live, &other, &remote, &old] {
            std::fs::write(p, b"partial").unwrap();
        }
        std::os::unix::fs::symlink(&other, &link).unwrap();
        write_all_atomically(&[(dir.path().join("out.msh"), b"mesh".to_vec())]).unwrap();
        assert!(!stale.exists(), "the stale temporary stays");
        assert!(live.exists() && other.exists() && link.symlink_metadata().is_ok());
        assert!(remote.exists(), "another host's temporary is removed");
        assert!(old.exists(), "a temporary of an unknown host is removed");
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names.len(), 6, "{names:?}");
    }
}
