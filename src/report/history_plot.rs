//! The convergence history of an adaptation run: vertices per iteration on the left
//! axis, conforming share and mean metric quality (both in [0, 1]) on the right, the
//! iteration whose mesh was kept marked by a dashed line. The x axis counts iterations
//! (the heading says so); the key of the three series takes its label's place.

use crate::history::{History, IterationRecord};

use super::axes::{self, nice_step, tick_label, Scale};
use super::palette;
use super::svg::{num, PathData, Svg};
use super::view::Rect;

/// One plotted series: name, colour, vertical scale, and the value of a record.
type Series<'a> = (&'a str, &'a str, &'a Scale, &'a dyn Fn(&IterationRecord) -> f64);

/// Height of a row of the key.
const KEY_ROW: f64 = 14.0;

/// The key's entries (a 14 px line, then the name): each one's x offset and row, in
/// rows of at most `width` pixels.
fn key_positions(names: &[&str], width: f64) -> Vec<(f64, usize)> {
    let (mut x, mut row) = (0.0, 0);
    let mut out = Vec::new();
    for name in names {
        let w = 18.0 + axes::TICK_FONT.width(name);
        if x > 0.0 && x + w > width {
            x = 0.0;
            row += 1;
        }
        out.push((x, row));
        x += w + 12.0;
    }
    out
}

/// Draws `h` into `panel`.
pub(super) fn draw(svg: &mut Svg, panel: &Rect, h: &History) {
    let bx = super::layout::data_box(panel);
    svg.open("g", &[("id", "history"), ("class", "panel history"), ("data-box", &bx)]);
    let state = if h.converged { "converged" } else { "not converged" };
    let figures = format!("{} iterations, {state}, best {}", h.iterations.len(), h.best_iteration);
    let top = axes::heading(svg, panel, "Adaptation history", &figures);
    let names = ["vertices", "conforming share", "mean quality"];
    let key = key_positions(&names, panel.width() - 20.0);
    let rows = key.last().map_or(1, |k| k.1 + 1);
    let area = axes::plot_area(panel, true, top, 26.0 + KEY_ROW * rows as f64);
    let last = h.iterations.iter().map(|r| r.iteration).max().unwrap_or(0).max(1) as f64;
    let x = Scale::new(0.0, last, area.x0 + 6.0, area.x1 - 6.0);
    let vmax = h.iterations.iter().map(|r| r.vertices).max().unwrap_or(0).max(1) as f64;
    let step = nice_step(vmax, 4).max(1.0); // vertex counts: whole ticks
    let vtop = (vmax / step).ceil() * step;
    let yv = Scale::new(0.0, vtop, area.y1, area.y0);
    let ys = Scale::new(0.0, 1.0, area.y1, area.y0);
    axes::y_axis(
        svg,
        &area,
        &yv,
        &axes::Ticks { max: vtop, step, right: false, colour: palette::SERIES_A },
        &tick_label,
    );
    axes::y_axis(
        svg,
        &area,
        &ys,
        &axes::Ticks { max: 1.0, step: 0.25, right: true, colour: palette::SERIES_B },
        &|v| format!("{}%", num(100.0 * v, 0)),
    );
    if let Some(best) = h.iterations.iter().find(|r| r.iteration == h.best_iteration) {
        let px = num(x.at(best.iteration as f64), 2);
        svg.element(
            "line",
            &[
                ("class", "best"),
                ("data-iteration", &best.iteration.to_string()),
                ("x1", &px),
                ("y1", &num(area.y0, 1)),
                ("x2", &px),
                ("y2", &num(area.y1, 1)),
                ("stroke", "#000"),
                ("stroke-dasharray", "4 3"),
                ("stroke-width", "1"),
            ],
        );
        // On the side of the line where it fits inside the plotting area.
        let bx = x.at(best.iteration as f64);
        let (lx, anchor) = if bx + 3.0 + axes::TICK_FONT.width("best") <= area.x1 - 2.0 {
            (bx + 3.0, "start")
        } else {
            (bx - 3.0, "end")
        };
        svg.text(
            lx,
            area.y0 + 11.0,
            "best",
            &[("font-size", "10"), ("text-anchor", anchor), ("class", "best-label")],
        );
    }
    let series: [Series<'_>; 3] = [
        ("vertices", palette::SERIES_A, &yv, &|r| r.vertices as f64),
        ("conforming share", palette::SERIES_B, &ys, &|r| r.conforming_share),
        ("mean quality", palette::SERIES_C, &ys, &|r| r.mean_quality),
    ];
    for (k, (name, colour, y, value)) in series.iter().enumerate() {
        let mut d = PathData::new(2);
        for (i, r) in h.iterations.iter().enumerate() {
            let p = [x.at(r.iteration as f64), y.at(value(r))];
            if i == 0 {
                d.move_to(p);
            } else {
                d.line_to(p);
            }
        }
        let class = format!("series series-{k}");
        svg.open("g", &[("class", &class), ("data-name", name)]);
        if !d.is_empty() {
            svg.element(
                "path",
                &[("d", d.as_str()), ("fill", "none"), ("stroke", colour), ("stroke-width", "1.8")],
            );
        }
        for r in &h.iterations {
            let (cx, cy) = (num(x.at(r.iteration as f64), 2), num(y.at(value(r)), 2));
            let v = num(value(r), 6);
            svg.element(
                "circle",
                &[("cx", &cx), ("cy", &cy), ("r", "2.5"), ("fill", colour), ("data-value", &v)],
            );
        }
        svg.close();
        // The key, under the x axis' tick labels, in as many rows as it needs.
        let (kx, row) = key[k];
        let lx = panel.x0 + 10.0 + kx;
        let ly = panel.y1 - 10.0 - KEY_ROW * (rows - 1 - row) as f64;
        svg.element(
            "line",
            &[
                ("x1", &num(lx, 1)),
                ("y1", &num(ly - 3.5, 1)),
                ("x2", &num(lx + 14.0, 1)),
                ("y2", &num(ly - 3.5, 1)),
                ("stroke", colour),
                ("stroke-width", "2"),
            ],
        );
        svg.text(lx + 18.0, ly, name, &[("font-size", "10")]);
    }
    axes::frame(svg, &area);
    let tstep = nice_step(last, 6).max(1.0);
    let ticks: Vec<f64> =
        (0..).map(|k| k as f64 * tstep).take_while(|&v| v <= last + 1e-9).collect();
    axes::x_axis(svg, &area, &x, &ticks, &|v| num(v, 0));
    svg.close();
}
