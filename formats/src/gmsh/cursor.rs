//! The reading cursor: text tokens ([`Tokens`]) and binary arrays over the same bytes,
//! positions as lines in ASCII files and byte offsets in binary ones, and the crate's
//! [`Scan`] for the numbers of the big ASCII sections, started on the cursor's line so
//! that the readers can check that an MSH record stays on its line; it falls back to
//! `Tokens` for anything unusual and for every error.

use crate::scan::Scan;
use crate::text::{self, Tokens};
use crate::{Error, ErrorKind, Position, Result};

/// A cursor that reads text tokens and binary arrays from the same bytes, and names
/// lines in ASCII files and byte offsets in binary ones.
pub(super) struct Cursor<'a> {
    /// Tokens over `full[base..]`.
    pub t: Tokens<'a>,
    pub(super) full: &'a [u8],
    /// 0 in ASCII files; in binary ones, where `t` was last restarted, so that moving
    /// past binary data costs nothing (lines are not counted there).
    base: usize,
    pub binary: bool,
}

pub(super) fn show(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(&tok[..tok.len().min(40)]).into_owned();
    if tok.len() > 40 {
        format!("`{s}…`")
    } else {
        format!("`{s}`")
    }
}

impl<'a> Cursor<'a> {
    pub(super) fn new(full: &'a [u8]) -> Self {
        Cursor { t: Tokens::new(full), full, base: 0, binary: false }
    }

    /// Byte offset of the cursor in the file.
    #[inline]
    pub fn pos(&self) -> usize {
        self.base + self.t.pos()
    }

    /// Moves forward to byte offset `abs`.
    #[inline]
    pub fn seek(&mut self, abs: usize) {
        let abs = abs.min(self.full.len());
        if self.binary {
            self.base = abs;
            self.t = Tokens::new(&self.full[abs..]);
        } else {
            self.t.seek(abs.saturating_sub(self.base));
        }
    }

    /// The bytes not read yet.
    pub fn remaining(&self) -> &'a [u8] {
        &self.full[self.pos()..]
    }

    /// Where the cursor is: a byte offset in binary files, a line in ASCII ones.
    pub fn here(&self) -> Position {
        if self.binary {
            Position::Byte(self.pos() as u64)
        } else {
            Position::Line(self.t.line())
        }
    }

    /// Where the next token starts (in a binary file, where the cursor is: binary data
    /// must not be skipped as if it were white space).
    pub fn mark(&mut self) -> Position {
        if !self.binary {
            self.t.skip_space();
        }
        self.here()
    }

    /// Where the token of `len` bytes just read started.
    pub fn here_before(&self, len: usize) -> Position {
        if self.binary {
            Position::Byte(self.pos().saturating_sub(len) as u64)
        } else {
            Position::Line(self.t.line())
        }
    }

    pub fn err(&self, kind: ErrorKind) -> Error {
        Error { path: None, at: Some(self.here()), kind }
    }

    pub fn err_at(&self, at: Position, kind: ErrorKind) -> Error {
        Error { path: None, at: Some(at), kind }
    }

    pub fn byte_err(&self, offset: usize, kind: ErrorKind) -> Error {
        Error::at_byte(offset as u64, kind)
    }

    /// Runs a text read; in a binary file its error is placed at the token's offset.
    #[inline]
    fn text<T>(&mut self, f: impl FnOnce(&mut Tokens<'a>) -> Result<T>) -> Result<T> {
        if self.binary {
            self.t.skip_space();
            let start = self.pos();
            f(&mut self.t).map_err(|mut e| {
                e.at = Some(Position::Byte(start as u64));
                e
            })
        } else {
            f(&mut self.t)
        }
    }

    #[inline]
    pub fn usize(&mut self, what: &str) -> Result<usize> {
        self.text(|t| t.usize(what))
    }

    #[inline]
    pub fn u64(&mut self, what: &str) -> Result<u64> {
        self.text(|t| t.usize(what)).map(|v| v as u64)
    }

    #[inline]
    pub fn i32(&mut self, what: &str) -> Result<i32> {
        self.text(|t| t.i32(what))
    }

    #[inline]
    pub fn i64(&mut self, what: &str) -> Result<i64> {
        self.text(|t| t.i64(what))
    }

    #[inline]
    pub fn f64(&mut self, what: &str) -> Result<f64> {
        self.text(|t| t.f64(what))
    }

    /// A count from a text header, checked against the bytes left.
    pub fn count(&mut self, what: &str, min_bytes_per_item: usize) -> Result<usize> {
        self.text(|t| t.count(what, min_bytes_per_item))
    }

    pub fn token(&mut self, what: &str) -> Result<&'a [u8]> {
        self.text(|t| t.token(what))
    }

    /// The `$End...` line of section `name`.
    pub fn expect_end(&mut self, name: &str) -> Result<()> {
        let end = format!("$End{name}");
        match self.t.next() {
            Some(tok) if tok == end.as_bytes() => Ok(()),
            Some(tok) => {
                let at = self.here_before(tok.len());
                Err(self.err_at(
                    at,
                    ErrorKind::Expected {
                        expected: format!("`{end}` (or fewer items than the section holds)"),
                        found: show(tok),
                    },
                ))
            }
            None => {
                Err(self.err(ErrorKind::UnexpectedEof { context: format!("expected `{end}`") }))
            }
        }
    }

    /// Ends a text line before binary data: the rest of the line must be blank, and the
    /// cursor moves just past its newline.
    pub fn end_text_line(&mut self) -> Result<()> {
        let at = self.here();
        let rest = self.t.rest_of_line();
        if rest.is_empty() {
            Ok(())
        } else {
            Err(self.err_at(
                at,
                ErrorKind::Expected {
                    expected: "the end of the line before binary data".into(),
                    found: show(rest),
                },
            ))
        }
    }

    /// The next `n` bytes of binary data.
    #[inline]
    pub fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        let pos = self.pos();
        let data = self.full;
        if data.len() - pos < n {
            return Err(self.byte_err(
                pos,
                ErrorKind::UnexpectedEof {
                    context: format!("{what}: {n} bytes needed, {} left", data.len() - pos),
                },
            ));
        }
        self.seek(pos + n);
        Ok(&data[pos..pos + n])
    }

    /// `n * size` bytes, with the product checked.
    pub fn take_array(&mut self, n: usize, size: usize, what: &str) -> Result<&'a [u8]> {
        let pos = self.pos();
        let total = n.checked_mul(size).ok_or_else(|| {
            self.byte_err(
                pos,
                ErrorKind::ImplausibleCount {
                    what: what.into(),
                    count: n as u64,
                    limit: "the byte count overflows".into(),
                },
            )
        })?;
        self.take(total, what)
    }

    #[inline]
    pub fn bin_i32(&mut self, what: &str) -> Result<i32> {
        let b = self.take(4, what)?;
        Ok(le_i32(b))
    }

    /// A binary `size_t` of `st` bytes (4 or 8).
    #[inline]
    pub fn bin_size(&mut self, st: usize, what: &str) -> Result<u64> {
        let b = self.take(st, what)?;
        Ok(le_size(b, st))
    }

    /// A binary count, checked against the bytes left.
    pub fn bin_count(&mut self, st: usize, what: &str, min_bytes_per_item: usize) -> Result<usize> {
        let pos = self.pos();
        let n = self.bin_size(st, what)?;
        let left = self.full.len() - self.pos();
        let n = usize::try_from(n).unwrap_or(usize::MAX);
        text::check_count(n, left, min_bytes_per_item, what).map_err(|k| self.byte_err(pos, k))
    }

    /// A binary double that must be finite.
    pub fn bin_f64(&mut self, what: &str) -> Result<f64> {
        let pos = self.pos();
        let v = le_f64(self.take(8, what)?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self
                .byte_err(pos, ErrorKind::NonFinite { what: what.into(), value: v.to_string() }))
        }
    }
}

impl<'a> Cursor<'a> {
    /// A scanner at the cursor.
    pub fn scan(&self) -> Scan<'a> {
        Scan::on_line(self.full, self.pos(), self.t.line())
    }

    /// Moves the cursor to where the scanner is (before an error or a text read).
    pub fn unscan(&mut self, s: &Scan<'a>) {
        self.seek(s.pos);
    }

    #[inline(always)]
    pub fn scan_u64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<u64> {
        s.ws();
        match s.uint() {
            Some(v) => Ok(v),
            None => self.slow_u64(s, what),
        }
    }

    #[cold]
    #[inline(never)]
    fn slow_u64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<u64> {
        self.seek(s.start());
        let v = self.u64(what)?;
        *s = self.scan();
        Ok(v)
    }

    #[inline(always)]
    pub fn scan_i64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<i64> {
        s.ws();
        match s.uint() {
            Some(v) if v <= i64::MAX as u64 => Ok(v as i64),
            _ => self.slow_i64(s, what),
        }
    }

    #[cold]
    #[inline(never)]
    fn slow_i64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<i64> {
        self.seek(s.start());
        let v = self.i64(what)?;
        *s = self.scan();
        Ok(v)
    }

    #[inline(always)]
    pub fn scan_f64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<f64> {
        s.ws();
        match s.f64() {
            Some(v) => Ok(v),
            None => self.slow_f64(s, what),
        }
    }

    /// [`Cursor::scan_f64`] for a data value: NaN and infinities (`nan`, `inf`, as Gmsh
    /// prints them) are kept.
    pub fn scan_value(&mut self, s: &mut Scan<'a>, what: &str) -> Result<f64> {
        s.ws();
        match s.f64() {
            Some(v) => Ok(v),
            None => self.slow_value(s, what),
        }
    }

    #[cold]
    #[inline(never)]
    fn slow_value(&mut self, s: &mut Scan<'a>, what: &str) -> Result<f64> {
        self.seek(s.start());
        let tok = self.token(what)?;
        let v = crate::text::parse_f64(tok).map_err(|_| {
            self.err(ErrorKind::Expected { expected: what.into(), found: show(tok) })
        })?;
        *s = self.scan();
        Ok(v)
    }

    #[cold]
    #[inline(never)]
    fn slow_f64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<f64> {
        self.seek(s.start());
        let v = self.f64(what)?;
        *s = self.scan();
        Ok(v)
    }
}

#[inline]
pub(super) fn le_i32(b: &[u8]) -> i32 {
    i32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

#[inline]
pub(super) fn le_f64(b: &[u8]) -> f64 {
    f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
}

#[inline(always)]
pub(super) fn le_size(b: &[u8], st: usize) -> u64 {
    if st == 8 {
        u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
    } else {
        u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64
    }
}
