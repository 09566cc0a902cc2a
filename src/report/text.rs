//! Text measured before it is placed: the width of a string in the report's font, and
//! strings fitted to a width (cut with an ellipsis, or wrapped at spaces).
//!
//! Widths come from a table of advances, not from the fonts of the machine: the SVG is
//! written before (and without) any rasterising, and the same input must give the same
//! bytes on every machine, whatever fonts it has. The table holds the advance widths of
//! DejaVu Sans and DejaVu Sans Bold (the first family the SVG asks for, and the one the
//! PNG uses where it is installed), in thousandths of an em, read from the fonts' `hmtx`
//! tables for printable ASCII and the few other characters the report prints. DejaVu Sans
//! is wider than the fallbacks the SVG names (Liberation Sans, Arial, Helvetica), so a
//! box measured here holds the text in any of them; a character outside the table counts
//! as a full em (the widest advance of those fonts, CJK ideographs included). Kerning only
//! narrows text. `tests/report.rs` lays every string of a report out with the installed
//! font (usvg) and checks that it fits in the width measured here.

/// Advances of DejaVu Sans, in 1/1000 em, for the characters from ' ' (32) to '~' (126).
const REGULAR: [u16; 95] = [
    318, 401, 460, 838, 636, 950, 780, 275, 390, 390, 500, 838, 318, 361, 318, 337, 636, 636, 636,
    636, 636, 636, 636, 636, 636, 636, 337, 337, 838, 838, 838, 531, 1000, 684, 686, 698, 770, 632,
    575, 775, 752, 295, 295, 656, 557, 863, 748, 787, 603, 787, 695, 635, 611, 732, 684, 989, 685,
    611, 685, 390, 337, 390, 838, 500, 500, 613, 635, 550, 635, 615, 352, 635, 634, 278, 278, 579,
    278, 974, 634, 612, 635, 635, 411, 521, 392, 634, 592, 818, 592, 592, 525, 636, 337, 636, 838,
];

/// Advances of DejaVu Sans Bold, in 1/1000 em, for ' ' (32) to '~' (126).
const BOLD: [u16; 95] = [
    348, 456, 521, 838, 696, 1002, 872, 306, 457, 457, 523, 838, 380, 415, 380, 365, 696, 696, 696,
    696, 696, 696, 696, 696, 696, 696, 400, 400, 838, 838, 838, 580, 1000, 774, 762, 734, 830, 683,
    683, 821, 837, 372, 372, 775, 637, 995, 837, 850, 733, 850, 770, 720, 682, 812, 774, 1103, 771,
    724, 725, 457, 365, 457, 838, 500, 500, 675, 716, 593, 716, 678, 435, 716, 712, 343, 343, 665,
    343, 1042, 712, 687, 716, 716, 493, 595, 478, 712, 652, 924, 645, 652, 582, 712, 365, 712, 838,
];

/// Other characters the report prints: (character, regular, bold) in 1/1000 em.
const OTHER: [(char, u16, u16); 16] = [
    ('…', 1000, 1000),
    ('×', 838, 838),
    ('≥', 838, 838),
    ('≤', 838, 838),
    ('√', 637, 667),
    ('°', 500, 500),
    ('–', 500, 500),
    ('—', 1000, 1000),
    ('·', 318, 380),
    ('é', 615, 678),
    ('è', 615, 678),
    ('µ', 636, 736),
    ('²', 401, 438),
    ('³', 401, 438),
    ('−', 838, 838),
    ('±', 838, 838),
];

/// Advance of a character outside the table, in 1/1000 em (bold: the widest of the
/// table's bold advances).
const UNKNOWN: [u16; 2] = [1000, 1103];

/// Height above the baseline and depth below it of DejaVu Sans's line, in em (its
/// `hhea` ascender 1901 and descender 483 over 2048 units).
pub const ASCENT: f64 = 0.928;
/// See [`ASCENT`].
pub const DESCENT: f64 = 0.236;

/// A font size and weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Font {
    /// Size in pixels.
    pub size: f64,
    /// Bold.
    pub bold: bool,
}

impl Font {
    /// A regular font of `size` pixels.
    pub const fn regular(size: f64) -> Font {
        Font { size, bold: false }
    }

    /// A bold font of `size` pixels.
    pub const fn bold(size: f64) -> Font {
        Font { size, bold: true }
    }

    /// The advance of `c` in pixels.
    pub fn advance(&self, c: char) -> f64 {
        let code = c as u32;
        let milli = if (32..127).contains(&code) {
            let i = (code - 32) as usize;
            if self.bold {
                BOLD[i]
            } else {
                REGULAR[i]
            }
        } else if let Some(&(_, r, b)) = OTHER.iter().find(|o| o.0 == c) {
            if self.bold {
                b
            } else {
                r
            }
        } else if c.is_control() {
            0
        } else {
            UNKNOWN[usize::from(self.bold)]
        };
        f64::from(milli) * 1e-3 * self.size
    }

    /// The width of `s` in pixels: the sum of its advances.
    pub fn width(&self, s: &str) -> f64 {
        s.chars().map(|c| self.advance(c)).sum()
    }

    /// `s` as it is, or cut and ended with "…" so that it is at most `max` pixels wide
    /// (just "…" when not even one character fits).
    pub fn fit(&self, s: &str, max: f64) -> String {
        if self.width(s) <= max {
            return s.to_string();
        }
        let room = max - self.advance('…');
        let mut out = String::new();
        let mut w = 0.0;
        for c in s.chars() {
            let a = self.advance(c);
            if w + a > room {
                break;
            }
            w += a;
            out.push(c);
        }
        let trimmed = out.trim_end().len();
        out.truncate(trimmed);
        out.push('…');
        out
    }

    /// `s` broken at spaces into lines at most `max` pixels wide, at most `max_lines` of
    /// them (at least one); a word longer than a line, or what does not fit in the last
    /// line, is cut with "…".
    pub fn wrap(&self, s: &str, max: f64, max_lines: usize) -> Vec<String> {
        let max_lines = max_lines.max(1);
        let mut lines: Vec<String> = Vec::new();
        let mut words = s.split(' ').filter(|w| !w.is_empty()).peekable();
        while let Some(first) = words.next() {
            if lines.len() + 1 == max_lines {
                // The last line takes the rest.
                let mut rest = first.to_string();
                for w in words.by_ref() {
                    rest.push(' ');
                    rest.push_str(w);
                }
                lines.push(self.fit(&rest, max));
                break;
            }
            let mut line = first.to_string();
            while let Some(w) = words.peek() {
                if self.width(&line) + self.advance(' ') + self.width(w) > max {
                    break;
                }
                line.push(' ');
                line.push_str(w);
                words.next();
            }
            lines.push(self.fit(&line, max));
        }
        if lines.is_empty() {
            lines.push(String::new());
        }
        lines
    }

    /// The first of `variants` that fits in `max` pixels, else the last one cut to fit.
    pub fn first_fitting(&self, variants: &[&str], max: f64) -> String {
        variants
            .iter()
            .find(|v| self.width(v) <= max)
            .map(|v| v.to_string())
            .unwrap_or_else(|| self.fit(variants.last().copied().unwrap_or(""), max))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_add_advances_and_bold_is_wider() {
        let f = Font::regular(10.0);
        assert!((f.width("ab") - (6.13 + 6.35)).abs() < 1e-9);
        assert!(Font::bold(10.0).width("Whole mesh") > f.width("Whole mesh"));
        // Outside the table: a full em.
        assert_eq!(f.width("漢"), 10.0);
    }

    #[test]
    fn fitting_cuts_to_the_width_and_wrapping_breaks_at_spaces() {
        let f = Font::regular(11.0);
        let s = "99.6% of 4452 edges in [0.71, 1.41]";
        assert_eq!(f.fit(s, 1000.0), s);
        let cut = f.fit(s, 120.0);
        assert!(cut.ends_with('…') && f.width(&cut) <= 120.0, "{cut}");
        let lines = f.wrap(s, 120.0, 3);
        assert!(lines.len() >= 2, "{lines:?}");
        assert!(lines.iter().all(|l| f.width(l) <= 120.0), "{lines:?}");
        assert_eq!(lines.join(" "), s);
        let one = f.wrap(s, 120.0, 1);
        assert_eq!(one, vec![cut]);
        assert_eq!(f.first_fitting(&["a long variant of it", "short"], 40.0), "short");
    }
}
