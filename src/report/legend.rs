//! The legend under the overview: a swatch per topological face (its fill) and a line
//! per curve (its stroke), named by tag and name, wrapped over as many rows as needed
//! (at most [`MAX_ENTRIES`], then a count of the rest).

use crate::topology::Topology;

use super::palette;
use super::svg::{num, Svg};
use super::view::Rect;

/// Entries shown at most.
pub const MAX_ENTRIES: usize = 40;
const ROW: f64 = 18.0;
/// Average advance of a character of the 11 px legend font, in pixels: text is not
/// measured (that needs the font), so entries are spaced for a generous estimate.
const CHAR: f64 = 6.6;

/// One legend entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// A face swatch (true) or a curve line.
    pub face: bool,
    /// Colour.
    pub colour: &'static str,
    /// Label.
    pub label: String,
}

fn name(tag: Option<i32>, name: &Option<String>) -> String {
    match (tag, name) {
        (Some(t), Some(n)) => format!("{t} {n}"),
        (Some(t), None) => t.to_string(),
        (None, _) => "untagged".into(),
    }
}

/// The entries of `topo`: faces, then curves, in topology order.
pub fn entries(topo: &Topology) -> Vec<Entry> {
    let faces = topo.faces.iter().enumerate().map(|(i, f)| Entry {
        face: true,
        colour: palette::face(i),
        label: format!("face {}", name(Some(f.tag), &f.name)),
    });
    let curves = topo.curves.iter().enumerate().map(|(i, c)| Entry {
        face: false,
        colour: palette::curve(i),
        label: format!("curve {}", name(c.tag, &c.name)),
    });
    faces.chain(curves).collect()
}

fn positions(entries: &[Entry], width: f64) -> (Vec<(f64, f64)>, f64) {
    let (mut x, mut y) = (0.0, 0.0);
    let mut out = Vec::new();
    for e in entries.iter().take(MAX_ENTRIES + usize::from(entries.len() > MAX_ENTRIES)) {
        let w = 26.0 + CHAR * e.label.chars().count().min(40) as f64 + 16.0;
        if x > 0.0 && x + w > width {
            x = 0.0;
            y += ROW;
        }
        out.push((x, y));
        x += w;
    }
    (out, if entries.is_empty() { 0.0 } else { y + ROW })
}

/// The height the legend needs in `width` pixels.
pub fn height(entries: &[Entry], width: f64) -> f64 {
    positions(entries, width).1
}

/// Draws the legend into `rect`.
pub fn draw(svg: &mut Svg, rect: &Rect, entries: &[Entry]) {
    let mut shown: Vec<Entry> = entries.iter().take(MAX_ENTRIES).cloned().collect();
    if entries.len() > MAX_ENTRIES {
        shown.push(Entry {
            face: true,
            colour: "#ffffff",
            label: format!("and {} more", entries.len() - MAX_ENTRIES),
        });
    }
    let (pos, _) = positions(&shown, rect.width());
    svg.open("g", &[("id", "legend")]);
    for (e, (dx, dy)) in shown.iter().zip(pos) {
        let (x, y) = (rect.x0 + dx, rect.y0 + dy);
        if e.face {
            svg.element(
                "rect",
                &[
                    ("x", &num(x, 1)),
                    ("y", &num(y + 3.0, 1)),
                    ("width", "20"),
                    ("height", "11"),
                    ("fill", e.colour),
                    ("stroke", "#999"),
                    ("stroke-width", "0.5"),
                ],
            );
        } else {
            svg.element(
                "line",
                &[
                    ("x1", &num(x, 1)),
                    ("y1", &num(y + 8.5, 1)),
                    ("x2", &num(x + 20.0, 1)),
                    ("y2", &num(y + 8.5, 1)),
                    ("stroke", e.colour),
                    ("stroke-width", "3"),
                ],
            );
        }
        let label: String = e.label.chars().take(40).collect();
        svg.text(x + 26.0, y + 13.0, &label, &[("font-size", "11"), ("class", "legend-entry")]);
    }
    svg.close();
}
