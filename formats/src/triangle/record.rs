//! Triangle's records: one line each, its fields read left to right ([`Rec`]: a missing
//! required field is an error at that line, a missing optional field takes its default,
//! extra fields are ignored), and the fast path that reads runs of plain records with
//! the crate's scanner and leaves the first unusual one to `Rec`.

use crate::error::{Error, ErrorKind, Result};
use crate::scan::Scan;
use crate::text::{check_count, parse_f64, parse_i64, Tokens};
use crate::{NodeIndex, MAX_POINTS};

/// Moves to the next record (skipping blank lines and comments) and returns its line;
/// an end-of-file error naming `what` when there is none.
pub(crate) fn start(t: &mut Tokens<'_>, what: impl FnOnce() -> String) -> Result<u64> {
    t.skip_space();
    if t.remaining().is_empty() {
        return Err(t.error(ErrorKind::UnexpectedEof { context: format!("expected {}", what()) }));
    }
    Ok(t.line())
}

/// The fields of one record (one line), read left to right. Triangle reads a record from
/// one line only: a missing required field is an error at that line, a missing optional
/// field takes its default, extra fields are ignored.
pub(crate) struct Rec<'t, 'a> {
    pub(crate) t: &'t mut Tokens<'a>,
    pub(crate) line: u64,
    pub(crate) item: &'static str,
    pub(crate) num: usize,
}

impl<'t, 'a> Rec<'t, 'a> {
    pub(crate) fn new(t: &'t mut Tokens<'a>, line: u64, item: &'static str, num: usize) -> Self {
        Rec { t, line, item, num }
    }

    pub(crate) fn describe(&self, what: &str) -> String {
        if self.num == 0 {
            format!("{what} in the {}", self.item)
        } else {
            format!("{what} of {} {}", self.item, self.num)
        }
    }

    /// Whether another field follows on this line.
    #[inline]
    pub(crate) fn more(&mut self) -> bool {
        !self.t.at_line_end()
    }

    #[inline]
    pub(crate) fn tok(&mut self, what: &str) -> Result<&'a [u8]> {
        if self.t.at_line_end() {
            return Err(Error::expected(self.line, self.describe(what), "end of line"));
        }
        match self.t.next() {
            Some(tok) => Ok(tok),
            None => Err(Error::expected(self.line, self.describe(what), "end of file")),
        }
    }

    #[inline]
    pub(crate) fn f64(&mut self, what: &str) -> Result<f64> {
        let tok = self.tok(what)?;
        match parse_f64(tok) {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(Error::at_line(
                self.line,
                ErrorKind::NonFinite { what: self.describe(what), value: crate::text::show(tok) },
            )),
            Err(()) => Err(self.bad(what, tok)),
        }
    }

    #[inline]
    pub(crate) fn opt_f64(&mut self, what: &str, default: f64) -> Result<f64> {
        if self.more() {
            self.f64(what)
        } else {
            Ok(default)
        }
    }

    #[inline]
    pub(crate) fn int(&mut self, what: &str) -> Result<i64> {
        let tok = self.tok(what)?;
        parse_i64(tok).ok_or_else(|| self.bad(&format!("{what} (an integer)"), tok))
    }

    #[inline]
    pub(crate) fn opt_int(&mut self, what: &str, default: i64) -> Result<i64> {
        if self.more() {
            self.int(what)
        } else {
            Ok(default)
        }
    }

    /// An optional marker: an integer that fits in 32 bits.
    #[inline]
    pub(crate) fn opt_marker(&mut self) -> Result<i32> {
        let v = self.opt_int("boundary marker", 0)?;
        i32::try_from(v).map_err(|_| {
            Error::expected(
                self.line,
                self.describe("boundary marker (a 32-bit integer)"),
                v.to_string(),
            )
        })
    }

    /// A count of items that need at least `min_bytes` bytes each in what remains.
    pub(crate) fn count(&mut self, what: &str, min_bytes: usize) -> Result<usize> {
        let v = self.int(what)?;
        self.check_count(what, v, min_bytes)
    }

    pub(crate) fn check_count(&self, what: &str, v: i64, min_bytes: usize) -> Result<usize> {
        if v < 0 {
            return Err(Error::expected(
                self.line,
                format!("{what} (a non-negative integer)"),
                v.to_string(),
            ));
        }
        let n = usize::try_from(v).unwrap_or(usize::MAX);
        check_count(n, self.t.remaining().len(), min_bytes, what)
            .map_err(|k| Error::at_line(self.line, k))
    }

    /// A vertex index as written, turned into a 0-based index below `n`.
    #[inline]
    pub(crate) fn index(&mut self, what: &str, base: i64, n: usize) -> Result<NodeIndex> {
        let v = self.int(what)?;
        match v.checked_sub(base) {
            Some(i) if i >= 0 && (i as u64) < n.min(MAX_POINTS) as u64 => Ok(i as NodeIndex),
            _ => {
                let mut what = self.describe(what);
                if v < base {
                    what.push_str(&format!(", numbered from {base} as the first vertex is,"));
                }
                Err(Error::at_line(
                    self.line,
                    ErrorKind::IndexOutOfRange { what, index: v, available: n },
                ))
            }
        }
    }

    /// The item number at the start of a record: checked to be an integer, otherwise
    /// ignored (Triangle numbers items by position).
    #[inline]
    pub(crate) fn number(&mut self) -> Result<i64> {
        self.int("number")
    }

    pub(crate) fn bad(&self, what: &str, tok: &[u8]) -> Error {
        Error::expected(self.line, self.describe(what), crate::text::show(tok))
    }

    /// Skips whatever else is on the line.
    #[inline]
    pub(crate) fn end(self) {
        self.t.rest_of_line();
    }
}

// ---------------------------------------------------------------------------------------
// The fast path: whole records of plain numbers on one line each
// ---------------------------------------------------------------------------------------

/// Records with more attributes than this always take the general path.
pub(crate) const FAST_ATTRIBUTES: usize = 8;

impl Scan<'_> {
    #[inline(always)]
    pub(crate) fn next_f64(&mut self) -> Option<f64> {
        self.blank();
        self.f64()
    }

    #[inline(always)]
    pub(crate) fn next_i32(&mut self) -> Option<i32> {
        self.blank();
        self.int().and_then(|v| i32::try_from(v).ok())
    }

    #[inline(always)]
    pub(crate) fn next_index(&mut self, base: i64, n: usize) -> Option<NodeIndex> {
        self.blank();
        let v = self.int()?.checked_sub(base)?;
        (v >= 0 && (v as u64) < n.min(MAX_POINTS) as u64).then_some(v as NodeIndex)
    }
}

/// Reads up to `max` records `<number> <fields...>` whose fields `fields` parses, and
/// hands each to `push`, as long as every record is complete, on one line, and nothing
/// else is on that line. Returns how many were read; the tokenizer is moved past them,
/// and the general path takes the record that stopped it (with its defaults, comments
/// and errors).
#[inline(always)]
pub(crate) fn fast<R>(
    t: &mut Tokens<'_>,
    max: usize,
    mut fields: impl FnMut(&mut Scan<'_>) -> Option<R>,
    mut push: impl FnMut(R),
    enabled: bool,
) -> usize {
    if !enabled {
        return 0;
    }
    let mut s = Scan::new(t.data(), t.pos());
    let (mut done, mut end) = (0, t.pos());
    while done < max {
        s.ws();
        if s.int().is_none() {
            break;
        }
        let Some(r) = fields(&mut s) else { break };
        if !s.eol() {
            break;
        }
        push(r);
        done += 1;
        end = s.pos;
    }
    t.seek(end);
    done
}
