//! Errors of the command line: the library's errors kept as typed sources, one mapping
//! from an error chain to an exit status ([`status_of`]), and the printing of a chain as
//! ruff prints it: the message, then one `Cause:` line per source that adds something.
//!
//! Exit statuses: 0 success, 1 the work failed (a tool that failed, a disk that is full),
//! 2 bad usage or input (a malformed file, a missing input, an output path that cannot be
//! created, a recipe that does not fit the mesh).

use std::error::Error as StdError;
use std::fmt::Write as _;
use std::io::ErrorKind as IoKind;

use smartmesh::adapt::{AdaptError, PhaseError, StartError};
use smartmesh::formats::{Error as FormatError, ErrorKind as FormatKind};
use smartmesh::mesher::MeshError;
use smartmesh::recipe::RecipeError;
use smartmesh::recipe::SizeMeshError;
use smartmesh::remesh::RemeshError;
use smartmesh::sizing::SizingError;
use smartmesh::AdapterError;
use smartmesh::ControlError;
use smartmesh::MeshGraphError;
use smartmesh::MetricError;

/// How a run ended (ruff's `ExitStatus`): 0 success, 1 the work failed, 2 bad usage or
/// input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExitStatus {
    /// Everything done (also: stdout closed by its reader, see [`io_status`]).
    Success,
    /// The work itself failed (I/O error, a tool that failed).
    Failure,
    /// Bad usage or bad input.
    Error,
    /// Stopped by Ctrl-C (or SIGTERM, SIGHUP) after saving what was done: 130, as a
    /// shell reports a command ended by SIGINT.
    Interrupted,
}

impl From<ExitStatus> for std::process::ExitCode {
    fn from(s: ExitStatus) -> std::process::ExitCode {
        std::process::ExitCode::from(match s {
            ExitStatus::Success => 0,
            ExitStatus::Failure => 1,
            ExitStatus::Error => 2,
            ExitStatus::Interrupted => 130,
        })
    }
}

/// A boxed library error, kept with its type for [`status_of`] and its chain for the
/// `Cause:` lines.
pub(super) type Source = Box<dyn StdError + Send + Sync + 'static>;

/// An error the CLI prints: a message, the error it came from (if any) and the exit
/// status, decided once, from the message's kind or the source's chain.
#[derive(Debug)]
pub(crate) struct CliError {
    /// Exit status.
    pub status: ExitStatus,
    /// What to print after `smartmesh: error: `.
    pub message: String,
    /// The library error behind the message.
    pub source: Option<Source>,
}

impl CliError {
    /// A usage or input error the CLI itself finds (exit 2).
    pub(crate) fn usage(message: impl Into<String>) -> Self {
        CliError { status: ExitStatus::Error, message: message.into(), source: None }
    }

    /// Bad input (exit 2) that a library error explains: the error is kept as the
    /// source, whatever status its type would give.
    pub(crate) fn input(message: impl Into<String>, source: impl Into<Source>) -> Self {
        CliError { status: ExitStatus::Error, message: message.into(), source: Some(source.into()) }
    }

    /// A library error under a message of the CLI's (what it was doing); the status
    /// comes from the error.
    pub(crate) fn context(message: impl Into<String>, source: impl Into<Source>) -> Self {
        let source = source.into();
        CliError {
            status: status_of(source.as_ref()),
            message: message.into(),
            source: Some(source),
        }
    }

    /// The text printed on stderr: `message`, then `  Cause: …` for each error of the
    /// chain whose text the lines above do not already hold (most library errors quote
    /// their source in their own message).
    pub(crate) fn render(&self) -> String {
        let mut out = self.message.clone();
        let mut printed = self.message.clone();
        let mut next: Option<&(dyn StdError + 'static)> = self.source.as_deref().map(|e| e as _);
        while let Some(e) = next {
            let text = e.to_string();
            if !text.is_empty() && !printed.contains(&text) {
                let _ = write!(out, "\n  Cause: {}", text.replace('\n', "\n         "));
                printed.push('\n');
                printed.push_str(&text);
            }
            next = e.source();
        }
        out
    }
}

/// Every library error becomes a [`CliError`] with its own message and the status of its
/// chain.
impl<E: StdError + Send + Sync + 'static> From<E> for CliError {
    fn from(e: E) -> Self {
        let message = e.to_string();
        let source: Source = Box::new(e);
        CliError { status: status_of(source.as_ref()), message, source: None }.with_source(source)
    }
}

impl CliError {
    /// `self` with `source` kept behind its message; the status stays.
    fn with_source(mut self, source: Source) -> Self {
        self.source = Some(source);
        self
    }
}

/// The exit status of an error chain: the outermost error whose type decides (a failed
/// iteration of `adapt` is a failure of the work even when a sizing error caused it),
/// passing through the wrappers that only carry their source (a read error inside the
/// loop's output error). Unknown errors are failures of the work.
pub(super) fn status_of(error: &(dyn StdError + 'static)) -> ExitStatus {
    let mut next = Some(error);
    while let Some(e) = next {
        if let Some(status) = decides(e) {
            return status;
        }
        next = e.source();
    }
    ExitStatus::Failure
}

/// What one error says about the exit status, `None` when its source must tell.
fn decides(e: &(dyn StdError + 'static)) -> Option<ExitStatus> {
    use ExitStatus::{Error, Failure};
    if let Some(e) = e.downcast_ref::<FormatError>() {
        return decides(&e.kind);
    }
    // Also reached on its own below a `#[error(transparent)]` wrapper, whose source is
    // the wrapped error's source.
    if let Some(kind) = e.downcast_ref::<FormatKind>() {
        return Some(match kind {
            FormatKind::Io(io) => io_status(io),
            _ => Error,
        });
    }
    if let Some(io) = e.downcast_ref::<std::io::Error>() {
        return Some(io_status(io));
    }
    if let Some(e) = e.downcast_ref::<RecipeError>() {
        return Some(if e.is_input_error() { Error } else { Failure });
    }
    if let Some(e) = e.downcast_ref::<smartmesh::layer::LayerError>() {
        return Some(if e.is_input_error() { Error } else { Failure });
    }
    if let Some(e) = e.downcast_ref::<MeshError>() {
        return Some(if e.is_input_error() { Error } else { Failure });
    }
    if let Some(e) = e.downcast_ref::<AdaptError>() {
        return match e {
            // A solver that fails on the starting mesh fails as it would on a later one;
            // a field it did not write, a directory that cannot be written are bad input.
            AdaptError::Start { source: PhaseError::Solver(s), .. } if !s.is_input() => {
                Some(Failure)
            }
            AdaptError::Interrupted { .. } => Some(ExitStatus::Interrupted),
            AdaptError::Start { .. }
            | AdaptError::TooManyVertices { .. }
            | AdaptError::Planar(_)
            | AdaptError::Surface(_) => Some(Error),
            AdaptError::Iteration { .. } => Some(Failure),
            AdaptError::Output(_) | AdaptError::Layer(_) | AdaptError::LayerOutput(_) => None,
        };
    }
    if let Some(e) = e.downcast_ref::<StartError>() {
        return match e {
            StartError::Read(_) => None,
            StartError::NotPlanar { .. } => Some(Error),
            StartError::Mesher { source, .. } => {
                Some(if source.is_input_error() { Error } else { Failure })
            }
        };
    }
    if let Some(e) = e.downcast_ref::<AdapterError>() {
        return match e {
            // A program the user named with --adapter-program that is missing or not
            // executable is bad input; a tool missing from PATH is not the input's fault.
            AdapterError::Option { .. }
            | AdapterError::Unusable { .. }
            | AdapterError::Periodic { .. }
            | AdapterError::Space { .. }
            | AdapterError::Kind(_) => Some(Error),
            AdapterError::Format(_) => None,
            _ => Some(Failure),
        };
    }
    if let Some(e) = e.downcast_ref::<MetricError>() {
        return match e {
            MetricError::Read(read) => decides(read),
            _ => Some(Error),
        };
    }
    let input = e.is::<SizeMeshError>()
        || e.is::<SizingError>()
        || e.is::<MeshGraphError>()
        || e.is::<RemeshError>()
        || e.is::<ControlError>()
        || e.is::<smartmesh::sizing::solution::input::FieldError>()
        || e.is::<smartmesh::NotPlanar>();
    input.then_some(Error)
}

/// The status of an I/O error: what the user named wrongly (a missing file, a directory
/// where a file belongs, a path that cannot be created or read) is usage (2); stdout
/// closed by its reader (`smartmesh convert x.msh - --to vtk | head -c 10`) ends the run
/// quietly with 0, as ripgrep and the coreutils under a shell do; anything else (a full
/// disk, a device error) is a failure of the work (1).
pub(super) fn io_status(e: &std::io::Error) -> ExitStatus {
    match e.kind() {
        IoKind::BrokenPipe => ExitStatus::Success,
        IoKind::NotFound | IoKind::PermissionDenied | IoKind::AlreadyExists => ExitStatus::Error,
        _ if names_a_wrong_path(e) => ExitStatus::Error,
        _ => ExitStatus::Failure,
    }
}

/// A directory where a file belongs, a file where a directory belongs, a read-only file
/// system or a name too long: by the OS error number, because the `ErrorKind`s for them
/// are newer than the crate's minimum Rust.
fn names_a_wrong_path(e: &std::io::Error) -> bool {
    // ENOTDIR, EISDIR, EROFS on Linux and the BSDs; ENAMETOOLONG is 36 on Linux, 63 on
    // the BSDs.
    #[cfg(unix)]
    let codes: &[i32] =
        if cfg!(target_os = "linux") { &[20, 21, 30, 36] } else { &[20, 21, 30, 63] };
    #[cfg(not(unix))]
    let codes: &[i32] = &[];
    e.raw_os_error().is_some_and(|c| codes.contains(&c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_status_comes_from_the_first_error_of_the_chain_that_decides() {
        let missing = FormatError::from(std::io::Error::from(IoKind::NotFound)).with_path("a.msh");
        assert_eq!(CliError::from(missing).status, ExitStatus::Error);
        let full = FormatError::from(std::io::Error::from(IoKind::StorageFull));
        assert_eq!(CliError::from(full).status, ExitStatus::Failure);
        let pipe = std::io::Error::from(IoKind::BrokenPipe);
        assert_eq!(CliError::from(pipe).status, ExitStatus::Success);
        // The loop's output error passes the decision on to the write error inside.
        let nodir = FormatError::from(std::io::Error::from(IoKind::NotFound));
        assert_eq!(CliError::from(AdaptError::Output(nodir)).status, ExitStatus::Error);
        // A transparent wrapper: its source is the wrapped error's source.
        let nan = FormatError::at_line(
            3,
            FormatKind::NonFinite { what: "x".into(), value: "nan".into() },
        );
        assert_eq!(CliError::from(MetricError::Read(nan)).status, ExitStatus::Error);
        let control = ControlError::NotSpd { vertex: 3 };
        assert_eq!(CliError::from(control).status, ExitStatus::Error);
        let option = AdapterError::Option { option: "--nosurf", adapter: "gmsh" };
        assert_eq!(CliError::from(option).status, ExitStatus::Error);
        let unusable = AdapterError::Unusable {
            program: "/nonexistent/mmg".into(),
            why: "does not exist",
            hint: "install it",
        };
        assert_eq!(CliError::from(unusable).status, ExitStatus::Error);
        let missing = AdapterError::NotFound { program: "mmg2d_O3".into(), hint: "install it" };
        assert_eq!(CliError::from(missing).status, ExitStatus::Failure);
        let failed = AdapterError::Failed {
            program: "mmg2d_O3".into(),
            status: "exit status 3".into(),
            output: String::new(),
        };
        assert_eq!(CliError::from(failed).status, ExitStatus::Failure);
    }

    #[test]
    fn causes_are_printed_once_each() {
        let io = std::io::Error::other("disk on fire");
        let e = CliError::context("writing out.msh", FormatError::from(io).with_path("out.msh"));
        assert_eq!(e.render(), "writing out.msh\n  Cause: out.msh: disk on fire");
        assert_eq!(e.status, ExitStatus::Failure);
        // A message that already quotes its source prints no Cause line.
        let e = CliError::from(FormatError::from(std::io::Error::other("gone")).with_path("a"));
        assert_eq!(e.render(), "a: gone");
    }
}
