//! A small SVG writer: elements, attributes, text and path data, with fixed-precision
//! number formatting so that the same picture always gives the same bytes.
//!
//! Written by hand rather than with an SVG crate because the report needs only a dozen
//! element kinds, and full control of number formatting is what makes the output
//! deterministic and small (a writer crate would print every f64 with all its digits).

use std::fmt::Write as _;

/// Formats `v` with at most `decimals` decimals, trailing zeros dropped, `-0` as `0`.
pub(super) fn num(v: f64, decimals: usize) -> String {
    if !v.is_finite() {
        return "0".into();
    }
    let mut s = format!("{v:.decimals$}");
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s = "0".into();
    }
    s
}

/// Escapes the five XML special characters of `text`.
pub(super) fn escape(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => s.push_str("&lt;"),
            '>' => s.push_str("&gt;"),
            '&' => s.push_str("&amp;"),
            '"' => s.push_str("&quot;"),
            '\'' => s.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => s.push(' '),
            c => s.push(c),
        }
    }
    s
}

/// The document being written. Attributes are `(name, value)` pairs; values are escaped
/// here, names are trusted (they are literals of this crate).
#[derive(Debug, Default)]
pub(super) struct Svg {
    buf: String,
    open: Vec<&'static str>,
}

impl Svg {
    /// A document of `width` × `height` pixels with a white background.
    pub(super) fn new(width: f64, height: f64) -> Svg {
        let mut s = Svg::default();
        let (w, h) = (num(width, 0), num(height, 0));
        let _ = writeln!(
            s.buf,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"DejaVu Sans, Liberation Sans, Arial, Helvetica, sans-serif\" font-size=\"12\">"
        );
        s.open.push("svg");
        s.element(
            "rect",
            &[("x", "0"), ("y", "0"), ("width", &w), ("height", &h), ("fill", "#ffffff")],
        );
        s
    }

    fn start(&mut self, tag: &str, attrs: &[(&str, &str)]) {
        let _ = write!(self.buf, "{}<{tag}", "  ".repeat(self.open.len().min(8)));
        for (k, v) in attrs {
            let _ = write!(self.buf, " {k}=\"{}\"", escape(v));
        }
    }

    /// Opens `<tag ...>`; close it with [`Svg::close`].
    pub(super) fn open(&mut self, tag: &'static str, attrs: &[(&str, &str)]) {
        self.start(tag, attrs);
        self.buf.push_str(">\n");
        self.open.push(tag);
    }

    /// Closes the innermost open element.
    pub(super) fn close(&mut self) {
        if let Some(tag) = self.open.pop() {
            let _ = writeln!(self.buf, "{}</{tag}>", "  ".repeat(self.open.len().min(8)));
        }
    }

    /// An empty element `<tag .../>`.
    pub(super) fn element(&mut self, tag: &str, attrs: &[(&str, &str)]) {
        self.start(tag, attrs);
        self.buf.push_str("/>\n");
    }

    /// A `<text>` element holding `content` (escaped).
    pub(super) fn text(&mut self, x: f64, y: f64, content: &str, attrs: &[(&str, &str)]) {
        let (xs, ys) = (num(x, 1), num(y, 1));
        let mut all: Vec<(&str, &str)> = vec![("x", &xs), ("y", &ys)];
        all.extend_from_slice(attrs);
        self.start("text", &all);
        let _ = writeln!(self.buf, ">{}</text>", escape(content));
    }

    /// A `<title>` child (a tooltip in browsers, a name for tests).
    pub(super) fn title(&mut self, content: &str) {
        let _ = writeln!(
            self.buf,
            "{}<title>{}</title>",
            "  ".repeat(self.open.len().min(8)),
            escape(content)
        );
    }

    /// Closes every open element and returns the document.
    pub(super) fn finish(mut self) -> String {
        while !self.open.is_empty() {
            self.close();
        }
        self.buf
    }
}

/// Path data (`d` attribute) with coordinates rounded to `decimals`.
#[derive(Debug, Clone)]
pub(super) struct PathData {
    d: String,
    decimals: usize,
}

impl PathData {
    /// Empty path data.
    pub(super) fn new(decimals: usize) -> PathData {
        PathData { d: String::new(), decimals }
    }

    /// Whether nothing was added.
    pub(super) fn is_empty(&self) -> bool {
        self.d.is_empty()
    }

    /// `M x y`.
    pub(super) fn move_to(&mut self, p: [f64; 2]) {
        let _ = write!(self.d, "M{} {}", num(p[0], self.decimals), num(p[1], self.decimals));
    }

    /// `L x y`.
    pub(super) fn line_to(&mut self, p: [f64; 2]) {
        let _ = write!(self.d, "L{} {}", num(p[0], self.decimals), num(p[1], self.decimals));
    }

    /// An axis-aligned rectangle as a closed subpath.
    pub(super) fn rect(&mut self, x: f64, y: f64, w: f64, h: f64) {
        let n = |v| num(v, self.decimals);
        let _ = write!(self.d, "M{} {}h{}v{}h{}z", n(x), n(y), n(w), n(h), n(-w));
    }

    /// `Z`.
    pub(super) fn close(&mut self) {
        self.d.push('Z');
    }

    /// The `d` string.
    pub(super) fn as_str(&self) -> &str {
        &self.d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_stable() {
        assert_eq!(num(1.0, 2), "1");
        assert_eq!(num(1.25, 1), "1.2");
        assert_eq!(num(-0.0001, 2), "0");
        assert_eq!(num(12.3400, 3), "12.34");
        assert_eq!(num(f64::NAN, 3), "0");
        assert_eq!(num(100.0, 0), "100");
    }

    #[test]
    fn text_is_escaped() {
        let mut s = Svg::new(10.0, 10.0);
        s.text(1.0, 2.0, "a < b & \"c\"", &[]);
        let out = s.finish();
        assert!(out.contains("a &lt; b &amp; &quot;c&quot;"));
        assert!(out.trim_end().ends_with("</svg>"));
    }
}
