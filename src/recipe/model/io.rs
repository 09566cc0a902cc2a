//! Reading a recipe from a file or text in any of its formats, and writing it.

use std::path::Path;

use super::{Recipe, RecipeFormat};
use crate::recipe::error::{RecipeError, RecipeErrorKind};
use crate::recipe::preprocess::ReadOptions;
use crate::recipe::{appendix, preprocess, serde_io};

/// Refuses the characters that look like a space or like nothing (pasted from a web
/// page or a word processor), naming the character and its line: a parser would quote
/// them invisibly, or not at all.
fn invisible_characters(text: &str, origin: &Path) -> Result<(), RecipeError> {
    const NAMES: [(char, &str); 6] = [
        ('\u{a0}', "U+00A0 NO-BREAK SPACE"),
        ('\u{200b}', "U+200B ZERO WIDTH SPACE"),
        ('\u{200c}', "U+200C ZERO WIDTH NON-JOINER"),
        ('\u{200d}', "U+200D ZERO WIDTH JOINER"),
        ('\u{2060}', "U+2060 WORD JOINER"),
        ('\u{feff}', "U+FEFF BYTE ORDER MARK (ZERO WIDTH NO-BREAK SPACE)"),
    ];
    for (i, line) in text.lines().enumerate() {
        if let Some((c, name)) = NAMES.iter().find(|(c, _)| line.contains(*c)) {
            let column = line[..line.find(*c).unwrap_or(0)].chars().count() + 1;
            return Err(RecipeError::new(RecipeErrorKind::Syntax(format!(
                "column {column} holds an invisible character, {name} (pasted from a web page or a word processor?): replace it with a plain space or remove it"
            )))
            .at(origin, i + 1));
        }
    }
    Ok(())
}

impl Recipe {
    /// Reads a recipe; the format comes from the extension (`.cfg`, `.conf`,
    /// `.libconfig`: libconfig through cpp when it holds directives; `.toml`; `.json`).
    pub fn from_path(path: &Path) -> Result<Recipe, RecipeError> {
        Recipe::from_path_with(path, &ReadOptions::default())
    }

    /// [`Recipe::from_path`] with what reading may do and pull in (a regular file of
    /// at most `options.max_bytes`; cpp and `@include` only when `options.preprocess`).
    pub fn from_path_with(path: &Path, options: &ReadOptions) -> Result<Recipe, RecipeError> {
        let format = RecipeFormat::from_path(path)
            .ok_or_else(|| RecipeError::new(RecipeErrorKind::UnknownFormat).in_file(path))?;
        let text = preprocess::read_file(path, options.max_bytes, options.max_bytes)
            .map_err(|e| e.in_file(path))?;
        Recipe::from_str_with(&text, format, path, options)
    }

    /// Reads a recipe from text; `origin` names it in errors and anchors relative
    /// `#include` and `@include` paths.
    #[allow(clippy::should_implement_trait)]
    pub fn from_str(
        text: &str,
        format: RecipeFormat,
        origin: &Path,
    ) -> Result<Recipe, RecipeError> {
        Recipe::from_str_with(text, format, origin, &ReadOptions::default())
    }

    /// [`Recipe::from_str`] with what reading may do and pull in.
    pub fn from_str_with(
        text: &str,
        format: RecipeFormat,
        origin: &Path,
        options: &ReadOptions,
    ) -> Result<Recipe, RecipeError> {
        // A byte-order mark opens many files saved on Windows: skipped, as Python's
        // `utf-8-sig` does.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        invisible_characters(text, origin)?;
        let recipe = match format {
            RecipeFormat::Libconfig => appendix::read(text, origin, options)?,
            RecipeFormat::Toml => serde_io::read_toml(text, origin)?,
            RecipeFormat::Json => serde_io::read_json(text, origin)?,
        };
        recipe.validate()?;
        Ok(recipe)
    }

    /// The recipe as TOML.
    pub fn to_toml(&self) -> String {
        serde_io::write_toml(self)
    }

    /// The recipe as JSON (pretty, newline at the end).
    pub fn to_json(&self) -> String {
        serde_io::write_json(self)
    }

    /// The recipe as libconfig, in the keywords of thesis appendix A.
    pub fn to_libconfig(&self) -> String {
        appendix::write(self)
    }

    /// The recipe in `format`.
    pub fn to_format(&self, format: RecipeFormat) -> String {
        match format {
            RecipeFormat::Libconfig => self.to_libconfig(),
            RecipeFormat::Toml => self.to_toml(),
            RecipeFormat::Json => self.to_json(),
        }
    }

    /// `error` placed at model path `path`.
    pub(crate) fn error_at(&self, kind: RecipeErrorKind, path: &str) -> RecipeError {
        self.places.locate(RecipeError::new(kind), path)
    }

    /// The file of the recipe that wrote `path` (an included file's), if known.
    pub(crate) fn file_of(&self, path: &str) -> Option<&Path> {
        self.places.file_of(path)
    }

    /// The key as the recipe's file wrote it at `path`.
    pub(crate) fn written_key<'a>(&'a self, path: &str, default: &'a str) -> &'a str {
        self.places.key(path, default)
    }
}
