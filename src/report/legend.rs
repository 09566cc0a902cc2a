//! The legend under the overview: a swatch per topological face (its fill), a line per
//! curve (its stroke), a diamond per tagged topological point (its marker), the marks of
//! the recipe's sources, and the colour scale of the shading that stands for edges too
//! short to draw; each named by tag and name, measured and wrapped over as many rows as
//! needed (at most [`MAX_ENTRIES`] entities, then a count of the rest).

use crate::topology::Topology;

use super::mesh_layer::{MAX_SHADING, MIN_EDGE_PX, SHADING_LEVELS};
use super::palette;
use super::svg::{num, Svg};
use super::text::Font;
use super::view::Rect;

/// Entries shown at most.
pub(super) const MAX_ENTRIES: usize = 40;
const ROW: f64 = 18.0;
/// The legend's font.
pub(super) const FONT: Font = Font::regular(11.0);
/// Room for the swatch before a label, and the gap after it.
const SWATCH: f64 = 26.0;
const GAP: f64 = 16.0;
/// Width of the shading scale's swatches (one per level).
const STEP: f64 = 12.0;

/// What an entry's swatch shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Swatch {
    /// A topological face's fill.
    Face,
    /// A topological curve's stroke.
    Curve,
    /// A tagged topological point's marker.
    Point,
    /// A point source of the recipe (a ring).
    SourcePoint,
    /// An imaginary polyline of the recipe (dashed).
    SourcePolyline,
    /// The shading levels of short edges, lightest to darkest: a colour scale.
    Shading,
    /// No swatch (the count of entries not shown).
    None,
}

/// One legend entry.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Entry {
    /// What the swatch shows.
    pub swatch: Swatch,
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

/// What the picture draws besides the entities of the topology.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct Extras {
    /// The recipe has point sources (drawn as rings).
    pub source_points: bool,
    /// The recipe has imaginary polylines (drawn dashed).
    pub source_polylines: bool,
    /// Some edges are drawn as shading.
    pub shading: bool,
    /// The picture is a planar cut of a mesh in space: its faces are volumes cut, its
    /// curves the traces of surfaces.
    pub cut: bool,
}

/// The entries of `topo` — faces, curves, tagged points, in topology order, at most
/// [`MAX_ENTRIES`] and then a count of the rest — and of `extras`.
pub(super) fn entries(topo: &Topology, extras: Extras) -> Vec<Entry> {
    let (face, curve) = if extras.cut { ("volume", "surface") } else { ("face", "curve") };
    let faces = topo.faces.iter().enumerate().map(|(i, f)| Entry {
        swatch: Swatch::Face,
        colour: palette::face(i),
        label: format!("{face} {}", name(Some(f.tag), &f.name)),
    });
    let curves = topo.curves.iter().enumerate().map(|(i, c)| Entry {
        swatch: Swatch::Curve,
        colour: palette::curve(i),
        label: format!("{curve} {}", name(c.tag, &c.name)),
    });
    let points =
        topo.points.iter().enumerate().filter(|(_, p)| p.tag.is_some()).map(|(i, p)| Entry {
            swatch: Swatch::Point,
            colour: palette::point(i),
            label: format!("point {}", name(p.tag, &p.name)),
        });
    let all: Vec<Entry> = faces.chain(curves).chain(points).collect();
    let mut out: Vec<Entry> = all.iter().take(MAX_ENTRIES).cloned().collect();
    if all.len() > MAX_ENTRIES {
        out.push(Entry {
            swatch: Swatch::None,
            colour: "#ffffff",
            label: format!("and {} more", all.len() - MAX_ENTRIES),
        });
    }
    if extras.source_points {
        out.push(Entry {
            swatch: Swatch::SourcePoint,
            colour: "#000",
            label: "point source of the recipe".into(),
        });
    }
    if extras.source_polylines {
        out.push(Entry {
            swatch: Swatch::SourcePolyline,
            colour: "#000",
            label: "imaginary polyline of the recipe".into(),
        });
    }
    if extras.shading {
        out.push(Entry {
            swatch: Swatch::Shading,
            colour: palette::EDGE,
            label: format!("edges under {} px: shading, darker where denser", num(MIN_EDGE_PX, 0)),
        });
    }
    out
}

/// The room the swatch of `e` takes before its label.
fn swatch_width(e: &Entry) -> f64 {
    match e.swatch {
        Swatch::Shading => SHADING_LEVELS as f64 * STEP + 6.0,
        Swatch::None => 0.0,
        _ => SWATCH,
    }
}

/// Each entry's label as drawn (cut to the legend's width) and its position.
fn positions(entries: &[Entry], width: f64) -> (Vec<(f64, f64, String)>, f64) {
    let (mut x, mut y) = (0.0, 0.0);
    let mut out = Vec::new();
    for e in entries {
        let label = FONT.fit(&e.label, width - swatch_width(e));
        let w = swatch_width(e) + FONT.width(&label) + GAP;
        if x > 0.0 && x + w - GAP > width {
            x = 0.0;
            y += ROW;
        }
        out.push((x, y, label));
        x += w;
    }
    (out, if entries.is_empty() { 0.0 } else { y + ROW })
}

/// The height the legend needs in `width` pixels.
pub(super) fn height(entries: &[Entry], width: f64) -> f64 {
    positions(entries, width).1
}

/// A diamond of half-diagonal `r` pixels at `(x, y)`, as path data.
pub(super) fn diamond(x: f64, y: f64, r: f64) -> String {
    format!(
        "M{} {}L{} {}L{} {}L{} {}Z",
        num(x, 1),
        num(y - r, 1),
        num(x + r, 1),
        num(y, 1),
        num(x, 1),
        num(y + r, 1),
        num(x - r, 1),
        num(y, 1)
    )
}

/// Draws the legend into `rect`.
pub(super) fn draw(svg: &mut Svg, rect: &Rect, entries: &[Entry]) {
    let (pos, _) = positions(entries, rect.width());
    let bx = super::layout::data_box(rect);
    svg.open("g", &[("id", "legend"), ("data-box", &bx)]);
    for (e, (dx, dy, label)) in entries.iter().zip(pos) {
        let (x, y) = (rect.x0 + dx, rect.y0 + dy);
        match e.swatch {
            Swatch::Face => svg.element(
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
            ),
            Swatch::Curve | Swatch::SourcePolyline => {
                let dashed = e.swatch == Swatch::SourcePolyline;
                svg.element(
                    "line",
                    &[
                        ("x1", &num(x, 1)),
                        ("y1", &num(y + 8.5, 1)),
                        ("x2", &num(x + 20.0, 1)),
                        ("y2", &num(y + 8.5, 1)),
                        ("stroke", e.colour),
                        ("stroke-width", if dashed { "1.5" } else { "3" }),
                        ("stroke-dasharray", if dashed { "6 4" } else { "none" }),
                    ],
                )
            }
            Swatch::Point => svg.element(
                "path",
                &[
                    ("class", "point-swatch"),
                    ("d", &diamond(x + 10.0, y + 8.5, 5.0)),
                    ("fill", e.colour),
                    ("stroke", "#000"),
                    ("stroke-width", "0.8"),
                ],
            ),
            Swatch::SourcePoint => svg.element(
                "circle",
                &[
                    ("cx", &num(x + 10.0, 1)),
                    ("cy", &num(y + 8.5, 1)),
                    ("r", "4.5"),
                    ("fill", "none"),
                    ("stroke", "#000"),
                    ("stroke-width", "1.5"),
                ],
            ),
            Swatch::Shading => {
                svg.open("g", &[("class", "colour-scale shading-scale")]);
                for l in 0..SHADING_LEVELS {
                    let op = num(MAX_SHADING * (l + 1) as f64 / SHADING_LEVELS as f64, 3);
                    svg.element(
                        "rect",
                        &[
                            ("x", &num(x + l as f64 * STEP, 1)),
                            ("y", &num(y + 3.0, 1)),
                            ("width", &num(STEP, 1)),
                            ("height", "11"),
                            ("fill", e.colour),
                            ("fill-opacity", &op),
                            ("data-level", &(l + 1).to_string()),
                        ],
                    );
                }
                svg.close();
            }
            Swatch::None => {}
        }
        svg.text(
            x + swatch_width(e),
            y + 13.0,
            &label,
            &[("font-size", "11"), ("class", "legend-entry")],
        );
    }
    svg.close();
}
