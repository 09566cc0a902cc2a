//! Where each panel goes: the title on top (as tall as its lines), the whole mesh at full
//! width (as tall as its aspect asks, at most 55 % of the width), its legend, the zoom
//! windows in rows of up to three (fewer where panels would be narrower than
//! [`MIN_ZOOM`]), then the charts (histograms, history) in rows of up to three (fewer
//! where a chart would be narrower than [`MIN_CHART`], so that its text fits).

use super::view::Rect;

/// Outer margin and gap between panels, in pixels.
pub(super) const MARGIN: f64 = 16.0;
/// Height of a panel's caption of one line.
pub(super) const CAPTION: f64 = 22.0;
/// Height of each further caption line.
pub(super) const CAPTION_LINE: f64 = 15.0;
const CHART: f64 = 250.0;
/// Narrowest zoom panel.
pub(super) const MIN_ZOOM: f64 = 200.0;
/// Narrowest chart panel: the history's key and the histograms' headings fit on it.
pub(super) const MIN_CHART: f64 = 260.0;

/// The panels of one report.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Layout {
    /// Picture width.
    pub width: f64,
    /// Picture height.
    pub height: f64,
    /// The title block.
    pub title: Rect,
    /// The whole mesh (caption included).
    pub overview: Rect,
    /// The legend under it.
    pub legend: Rect,
    /// One per zoom window (caption included).
    pub zooms: Vec<Rect>,
    /// The caption height of each zoom panel (the tallest caption of its row).
    pub zoom_captions: Vec<f64>,
    /// One per chart.
    pub charts: Vec<Rect>,
}

/// Zoom windows wider than this (width / height) get a panel of the full width.
pub(super) const WIDE: f64 = 2.2;

/// What a layout is made for.
pub(super) struct Request<'a> {
    /// Picture width.
    pub width: f64,
    /// The domain's aspect (width / height).
    pub aspect: f64,
    /// The title block's height.
    pub title_height: f64,
    /// The legend's height in a given width.
    pub legend_height: &'a dyn Fn(f64) -> f64,
    /// The aspects of the zoom windows (wide ones get full-width panels after the others).
    pub zooms: &'a [f64],
    /// The number of caption lines of zoom `k` in a panel of a given width.
    pub caption_lines: &'a dyn Fn(usize, f64) -> usize,
    /// The number of charts.
    pub charts: usize,
}

/// How many panels of at least `min` pixels go in a row of `inner` pixels, at most `max`.
fn per_row(inner: f64, min: f64, max: usize) -> usize {
    (((inner + MARGIN) / (min + MARGIN)).floor() as usize).clamp(1, max.max(1))
}

/// A panel's rectangle as the value of its `data-box` attribute: `x0 y0 x1 y1` in
/// pixels, so that a reader of the SVG (and the tests) can check what lies inside it.
pub(super) fn data_box(r: &Rect) -> String {
    use super::svg::num;
    format!("{} {} {} {}", num(r.x0, 1), num(r.y0, 1), num(r.x1, 1), num(r.y1, 1))
}

/// The height of a caption of `lines` lines.
pub(super) fn caption_height(lines: usize) -> f64 {
    CAPTION + CAPTION_LINE * lines.saturating_sub(1) as f64
}

/// The height of the overview's drawing (below its caption) in a picture `width` wide,
/// for a domain of aspect `aspect`.
pub(super) fn overview_height(width: f64, aspect: f64) -> f64 {
    let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
    ((width - 2.0 * MARGIN) / aspect).min(0.55 * width).max(80.0)
}

/// Lays out the picture `req` asks for.
pub(super) fn layout(req: &Request<'_>) -> Layout {
    let width = req.width;
    let zooms = req.zooms;
    let inner = width - 2.0 * MARGIN;
    let mut y = MARGIN;
    let title = Rect::new(MARGIN, y, width - MARGIN, y + req.title_height);
    y = title.y1;
    let oh = overview_height(width, req.aspect);
    let overview = Rect::new(MARGIN, y, width - MARGIN, y + CAPTION + oh);
    y = overview.y1;
    let legend_height = (req.legend_height)(inner);
    let legend = Rect::new(MARGIN, y + 4.0, width - MARGIN, y + 4.0 + legend_height);
    y = legend.y1 + MARGIN;
    let mut zoom_rects = vec![Rect::new(0.0, 0.0, 0.0, 0.0); zooms.len()];
    let mut captions = vec![CAPTION; zooms.len()];
    let normal: Vec<usize> =
        (0..zooms.len()).filter(|&k| zooms[k] <= WIDE || zooms[k].is_nan()).collect();
    let wide: Vec<usize> = (0..zooms.len()).filter(|&k| zooms[k] > WIDE).collect();
    if !normal.is_empty() {
        let cols = per_row(inner, MIN_ZOOM, normal.len().min(3));
        let w = (inner - (cols - 1) as f64 * MARGIN) / cols as f64;
        let body = if cols == 1 { 0.5 * w } else { 0.75 * w };
        for row in normal.chunks(cols) {
            let cap = row
                .iter()
                .map(|&k| caption_height((req.caption_lines)(k, w)))
                .fold(CAPTION, f64::max);
            for (c, &k) in row.iter().enumerate() {
                let x0 = MARGIN + c as f64 * (w + MARGIN);
                zoom_rects[k] = Rect::new(x0, y, x0 + w, y + cap + body);
                captions[k] = cap;
            }
            y += cap + body + MARGIN;
        }
    }
    for &k in &wide {
        let cap = caption_height((req.caption_lines)(k, inner));
        let h = cap + (inner / zooms[k]).clamp(0.2 * inner, 0.45 * inner);
        zoom_rects[k] = Rect::new(MARGIN, y, width - MARGIN, y + h);
        captions[k] = cap;
        y += h + MARGIN;
    }
    let mut chart_rects = Vec::new();
    if req.charts > 0 {
        let cols = per_row(inner, MIN_CHART, req.charts.min(3));
        let w = (inner - (cols - 1) as f64 * MARGIN) / cols as f64;
        for k in 0..req.charts {
            let (r, c) = (k / cols, k % cols);
            let x0 = MARGIN + c as f64 * (w + MARGIN);
            let y0 = y + r as f64 * (CHART + MARGIN);
            chart_rects.push(Rect::new(x0, y0, x0 + w, y0 + CHART));
        }
        y += req.charts.div_ceil(cols) as f64 * (CHART + MARGIN);
    }
    Layout {
        width,
        height: y.ceil(),
        title,
        overview,
        legend,
        zooms: zoom_rects,
        zoom_captions: captions,
        charts: chart_rects,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(width: f64, aspect: f64, legend: f64, zooms: &[f64], charts: usize) -> Layout {
        super::layout(&Request {
            width,
            aspect,
            title_height: 62.0,
            legend_height: &|_| legend,
            zooms,
            caption_lines: &|_, _| 1,
            charts,
        })
    }

    #[test]
    fn panels_do_not_overlap_and_fit() {
        let l = layout(1200.0, 4.0, 40.0, &[1.0, 1.0, 1.0, 1.0], 3);
        assert_eq!(l.zooms.len(), 4);
        assert!(l.zooms[3].y0 > l.zooms[0].y1);
        for r in l.zooms.iter().chain(&l.charts) {
            assert!(r.x0 >= 0.0 && r.x1 <= l.width && r.y1 <= l.height);
            assert!(r.y0 > l.legend.y1);
        }
        assert!(l.charts[0].y0 > l.zooms[3].y1);
        let l = layout(1200.0, 4.0, 40.0, &[5.0, 1.0], 2);
        assert_eq!(l.zooms[0].width(), 1200.0 - 2.0 * MARGIN);
        assert!(l.zooms[0].y0 > l.zooms[1].y1);
    }

    #[test]
    fn narrow_pictures_put_fewer_panels_in_a_row() {
        let l = layout(600.0, 1.0, 20.0, &[1.0, 1.0, 1.0], 3);
        assert!(l.zooms.iter().all(|r| r.width() >= MIN_ZOOM), "{:?}", l.zooms);
        assert!(l.charts.iter().all(|r| r.width() >= MIN_CHART), "{:?}", l.charts);
        assert!(l.charts[2].y0 > l.charts[0].y1);
        let l = layout(1200.0, 1.0, 20.0, &[1.0, 1.0, 1.0], 3);
        assert_eq!(l.charts[0].y0, l.charts[2].y0);
        // A caption of two lines makes its whole row taller, the panels' bodies equal.
        let l = super::layout(&Request {
            width: 900.0,
            aspect: 1.0,
            title_height: 62.0,
            legend_height: &|_| 20.0,
            zooms: &[1.0, 1.0],
            caption_lines: &|k, _| k + 1,
            charts: 0,
        });
        assert_eq!(l.zoom_captions, vec![caption_height(2); 2]);
        assert_eq!(l.zooms[0].height(), l.zooms[1].height());
    }
}
