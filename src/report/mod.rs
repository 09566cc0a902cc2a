//! `smartmesh report`: a picture of a mesh and its metric that a user would rather look
//! at than read — the whole mesh (faces filled by tag, edges, boundary curves by tag,
//! with a legend), zoom windows around the recipe's sources (or the smallest metric
//! sizes), size ellipses in the zooms, histograms of metric edge length and quality, and
//! the convergence history of an adaptation run.
//!
//! - `svg`: the SVG writer with deterministic number formatting;
//! - `view`: rectangles and the mesh-to-pixel map;
//! - `layout` and `legend`: where the panels and legend entries go;
//! - `mesh_layer`: faces, edges (shaded below 2 px, so big meshes stay small) and curves;
//! - `windows`: the zoom windows;
//! - `ellipses`: size ellipses and the vertices they are drawn at;
//! - `panels`: the zoom panels and what the overview shares with them;
//! - `tabs`: where the overview puts each zoom frame's number tab;
//! - `axes`, `histogram`, `history_plot`: the charts;
//! - `text`: text measured (a table of the font's advances) and fitted to its panel;
//! - `png`: rasterising through resvg;
//! - `skin`: zooms on a boundary-layer skin and its thinned columns;
//! - `cut`: `report --cut`, the planar cut of a tetrahedral mesh (computed by the
//!   crate's `section`, which knows no picture) drawn as a planar mesh, its volumes as
//!   faces, its surfaces' traces as curves, with the ellipses of the 3D metric
//!   *restricted* to the plane (its section through each point, not its projection).
//!
//! Everything is a pure function of its input: the same mesh, metric, recipe and history
//! give the same bytes.

mod axes;
mod cut;
mod ellipses;
mod histogram;
mod history_plot;
mod layout;
mod legend;
mod mesh_layer;
mod palette;
mod panels;
mod png;
mod skin;
mod svg;
mod tabs;
mod text;
mod view;
mod windows;

use std::path::Path;

// What the CLI and the tests use of the drawing modules: the PNG rasteriser and the
// font table the layout measures text with.
pub use self::cut::{render_cut, CutError, CutInput, CutSummary};
pub use self::png::{rasterise, PngOptions};
pub use self::text::{Font, ASCENT, DESCENT};
pub use self::windows::ZoomWindow;
pub use crate::section::{Axis, CutPlane, SectionCounts};

use crate::conformity::Conformity;
use crate::history::History;
use crate::metric::SizeTensor;
use crate::metric_field::MetricField;
use crate::sizing::plan::SizingPlan;
use crate::topology::Topology;
use smartmesh_formats::TaggedMesh;

use self::layout::CAPTION;
use self::mesh_layer::MeshLayers;
use self::panels::{
    clip, draw_marks, draw_zoom, panel_border, plural, scale_bar, source_marks, zoom_inner, Scene,
};
use crate::mesh_graph::MeshGraph;
use crate::sizing::field::run_algorithm;

/// The font of the report's title (the mesh's name).
const TITLE_FONT: Font = Font::bold(18.0);
/// The font of the lines under it.
const TITLE_INFO_FONT: Font = Font::regular(13.0);
use self::svg::{num, Svg};
use self::view::{Rect, View};

/// Default picture width in pixels.
pub const DEFAULT_WIDTH: u32 = 1200;
/// Narrowest and widest pictures accepted.
pub const WIDTH_RANGE: [u32; 2] = [400, 8000];
/// Zoom windows around the smallest sizes when there is no recipe.
const SIZE_WINDOWS: usize = 3;

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
    pub metric: Option<&'a MetricField>,
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
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    /// The SVG document.
    #[serde(skip)]
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
    /// What a planar cut (`report --cut`) drew.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cut: Option<CutSummary>,
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

/// Draws the report: the zoom windows chosen, the title lines written, the page laid
/// out, then the title, the overview, the legend, the zooms and the charts drawn.
pub fn render(input: &ReportInput<'_>, options: &ReportOptions) -> Report {
    render_page(input, options, None)
}

/// What a cut changes on the page: the title's lines, the legend's words, ellipses on
/// the overview, no conformity charts (the cut's polygons are no cells of the mesh).
struct CutPage {
    /// The lines under the title.
    lines: Vec<String>,
    /// What the report says it drew.
    summary: CutSummary,
}

/// [`render`], as a cut when `cut` is given.
fn render_page(input: &ReportInput<'_>, options: &ReportOptions, cut: Option<&CutPage>) -> Report {
    let width = options.width.clamp(WIDTH_RANGE[0], WIDTH_RANGE[1]) as f64;
    let mesh = input.mesh;
    let topo = input.topology;
    let points: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let layers = MeshLayers::new(topo, points.clone());
    let domain = layers
        .bounds()
        .or_else(|| Rect::bounding(points.iter().copied()))
        .unwrap_or(Rect::new(0.0, 0.0, 1.0, 1.0));
    let mut notes = Vec::new();

    let conformity =
        input.metric.filter(|_| cut.is_none()).and_then(|m| Conformity::of_mesh(mesh, m.tensors()));
    let sizes: Option<Vec<Option<SizeTensor>>> = input
        .metric
        .map(|m| m.tensors().iter().map(|t| SizeTensor::try_from_metric(t).ok()).collect());
    let (mut zooms, skin) =
        zoom_windows(input, &points, &domain, sizes.as_deref(), cut.is_none(), &mut notes);
    let marks = source_marks(input.plan, topo, &points);

    let inner_width = width - 2.0 * layout::MARGIN;
    let aspect = domain.width().max(1e-300) / domain.height().max(1e-300 + domain.width() * 1e-3);
    let ov_world = domain.inflate(0.01 * domain.diagonal());
    // The overview's scale does not depend on where it is placed: whether it shades
    // edges is known before the layout, for the legend's colour scale.
    let ov_scale = View::fit(
        ov_world,
        Rect::new(0.0, 0.0, inner_width, layout::overview_height(width, aspect)),
    )
    .scale;
    let extras = legend::Extras {
        source_points: !marks.points.is_empty(),
        source_polylines: !marks.polylines.is_empty(),
        shading: layers.has_short_edges(ov_scale),
        cut: cut.is_some(),
    };
    let entries = legend::entries(topo, extras);
    let charts = if conformity.is_some() { 2 } else { 0 } + usize::from(input.history.is_some());
    let zoom_aspects: Vec<f64> =
        zooms.iter().map(|z| z.region.width() / z.region.height().max(1e-300)).collect();
    let zoom_captions: Vec<String> =
        zooms.iter().enumerate().map(|(k, z)| format!("{}: {}", k + 1, z.label)).collect();
    let info_lines = match cut {
        Some(c) => c.lines.iter().flat_map(|l| TITLE_INFO_FONT.wrap(l, inner_width, 2)).collect(),
        None => title_lines(input, conformity.as_ref(), inner_width, &mut notes),
    };
    let title_height = 46.0 + 16.0 * (info_lines.len() - 1) as f64;

    let lay = layout::layout(&layout::Request {
        width,
        aspect,
        title_height,
        legend_height: &|w| legend::height(&entries, w),
        zooms: &zoom_aspects,
        caption_lines: &|k, w| panels::caption_lines(&zoom_captions[k], w).len(),
        charts,
    });
    let zoom_views = zoom_views(&zooms, &lay, &domain);
    let mut svg = Svg::new(lay.width, lay.height);

    draw_title(&mut svg, &lay.title, input.name, &info_lines);
    let ellipses = match (cut, sizes.as_deref()) {
        (Some(_), Some(s)) => Some((topo, s)),
        _ => None,
    };
    let overview =
        Overview { rect: lay.overview, world: ov_world, domain, zoom_views: &zoom_views, ellipses };
    let mut shaded = draw_overview(&mut svg, &overview, &layers, &marks, &skin);
    legend::draw(&mut svg, &lay.legend, &entries);

    // Zooms.
    for (k, ((z, r), view)) in zooms.iter().zip(&lay.zooms).zip(&zoom_views).enumerate() {
        let scene = Scene {
            layers: &layers,
            topology: topo,
            sizes: sizes.as_deref(),
            marks: &marks,
            skin: &skin,
        };
        let stats = draw_zoom(&mut svg, k, z, r, view, &scene);
        shaded = shaded.max(stats.shaded);
    }
    if shaded > 0 {
        notes.push(format!(
            "edges shorter than {} px are drawn as shading (up to {shaded} edges in one panel)",
            mesh_layer::MIN_EDGE_PX
        ));
    }

    draw_charts(&mut svg, &lay.charts, conformity.as_ref(), input.history);

    for (z, v) in zooms.iter_mut().zip(&zoom_views) {
        z.shown = v.world;
    }
    Report {
        svg: svg.finish(),
        width: lay.width as u32,
        height: lay.height as u32,
        zooms,
        conformity,
        notes,
        cut: cut.map(|c| c.summary.clone()),
    }
}

/// The zoom windows, in the order they are numbered: around the plan's sources (or the
/// smallest sizes without a plan), then around a boundary-layer skin (when `skin` is
/// asked: a cut's quads are no skin); with the skin's marks, and a note when columns
/// were thinned.
fn zoom_windows(
    input: &ReportInput<'_>,
    points: &[[f64; 2]],
    domain: &Rect,
    sizes: Option<&[Option<SizeTensor>]>,
    skin: bool,
    notes: &mut Vec<String>,
) -> (Vec<ZoomWindow>, skin::SkinMarks) {
    let (mesh, topo) = (input.mesh, input.topology);
    // The mesh graph, built only when a step's source is as large as the domain and its
    // window is framed where the step asks for its finest sizes.
    let mut graph: Option<Option<MeshGraph>> = None;
    let mut focus = |k: usize| {
        let plan = input.plan?;
        let step = plan.steps.get(k)?;
        let g = graph.get_or_insert_with(|| MeshGraph::from_topology(topo, mesh).ok()).as_ref()?;
        let c = run_algorithm(g, topo, &step.algorithm, k, &step.label).ok()?;
        windows::finest(&c, points)
    };
    let mut zooms = match (input.plan, sizes) {
        (Some(plan), _) => windows::from_plan(plan, topo, points, domain, &mut focus),
        (None, Some(s)) => windows::from_sizes(s, topo, points, domain, SIZE_WINDOWS),
        (None, None) => Vec::new(),
    };
    let skin = if skin { skin::skin_marks(mesh, domain) } else { skin::SkinMarks::default() };
    zooms.extend(skin.windows.iter().cloned());
    if !skin.thinned.is_empty() {
        notes.push(format!(
            "{} points of boundary-layer columns thinned or stopped, drawn in red",
            skin.thinned.len()
        ));
    }
    // Wide windows get full-width panels after the others; number them in that order.
    zooms.sort_by_key(|z| z.region.width() > layout::WIDE * z.region.height());
    (zooms, skin)
}

/// The lines under the title, wrapped to `width`: the mesh's counts, then its metric's
/// conformity (or why there is none, also a note).
fn title_lines(
    input: &ReportInput<'_>,
    conformity: Option<&Conformity>,
    width: f64,
    notes: &mut Vec<String>,
) -> Vec<String> {
    let (mesh, topo) = (input.mesh, input.topology);
    let triangles = topo.surface_cells.len();
    let counts = format!(
        "{}, {}, {}, {}, {}",
        plural(mesh.points.len(), "vertex", "vertices"),
        plural(triangles, "surface cell", "surface cells"),
        plural(topo.faces.len(), "face", "faces"),
        plural(topo.curves.len(), "curve", "curves"),
        plural(
            topo.points.iter().filter(|p| p.tag.is_some()).count(),
            "tagged point",
            "tagged points"
        )
    );
    let metric_line = match (input.metric, conformity) {
        (Some(m), Some(c)) => format!(
            "metric {}: {}% of edges conforming, mean metric quality {}",
            m.source(),
            num(100.0 * c.conforming_share, 1),
            num(c.mean_quality, 3)
        ),
        (Some(m), None) => format!("metric {}: no triangle to measure", m.source()),
        (None, _) => {
            let why = format!(
                "no metric: {} has no point data `metric` and no --metric was given",
                input.name
            );
            notes.push(why.clone());
            why
        }
    };
    [counts, metric_line].iter().flat_map(|l| TITLE_INFO_FONT.wrap(l, width, 2)).collect()
}

/// The view of each zoom panel: its window grown to the panel's aspect, moved inside the
/// domain where it fits (a window around a corner shows mesh, not the page), less a
/// margin of 4 % of the window, so that a boundary at its edge is not drawn on the
/// panel's border.
fn zoom_views(zooms: &[ZoomWindow], lay: &layout::Layout, domain: &Rect) -> Vec<View> {
    zooms
        .iter()
        .zip(&lay.zooms)
        .zip(&lay.zoom_captions)
        .map(|((z, r), &cap)| {
            let inner = zoom_inner(r, cap);
            let world = View::fit(z.region, inner).world;
            let pad = 0.04 * world.width().min(world.height());
            let grown = world.shift_inside(&domain.inflate(pad));
            View::fit(grown, inner)
        })
        .collect()
}

/// Where the overview goes and what it frames.
struct Overview<'a> {
    /// Its panel on the page.
    rect: Rect,
    /// The part of the plane it shows.
    world: Rect,
    /// The mesh's bounds.
    domain: Rect,
    /// The zoom panels' views, framed on it.
    zoom_views: &'a [View],
    /// Size ellipses to draw on it too (a cut's), with the topology that says which
    /// vertices are used.
    ellipses: Option<(&'a Topology, &'a [Option<SizeTensor>])>,
}

/// The overview panel: the whole mesh, the source marks, the skin, a frame and a number
/// tab for each zoom, the scale bar; returns how many of its edges were shaded.
fn draw_overview(
    svg: &mut Svg,
    o: &Overview<'_>,
    layers: &MeshLayers,
    marks: &panels::SourceMarks,
    skin: &skin::SkinMarks,
) -> usize {
    let (ov, domain) = (o.rect, o.domain);
    let ov_inner = Rect::new(ov.x0, ov.y0 + CAPTION, ov.x1, ov.y1);
    let ov_view = View::fit(o.world, ov_inner);
    svg.open(
        "g",
        &[
            ("id", "overview"),
            ("class", "panel overview"),
            ("data-scale", &num(ov_view.scale, 6)),
            ("data-box", &layout::data_box(&ov)),
        ],
    );
    clip(svg, "clip-overview", &ov_inner);
    svg.open("g", &[("clip-path", "url(#clip-overview)")]);
    layers.draw_faces(svg, &ov_view);
    let ov_stats = layers.draw_edges(svg, &ov_view, 0.35);
    layers.draw_curves(svg, &ov_view, 1.8);
    layers.draw_points(svg, &ov_view, 4.0);
    draw_marks(svg, &ov_view, marks);
    skin::draw(svg, &ov_view, skin, 1.5);
    if let Some((topo, sizes)) = o.ellipses {
        panels::draw_ellipses(svg, &ov_view, layers, topo, sizes);
    }
    // A window wider or taller than the domain is framed where the mesh is.
    let frames: Vec<Rect> = o
        .zoom_views
        .iter()
        .map(|zv| ov_view.rect_to_px(&zv.world.intersect(&domain).unwrap_or(domain)))
        .collect();
    let content = ov_view.rect_to_px(&domain).intersect(&ov_inner).unwrap_or(ov_inner);
    let placed = tabs::place(&frames, &ov_inner, &[panels::scale_bar_box(&ov_view, &content)]);
    draw_zoom_frames(svg, &frames, &placed);
    svg.close();
    scale_bar(svg, &ov_view, &content);
    svg.text(ov.x0, ov.y0 + 14.0, "Whole mesh", &[("font-size", "13"), ("font-weight", "bold")]);
    if ov_stats.shaded > 0 {
        let n = ov_stats.shaded;
        let long = format!(
            "{n} edges shorter than {} px drawn as shading",
            num(mesh_layer::MIN_EDGE_PX, 0)
        );
        let short = format!("{n} edges shaded");
        let room = ov.width() - Font::bold(13.0).width("Whole mesh") - 16.0;
        let s = Font::regular(11.0).first_fitting(&[&long, &short], room);
        svg.text(
            ov.x1,
            ov.y0 + 14.0,
            &s,
            &[("font-size", "11"), ("fill", palette::MUTED), ("text-anchor", "end")],
        );
    }
    svg.close();
    ov_stats.shaded
}

/// The title panel: the mesh's name and the information lines under it.
fn draw_title(svg: &mut Svg, title: &Rect, name: &str, info_lines: &[String]) {
    svg.open("g", &[("id", "title"), ("data-box", &layout::data_box(title))]);
    svg.text(
        title.x0,
        title.y0 + 18.0,
        &TITLE_FONT.fit(name, title.width()),
        &[("font-size", "18"), ("font-weight", "bold")],
    );
    for (k, line) in info_lines.iter().enumerate() {
        svg.text(
            title.x0,
            title.y0 + 37.0 + 16.0 * k as f64,
            line,
            &[("font-size", "13"), ("fill", palette::MUTED)],
        );
    }
    svg.close();
}

/// The overview's frame of each zoom window and its number tab, on a corner of its frame
/// when one is free (see `tabs`), else joined to it by a leader line.
fn draw_zoom_frames(svg: &mut Svg, frames: &[Rect], placed: &[tabs::Tab]) {
    for (k, r) in frames.iter().enumerate() {
        svg.element(
            "rect",
            &[
                ("class", "zoom-frame"),
                ("data-zoom", &(k + 1).to_string()),
                ("x", &num(r.x0, 1)),
                ("y", &num(r.y0, 1)),
                ("width", &num(r.width(), 1)),
                ("height", &num(r.height(), 1)),
                ("fill", "none"),
                ("stroke", palette::FRAME),
                ("stroke-width", "1.5"),
            ],
        );
    }
    // The number tabs over every frame, each on a corner of its frame when one is free
    // (see `tabs`), else joined to it by a leader line.
    for (k, (r, tab)) in frames.iter().zip(placed).enumerate() {
        let id = (k + 1).to_string();
        let t = tab.rect;
        if !tab.on_frame {
            let c = t.centre();
            let e = tabs::nearest_on_border(r, c);
            svg.element(
                "line",
                &[
                    ("class", "zoom-tab-leader"),
                    ("data-zoom", &id),
                    ("x1", &num(c[0], 1)),
                    ("y1", &num(c[1], 1)),
                    ("x2", &num(e[0], 1)),
                    ("y2", &num(e[1], 1)),
                    ("stroke", palette::FRAME),
                    ("stroke-width", "1"),
                ],
            );
        }
        svg.element(
            "rect",
            &[
                ("class", "zoom-tab"),
                ("data-zoom", &id),
                ("x", &num(t.x0, 1)),
                ("y", &num(t.y0, 1)),
                ("width", &num(tabs::SIDE, 1)),
                ("height", &num(tabs::SIDE, 1)),
                ("fill", palette::FRAME),
            ],
        );
        svg.text(
            t.x0 + 0.5 * tabs::SIDE,
            t.y0 + 11.5,
            &id,
            &[
                ("font-size", "11"),
                ("font-weight", "bold"),
                ("fill", "#ffffff"),
                ("text-anchor", "middle"),
                ("class", "on-mesh"),
            ],
        );
    }
}

/// The charts: edge lengths and quality when the mesh has a metric, the adapt history
/// when there is one; each in a border.
fn draw_charts(
    svg: &mut Svg,
    charts: &[Rect],
    conformity: Option<&Conformity>,
    history: Option<&History>,
) {
    let mut chart = charts.iter();
    if let Some(c) = conformity {
        if let (Some(a), Some(b)) = (chart.next(), chart.next()) {
            histogram::edge_lengths(svg, a, c);
            histogram::quality(svg, b, c);
        }
    }
    if let (Some(h), Some(r)) = (history, chart.next()) {
        history_plot::draw(svg, r, h);
    }
    for r in charts {
        panel_border(svg, r);
    }
}
