//! Errors that say where: file, line (or byte offset) and what was expected.
//!
//! Every reader returns [`Error`]; its `Display` reads like a compiler message,
//! `naca.msh:1204: expected 3 coordinates after node 88, found 2`. Readers fill in
//! the position; the caller that knows the path fills in the file with
//! [`Error::with_path`].

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in a file an error was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Position {
    /// 1-based line of a text file.
    Line(u64),
    /// 0-based byte offset into a binary file (or the binary part of a file).
    Byte(u64),
}

/// A reading or writing error, with its file and position when known.
#[derive(Debug, thiserror::Error)]
pub struct Error {
    /// The file, when the caller knows it (`None` for a stream read from stdin).
    pub path: Option<PathBuf>,
    /// Where in the file, when the error is about its content.
    pub at: Option<Position>,
    /// What went wrong.
    #[source]
    pub kind: ErrorKind,
}

impl Error {
    /// An error at a line.
    pub fn at_line(line: u64, kind: ErrorKind) -> Self {
        Error { path: None, at: Some(Position::Line(line)), kind }
    }

    /// An error at a byte offset.
    pub fn at_byte(offset: u64, kind: ErrorKind) -> Self {
        Error { path: None, at: Some(Position::Byte(offset)), kind }
    }

    /// An error without a position (a whole-file or I/O problem).
    pub fn new(kind: ErrorKind) -> Self {
        Error { path: None, at: None, kind }
    }

    /// Shorthand for a syntax error at a line: expected `expected`, found `found`.
    pub fn expected(line: u64, expected: impl Into<String>, found: impl Into<String>) -> Self {
        Error::at_line(line, ErrorKind::Expected { expected: expected.into(), found: found.into() })
    }

    /// Sets the file if it is not set yet.
    pub fn with_path(mut self, path: impl AsRef<Path>) -> Self {
        if self.path.is_none() {
            self.path = Some(path.as_ref().to_path_buf());
        }
        self
    }

    /// Whether the error is about the input (exit code 2) rather than the system (I/O).
    pub fn is_input_error(&self) -> bool {
        !matches!(self.kind, ErrorKind::Io(_))
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.path {
            Some(p) => write!(f, "{}", p.display())?,
            None => f.write_str("<stdin>")?,
        }
        match self.at {
            Some(Position::Line(l)) => write!(f, ":{l}")?,
            Some(Position::Byte(b)) => write!(f, ": byte {b}")?,
            None => {}
        }
        write!(f, ": {}", self.kind)
    }
}

/// What went wrong. Each variant says what to do about it.
#[derive(Debug, thiserror::Error)]
pub enum ErrorKind {
    /// The operating system failed to read or write. Check the path and permissions.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The file does not have the expected syntax at this point.
    #[error("expected {expected}, found {found}")]
    Expected {
        /// What the format requires here.
        expected: String,
        /// What the file has instead.
        found: String,
    },
    /// The file ended before a section or array was complete.
    #[error("unexpected end of file: {context}")]
    UnexpectedEof {
        /// What was being read.
        context: String,
    },
    /// A count announced in a header cannot be right (larger than the bytes left could
    /// hold, or negative). Nothing was allocated for it.
    #[error("{what} announces {count} items, but the file cannot hold that many ({limit})")]
    ImplausibleCount {
        /// What was counted.
        what: String,
        /// The announced count.
        count: u64,
        /// Why it is implausible.
        limit: String,
    },
    /// A cell or set refers to a point (or cell) that does not exist.
    #[error("{what} refers to {index}, but only {available} exist")]
    IndexOutOfRange {
        /// The referring item.
        what: String,
        /// The index as written in the file.
        index: i64,
        /// How many exist.
        available: usize,
    },
    /// A coordinate or value is NaN or infinite.
    #[error("{what} is not a finite number ({value})")]
    NonFinite {
        /// The value's role.
        what: String,
        /// The text or value found.
        value: String,
    },
    /// The file uses a feature or version smartmesh does not read or write.
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// The file is inconsistent with itself (counts that disagree, a duplicate id).
    #[error("{0}")]
    Inconsistent(String),
    /// The format cannot be determined from the path; name it with --from/--to.
    #[error("cannot tell the format of `{0}`; name it with --from/--to")]
    UnknownFormat(String),
    /// The mesh cannot be written in this format at all.
    #[error("cannot write this mesh as {format}: {reason}")]
    CannotWrite {
        /// The format.
        format: &'static str,
        /// Why not.
        reason: String,
    },
}

/// `Result` with this crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::new(ErrorKind::Io(e))
    }
}
