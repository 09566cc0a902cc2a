//! The two histograms of a metric report: metric edge length (bins of 0.1 from 0 to 3,
//! the last holding everything longer, the conforming band [1/√2, √2] shaded and the
//! share of edges in it printed) and metric triangle quality (bins of 0.1 on [0, 1]).
//! The bars are [`Conformity`]'s own counts; each carries them in `data-count`.

use crate::conformity::{Conformity, LENGTH_BINS};
use crate::metric::length::CONFORMING;

use super::axes::{self, nice_step, tick_label, Scale};
use super::palette;
use super::svg::{num, Svg};
use super::view::Rect;

/// What one histogram shows.
struct Bars<'a> {
    id: &'static str,
    title: &'static str,
    figures: String,
    counts: &'a [usize],
    bin_width: f64,
    /// The x axis' label, longest first: the first that fits is drawn.
    x_label: &'static [&'static str],
    x_ticks: Vec<f64>,
    band: Option<[f64; 2]>,
    overflow_last: bool,
}

fn draw(svg: &mut Svg, panel: &Rect, b: &Bars<'_>) {
    let bx = super::layout::data_box(panel);
    svg.open("g", &[("id", b.id), ("class", "panel histogram"), ("data-box", &bx)]);
    let top = axes::heading(svg, panel, b.title, &b.figures);
    let area = axes::plot_area(panel, false, top, 40.0);
    let n = b.counts.len();
    let x = Scale::new(0.0, n as f64 * b.bin_width, area.x0, area.x1);
    let top = b.counts.iter().copied().max().unwrap_or(0).max(1) as f64;
    let step = nice_step(top, 4).max(1.0); // counts: whole ticks
    let ymax = (top / step).ceil() * step;
    let y = Scale::new(0.0, ymax, area.y1, area.y0);
    if let Some([lo, hi]) = b.band {
        let (x0, x1) = (x.at(lo), x.at(hi));
        svg.element(
            "rect",
            &[
                ("class", "band"),
                ("x", &num(x0, 2)),
                ("y", &num(area.y0, 1)),
                ("width", &num(x1 - x0, 2)),
                ("height", &num(area.height(), 1)),
                ("fill", palette::BAND),
            ],
        );
    }
    axes::y_axis(
        svg,
        &area,
        &y,
        &axes::Ticks { max: ymax, step, right: false, colour: palette::AXIS },
        &tick_label,
    );
    for (i, &c) in b.counts.iter().enumerate() {
        let (lo, hi) = (i as f64 * b.bin_width, (i + 1) as f64 * b.bin_width);
        let (x0, x1) = (x.at(lo), x.at(hi));
        let (y0, y1) = (y.at(c as f64), y.at(0.0));
        let inside = b.band.is_some_and(|[l, h]| lo >= l - 1e-12 && hi <= h + 1e-12);
        let hi_label = if b.overflow_last && i + 1 == n { "inf".to_string() } else { num(hi, 3) };
        let (cs, los) = (c.to_string(), num(lo, 3));
        svg.element(
            "rect",
            &[
                ("class", "bar"),
                ("data-count", &cs),
                ("data-lo", &los),
                ("data-hi", &hi_label),
                ("x", &num(x0 + 0.5, 2)),
                ("y", &num(y0, 2)),
                ("width", &num((x1 - x0 - 1.0).max(0.5), 2)),
                ("height", &num(y1 - y0, 2)),
                ("fill", if inside { palette::BAR_OK } else { palette::BAR }),
            ],
        );
    }
    axes::frame(svg, &area);
    let fmt = |v: f64| {
        if b.overflow_last && (v - n as f64 * b.bin_width).abs() < 1e-9 {
            format!("≥{}", num(v - b.bin_width, 1))
        } else {
            num(v, 2)
        }
    };
    axes::x_axis(svg, &area, &x, &b.x_ticks, &fmt);
    svg.text(
        0.5 * (panel.x0 + panel.x1),
        panel.y1 - 8.0,
        &axes::LABEL_FONT.first_fitting(b.x_label, panel.width() - 16.0),
        &[("text-anchor", "middle"), ("font-size", "11"), ("fill", palette::MUTED)],
    );
    svg.close();
}

/// The histogram of metric edge lengths.
pub(super) fn edge_lengths(svg: &mut Svg, panel: &Rect, c: &Conformity) {
    let figures = format!(
        "{}% of {} edges in [{}, {}]",
        num(100.0 * c.conforming_share, 1),
        c.edges,
        num(CONFORMING[0], 2),
        num(CONFORMING[1], 2)
    );
    let bars = Bars {
        id: "hist-length",
        title: "Metric edge length",
        figures,
        counts: &c.edge_length_histogram,
        bin_width: 0.1,
        x_label: &[
            "metric length (1 = as asked; last bar: all longer)",
            "metric length (last bar: all longer)",
            "metric length",
        ],
        x_ticks: (0..=LENGTH_BINS / 5).map(|k| k as f64 * 0.5).collect(),
        band: Some(CONFORMING),
        overflow_last: true,
    };
    draw(svg, panel, &bars);
}

/// The histogram of metric triangle quality.
pub(super) fn quality(svg: &mut Svg, panel: &Rect, c: &Conformity) {
    let figures = format!(
        "mean {}, min {} over {} triangles",
        num(c.mean_quality, 3),
        num(c.min_quality, 3),
        c.triangles
    );
    let bars = Bars {
        id: "hist-quality",
        title: "Metric quality",
        figures,
        counts: &c.quality_histogram,
        bin_width: 0.1,
        x_label: &[
            "metric quality (1 = equilateral in the metric)",
            "metric quality (1 = equilateral)",
            "metric quality",
        ],
        x_ticks: (0..=5).map(|k| k as f64 * 0.2).collect(),
        band: None,
        overflow_last: false,
    };
    draw(svg, panel, &bars);
}
