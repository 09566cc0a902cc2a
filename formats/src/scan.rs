//! The crate's one fast path for the big numeric blocks of ASCII files (Triangle's
//! records, Medit's vertices and elements, Gmsh's nodes, elements and data): plain
//! numbers separated by ASCII blanks, read with a bare cursor. It never reports errors:
//! at anything unusual (a comment, a missing field, a non-finite or malformed number) it
//! gives up, and the reader redoes that record with [`crate::text::Tokens`], which says
//! precisely what is wrong and where.
//!
//! Lines: [`Scan::ws`] and [`Scan::eol`] count the newlines they cross, from the line
//! the scanner was started on ([`Scan::on_line`]), so a reader can check that a record
//! stays on its line ([`Scan::line`], [`Scan::at_line_end`]) without going back to the
//! tokenizer (Gmsh's readers do). Readers that check with [`Scan::eol`] instead
//! (Triangle, Medit) move the tokenizer past what the fast path consumed with
//! `Tokens::seek`, which counts the newlines crossed itself. After a miss, the reader
//! resumes the tokenizer at [`Scan::start`], where the token that failed begins.

/// A cursor over bytes.
pub(crate) struct Scan<'a> {
    d: &'a [u8],
    /// Byte offset of the cursor.
    pub pos: usize,
    /// The line of the cursor (1-based when started with [`Scan::on_line`]).
    line: u64,
    /// Where the last blanks skipped by [`Scan::ws`] end: the start of the next token.
    start: usize,
}

#[inline(always)]
fn is_delimiter(c: u8) -> bool {
    matches!(c, b' ' | b'\t' | b'\r' | b'\n')
}

impl<'a> Scan<'a> {
    /// A cursor at `pos` of `d`, its lines counted from 0.
    pub fn new(d: &'a [u8], pos: usize) -> Self {
        Scan::on_line(d, pos, 0)
    }

    /// A cursor at `pos` of `d`, which is on line `line`.
    pub fn on_line(d: &'a [u8], pos: usize, line: u64) -> Self {
        Scan { d, pos, line, start: pos }
    }

    /// Skips blanks and newlines (free-format files), counting the newlines; the next
    /// token starts here ([`Scan::start`]).
    #[inline(always)]
    pub fn ws(&mut self) {
        while let Some(&c) = self.d.get(self.pos) {
            match c {
                b' ' | b'\t' | b'\r' => {}
                b'\n' => self.line += 1,
                _ => break,
            }
            self.pos += 1;
        }
        self.start = self.pos;
    }

    /// Where the token after the last [`Scan::ws`] starts.
    #[inline]
    pub fn start(&self) -> usize {
        self.start
    }

    /// The line of the cursor.
    #[inline]
    pub fn line(&self) -> u64 {
        self.line
    }

    /// Bytes not read yet.
    #[inline]
    pub fn bytes_left(&self) -> usize {
        self.d.len() - self.pos
    }

    /// Whether only blanks remain on the current line.
    #[inline]
    pub fn at_line_end(&self) -> bool {
        let mut p = self.pos;
        while let Some(&c) = self.d.get(p) {
            match c {
                b' ' | b'\t' | b'\r' => p += 1,
                b'\n' => return true,
                _ => return false,
            }
        }
        true
    }

    /// An unsigned decimal integer of at most 19 digits (no sign) at the cursor,
    /// followed by a delimiter or the end; the cursor does not move when there is none.
    #[inline(always)]
    pub fn uint(&mut self) -> Option<u64> {
        let mut v: u64 = 0;
        let mut p = self.pos;
        while let Some(&c) = self.d.get(p) {
            let digit = c.wrapping_sub(b'0');
            if digit > 9 {
                break;
            }
            v = v.wrapping_mul(10).wrapping_add(digit as u64);
            p += 1;
        }
        // 19 digits cannot overflow a u64; longer numbers go to the careful parser.
        if p == self.pos || p - self.pos > 19 || !(p >= self.d.len() || is_delimiter(self.d[p])) {
            return None;
        }
        self.pos = p;
        Some(v)
    }

    /// Skips spaces and tabs (line-based files).
    #[inline(always)]
    pub fn blank(&mut self) {
        while self.pos < self.d.len() && matches!(self.d[self.pos], b' ' | b'\t') {
            self.pos += 1;
        }
    }

    /// Whether the number that ends here is followed by a delimiter or the end.
    #[inline(always)]
    fn ends_token(&self) -> bool {
        self.pos >= self.d.len() || is_delimiter(self.d[self.pos])
    }

    /// A decimal integer with an optional sign, at most 18 digits, at the cursor.
    #[inline(always)]
    pub fn int(&mut self) -> Option<i64> {
        let d = self.d;
        let mut p = self.pos;
        let neg = match d.get(p) {
            Some(b'-') => {
                p += 1;
                true
            }
            Some(b'+') => {
                p += 1;
                false
            }
            _ => false,
        };
        let start = p;
        let mut v: i64 = 0;
        while p < d.len() {
            let c = d[p].wrapping_sub(b'0');
            if c > 9 {
                break;
            }
            // A 19th digit could overflow i64: refuse it before multiplying.
            if p - start >= 18 {
                return None;
            }
            v = v * 10 + c as i64;
            p += 1;
        }
        if p == start {
            return None;
        }
        self.pos = p;
        if !self.ends_token() {
            return None;
        }
        Some(if neg { -v } else { v })
    }

    /// A finite float at the cursor.
    #[inline(always)]
    pub fn f64(&mut self) -> Option<f64> {
        let (v, n) = fast_float2::parse_partial::<f64, _>(&self.d[self.pos..]).ok()?;
        if n == 0 || !v.is_finite() {
            return None;
        }
        self.pos += n;
        self.ends_token().then_some(v)
    }

    /// Skips blanks and a carriage return, then consumes the end of the line (or sees
    /// the end of the input). False when something else is there.
    #[inline(always)]
    pub fn eol(&mut self) -> bool {
        while self.pos < self.d.len() && matches!(self.d[self.pos], b' ' | b'\t' | b'\r') {
            self.pos += 1;
        }
        if self.pos >= self.d.len() {
            return true;
        }
        if self.d[self.pos] == b'\n' {
            self.pos += 1;
            self.line += 1;
            return true;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_give_ups() {
        let mut s = Scan::new(b"12 -3 +4 5.5e1 7#c", 0);
        assert_eq!(s.int(), Some(12));
        s.ws();
        assert_eq!(s.int(), Some(-3));
        s.ws();
        assert_eq!(s.int(), Some(4));
        s.ws();
        assert_eq!(s.f64(), Some(55.0));
        s.ws();
        // A comment glued to the number: left to the tokenizer.
        assert_eq!(s.int(), None);
        assert_eq!(Scan::new(b"nan ", 0).f64(), None);
        assert_eq!(Scan::new(b"1.0D+02 ", 0).f64(), None);
        assert_eq!(Scan::new(b"1234567890123456789 ", 0).int(), None);
        assert_eq!(Scan::new(b"999999999999999999 ", 0).int(), Some(999_999_999_999_999_999));
        // Found by fuzzing: 19+ digits used to overflow before the length check.
        assert_eq!(Scan::new(b"99999999999999999999 ", 0).int(), None);
        assert_eq!(Scan::new(b"-9999999999999999999 ", 0).int(), None);
        assert_eq!(Scan::new(b"x", 0).int(), None);
        let mut s = Scan::new(b"1 \r\n2", 0);
        s.int();
        assert!(s.eol());
        assert_eq!((s.pos, s.line()), (4, 1));
    }

    /// Lines counted across blanks and ends of lines, the start of the next token, the
    /// end-of-line look-ahead, and unsigned integers up to 19 digits.
    #[test]
    fn lines_starts_and_unsigned_integers() {
        let mut s = Scan::on_line(b"7 \n\n  12 x\n 9", 0, 3);
        s.ws();
        assert_eq!((s.uint(), s.line(), s.start()), (Some(7), 3, 0));
        assert!(s.at_line_end());
        s.ws();
        assert_eq!((s.uint(), s.line(), s.start()), (Some(12), 5, 6));
        assert!(!s.at_line_end());
        s.ws();
        assert_eq!((s.uint(), s.pos), (None, 9));
        assert_eq!(Scan::new(b"9999999999999999999 ", 0).uint(), Some(9_999_999_999_999_999_999));
        assert_eq!(Scan::new(b"18446744073709551616 ", 0).uint(), None);
        assert_eq!(Scan::new(b"-1 ", 0).uint(), None);
        assert_eq!(Scan::new(b"12a", 0).uint(), None);
        assert_eq!(Scan::new(b"", 0).bytes_left(), 0);
    }
}
