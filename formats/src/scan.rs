//! A fast path for the big numeric blocks of ASCII files (Triangle's records, Medit's
//! vertices and elements): plain numbers separated by ASCII blanks, read with a bare
//! cursor. It never reports errors: at anything unusual (a comment, a missing field, a
//! non-finite or malformed number) it gives up, and the reader redoes that record with
//! [`crate::text::Tokens`], which says precisely what is wrong and where. The reader then
//! moves the tokenizer past what the fast path consumed with `Tokens::seek`, which
//! counts the newlines crossed, so line numbers stay right.

/// A cursor over bytes.
pub(crate) struct Scan<'a> {
    d: &'a [u8],
    /// Byte offset of the cursor.
    pub pos: usize,
}

#[inline(always)]
fn is_delimiter(c: u8) -> bool {
    matches!(c, b' ' | b'\t' | b'\r' | b'\n')
}

impl<'a> Scan<'a> {
    /// A cursor at `pos` of `d`.
    pub fn new(d: &'a [u8], pos: usize) -> Self {
        Scan { d, pos }
    }

    /// Skips blanks and newlines (free-format files).
    #[inline(always)]
    pub fn ws(&mut self) {
        while self.pos < self.d.len() && is_delimiter(self.d[self.pos]) {
            self.pos += 1;
        }
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
        assert_eq!(s.pos, 4);
    }
}
