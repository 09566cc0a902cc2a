//! Recipe errors: what went wrong, in which file, at which line, under which key, and the
//! nearest valid name when a name was misspelt.
//!
//! Every error a user can cause is a value of [`RecipeError`]; its `Display` reads like
//! `unknown key MINSIZ at recipe.cfg:12 (in CREATE_DISTANCE_FUNCTIONS[0]), did you mean MINSIZE?`.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::sizing::FunctionError;

/// What went wrong, without the place.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecipeErrorKind {
    /// The file could not be read.
    #[error("cannot read the recipe: {0}")]
    Io(String),
    /// The extension tells no recipe format.
    #[error("unknown recipe format (extension .cfg, .conf, .libconfig, .toml or .json expected)")]
    UnknownFormat,
    /// The text is not valid libconfig, TOML or JSON.
    #[error("{0}")]
    Syntax(String),
    /// The C preprocessor is missing or failed.
    #[error("{0}")]
    Preprocessor(String),
    /// The recipe passes a limit on what it may pull in or how deep it nests (its
    /// text with includes and cpp's output, cpp's time, nesting of values).
    #[error("{0}")]
    Limit(String),
    /// The recipe asks for something its reading options turn off (a directive or an
    /// `@include` under `--no-preprocess`).
    #[error("{0}")]
    NotAllowed(String),
    /// A key the recipe does not know.
    #[error("unknown key {key}")]
    UnknownKey {
        /// The key as written.
        key: String,
    },
    /// A key the item needs.
    #[error("missing key {key}")]
    MissingKey {
        /// The key, as the format spells it.
        key: String,
    },
    /// Two spellings of one key, or one key twice.
    #[error("key {key} given twice (also as {other})")]
    DuplicateKey {
        /// The second occurrence.
        key: String,
        /// The first one.
        other: String,
    },
    /// A value of the wrong kind.
    #[error("{key} must be {expected}, found {found}")]
    WrongType {
        /// The key.
        key: String,
        /// What it must be.
        expected: String,
        /// What it is.
        found: String,
    },
    /// A value of the right kind but not acceptable.
    #[error("{0}")]
    Invalid(String),
    /// Two items share a name.
    #[error("{what} \"{name}\" is defined twice")]
    DuplicateName {
        /// Region, polyline or function.
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A reference to a region, function or polyline that does not exist.
    #[error("{referrer} names {what} \"{name}\"")]
    UnknownName {
        /// Who refers (`algorithm 3`).
        referrer: String,
        /// `region`, `function`, `polyline`, `algorithm type`.
        what: &'static str,
        /// The name as written.
        name: String,
    },
    /// A function of the wrong kind for the key that names it.
    #[error(
        "{referrer}: {key} names \"{name}\", a {found} function; expected a {expected} function"
    )]
    WrongFunctionKind {
        /// Who refers.
        referrer: String,
        /// The key naming the function.
        key: String,
        /// The function name.
        name: String,
        /// Its kind.
        found: &'static str,
        /// The kind needed.
        expected: &'static str,
    },
    /// A size function parameter out of range.
    #[error("function \"{name}\": {source}")]
    Function {
        /// The function name.
        name: String,
        /// What the function builder said.
        source: FunctionError,
    },
    /// A region names a tag (or tag name) the mesh does not have.
    #[error("region \"{region}\" names {entity}, which the mesh does not have{available}")]
    AbsentEntity {
        /// The region.
        region: String,
        /// `tag 17` or `"Wall"`.
        entity: String,
        /// A list of what the mesh has, starting with `; `.
        available: String,
    },
    /// A region whose entities cannot be put in one dimension.
    #[error("region \"{region}\": {detail}")]
    Dimension {
        /// The region.
        region: String,
        /// What is ambiguous or mixed.
        detail: String,
    },
}

/// A recipe error with its place.
#[derive(Debug, Clone, PartialEq)]
pub struct RecipeError {
    /// What went wrong (boxed: errors travel through many `Result`s, kept small).
    pub kind: Box<RecipeErrorKind>,
    /// The file (the recipe, or a file it includes), when known.
    pub file: Option<PathBuf>,
    /// The 1-based line, when known.
    pub line: Option<usize>,
    /// Where in the recipe's structure (`CREATE_ALGORITHMS[2]`, `functions.F3`), when
    /// it helps.
    pub context: Option<String>,
    /// The nearest valid name, for a misspelt one (already quoted as the format writes it).
    pub suggestion: Option<String>,
}

impl RecipeError {
    /// An error without a place yet.
    pub fn new(kind: RecipeErrorKind) -> RecipeError {
        RecipeError {
            kind: Box::new(kind),
            file: None,
            line: None,
            context: None,
            suggestion: None,
        }
    }

    /// Sets the place.
    pub fn at(mut self, file: &Path, line: usize) -> RecipeError {
        self.file = Some(file.to_path_buf());
        self.line = (line > 0).then_some(line);
        self
    }

    /// Sets the file when no place is known yet.
    pub fn in_file(mut self, file: &Path) -> RecipeError {
        if self.file.is_none() {
            self.file = Some(file.to_path_buf());
        }
        self
    }

    /// Sets the structural context when none is set yet.
    pub fn within(mut self, context: impl Into<String>) -> RecipeError {
        if self.context.is_none() {
            self.context = Some(context.into());
        }
        self
    }

    /// Adds a suggestion.
    pub fn suggest(mut self, suggestion: Option<String>) -> RecipeError {
        self.suggestion = suggestion;
        self
    }

    /// Whether the error lies in the input (a recipe that cannot be read, is wrong or does
    /// not fit the mesh: exit status 2) rather than in running a tool (a preprocessor
    /// that exists but cannot be started: exit status 1).
    pub fn is_input_error(&self) -> bool {
        !matches!(&*self.kind, RecipeErrorKind::Preprocessor(m) if m.starts_with("cannot run"))
    }
}

impl fmt::Display for RecipeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.kind)?;
        match (&self.file, self.line) {
            (Some(file), Some(line)) => write!(f, " at {}:{line}", file.display())?,
            (Some(file), None) => write!(f, " in {}", file.display())?,
            (None, Some(line)) => write!(f, " at line {line}")?,
            (None, None) => {}
        }
        if let Some(c) = &self.context {
            write!(f, " (in {c})")?;
        }
        if let Some(s) = &self.suggestion {
            write!(f, ", did you mean {s}?")?;
        }
        Ok(())
    }
}

impl std::error::Error for RecipeError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &*self.kind {
            RecipeErrorKind::Function { source, .. } => Some(source),
            _ => None,
        }
    }
}
