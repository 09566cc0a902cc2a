//! `smartmesh report`: a picture of a mesh and its metric that a user would rather look
//! at than read — the whole mesh (faces filled by tag, edges, boundary curves by tag,
//! with a legend), zoom windows around the recipe's sources (or the smallest metric
//! sizes), size ellipses in the zooms, histograms of metric edge length and quality, and
//! the convergence history of an adaptation run.
//!
//! - [`svg`]: the SVG writer with deterministic number formatting;
//! - [`view`]: rectangles and the mesh-to-pixel map;
//! - [`layout`] and [`legend`]: where the panels and legend entries go;
//! - [`mesh_layer`]: faces, edges (shaded below 2 px, so big meshes stay small) and curves;
//! - [`windows`]: the zoom windows;
//! - [`ellipses`]: size ellipses and the vertices they are drawn at;
//! - [`axes`], [`histogram`], [`history_plot`]: the charts;
//! - [`png`]: rasterising through resvg.
//!
//! Everything is a pure function of its input: the same mesh, metric, recipe and history
//! give the same bytes.

pub mod axes;
pub mod ellipses;
pub mod histogram;
pub mod history_plot;
pub mod layout;
pub mod legend;
pub mod mesh_layer;
pub mod palette;
pub mod png;
pub mod svg;
pub mod view;
pub mod windows;

use std::path::Path;

use crate::conformity::Conformity;
use crate::formats::TaggedMesh;
use crate::history::History;
use crate::metric::SizeTensor;
use crate::metric_input::LoadedMetric;
use crate::sizing::plan::{Algorithm, SizingPlan};
use crate::topology::{Classification, Topology};

use self::ellipses::{ellipse_in_view, fit_factor, pick};
use self::layout::CAPTION;
use self::mesh_layer::{EdgeStats, MeshLayers};
use self::svg::{num, PathData, Svg};
use self::view::{Rect, View};
use self::windows::ZoomWindow;

/// Default picture width in pixels.
pub const DEFAULT_WIDTH: u32 = 1200;
/// Narrowest and widest pictures accepted.
pub const WIDTH_RANGE: [u32; 2] = [400, 8000];
/// Zoom windows around the smallest sizes when there is no recipe.
const SIZE_WINDOWS: usize = 3;
/// Smallest distance between two ellipse centres, in pixels.
const ELLIPSE_GAP_PX: f64 = 10.0;

/// What a report is drawn from.
#[derive(Debug, Clone, Copy)]
pub struct ReportInput<'a> {
    /// The mesh's name for the title (usually its path).
    pub name: &'a str,
    /// The mesh.
    pub mesh: &'a TaggedMesh,
    /// Its topology.
    pub topology: &'a Topology,
    /// The metric on its vertices, if any.
    pub metric: Option<&'a LoadedMetric>,
    /// A sizing plan resolved on this mesh, for the zoom windows and source marks.
    pub plan: Option<&'a SizingPlan>,
    /// The history of an adaptation run.
    pub history: Option<&'a History>,
}

/// How a report is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReportOptions {
    /// Picture width in pixels.
    pub width: u32,
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions { width: DEFAULT_WIDTH }
    }
}

/// A drawn report.
#[derive(Debug, Clone)]
pub struct Report {
    /// The SVG document.
    pub svg: String,
    /// Its size in pixels.
    pub width: u32,
    /// Its height in pixels.
    pub height: u32,
    /// The zoom windows drawn.
    pub zooms: Vec<ZoomWindow>,
    /// The conformity figures drawn, when there is a metric.
    pub conformity: Option<Conformity>,
    /// What the user should know (no metric, shaded edges …).
    pub notes: Vec<String>,
}

/// The file kinds a report can be written as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReportFormat {
    /// SVG text.
    Svg,
    /// PNG, rasterised from the SVG.
    Png,
}

impl ReportFormat {
    /// By the extension of `path` (`.svg`, `.png`, any case).
    pub fn from_path(path: &Path) -> Option<ReportFormat> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "svg" => Some(ReportFormat::Svg),
            "png" => Some(ReportFormat::Png),
            _ => None,
        }
    }
}

/// `v` with 4 significant digits, plain between 0.001 and 100 000, else in e-notation.
pub fn fmt_sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return num(v, 0);
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i64).max(0) as usize;
        num(v, decimals)
    } else {
        format!("{v:.3e}")
    }
}

/// Imaginary polylines and point sources of a plan, in mesh coordinates.
struct SourceMarks {
    polylines: Vec<Vec<[f64; 2]>>,
    points: Vec<[f64; 2]>,
}

fn source_marks(plan: Option<&SizingPlan>, topo: &Topology, points: &[[f64; 2]]) -> SourceMarks {
    let mut m = SourceMarks { polylines: Vec::new(), points: Vec::new() };
    for step in plan.map(|p| p.steps.as_slice()).unwrap_or_default() {
        match &step.algorithm {
            Algorithm::DistanceToImaginaryPolyline { polyline, .. } => m.polylines.push(polyline.clone()),
            Algorithm::DistanceToPoint { sources, .. } | Algorithm::DistanceToBorder { borders: sources, .. } => {
                m.points.extend(sources.points.iter().filter_map(|&p| topo.points.get(p)).map(|p| points[p.vertex]));
            }
            _ => {}
        }
    }
    m
}

fn draw_marks(svg: &mut Svg, view: &View, marks: &SourceMarks) {
    for pl in &marks.polylines {
        let mut d = PathData::new(1);
        for (i, &p) in pl.iter().enumerate() {
            if i == 0 {
                d.move_to(view.to_px(p));
            } else {
                d.line_to(view.to_px(p));
            }
        }
        svg.element("path", &[("class", "source-polyline"), ("d", d.as_str()), ("fill", "none"), ("stroke", "#000"), ("stroke-width", "1.5"), ("stroke-dasharray", "6 4")]);
    }
    for &p in &marks.points {
        let [x, y] = view.to_px(p);
        svg.element("circle", &[("class", "source-point"), ("cx", &num(x, 1)), ("cy", &num(y, 1)), ("r", "4.5"), ("fill", "none"), ("stroke", "#000"), ("stroke-width", "1.5")]);
    }
}

/// A scale bar of a round length at the bottom left of `content` (the pixels where the
/// mesh is, within the view), drawn over a white outline so that it reads on any fill.
fn scale_bar(svg: &mut Svg, view: &View, content: &Rect) {
    let len = axes::nice_step(0.12 * content.width() / view.scale, 1);
    let px = len * view.scale;
    let (x, y) = (content.x0 + 10.0, content.y1 - 10.0);
    let d = format!("M{} {}v4h{}v-4", num(x, 1), num(y - 4.0, 1), num(px, 2));
    svg.open("g", &[("class", "scale-bar")]);
    svg.element("path", &[("d", &d), ("fill", "none"), ("stroke", "#ffffff"), ("stroke-width", "4"), ("stroke-opacity", "0.85")]);
    svg.element("path", &[("d", &d), ("fill", "none"), ("stroke", "#000"), ("stroke-width", "1.5")]);
    halo_text(svg, x + 0.5 * px, y - 8.0, &fmt_sig(len), "middle", "#000");
    svg.close();
}

/// 11 px text on a translucent white box, readable over the mesh. The box is sized for
/// an estimated 6.3 px per character (text is not measured: that needs the font).
fn halo_text(svg: &mut Svg, x: f64, y: f64, text: &str, anchor: &str, colour: &str) {
    let w = 6.3 * text.chars().count() as f64 + 6.0;
    let x0 = match anchor {
        "end" => x - w + 3.0,
        "middle" => x - 0.5 * w,
        _ => x - 3.0,
    };
    svg.element("rect", &[("x", &num(x0, 1)), ("y", &num(y - 10.0, 1)), ("width", &num(w, 1)), ("height", "14"), ("fill", "#ffffff"), ("fill-opacity", "0.85")]);
    svg.text(x, y, text, &[("font-size", "11"), ("text-anchor", anchor), ("fill", colour)]);
}

fn clip(svg: &mut Svg, id: &str, r: &Rect) {
    svg.open("clipPath", &[("id", id)]);
    svg.element("rect", &[("x", &num(r.x0, 1)), ("y", &num(r.y0, 1)), ("width", &num(r.width(), 1)), ("height", &num(r.height(), 1))]);
    svg.close();
}

fn panel_border(svg: &mut Svg, r: &Rect) {
    svg.element("rect", &[("class", "border"), ("x", &num(r.x0, 1)), ("y", &num(r.y0, 1)), ("width", &num(r.width(), 1)), ("height", &num(r.height(), 1)), ("fill", "none"), ("stroke", "#bbbbbb"), ("stroke-width", "1")]);
}

/// The part of a zoom panel below its caption.
fn zoom_inner(r: &Rect) -> Rect {
    Rect::new(r.x0, r.y0 + CAPTION, r.x1, r.y1)
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// Truncates `s` to about `px` pixels of 12 px text.
fn fit_text(s: &str, px: f64) -> String {
    let max = (px / 6.9).floor().max(4.0) as usize;
    if s.chars().count() <= max {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(max - 1).collect();
        t.push('…');
        t
    }
}

/// Draws the report.
pub fn render(input: &ReportInput<'_>, options: &ReportOptions) -> Report {
    let width = options.width.clamp(WIDTH_RANGE[0], WIDTH_RANGE[1]) as f64;
    let mesh = input.mesh;
    let topo = input.topology;
    let points: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let layers = MeshLayers::new(topo, points.clone());
    let domain = layers.bounds().or_else(|| Rect::bounding(points.iter().copied())).unwrap_or(Rect::new(0.0, 0.0, 1.0, 1.0));
    let mut notes = Vec::new();

    let conformity = input.metric.and_then(|m| Conformity::of_mesh(mesh, &m.field));
    let sizes: Option<Vec<Option<SizeTensor>>> = input.metric.map(|m| m.field.iter().map(|t| SizeTensor::try_from_metric(t).ok()).collect());
    let zooms = match (input.plan, &sizes) {
        (Some(plan), _) => windows::from_plan(plan, topo, &points, &domain),
        (None, Some(s)) => windows::from_sizes(s, topo, &points, &domain, SIZE_WINDOWS),
        (None, None) => Vec::new(),
    };
    let mut zooms = zooms;
    // Wide windows get full-width panels after the others; number them in that order.
    zooms.sort_by_key(|z| z.region.width() > layout::WIDE * z.region.height());
    let marks = source_marks(input.plan, topo, &points);

    let entries = legend::entries(topo);
    let legend_h = legend::height(&entries, width - 2.0 * layout::MARGIN);
    let charts = if conformity.is_some() { 2 } else { 0 } + usize::from(input.history.is_some());
    let aspect = domain.width().max(1e-300) / domain.height().max(1e-300 + domain.width() * 1e-3);
    let zoom_aspects: Vec<f64> = zooms.iter().map(|z| z.region.width() / z.region.height().max(1e-300)).collect();
    let lay = layout::layout(width, aspect, legend_h, &zoom_aspects, charts);
    // Each zoom shows its window grown to the panel's aspect, moved inside the domain
    // where it fits (a window around a corner shows mesh, not the page).
    let zoom_views: Vec<View> = zooms
        .iter()
        .zip(&lay.zooms)
        .map(|(z, r)| {
            let inner = zoom_inner(r);
            let grown = View::fit(z.region, inner).world.shift_inside(&domain);
            View::fit(grown, inner)
        })
        .collect();
    let mut svg = Svg::new(lay.width, lay.height);

    // Title.
    let triangles = topo.surface_cells.len();
    svg.open("g", &[("id", "title")]);
    svg.text(lay.title.x0, lay.title.y0 + 18.0, &fit_text(input.name, lay.title.width() * 0.75), &[("font-size", "18"), ("font-weight", "bold")]);
    let counts = format!(
        "{}, {}, {}, {}",
        plural(mesh.points.len(), "vertex", "vertices"),
        plural(triangles, "surface cell", "surface cells"),
        plural(topo.faces.len(), "face", "faces"),
        plural(topo.curves.len(), "curve", "curves")
    );
    let metric_line = match (input.metric, &conformity) {
        (Some(m), Some(c)) => format!(
            "metric {}: {}% of edges conforming, mean metric quality {}",
            m.source,
            num(100.0 * c.conforming_share, 1),
            num(c.mean_quality, 3)
        ),
        (Some(m), None) => format!("metric {}: no triangle to measure", m.source),
        (None, _) => {
            let why = format!("no metric: {} has no point data `metric` and no --metric was given", input.name);
            notes.push(why.clone());
            why
        }
    };
    for (k, line) in [counts, metric_line].iter().enumerate() {
        svg.text(lay.title.x0, lay.title.y0 + 37.0 + 16.0 * k as f64, &fit_text(line, lay.title.width() * 1.05), &[("font-size", "13"), ("fill", palette::MUTED)]);
    }
    svg.close();

    // Overview.
    let ov = lay.overview;
    let ov_inner = Rect::new(ov.x0, ov.y0 + CAPTION, ov.x1, ov.y1);
    let ov_view = View::fit(domain.inflate(0.01 * domain.diagonal()), ov_inner);
    svg.open("g", &[("id", "overview"), ("class", "panel overview"), ("data-scale", &num(ov_view.scale, 6))]);
    clip(&mut svg, "clip-overview", &ov_inner);
    svg.open("g", &[("clip-path", "url(#clip-overview)")]);
    layers.draw_faces(&mut svg, &ov_view);
    let ov_stats = layers.draw_edges(&mut svg, &ov_view, 0.35);
    layers.draw_curves(&mut svg, &ov_view, 1.8);
    draw_marks(&mut svg, &ov_view, &marks);
    for (k, zv) in zoom_views.iter().enumerate() {
        let r = ov_view.rect_to_px(&zv.world);
        let id = (k + 1).to_string();
        svg.element("rect", &[("class", "zoom-frame"), ("data-zoom", &id), ("x", &num(r.x0, 1)), ("y", &num(r.y0, 1)), ("width", &num(r.width(), 1)), ("height", &num(r.height(), 1)), ("fill", "none"), ("stroke", palette::FRAME), ("stroke-width", "1.5")]);
        // The number tab sits on the frame's top-left corner, inside the panel.
        let (tx, ty) = (r.x0.max(ov_inner.x0), (r.y0 - 15.0).max(ov_inner.y0));
        svg.element("rect", &[("x", &num(tx, 1)), ("y", &num(ty, 1)), ("width", "15"), ("height", "15"), ("fill", palette::FRAME)]);
        svg.text(tx + 7.5, ty + 11.5, &id, &[("font-size", "11"), ("font-weight", "bold"), ("fill", "#ffffff"), ("text-anchor", "middle")]);
    }
    svg.close();
    let content = ov_view.rect_to_px(&domain).intersect(&ov_inner).unwrap_or(ov_inner);
    scale_bar(&mut svg, &ov_view, &content);
    svg.text(ov.x0, ov.y0 + 14.0, "Whole mesh", &[("font-size", "13"), ("font-weight", "bold")]);
    if ov_stats.shaded > 0 {
        let s = format!("{} edges shorter than {} px drawn as shading", ov_stats.shaded, mesh_layer::MIN_EDGE_PX);
        svg.text(ov.x1, ov.y0 + 14.0, &s, &[("font-size", "11"), ("fill", palette::MUTED), ("text-anchor", "end")]);
    }
    svg.close();
    legend::draw(&mut svg, &lay.legend, &entries);

    // Zooms.
    let mut shaded = ov_stats.shaded;
    for (k, ((z, r), view)) in zooms.iter().zip(&lay.zooms).zip(&zoom_views).enumerate() {
        let stats = draw_zoom(&mut svg, k, z, r, view, &layers, topo, sizes.as_deref(), &marks);
        shaded = shaded.max(stats.shaded);
    }
    if shaded > 0 {
        notes.push(format!("edges shorter than {} px are drawn as shading (up to {shaded} edges in one panel)", mesh_layer::MIN_EDGE_PX));
    }

    // Charts.
    let mut chart = lay.charts.iter();
    if let Some(c) = &conformity {
        if let (Some(a), Some(b)) = (chart.next(), chart.next()) {
            histogram::edge_lengths(&mut svg, a, c);
            histogram::quality(&mut svg, b, c);
        }
    }
    if let (Some(h), Some(r)) = (input.history, chart.next()) {
        history_plot::draw(&mut svg, r, h);
    }
    for r in &lay.charts {
        panel_border(&mut svg, r);
    }

    Report { svg: svg.finish(), width: lay.width as u32, height: lay.height as u32, zooms, conformity, notes }
}

#[allow(clippy::too_many_arguments)]
fn draw_zoom(svg: &mut Svg, k: usize, z: &ZoomWindow, r: &Rect, view: &View, layers: &MeshLayers, topo: &Topology, sizes: Option<&[Option<SizeTensor>]>, marks: &SourceMarks) -> EdgeStats {
    let view = *view;
    let inner = view.screen;
    let w = &view.world;
    let id = format!("zoom-{}", k + 1);
    let clip_id = format!("clip-{id}");
    let window = format!("{} {} {} {}", num(w.x0, 9), num(w.y0, 9), num(w.x1, 9), num(w.y1, 9));
    svg.open("g", &[("id", &id), ("class", "panel zoom"), ("data-window", &window), ("data-scale", &num(view.scale, 6))]);
    svg.title(&if z.steps.is_empty() { z.label.clone() } else { z.steps.join("; ") });
    clip(svg, &clip_id, &inner);
    svg.open("g", &[("clip-path", &format!("url(#{clip_id})"))]);
    layers.draw_faces(svg, &view);
    let stats = layers.draw_edges(svg, &view, 0.6);
    layers.draw_curves(svg, &view, 2.4);
    draw_marks(svg, &view, marks);
    let mut ellipse_note = String::new();
    if let Some(sizes) = sizes {
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
        svg.open("g", &[("class", "ellipses"), ("data-scale", &num(s, 6)), ("data-factor", &num(factor, 6)), ("fill", palette::ELLIPSE), ("fill-opacity", "0.12"), ("stroke", palette::ELLIPSE), ("stroke-width", "1")]);
        let by_vertex: std::collections::BTreeMap<usize, &(usize, [f64; 2], SizeTensor)> = candidates.iter().map(|c| (c.0, c)).collect();
        for v in &kept {
            let (_, p, t) = by_vertex[v];
            let e = ellipse_in_view(t, *p, &view, factor);
            let (cx, cy) = (num(e.cx, 3), num(e.cy, 3));
            let rot = format!("rotate({} {cx} {cy})", num(e.angle_deg, 3));
            svg.element("ellipse", &[("data-vertex", &v.to_string()), ("cx", &cx), ("cy", &cy), ("rx", &num(e.rx, 3)), ("ry", &num(e.ry, 3)), ("transform", &rot)]);
        }
        svg.close();
        ellipse_note = if factor == 1.0 { format!("{} ellipses, true size", kept.len()) } else { format!("{} ellipses ×{}", kept.len(), fmt_sig(factor)) };
    }
    svg.close();
    scale_bar(svg, &view, &inner);
    panel_border(svg, &inner);
    let caption = format!("{}: {}", k + 1, z.label);
    svg.text(r.x0, r.y0 + 14.0, &fit_text(&caption, r.width()), &[("font-size", "12"), ("font-weight", "bold")]);
    if !ellipse_note.is_empty() {
        halo_text(svg, inner.x1 - 8.0, inner.y1 - 9.0, &ellipse_note, "end", palette::ELLIPSE);
    }
    svg.close();
    stats
}
