//! The libconfig syntax (thesis 5.3.2, appendix A): a small recursive-descent parser that
//! keeps the line of every setting and value.
//!
//! Written by hand because the crates that read libconfig do not fit: `libconfig-rs`
//! returns values without any source position (a recipe error must name its line), and
//! others bind the C library. The grammar is libconfig 1.7's:
//!
//! ```text
//! configuration = setting*
//! setting       = name (':' | '=') value (';' | ',')?
//! value         = scalar | array | list | group
//! scalar        = boolean | integer | integer64 | hex | hex64 | float | string
//! array         = '[' (scalar (',' scalar)*)? ']'      all elements of one scalar type
//! list          = '(' (value (',' value)*)? ')'
//! group         = '{' setting* '}'
//! ```
//!
//! Names are `[A-Za-z*][-A-Za-z0-9_*]*`; booleans `true`/`false` in any case; integers
//! decimal or `0x` hex with an optional `L`/`LL` suffix; floats with a point and/or an
//! exponent; strings in double quotes with `\\ \" \n \r \t \f \xNN` escapes, adjacent
//! strings joined. Comments: `#`, `//` to the end of the line, `/* … */`. Two departures,
//! both lenient: an array may mix integers and floats (coordinates such as `[-50, -48.5]`
//! are natural), and a trailing comma is allowed in lists and arrays. `@include` is
//! handled before parsing, in [`super::preprocess`].
//!
//! Values nest at most [`MAX_NESTING`] deep: the parser recurses once per level (and so
//! do the readers of its tree and its destructor), so an unbounded depth would let a
//! recipe of `[[[[…` overflow the stack. Names within one group are checked for
//! duplicates through a map, so a group of n settings costs O(n log n).

use std::collections::BTreeMap;

use super::error::{RecipeError, RecipeErrorKind};
use super::preprocess::Source;

/// How deeply groups, lists and arrays may nest. Recipes of the thesis nest four
/// levels (a list of groups holding lists of arrays); this leaves room for any
/// hand-written recipe and keeps the recursion a few hundred kilobytes of stack.
pub const MAX_NESTING: usize = 64;

/// A libconfig value with the 0-based line of the source text where it starts.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// The value.
    pub value: Value,
    /// Line in [`Source::text`] (0-based), to be mapped with [`Source::place`].
    pub at: usize,
}

/// A libconfig value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// `true` / `false`.
    Bool(bool),
    /// An integer (int, int64 or hex).
    Int(i64),
    /// A float.
    Float(f64),
    /// A string, escapes decoded and adjacent pieces joined.
    Str(String),
    /// `[ … ]`: scalars.
    Array(Vec<Node>),
    /// `( … )`: any values.
    List(Vec<Node>),
    /// `{ … }`: settings.
    Group(Vec<Setting>),
}

impl Value {
    /// The value's kind in words, for error messages.
    pub fn describe(&self) -> &'static str {
        match self {
            Value::Bool(_) => "a boolean",
            Value::Int(_) => "an integer",
            Value::Float(_) => "a float",
            Value::Str(_) => "a string",
            Value::Array(_) => "an array [ ]",
            Value::List(_) => "a list ( )",
            Value::Group(_) => "a group { }",
        }
    }

    fn scalar_kind(&self) -> Option<u8> {
        match self {
            Value::Bool(_) => Some(0),
            Value::Int(_) | Value::Float(_) => Some(1),
            Value::Str(_) => Some(2),
            _ => None,
        }
    }
}

/// `name = value;`
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// The name.
    pub name: String,
    /// The 0-based line of the name.
    pub at: usize,
    /// The value.
    pub value: Node,
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Name(String),
    Assign,
    Semi,
    Comma,
    Open(char),
    Close(char),
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
    End,
}

fn describe_tok(t: &Tok) -> String {
    match t {
        Tok::Name(n) => format!("name {n}"),
        Tok::Assign => "'='".into(),
        Tok::Semi => "';'".into(),
        Tok::Comma => "','".into(),
        Tok::Open(c) | Tok::Close(c) => format!("'{c}'"),
        Tok::Str(_) => "a string".into(),
        Tok::Int(_) | Tok::Float(_) => "a number".into(),
        Tok::Bool(_) => "a boolean".into(),
        Tok::End => "the end of the file".into(),
    }
}

struct Lexer<'a> {
    src: &'a [u8],
    text: &'a str,
    pos: usize,
    line: usize,
}

impl<'a> Lexer<'a> {
    fn err(&self, source: &Source, line: usize, msg: String) -> RecipeError {
        let (f, l) = source.place(line);
        RecipeError::new(RecipeErrorKind::Syntax(msg)).at(f, l)
    }

    fn skip_space(&mut self, source: &Source) -> Result<(), RecipeError> {
        loop {
            match self.src.get(self.pos) {
                Some(b'\n') => {
                    self.line += 1;
                    self.pos += 1;
                }
                Some(c) if c.is_ascii_whitespace() => self.pos += 1,
                Some(b'#') => self.skip_line(),
                Some(b'/') if self.src.get(self.pos + 1) == Some(&b'/') => self.skip_line(),
                Some(b'/') if self.src.get(self.pos + 1) == Some(&b'*') => {
                    let start = self.line;
                    self.pos += 2;
                    loop {
                        match self.src.get(self.pos) {
                            None => {
                                return Err(self.err(
                                    source,
                                    start,
                                    "comment /* is never closed".into(),
                                ))
                            }
                            Some(b'*') if self.src.get(self.pos + 1) == Some(&b'/') => {
                                self.pos += 2;
                                break;
                            }
                            Some(b'\n') => {
                                self.line += 1;
                                self.pos += 1;
                            }
                            _ => self.pos += 1,
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    fn skip_line(&mut self) {
        while let Some(&c) = self.src.get(self.pos) {
            if c == b'\n' {
                break;
            }
            self.pos += 1;
        }
    }

    /// The next token and the line where it starts.
    fn next(&mut self, source: &Source) -> Result<(Tok, usize), RecipeError> {
        self.skip_space(source)?;
        let line = self.line;
        let Some(&c) = self.src.get(self.pos) else { return Ok((Tok::End, line)) };
        let tok = match c {
            b'=' | b':' => {
                self.pos += 1;
                Tok::Assign
            }
            b';' => {
                self.pos += 1;
                Tok::Semi
            }
            b',' => {
                self.pos += 1;
                Tok::Comma
            }
            b'{' | b'(' | b'[' => {
                self.pos += 1;
                Tok::Open(c as char)
            }
            b'}' | b')' | b']' => {
                self.pos += 1;
                Tok::Close(c as char)
            }
            b'"' => Tok::Str(self.string(source)?),
            b'0'..=b'9' | b'-' | b'+' | b'.' => self.number(source)?,
            c if c.is_ascii_alphabetic() || c == b'*' => {
                let start = self.pos;
                while let Some(&c) = self.src.get(self.pos) {
                    if c.is_ascii_alphanumeric() || c == b'_' || c == b'-' || c == b'*' {
                        self.pos += 1;
                    } else {
                        break;
                    }
                }
                let word = &self.text[start..self.pos];
                if word.eq_ignore_ascii_case("true") {
                    Tok::Bool(true)
                } else if word.eq_ignore_ascii_case("false") {
                    Tok::Bool(false)
                } else {
                    Tok::Name(word.to_string())
                }
            }
            _ => {
                let ch = self.text[self.pos..].chars().next().unwrap_or('?');
                return Err(self.err(source, line, format!("unexpected character '{ch}'")));
            }
        };
        Ok((tok, line))
    }

    fn string(&mut self, source: &Source) -> Result<String, RecipeError> {
        let start_line = self.line;
        self.pos += 1;
        let mut bytes = Vec::new();
        loop {
            let Some(&c) = self.src.get(self.pos) else {
                return Err(self.err(
                    source,
                    start_line,
                    "string is never closed (missing \")".into(),
                ));
            };
            self.pos += 1;
            match c {
                b'"' => break,
                b'\n' => {
                    return Err(self.err(
                        source,
                        start_line,
                        "string runs past the end of the line (missing \")".into(),
                    ))
                }
                b'\\' => {
                    let e = self.src.get(self.pos).copied();
                    self.pos += 1;
                    match e {
                        Some(b'\\') => bytes.push(b'\\'),
                        Some(b'"') => bytes.push(b'"'),
                        Some(b'n') => bytes.push(b'\n'),
                        Some(b'r') => bytes.push(b'\r'),
                        Some(b't') => bytes.push(b'\t'),
                        Some(b'f') => bytes.push(0x0c),
                        Some(b'x') => {
                            let hex = self
                                .text
                                .get(self.pos..self.pos + 2)
                                .and_then(|h| u8::from_str_radix(h, 16).ok());
                            let Some(b) = hex else {
                                return Err(self.err(
                                    source,
                                    self.line,
                                    "\\x needs two hexadecimal digits".into(),
                                ));
                            };
                            self.pos += 2;
                            bytes.push(b);
                        }
                        _ => {
                            return Err(self.err(
                                source,
                                self.line,
                                "unknown escape in string (known: \\\\ \\\" \\n \\r \\t \\f \\xNN)"
                                    .into(),
                            ))
                        }
                    }
                }
                c => bytes.push(c),
            }
        }
        String::from_utf8(bytes)
            .map_err(|_| self.err(source, start_line, "string is not valid UTF-8".into()))
    }

    fn number(&mut self, source: &Source) -> Result<Tok, RecipeError> {
        let start = self.pos;
        let line = self.line;
        let mut p = self.pos;
        if matches!(self.src.get(p), Some(b'-' | b'+')) {
            p += 1;
        }
        // Hexadecimal.
        if self.src.get(p) == Some(&b'0') && matches!(self.src.get(p + 1), Some(b'x' | b'X')) {
            let digits_start = p + 2;
            let mut q = digits_start;
            while self.src.get(q).is_some_and(u8::is_ascii_hexdigit) {
                q += 1;
            }
            let digits = &self.text[digits_start..q];
            self.pos = q;
            self.skip_long_suffix();
            let v = u64::from_str_radix(digits, 16).map_err(|_| {
                self.err(
                    source,
                    line,
                    format!("bad hexadecimal number {}", &self.text[start..self.pos]),
                )
            })?;
            let v = v as i64; // libconfig's hex64 keeps the bit pattern
            return Ok(Tok::Int(if self.src[start] == b'-' { v.wrapping_neg() } else { v }));
        }
        let mut is_float = false;
        while let Some(&c) = self.src.get(p) {
            match c {
                b'0'..=b'9' => p += 1,
                b'.' => {
                    is_float = true;
                    p += 1;
                }
                b'e' | b'E' => {
                    is_float = true;
                    p += 1;
                    if matches!(self.src.get(p), Some(b'-' | b'+')) {
                        p += 1;
                    }
                }
                _ => break,
            }
        }
        let lexeme = &self.text[start..p];
        self.pos = p;
        if is_float {
            let v: f64 = lexeme
                .parse()
                .map_err(|_| self.err(source, line, format!("bad number {lexeme}")))?;
            Ok(Tok::Float(v))
        } else {
            self.skip_long_suffix();
            let v: i64 = lexeme.parse().map_err(|_| {
                self.err(source, line, format!("bad integer {lexeme} (out of range, or no digits)"))
            })?;
            Ok(Tok::Int(v))
        }
    }

    fn skip_long_suffix(&mut self) {
        if self.src.get(self.pos) == Some(&b'L') {
            self.pos += 1;
            if self.src.get(self.pos) == Some(&b'L') {
                self.pos += 1;
            }
        }
    }
}

struct Parser<'a> {
    lexer: Lexer<'a>,
    source: &'a Source,
    peeked: Option<(Tok, usize)>,
    /// Groups, lists and arrays open around the current token (at most [`MAX_NESTING`]).
    depth: usize,
}

/// Parses a whole configuration (its top-level settings).
pub fn parse(source: &Source) -> Result<Vec<Setting>, RecipeError> {
    let mut p = Parser {
        lexer: Lexer { src: source.text.as_bytes(), text: &source.text, pos: 0, line: 0 },
        source,
        peeked: None,
        depth: 0,
    };
    let settings = p.settings(None)?;
    Ok(settings)
}

impl Parser<'_> {
    fn peek(&mut self) -> Result<&(Tok, usize), RecipeError> {
        if self.peeked.is_none() {
            self.peeked = Some(self.lexer.next(self.source)?);
        }
        Ok(self.peeked.as_ref().expect("just set"))
    }

    fn bump(&mut self) -> Result<(Tok, usize), RecipeError> {
        match self.peeked.take() {
            Some(t) => Ok(t),
            None => self.lexer.next(self.source),
        }
    }

    fn err(&self, line: usize, msg: String) -> RecipeError {
        let (f, l) = self.source.place(line);
        RecipeError::new(RecipeErrorKind::Syntax(msg)).at(f, l)
    }

    /// Settings until `close` (or the end of the file when `None`).
    fn settings(&mut self, close: Option<(char, usize)>) -> Result<Vec<Setting>, RecipeError> {
        let mut out: Vec<Setting> = Vec::new();
        // Name -> index in `out`, for the duplicate check.
        let mut seen: BTreeMap<String, usize> = BTreeMap::new();
        loop {
            let (tok, line) = self.bump()?;
            match tok {
                Tok::End => {
                    return match close {
                        None => Ok(out),
                        Some((c, open_line)) => {
                            let (_, l) = self.source.place(open_line);
                            Err(self.err(
                                line,
                                format!("group opened at line {l} is never closed with '{c}'"),
                            ))
                        }
                    }
                }
                Tok::Close(c) if close.is_some_and(|(cc, _)| cc == c) => return Ok(out),
                Tok::Name(name) => {
                    let (t, l) = self.bump()?;
                    if t != Tok::Assign {
                        return Err(self.err(
                            l,
                            format!("expected '=' or ':' after {name}, found {}", describe_tok(&t)),
                        ));
                    }
                    let value = self.value(&name)?;
                    if matches!(self.peek()?.0, Tok::Semi | Tok::Comma) {
                        self.bump()?;
                    }
                    if let Some(&prev) = seen.get(&name) {
                        let (_, pl) = self.source.place(out[prev].at);
                        return Err(self.err(line, format!("setting {name} appears twice in the same group (first at line {pl})")));
                    }
                    seen.insert(name.clone(), out.len());
                    out.push(Setting { name, at: line, value });
                }
                t => {
                    let what =
                        if close.is_some() { "a setting name or '}'" } else { "a setting name" };
                    return Err(
                        self.err(line, format!("expected {what}, found {}", describe_tok(&t)))
                    );
                }
            }
        }
    }

    fn value(&mut self, setting: &str) -> Result<Node, RecipeError> {
        let (tok, line) = self.bump()?;
        let opens = matches!(tok, Tok::Open(_));
        if opens {
            if self.depth >= MAX_NESTING {
                let (f, l) = self.source.place(line);
                return Err(RecipeError::new(RecipeErrorKind::Limit(format!(
                    "{setting}: values nested deeper than {MAX_NESTING} levels of {{ }}, ( ) and [ ]"
                )))
                .at(f, l));
            }
            self.depth += 1;
        }
        let value = self.open_value(tok, line, setting);
        if opens {
            self.depth -= 1;
        }
        Ok(Node { value: value?, at: line })
    }

    /// The value that starts with `tok` (its nesting already counted when it opens one).
    fn open_value(&mut self, tok: Tok, line: usize, setting: &str) -> Result<Value, RecipeError> {
        let value = match tok {
            Tok::Bool(b) => Value::Bool(b),
            Tok::Int(i) => Value::Int(i),
            Tok::Float(f) => Value::Float(f),
            Tok::Str(mut s) => {
                while let Tok::Str(_) = self.peek()?.0 {
                    if let (Tok::Str(more), _) = self.bump()? {
                        s.push_str(&more);
                    }
                }
                Value::Str(s)
            }
            Tok::Open('{') => Value::Group(self.settings(Some(('}', line)))?),
            Tok::Open('(') => Value::List(self.sequence(')', line, setting)?),
            Tok::Open('[') => {
                let items = self.sequence(']', line, setting)?;
                let mut kind = None;
                for item in &items {
                    let Some(k) = item.value.scalar_kind() else {
                        return Err(self.err(item.at, format!("an array [ ] holds scalars only, found {} in {setting} (use a list ( ) instead)", item.value.describe())));
                    };
                    if *kind.get_or_insert(k) != k {
                        return Err(self.err(item.at, format!("array of {setting} mixes element types ({})", item.value.describe())));
                    }
                }
                Value::Array(items)
            }
            Tok::Name(n) => return Err(self.err(line, format!("expected a value for {setting}, found the bare name {n} (a string needs quotes; a macro needs its #define)"))),
            t => return Err(self.err(line, format!("expected a value for {setting}, found {}", describe_tok(&t)))),
        };
        Ok(value)
    }

    fn sequence(
        &mut self,
        close: char,
        open_line: usize,
        setting: &str,
    ) -> Result<Vec<Node>, RecipeError> {
        let mut items = Vec::new();
        loop {
            match self.peek()? {
                (Tok::Close(c), _) if *c == close => {
                    self.bump()?;
                    return Ok(items);
                }
                (Tok::End, line) => {
                    let line = *line;
                    let (_, l) = self.source.place(open_line);
                    return Err(self.err(
                        line,
                        format!(
                            "'{}' opened at line {l} for {setting} is never closed with '{close}'",
                            if close == ')' { '(' } else { '[' }
                        ),
                    ));
                }
                _ => {}
            }
            items.push(self.value(setting)?);
            let (t, line) = self.bump()?;
            match t {
                Tok::Comma => {}
                Tok::Close(c) if c == close => return Ok(items),
                t => {
                    return Err(self.err(
                        line,
                        format!(
                            "expected ',' or '{close}' in {setting}, found {}",
                            describe_tok(&t)
                        ),
                    ))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn parse_text(t: &str) -> Result<Vec<Setting>, RecipeError> {
        let options = crate::recipe::ReadOptions::default();
        parse(&crate::recipe::preprocess::load(t, Path::new("t.cfg"), &options).unwrap())
    }

    #[test]
    fn scalars_and_comments() {
        let s = parse_text("a = 1; b : -2.5e1, c = 0x1F; d = 12L; e = TRUE; # x\nf = \"x\\ty\" /* c */ \"z\"; // end\ng = .5;").unwrap();
        let v: Vec<&Value> = s.iter().map(|s| &s.value.value).collect();
        assert_eq!(
            v,
            [
                &Value::Int(1),
                &Value::Float(-25.0),
                &Value::Int(31),
                &Value::Int(12),
                &Value::Bool(true),
                &Value::Str("x\tyz".into()),
                &Value::Float(0.5)
            ]
        );
        assert_eq!(s[5].at, 1);
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse_text("a = 1;\nb = [1, \"x\"];").unwrap_err();
        assert_eq!(e.line, Some(2), "{e}");
        let e = parse_text("a = {\n b = 1;\n").unwrap_err();
        assert!(e.to_string().contains("never closed"), "{e}");
        let e = parse_text("a = 1;\n\n a = 2;").unwrap_err();
        assert!(e.to_string().contains("twice") && e.line == Some(3), "{e}");
        let e = parse_text("x = [ GUIDEVANE ];").unwrap_err();
        assert!(e.to_string().contains("#define"), "{e}");
    }
}
