//! Where each panel goes: the title on top, the whole mesh at full width (as tall as its
//! aspect asks, at most 55 % of the width), its legend, the zoom windows in rows of up
//! to three, then the charts (histograms, history) in one row.

use super::view::Rect;

/// Outer margin and gap between panels, in pixels.
pub const MARGIN: f64 = 16.0;
/// Height of a panel's caption line.
pub const CAPTION: f64 = 22.0;
const TITLE: f64 = 62.0;
const CHART: f64 = 250.0;

/// The panels of one report.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
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
    /// One per chart.
    pub charts: Vec<Rect>,
}

/// Zoom windows wider than this (width / height) get a panel of the full width.
pub const WIDE: f64 = 2.2;

/// Lays out a picture `width` pixels wide for a domain of aspect `aspect` (width /
/// height), a legend `legend_height` tall, zoom panels for windows of the aspects
/// `zooms` (wide ones at full width, in order, after the others) and `charts` charts.
pub fn layout(width: f64, aspect: f64, legend_height: f64, zooms: &[f64], charts: usize) -> Layout {
    let inner = width - 2.0 * MARGIN;
    let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
    let mut y = MARGIN;
    let title = Rect::new(MARGIN, y, width - MARGIN, y + TITLE);
    y += TITLE;
    let oh = (inner / aspect).min(0.55 * width).max(80.0);
    let overview = Rect::new(MARGIN, y, width - MARGIN, y + CAPTION + oh);
    y = overview.y1;
    let legend = Rect::new(MARGIN, y + 4.0, width - MARGIN, y + 4.0 + legend_height);
    y = legend.y1 + MARGIN;
    let mut zoom_rects = vec![Rect::new(0.0, 0.0, 0.0, 0.0); zooms.len()];
    let normal: Vec<usize> =
        (0..zooms.len()).filter(|&k| zooms[k] <= WIDE || zooms[k].is_nan()).collect();
    let wide: Vec<usize> = (0..zooms.len()).filter(|&k| zooms[k] > WIDE).collect();
    if !normal.is_empty() {
        let cols = normal.len().min(3);
        let w = (inner - (cols - 1) as f64 * MARGIN) / cols as f64;
        let h = CAPTION + if cols == 1 { 0.5 * w } else { 0.75 * w };
        for (i, &k) in normal.iter().enumerate() {
            let (r, c) = (i / cols, i % cols);
            let x0 = MARGIN + c as f64 * (w + MARGIN);
            let y0 = y + r as f64 * (h + MARGIN);
            zoom_rects[k] = Rect::new(x0, y0, x0 + w, y0 + h);
        }
        y += normal.len().div_ceil(cols) as f64 * (h + MARGIN);
    }
    for &k in &wide {
        let h = CAPTION + (inner / zooms[k]).clamp(0.2 * inner, 0.45 * inner);
        zoom_rects[k] = Rect::new(MARGIN, y, width - MARGIN, y + h);
        y += h + MARGIN;
    }
    let mut chart_rects = Vec::new();
    if charts > 0 {
        let w = (inner - (charts - 1) as f64 * MARGIN) / charts as f64;
        for k in 0..charts {
            let x0 = MARGIN + k as f64 * (w + MARGIN);
            chart_rects.push(Rect::new(x0, y, x0 + w, y + CHART));
        }
        y += CHART + MARGIN;
    }
    Layout {
        width,
        height: y.ceil(),
        title,
        overview,
        legend,
        zooms: zoom_rects,
        charts: chart_rects,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
