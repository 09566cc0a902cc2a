//! A whitespace tokenizer over a byte slice that knows its line, for the ASCII formats.
//!
//! Hand-written rather than built on a parser crate because the ASCII readers spend
//! almost all their time here: tokens are slices of the input (no allocation), numbers
//! go through `fast-float2`, and the line counter advances only when a newline is
//! skipped, so every error can name its line at no extra cost.
//!
//! Writers use [`push_f64`] / [`push_int`]: shortest round-trip decimal (`ryu`), so
//! that what is written reads back bit for bit.

use crate::error::{Error, ErrorKind, Result};

/// A cursor over the tokens of a text file.
#[derive(Debug, Clone)]
pub struct Tokens<'a> {
    data: &'a [u8],
    pos: usize,
    line: u64,
    comment: Option<u8>,
}

/// At most this many bytes of a token are quoted in a message, so that a 2-million-digit
/// number gives a short error.
const QUOTE_MAX: usize = 40;

/// Characters that make a token look right but read wrong, and what to call them.
const INVISIBLE: [(&str, &str); 6] = [
    ("\u{feff}", "a byte order mark (U+FEFF)"),
    ("\u{a0}", "a no-break space (U+00A0)"),
    ("\u{202f}", "a narrow no-break space (U+202F)"),
    ("\u{200b}", "a zero-width space (U+200B)"),
    ("\u{2009}", "a thin space (U+2009)"),
    ("\u{3000}", "an ideographic space (U+3000)"),
];

/// At most the first [`QUOTE_MAX`] bytes of `tok` (cut at a character boundary), with
/// `…` when cut.
pub(crate) fn quote_prefix(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(&tok[..tok.len().min(QUOTE_MAX + 4)]);
    let mut cut: String = s
        .chars()
        .scan(0, |n, c| {
            *n += c.len_utf8();
            (*n <= QUOTE_MAX).then_some(c)
        })
        .collect();
    if cut.len() < tok.len() {
        cut.push('…');
    }
    cut
}

/// A token as messages quote it: a bounded prefix in backticks, followed by the
/// invisible characters it holds, named (a byte order mark, a no-break space, a control
/// byte), since the quote alone shows nothing wrong.
pub(crate) fn show(tok: &[u8]) -> String {
    let mut out = format!("`{}`", quote_prefix(tok));
    let text = String::from_utf8_lossy(tok);
    let mut named: Vec<&str> =
        INVISIBLE.iter().filter(|(c, _)| text.contains(c)).map(|&(_, n)| n).collect();
    if tok.iter().any(|&b| b < 0x20 || b == 0x7f) {
        named.push("a control character");
    }
    if !named.is_empty() {
        out.push_str(&format!(" (it holds {})", named.join(" and ")));
    }
    out
}

impl<'a> Tokens<'a> {
    /// A cursor at the start of `data`, line 1, without comment handling.
    pub fn new(data: &'a [u8]) -> Self {
        Tokens { data, pos: 0, line: 1, comment: None }
    }

    /// A cursor that skips everything from `marker` to the end of a line (`#` for
    /// Triangle, Medit and OBJ).
    pub fn with_comments(data: &'a [u8], marker: u8) -> Self {
        Tokens { data, pos: 0, line: 1, comment: Some(marker) }
    }

    /// Current 1-based line (of the last token returned, or of the cursor when the
    /// token has not been read yet).
    pub fn line(&self) -> u64 {
        self.line
    }

    /// Current byte offset.
    pub fn pos(&self) -> usize {
        self.pos
    }

    /// The bytes not consumed yet.
    pub fn remaining(&self) -> &'a [u8] {
        &self.data[self.pos..]
    }

    /// The whole input.
    pub fn data(&self) -> &'a [u8] {
        self.data
    }

    /// Moves the cursor to byte `pos`, counting the newlines passed (for readers that
    /// read a binary block and then continue with text).
    pub fn seek(&mut self, pos: usize) {
        let pos = pos.min(self.data.len());
        if pos >= self.pos {
            self.line += memchr::memchr_iter(b'\n', &self.data[self.pos..pos]).count() as u64;
        }
        self.pos = pos;
    }

    /// Skips spaces, tabs, carriage returns, newlines and comments.
    #[inline]
    pub fn skip_space(&mut self) {
        let d = self.data;
        while self.pos < d.len() {
            match d[self.pos] {
                b'\n' => {
                    self.line += 1;
                    self.pos += 1;
                }
                b' ' | b'\t' | b'\r' | 0x0b | 0x0c => self.pos += 1,
                c if Some(c) == self.comment => {
                    while self.pos < d.len() && d[self.pos] != b'\n' {
                        self.pos += 1;
                    }
                }
                _ => break,
            }
        }
    }

    /// Skips spaces and tabs but not newlines; returns whether the cursor is now at the
    /// end of a line (or of the file, or at a comment).
    #[inline]
    pub fn at_line_end(&mut self) -> bool {
        let d = self.data;
        while self.pos < d.len() && matches!(d[self.pos], b' ' | b'\t' | b'\r') {
            self.pos += 1;
        }
        self.pos >= d.len() || d[self.pos] == b'\n' || Some(d[self.pos]) == self.comment
    }

    /// The next token, or `None` at the end of the input.
    #[inline]
    // A cursor rather than an `Iterator`: its other methods (line, peek, seek) read and
    // move the same position, which an iterator adaptor would hide.
    #[allow(clippy::should_implement_trait)]
    pub fn next(&mut self) -> Option<&'a [u8]> {
        self.skip_space();
        let d = self.data;
        let start = self.pos;
        while self.pos < d.len()
            && !matches!(d[self.pos], b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c)
        {
            if Some(d[self.pos]) == self.comment {
                break;
            }
            self.pos += 1;
        }
        (self.pos > start).then(|| &d[start..self.pos])
    }

    /// The next token without consuming it. The whitespace before it is consumed (and
    /// its newlines counted once), so the line names the token's line and a following
    /// [`Tokens::next`] does not count those newlines again.
    pub fn peek(&mut self) -> Option<&'a [u8]> {
        self.skip_space();
        let (pos, line) = (self.pos, self.line);
        let t = self.next();
        self.pos = pos;
        self.line = line;
        t
    }

    /// The next token, or an end-of-file error naming `what`.
    #[inline]
    pub fn token(&mut self, what: &str) -> Result<&'a [u8]> {
        match self.next() {
            Some(t) => Ok(t),
            None => Err(Error::at_line(
                self.line,
                ErrorKind::UnexpectedEof { context: format!("expected {what}") },
            )),
        }
    }

    /// Consumes the next token, which must equal `word` (ASCII case-insensitive when
    /// `ignore_case`).
    pub fn expect(&mut self, word: &str, ignore_case: bool) -> Result<()> {
        let t = self.token(&format!("`{word}`"))?;
        let ok = if ignore_case {
            t.eq_ignore_ascii_case(word.as_bytes())
        } else {
            t == word.as_bytes()
        };
        if ok {
            Ok(())
        } else {
            Err(Error::expected(self.line, format!("`{word}`"), show(t)))
        }
    }

    /// The rest of the current line (without the newline), trimmed; the cursor moves
    /// to the start of the next line.
    pub fn rest_of_line(&mut self) -> &'a [u8] {
        let d = self.data;
        let start = self.pos;
        let end = memchr::memchr(b'\n', &d[start..]).map_or(d.len(), |i| start + i);
        self.pos = end;
        if end < d.len() {
            self.pos += 1;
            self.line += 1;
        }
        trim(&d[start..end])
    }

    /// Parses the next token as a float; `what` names it in errors. NaN and infinities
    /// are refused.
    #[inline]
    pub fn f64(&mut self, what: &str) -> Result<f64> {
        let t = self.token(what)?;
        parse_f64(t).map_err(|_| Error::expected(self.line, what, show(t))).and_then(|v| {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(Error::at_line(
                    self.line,
                    ErrorKind::NonFinite { what: what.into(), value: show(t) },
                ))
            }
        })
    }

    /// Parses the next token as a signed integer.
    #[inline]
    pub fn i64(&mut self, what: &str) -> Result<i64> {
        let t = self.token(what)?;
        parse_i64(t).ok_or_else(|| Error::expected(self.line, what, show(t)))
    }

    /// Parses the next token as an `i32` (tags).
    #[inline]
    pub fn i32(&mut self, what: &str) -> Result<i32> {
        let line = self.line;
        let v = self.i64(what)?;
        i32::try_from(v).map_err(|_| {
            Error::expected(
                line.max(self.line),
                format!("{what} (a 32-bit integer)"),
                v.to_string(),
            )
        })
    }

    /// Parses the next token as a non-negative integer.
    #[inline]
    pub fn usize(&mut self, what: &str) -> Result<usize> {
        let t = self.token(what)?;
        match parse_i64(t) {
            Some(v) if v >= 0 => Ok(v as usize),
            _ => {
                Err(Error::expected(self.line, format!("{what} (a non-negative integer)"), show(t)))
            }
        }
    }

    /// Parses a count announced by a header and checks it against the bytes left:
    /// each item needs at least `min_bytes_per_item` bytes, so a file that claims
    /// 10^15 nodes is refused before anything is allocated.
    pub fn count(&mut self, what: &str, min_bytes_per_item: usize) -> Result<usize> {
        let n = self.usize(what)?;
        check_count(n, self.data.len() - self.pos, min_bytes_per_item, what)
            .map_err(|k| Error::at_line(self.line, k))
    }

    /// An error at the current line.
    pub fn error(&self, kind: ErrorKind) -> Error {
        Error::at_line(self.line, kind)
    }

    /// A syntax error at the current line.
    pub fn expected(&self, expected: impl Into<String>, found: &[u8]) -> Error {
        Error::expected(self.line, expected, show(found))
    }
}

/// `data` with every lone carriage return (old Mac line ends, not followed by `\n`) made
/// a newline, as tobj and most readers take it; borrowed when there is none. Readers of
/// line-based formats call it first, so that a CR-only file is not one long line (or one
/// long comment).
pub(crate) fn lone_cr_as_newline(data: &[u8]) -> std::borrow::Cow<'_, [u8]> {
    let lone = |i: usize| data.get(i + 1) != Some(&b'\n');
    match memchr::memchr_iter(b'\r', data).find(|&i| lone(i)) {
        None => std::borrow::Cow::Borrowed(data),
        Some(first) => {
            let mut out = data.to_vec();
            for i in memchr::memchr_iter(b'\r', &data[first..]).map(|i| i + first) {
                if lone(i) {
                    out[i] = b'\n';
                }
            }
            std::borrow::Cow::Owned(out)
        }
    }
}

/// Checks that `n` items of at least `min_bytes_per_item` bytes each fit in
/// `bytes_left` bytes.
pub fn check_count(
    n: usize,
    bytes_left: usize,
    min_bytes_per_item: usize,
    what: &str,
) -> std::result::Result<usize, ErrorKind> {
    if (n as u128) * (min_bytes_per_item.max(1) as u128) > bytes_left as u128 {
        Err(ErrorKind::ImplausibleCount {
            what: what.into(),
            count: n as u64,
            limit: format!(
                "{bytes_left} bytes remain, at least {min_bytes_per_item} needed per item"
            ),
        })
    } else {
        Ok(n)
    }
}

/// ASCII-trims spaces, tabs and carriage returns.
pub fn trim(mut s: &[u8]) -> &[u8] {
    while let [b' ' | b'\t' | b'\r', rest @ ..] = s {
        s = rest;
    }
    while let [rest @ .., b' ' | b'\t' | b'\r'] = s {
        s = rest;
    }
    s
}

/// Parses a float token (also Fortran-style `1.0D+03`, which some Medit writers emit).
#[inline]
// The callers turn `Err(())` into an error naming the file, line and token, which only
// they know.
#[allow(clippy::result_unit_err)]
pub fn parse_f64(t: &[u8]) -> std::result::Result<f64, ()> {
    match fast_float2::parse::<f64, _>(t) {
        Ok(v) => Ok(v),
        Err(_) => {
            if t.iter().any(|&c| c == b'd' || c == b'D') {
                let s: Vec<u8> =
                    t.iter().map(|&c| if c == b'd' || c == b'D' { b'e' } else { c }).collect();
                fast_float2::parse::<f64, _>(&s).map_err(|_| ())
            } else {
                Err(())
            }
        }
    }
}

/// Parses a decimal integer token with an optional sign.
#[inline]
pub fn parse_i64(t: &[u8]) -> Option<i64> {
    let (neg, digits) = match t {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, t),
    };
    if digits.is_empty() || digits.len() > 19 {
        return None;
    }
    let mut v: i64 = 0;
    for &c in digits {
        if !c.is_ascii_digit() {
            return None;
        }
        v = v.checked_mul(10)?.checked_add((c - b'0') as i64)?;
    }
    Some(if neg { -v } else { v })
}

/// Appends the shortest decimal that reads back as exactly `v`. Integral values are
/// written without a fraction (`3`, not `3.0`) where `integral_plain` is set, as
/// several tools' own writers do.
#[inline]
pub fn push_f64(out: &mut Vec<u8>, v: f64) {
    let mut b = ryu::Buffer::new();
    let s = b.format(v);
    // ryu writes `1e-5`, `1e20`, `0.1`, `3.0`: all read back exactly by strtod,
    // std::istream, fast-float and Python's float().
    out.extend_from_slice(s.as_bytes());
}

/// Appends a decimal integer.
#[inline]
pub fn push_int<I: itoa::Integer>(out: &mut Vec<u8>, v: I) {
    let mut b = itoa::Buffer::new();
    out.extend_from_slice(b.format(v).as_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_track_lines_and_comments() {
        let mut t = Tokens::with_comments(b"# head\n 1 2.5 # c\n\n  -3\n", b'#');
        assert_eq!(t.usize("a").unwrap(), 1);
        assert_eq!(t.line(), 2);
        assert_eq!(t.f64("b").unwrap(), 2.5);
        assert_eq!(t.i64("c").unwrap(), -3);
        assert_eq!(t.line(), 4);
        assert!(t.next().is_none());
    }

    #[test]
    fn peek_then_next_counts_each_newline_once() {
        let mut t = Tokens::with_comments(b"a\n\n  b # note\nc\n", b'#');
        assert_eq!(t.next(), Some(&b"a"[..]));
        assert_eq!(t.peek(), Some(&b"b"[..]));
        assert_eq!(t.line(), 3);
        assert_eq!(t.peek(), Some(&b"b"[..]));
        assert_eq!(t.next(), Some(&b"b"[..]));
        assert_eq!(t.line(), 3);
        assert_eq!(t.next(), Some(&b"c"[..]));
        assert_eq!(t.line(), 4);
        assert_eq!(t.peek(), None);
        assert_eq!(t.next(), None);
        assert_eq!(t.line(), 5);
    }

    #[test]
    fn errors_name_the_line() {
        let mut t = Tokens::new(b"1\n2\nx\n");
        t.usize("a").unwrap();
        t.usize("b").unwrap();
        let e = t.f64("coordinate").unwrap_err();
        assert_eq!(e.to_string(), "<stdin>:3: expected coordinate, found `x`");
    }

    #[test]
    fn nan_is_refused() {
        let e = Tokens::new(b"nan").f64("x").unwrap_err();
        assert!(matches!(e.kind, ErrorKind::NonFinite { .. }));
    }

    #[test]
    fn huge_counts_are_refused_before_allocation() {
        let e = Tokens::new(b"1000000000000000 1 2 3").count("nodes", 8).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::ImplausibleCount { .. }));
    }

    #[test]
    fn floats_round_trip_bitwise() {
        for v in [0.1, 1.0 / 3.0, 1e-300, -2.5e17, 123456789.12345679, 5e-324] {
            let mut out = Vec::new();
            push_f64(&mut out, v);
            assert_eq!(parse_f64(&out).unwrap().to_bits(), v.to_bits());
        }
    }

    #[test]
    fn fortran_exponent() {
        assert_eq!(parse_f64(b"1.5D+02").unwrap(), 150.0);
    }
}
