//! Chart furniture shared by the histograms and the history plot: round tick steps,
//! a linear scale from data to pixels, and the frame, ticks and labels of an axis.

use super::palette;
use super::svg::{num, Svg};
use super::text::Font;
use super::view::Rect;

/// A round step (1, 2 or 5 × 10^k) giving about `n` ticks from 0 to `max`.
pub(super) fn nice_step(max: f64, n: usize) -> f64 {
    if !(max > 0.0 && max.is_finite()) {
        return 1.0;
    }
    let raw = max / n.max(1) as f64;
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    p * if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    }
}

/// Formats a tick value: integers plain, others with up to 3 decimals.
pub(super) fn tick_label(v: f64) -> String {
    if v.abs() >= 10_000.0 && v.fract() == 0.0 {
        let k = v / 1000.0;
        format!("{}k", num(k, 1))
    } else {
        num(v, 3)
    }
}

/// A linear map from `[d0, d1]` to pixels `[p0, p1]`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Scale {
    d0: f64,
    d1: f64,
    p0: f64,
    p1: f64,
}

impl Scale {
    /// Maps `d0 → p0`, `d1 → p1`.
    pub(super) fn new(d0: f64, d1: f64, p0: f64, p1: f64) -> Scale {
        Scale { d0, d1: if d1 == d0 { d0 + 1.0 } else { d1 }, p0, p1 }
    }

    /// The pixel of data value `v`.
    pub(super) fn at(&self, v: f64) -> f64 {
        self.p0 + (v - self.d0) / (self.d1 - self.d0) * (self.p1 - self.p0)
    }
}

/// The font of a chart's title.
pub(super) const TITLE_FONT: Font = Font::bold(13.0);
/// The font of a chart's figures and axis labels.
pub(super) const LABEL_FONT: Font = Font::regular(11.0);
/// The font of tick labels.
pub(super) const TICK_FONT: Font = Font::regular(10.0);
/// Line height of the figures under a chart's title.
const FIGURE_LINE: f64 = 14.0;

/// The plotting area of a chart panel: the panel less `top` pixels for the heading, room
/// for the tick labels (`right` more on the right for a second axis) and `bottom` pixels
/// under the axis for its tick labels and what goes under them.
pub(super) fn plot_area(panel: &Rect, right: bool, top: f64, bottom: f64) -> Rect {
    Rect::new(
        panel.x0 + 52.0,
        panel.y0 + top,
        panel.x1 - if right { 48.0 } else { 14.0 },
        panel.y1 - bottom,
    )
}

/// A chart's heading: a bold title cut to the panel's width and the figures under it,
/// wrapped over up to two lines. Returns the room it takes from the panel's top, plus
/// the room the top tick label needs.
pub(super) fn heading(svg: &mut Svg, panel: &Rect, title: &str, figures: &str) -> f64 {
    let room = panel.width() - 16.0;
    svg.text(
        panel.x0 + 8.0,
        panel.y0 + 17.0,
        &TITLE_FONT.fit(title, room),
        &[("font-size", "13"), ("font-weight", "bold")],
    );
    let mut baseline = panel.y0 + 17.0;
    if !figures.is_empty() {
        for line in LABEL_FONT.wrap(figures, room, 2) {
            baseline += if baseline == panel.y0 + 17.0 { 16.0 } else { FIGURE_LINE };
            svg.text(
                panel.x0 + 8.0,
                baseline,
                &line,
                &[("font-size", "11"), ("fill", palette::MUTED), ("class", "figures")],
            );
        }
    }
    baseline + 13.0 - panel.y0
}

/// The ticks of a vertical axis: from 0 to `max` by `step`, on the left (with grid lines)
/// or on the right, labels coloured `colour`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Ticks<'a> {
    /// Last tick.
    pub max: f64,
    /// Tick spacing.
    pub step: f64,
    /// On the right side (a second axis).
    pub right: bool,
    /// Label colour.
    pub colour: &'a str,
}

/// Horizontal grid lines and labels of a vertical axis.
pub(super) fn y_axis(
    svg: &mut Svg,
    area: &Rect,
    y: &Scale,
    ticks: &Ticks<'_>,
    fmt: &dyn Fn(f64) -> String,
) {
    let Ticks { max, step, right, colour } = *ticks;
    let mut v = 0.0;
    let mut k = 0;
    while v <= max * (1.0 + 1e-9) && k < 50 {
        let py = y.at(v);
        if !right {
            svg.element(
                "line",
                &[
                    ("x1", &num(area.x0, 1)),
                    ("y1", &num(py, 1)),
                    ("x2", &num(area.x1, 1)),
                    ("y2", &num(py, 1)),
                    ("stroke", "#e6e6e6"),
                    ("stroke-width", "1"),
                ],
            );
        }
        let (x, anchor) = if right { (area.x1 + 5.0, "start") } else { (area.x0 - 5.0, "end") };
        svg.text(
            x,
            py + 4.0,
            &fmt(v),
            &[("text-anchor", anchor), ("font-size", "10"), ("fill", colour)],
        );
        k += 1;
        v = k as f64 * step;
    }
}

/// Ticks and labels of the horizontal axis at `values`.
pub(super) fn x_axis(
    svg: &mut Svg,
    area: &Rect,
    x: &Scale,
    values: &[f64],
    fmt: &dyn Fn(f64) -> String,
) {
    for &v in values {
        let px = x.at(v);
        svg.element(
            "line",
            &[
                ("x1", &num(px, 1)),
                ("y1", &num(area.y1, 1)),
                ("x2", &num(px, 1)),
                ("y2", &num(area.y1 + 4.0, 1)),
                ("stroke", palette::AXIS),
                ("stroke-width", "1"),
            ],
        );
        svg.text(
            px,
            area.y1 + 15.0,
            &fmt(v),
            &[("text-anchor", "middle"), ("font-size", "10"), ("fill", palette::AXIS)],
        );
    }
}

/// The frame of the plotting area.
pub(super) fn frame(svg: &mut Svg, area: &Rect) {
    svg.element(
        "rect",
        &[
            ("x", &num(area.x0, 1)),
            ("y", &num(area.y0, 1)),
            ("width", &num(area.width(), 1)),
            ("height", &num(area.height(), 1)),
            ("fill", "none"),
            ("stroke", palette::AXIS),
            ("stroke-width", "1"),
        ],
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_round() {
        assert_eq!(nice_step(100.0, 5), 20.0);
        assert_eq!(nice_step(7.0, 5), 2.0);
        assert_eq!(nice_step(0.0, 5), 1.0);
        assert_eq!(nice_step(1234.0, 4), 500.0);
        assert_eq!(tick_label(20000.0), "20k");
        assert_eq!(tick_label(0.25), "0.25");
    }
}
