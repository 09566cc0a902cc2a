//! The panels of a report that show the mesh: the zoom windows (mesh, source marks and
//! size ellipses), and what the overview shares with them (source marks, scale bars,
//! labels on a white box, clip paths, borders).

use crate::metric::SizeTensor;
use crate::sizing::plan::SizingPlan;
use crate::topology::{Classification, Topology};

use super::ellipses::{ellipse_in_view, fit_factor, pick};
use super::layout::CAPTION_LINE;
use super::mesh_layer::{EdgeStats, MeshLayers};
use super::svg::{num, PathData, Svg};
use super::text::Font;
use super::view::{Rect, View};
use super::windows::ZoomWindow;
use super::{axes, fmt_sig, palette};

/// Smallest distance between two ellipse centres, in pixels.
const ELLIPSE_GAP_PX: f64 = 10.0;

/// What every mesh panel draws from.
pub(super) struct Scene<'a> {
    /// The mesh as layers.
    pub layers: &'a MeshLayers,
    /// Its topology.
    pub topology: &'a Topology,
    /// The size tensor of each vertex, when there is a metric (`None` where a tensor is
    /// out of range).
    pub sizes: Option<&'a [Option<SizeTensor>]>,
    /// The plan's source marks.
    pub marks: &'a SourceMarks,
    /// The boundary-layer skin's thinned columns.
    pub skin: &'a super::skin::SkinMarks,
}

/// Imaginary polylines and point sources of a plan, in mesh coordinates.
pub(super) struct SourceMarks {
    /// The imaginary polylines.
    pub polylines: Vec<Vec<[f64; 2]>>,
    /// The point sources.
    pub points: Vec<[f64; 2]>,
}

/// The imaginary polylines and point sources of `plan`'s steps, to draw over the mesh.
pub(super) fn source_marks(
    plan: Option<&SizingPlan>,
    topo: &Topology,
    points: &[[f64; 2]],
) -> SourceMarks {
    let mut m = SourceMarks { polylines: Vec::new(), points: Vec::new() };
    for step in plan.map(|p| p.steps.as_slice()).unwrap_or_default() {
        let marks = step.algorithm.marks();
        if let Some(polyline) = marks.polyline {
            m.polylines.push(polyline.to_vec());
        }
        m.points.extend(
            marks.points.iter().filter_map(|&p| topo.points.get(p)).map(|p| points[p.vertex]),
        );
    }
    m
}

/// Polylines dashed, point sources as rings.
pub(super) fn draw_marks(svg: &mut Svg, view: &View, marks: &SourceMarks) {
    for pl in &marks.polylines {
        let mut d = PathData::new(1);
        for (i, &p) in pl.iter().enumerate() {
            if i == 0 {
                d.move_to(view.to_px(p));
            } else {
                d.line_to(view.to_px(p));
            }
        }
        svg.element(
            "path",
            &[
                ("class", "source-polyline"),
                ("d", d.as_str()),
                ("fill", "none"),
                ("stroke", "#000"),
                ("stroke-width", "1.5"),
                ("stroke-dasharray", "6 4"),
            ],
        );
    }
    for &p in &marks.points {
        let [x, y] = view.to_px(p);
        svg.element(
            "circle",
            &[
                ("class", "source-point"),
                ("cx", &num(x, 1)),
                ("cy", &num(y, 1)),
                ("r", "4.5"),
                ("fill", "none"),
                ("stroke", "#000"),
                ("stroke-width", "1.5"),
            ],
        );
    }
}

/// A scale bar of a round length at the bottom left of `content` (the pixels where the
/// mesh is, within the view), drawn over a white outline so that it reads on any fill.
/// Returns the box of its label.
pub(super) fn scale_bar(svg: &mut Svg, view: &View, content: &Rect) -> Rect {
    let (len, px, x, y) = scale_bar_geometry(view, content);
    let d = format!("M{} {}v4h{}v-4", num(x, 1), num(y - 4.0, 1), num(px, 2));
    svg.open("g", &[("class", "scale-bar")]);
    svg.element(
        "path",
        &[
            ("d", &d),
            ("fill", "none"),
            ("stroke", "#ffffff"),
            ("stroke-width", "4"),
            ("stroke-opacity", "0.85"),
        ],
    );
    svg.element(
        "path",
        &[("d", &d), ("fill", "none"), ("stroke", "#000"), ("stroke-width", "1.5")],
    );
    let label = fmt_sig(len);
    halo_text(svg, x + 0.5 * px, y - 8.0, &label, "middle", "#000");
    svg.close();
    halo_box(x + 0.5 * px, y - 8.0, &label, "middle")
}

/// The scale bar's round length, its length in pixels and where it starts.
fn scale_bar_geometry(view: &View, content: &Rect) -> (f64, f64, f64, f64) {
    let len = axes::nice_step(0.12 * content.width() / view.scale, 1);
    (len, len * view.scale, content.x0 + 10.0, content.y1 - 10.0)
}

/// What [`scale_bar`] will cover, its label and its bar, to keep other labels off it.
pub(super) fn scale_bar_box(view: &View, content: &Rect) -> Rect {
    let (len, px, x, y) = scale_bar_geometry(view, content);
    let label = halo_box(x + 0.5 * px, y - 8.0, &fmt_sig(len), "middle");
    Rect::new(label.x0.min(x - 2.0), label.y0, label.x1.max(x + px + 2.0), y + 2.0)
}

/// The font of labels over the mesh.
pub(super) const HALO_FONT: Font = Font::regular(11.0);

/// The box of 11 px text at `(x, y)` anchored `anchor`, with 3 px of padding: what
/// [`halo_text`] paints white.
pub(super) fn halo_box(x: f64, y: f64, text: &str, anchor: &str) -> Rect {
    let w = HALO_FONT.width(text) + 6.0;
    let x0 = match anchor {
        "end" => x - w + 3.0,
        "middle" => x - 0.5 * w,
        _ => x - 3.0,
    };
    Rect::new(x0, y - 10.0, x0 + w, y + 4.0)
}

/// 11 px text on a translucent white box (measured, see [`super::text`]), readable over
/// the mesh.
pub(super) fn halo_text(svg: &mut Svg, x: f64, y: f64, text: &str, anchor: &str, colour: &str) {
    let b = halo_box(x, y, text, anchor);
    svg.element(
        "rect",
        &[
            ("x", &num(b.x0, 1)),
            ("y", &num(b.y0, 1)),
            ("width", &num(b.width(), 1)),
            ("height", &num(b.height(), 1)),
            ("fill", "#ffffff"),
            ("fill-opacity", "0.85"),
        ],
    );
    svg.text(
        x,
        y,
        text,
        &[("font-size", "11"), ("text-anchor", anchor), ("fill", colour), ("class", "on-mesh")],
    );
}

/// A clip path `id` of rectangle `r`.
pub(super) fn clip(svg: &mut Svg, id: &str, r: &Rect) {
    svg.open("clipPath", &[("id", id)]);
    svg.element(
        "rect",
        &[
            ("x", &num(r.x0, 1)),
            ("y", &num(r.y0, 1)),
            ("width", &num(r.width(), 1)),
            ("height", &num(r.height(), 1)),
        ],
    );
    svg.close();
}

/// A thin grey border around `r`.
pub(super) fn panel_border(svg: &mut Svg, r: &Rect) {
    svg.element(
        "rect",
        &[
            ("class", "border"),
            ("x", &num(r.x0, 1)),
            ("y", &num(r.y0, 1)),
            ("width", &num(r.width(), 1)),
            ("height", &num(r.height(), 1)),
            ("fill", "none"),
            ("stroke", "#bbbbbb"),
            ("stroke-width", "1"),
        ],
    );
}

/// The part of a zoom panel below its caption of `caption` pixels.
pub(super) fn zoom_inner(r: &Rect, caption: f64) -> Rect {
    Rect::new(r.x0, r.y0 + caption, r.x1, r.y1)
}

/// The font of zoom captions.
pub(super) const CAPTION_FONT: Font = Font::bold(12.0);
/// Lines a zoom caption may take.
pub(super) const CAPTION_LINES: usize = 2;

/// The lines of zoom caption `caption` in a panel `width` pixels wide.
pub(super) fn caption_lines(caption: &str, width: f64) -> Vec<String> {
    CAPTION_FONT.wrap(caption, width, CAPTION_LINES)
}

/// `n` and the word for one or many.
pub(super) fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// Zoom panel `k` (0-based) of window `z` in panel rectangle `r`, showing `view`.
pub(super) fn draw_zoom(
    svg: &mut Svg,
    k: usize,
    z: &ZoomWindow,
    r: &Rect,
    view: &View,
    scene: &Scene<'_>,
) -> EdgeStats {
    let Scene { layers, topology: topo, sizes, marks, skin } = *scene;
    let view = *view;
    let inner = view.screen;
    let w = &view.world;
    let id = format!("zoom-{}", k + 1);
    let clip_id = format!("clip-{id}");
    let window = format!("{} {} {} {}", num(w.x0, 9), num(w.y0, 9), num(w.x1, 9), num(w.y1, 9));
    svg.open(
        "g",
        &[
            ("id", &id),
            ("class", "panel zoom"),
            ("data-window", &window),
            ("data-scale", &num(view.scale, 6)),
            ("data-box", &super::layout::data_box(r)),
        ],
    );
    svg.title(&if z.steps.is_empty() { z.label.clone() } else { z.steps.join("; ") });
    clip(svg, &clip_id, &inner);
    svg.open("g", &[("clip-path", &format!("url(#{clip_id})"))]);
    layers.draw_faces(svg, &view);
    let stats = layers.draw_edges(svg, &view, 0.6);
    layers.draw_curves(svg, &view, 2.4);
    layers.draw_points(svg, &view, 5.0);
    draw_marks(svg, &view, marks);
    super::skin::draw(svg, &view, skin, 3.0);
    let ellipse_note = match sizes {
        Some(sizes) => draw_ellipses(svg, &view, layers, topo, sizes),
        None => String::new(),
    };
    svg.close();
    let bar = scale_bar(svg, &view, &inner);
    panel_border(svg, &inner);
    let caption = format!("{}: {}", k + 1, z.label);
    for (i, line) in caption_lines(&caption, r.width()).iter().enumerate() {
        svg.text(
            r.x0,
            r.y0 + 14.0 + CAPTION_LINE * i as f64,
            line,
            &[("font-size", "12"), ("font-weight", "bold")],
        );
    }
    if !ellipse_note.is_empty() {
        // Bottom right, beside the scale bar's label; top right where they would meet.
        let (x, mut y) = (inner.x1 - 8.0, inner.y1 - 9.0);
        if halo_box(x, y, &ellipse_note, "end").x0 < bar.x1 + 4.0 {
            y = inner.y0 + 16.0;
        }
        let note = HALO_FONT.fit(&ellipse_note, inner.width() - 22.0);
        halo_text(svg, x, y, &note, "end", palette::ELLIPSE);
    }
    svg.close();
    stats
}

/// The size ellipses of the used vertices in `view`'s window, a subset kept apart
/// ([`pick`]), at true size unless the largest would not fit; returns the note that
/// says how many and at which factor.
pub(super) fn draw_ellipses(
    svg: &mut Svg,
    view: &View,
    layers: &MeshLayers,
    topo: &Topology,
    sizes: &[Option<SizeTensor>],
) -> String {
    let view = *view;
    let w = &view.world;
    let candidates: Vec<(usize, [f64; 2], SizeTensor)> = sizes
        .iter()
        .enumerate()
        .filter(|(v, _)| !matches!(topo.vertex_class.get(*v), Some(Classification::Unused) | None))
        .filter_map(|(v, t)| t.map(|t| (v, layers.points[v], t)))
        .filter(|(_, p, _)| w.contains(*p))
        .collect();
    let factor = fit_factor(&candidates, &view);
    let kept = pick(&candidates, &view, factor, ELLIPSE_GAP_PX);
    let s = view.scale * factor;
    svg.open(
        "g",
        &[
            ("class", "ellipses"),
            ("data-scale", &num(s, 6)),
            ("data-factor", &num(factor, 6)),
            ("fill", palette::ELLIPSE),
            ("fill-opacity", "0.12"),
            ("stroke", palette::ELLIPSE),
            ("stroke-width", "1"),
        ],
    );
    let by_vertex: std::collections::BTreeMap<usize, &(usize, [f64; 2], SizeTensor)> =
        candidates.iter().map(|c| (c.0, c)).collect();
    for v in &kept {
        let (_, p, t) = by_vertex[v];
        let e = ellipse_in_view(t, *p, &view, factor);
        let (cx, cy) = (num(e.cx, 3), num(e.cy, 3));
        let rot = format!("rotate({} {cx} {cy})", num(e.angle_deg, 3));
        svg.element(
            "ellipse",
            &[
                ("data-vertex", &v.to_string()),
                ("cx", &cx),
                ("cy", &cy),
                ("rx", &num(e.rx, 3)),
                ("ry", &num(e.ry, 3)),
                ("transform", &rot),
            ],
        );
    }
    svg.close();
    if factor == 1.0 {
        format!("{} ellipses, true size", kept.len())
    } else {
        format!("{} ellipses ×{}", kept.len(), fmt_sig(factor))
    }
}
