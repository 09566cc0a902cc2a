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

    /// Whether the error is about what the user gave (exit code 2): the input's content,
    /// an input that cannot be read, an output that cannot be written where it was
    /// named; rather than the work failing (other I/O errors: a full disk, a closed
    /// stream).
    pub fn is_input_error(&self) -> bool {
        !matches!(self.kind, ErrorKind::Io(_))
    }

    /// An error while writing standard output: named so in messages.
    pub fn on_stdout(mut self) -> Self {
        self.path = Some(PathBuf::from("<stdout>"));
        self
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
    /// The input file cannot be read: it does not exist, is a directory, or its
    /// permissions forbid it. Check the path.
    #[error("cannot read it: {0}")]
    Unreadable(std::io::Error),
    /// The output cannot be written where it was named: its directory does not exist or
    /// is not writable, or it is a directory. Check the path.
    #[error("cannot write it: {0}")]
    Unwritable(std::io::Error),
    /// The output exists and is read-only. smartmesh does not replace a read-only file
    /// (as `cp` refuses to); make it writable or remove it first.
    #[error(
        "the file is read-only; smartmesh does not replace it (make it writable or remove it)"
    )]
    ReadOnly,
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
    #[error("{what} refers to {index}{}", out_of_range(*.index, *.available))]
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
    /// The format cannot be determined from the path's extension (the extension, empty
    /// when there is none or the file is a stream); name it with --from/--to.
    #[error("cannot tell the format {}; smartmesh knows {}; name it with --from/--to", unknown_extension(.0), crate::Format::known_extensions())]
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

/// Why an index names nothing: a negative one never does; otherwise there are too few.
fn out_of_range(index: i64, available: usize) -> String {
    if index < 0 {
        ", a negative number".into()
    } else if index as u64 >= available as u64 {
        format!(", but only {available} exist")
    } else {
        String::new()
    }
}

fn unknown_extension(ext: &str) -> String {
    if ext.is_empty() {
        "without an extension".into()
    } else {
        format!("from the extension `.{}`", crate::text::quote_prefix(ext.as_bytes()))
    }
}

/// `Result` with this crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::new(ErrorKind::Io(e))
    }
}
