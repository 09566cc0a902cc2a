//! Size ellipses: the ellipse of semi-axes h1, h2 along a size tensor's axes (the unit
//! ball of the metric, the edge lengths the metric asks for), placed in a view, at a
//! deterministic subset of the vertices that keeps them apart.

use crate::metric::SizeTensor;

use super::view::View;

/// An ellipse in pixels: centre, semi-axes, and the angle of its first axis measured
/// clockwise from the picture's x axis (SVG's `rotate`, y pointing down).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Ellipse {
    /// Centre x.
    pub cx: f64,
    /// Centre y.
    pub cy: f64,
    /// Semi-axis along the first axis (h1 · scale).
    pub rx: f64,
    /// Semi-axis along the second axis (h2 · scale).
    pub ry: f64,
    /// Rotation in degrees, in (−180, 180].
    pub angle_deg: f64,
}

/// The size ellipse of `t` at mesh point `p`, drawn `factor` times its true size.
pub(super) fn ellipse_in_view(t: &SizeTensor, p: [f64; 2], view: &View, factor: f64) -> Ellipse {
    let [cx, cy] = view.to_px(p);
    let [ax, ay] = t.axis();
    // The picture's y axis points down: a direction at +θ in the mesh is at −θ on screen.
    let angle_deg = (-ay).atan2(ax).to_degrees();
    let s = view.scale * factor;
    Ellipse { cx, cy, rx: t.h1() * s, ry: t.h2() * s, angle_deg }
}

/// The factor that keeps the largest ellipse of the candidates within 30 % of the view's
/// shorter side: 1 (true size) when they fit, smaller otherwise.
pub(super) fn fit_factor(candidates: &[(usize, [f64; 2], SizeTensor)], view: &View) -> f64 {
    let largest = candidates.iter().map(|c| c.2.h_max()).fold(0.0, f64::max) * view.scale;
    let room = 0.3 * view.screen.width().min(view.screen.height());
    if largest > room {
        room / largest
    } else {
        1.0
    }
}

/// How far apart two kept ellipses are, in sums of their radii towards each other. Two
/// equal ellipses are disjoint exactly when this is at least 1 (|d|_M ≥ 2); unequal
/// ones may still touch a little at 1, hence the slack.
const SPACING: f64 = 1.15;

/// Picks the vertices whose ellipses are drawn: candidates in order of their larger size
/// (then vertex index), each kept when it lies at least `min_gap_px` and 1.15 × the sum of
/// the two ellipses' radii towards each other away from every vertex kept before. Small
/// ellipses come first, so that the finest regions are shown; the result is sorted by
/// vertex index. Cost: O(n · k) for k kept ellipses, bounded by the view's area.
pub(super) fn pick(
    candidates: &[(usize, [f64; 2], SizeTensor)],
    view: &View,
    factor: f64,
    min_gap_px: f64,
) -> Vec<usize> {
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by(|&a, &b| {
        candidates[a]
            .2
            .h_max()
            .total_cmp(&candidates[b].2.h_max())
            .then(candidates[a].0.cmp(&candidates[b].0))
    });
    let s = view.scale * factor;
    // Kept ellipses in a grid of cells of `cell` pixels, to look only at near ones (a
    // hash map: only looked up, never iterated, so its order cannot reach the output).
    let cell = (2.0 * min_gap_px).max(1.0);
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> =
        std::collections::HashMap::new();
    let mut kept: Vec<usize> = Vec::new();
    let max_r = candidates.iter().map(|c| c.2.h_max()).fold(0.0, f64::max) * s;
    for i in order {
        let (_, p, t) = &candidates[i];
        let pi = view.to_px(*p);
        let reach = (min_gap_px.max(SPACING * (t.h_max() * s + max_r)) / cell).ceil() as i64;
        let (gx, gy) = ((pi[0] / cell).floor() as i64, (pi[1] / cell).floor() as i64);
        let mut ok = true;
        'search: for dx in -reach..=reach {
            for dy in -reach..=reach {
                if let Some(list) = grid.get(&(gx + dx, gy + dy)) {
                    for &j in list {
                        let (_, q, u) = &candidates[j];
                        let d = [p[0] - q[0], p[1] - q[1]];
                        let dist_px = d[0].hypot(d[1]) * view.scale;
                        if dist_px < min_gap_px {
                            ok = false;
                            break 'search;
                        }
                        let need = SPACING * s * (t.size_along(d) + u.size_along(d));
                        if dist_px < need {
                            ok = false;
                            break 'search;
                        }
                    }
                }
            }
        }
        if ok {
            grid.entry((gx, gy)).or_default().push(i);
            kept.push(i);
        }
    }
    let mut v: Vec<usize> = kept.into_iter().map(|i| candidates[i].0).collect();
    v.sort_unstable();
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::view::Rect;

    #[test]
    fn axis_at_thirty_degrees_turns_minus_thirty_on_screen() {
        let view = View::fit(Rect::new(0.0, 0.0, 1.0, 1.0), Rect::new(0.0, 0.0, 100.0, 100.0));
        let t = SizeTensor::from_angle(30f64.to_radians(), 0.2, 0.05).unwrap();
        let e = ellipse_in_view(&t, [0.5, 0.5], &view, 1.0);
        assert!((e.angle_deg + 30.0).abs() < 1e-9);
        assert!((e.rx - 20.0).abs() < 1e-9 && (e.ry - 5.0).abs() < 1e-9);
        assert_eq!((e.cx, e.cy), (50.0, 50.0));
    }

    #[test]
    fn picked_circles_do_not_overlap() {
        let view = View::fit(Rect::new(0.0, 0.0, 1.0, 1.0), Rect::new(0.0, 0.0, 200.0, 200.0));
        let mut c = Vec::new();
        for j in 0..21 {
            for i in 0..21 {
                c.push((
                    j * 21 + i,
                    [i as f64 / 20.0, j as f64 / 20.0],
                    SizeTensor::isotropic(0.04),
                ));
            }
        }
        let kept = pick(&c, &view, 1.0, 4.0);
        assert!(!kept.is_empty());
        for (a, &i) in kept.iter().enumerate() {
            for &j in &kept[a + 1..] {
                let (p, q) = (c[i].1, c[j].1);
                assert!((p[0] - q[0]).hypot(p[1] - q[1]) >= 0.08 * SPACING - 1e-12);
            }
        }
    }
}
