//! Where the overview puts the number tab of each zoom frame: on a corner of its frame
//! when one is free, else at the nearest free place, so that no tab covers another or
//! the scale bar. Frames of zooms on one source often nest or nearly coincide (the
//! leading edge's windows at three reaches); tabs all put on the top-left corner then
//! hid one another.
//!
//! Invariant: the tabs returned lie inside the area and none overlaps another or an
//! obstacle (gaps of [`GAP`] pixels), whenever the area holds a free place for each; a
//! tab off its frame's corners is marked so that a leader line joins them.

use super::view::Rect;

/// The side of a tab, in pixels.
pub(super) const SIDE: f64 = 15.0;
/// The least gap between a tab and another tab or an obstacle.
pub(super) const GAP: f64 = 1.0;
/// The step of the search for a free place when no corner is free.
const STEP: f64 = 2.0;

/// A tab as placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Tab {
    /// Its square.
    pub rect: Rect,
    /// Whether it sits on a corner of its frame (else a leader line joins them).
    pub on_frame: bool,
}

/// Whether the open interiors of `a` and `b` meet (touching edges do not).
fn overlaps(a: &Rect, b: &Rect) -> bool {
    a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1
}

/// The tab whose top-left corner is `(x, y)`, moved inside `area`.
fn tab_at(x: f64, y: f64, area: &Rect) -> Rect {
    let x = x.min(area.x1 - SIDE).max(area.x0);
    let y = y.min(area.y1 - SIDE).max(area.y0);
    Rect::new(x, y, x + SIDE, y + SIDE)
}

/// The tabs of `frames` (in pixels, in order), inside `area`, apart from each other and
/// from `obstacles`.
pub(super) fn place(frames: &[Rect], area: &Rect, obstacles: &[Rect]) -> Vec<Tab> {
    let mut taken: Vec<Rect> = obstacles.to_vec();
    let mut tabs = Vec::with_capacity(frames.len());
    for f in frames {
        let free = |r: &Rect, taken: &[Rect]| taken.iter().all(|t| !overlaps(&r.inflate(GAP), t));
        // Outside the frame first (the frame's content stays visible), then inside.
        let corners = [
            (f.x0, f.y0 - SIDE),
            (f.x1 - SIDE, f.y0 - SIDE),
            (f.x0 - SIDE, f.y0),
            (f.x1, f.y0),
            (f.x0, f.y1),
            (f.x1 - SIDE, f.y1),
            (f.x0 - SIDE, f.y1 - SIDE),
            (f.x1, f.y1 - SIDE),
            (f.x0, f.y0),
            (f.x1 - SIDE, f.y0),
            (f.x0, f.y1 - SIDE),
            (f.x1 - SIDE, f.y1 - SIDE),
        ];
        let first = tab_at(corners[0].0, corners[0].1, area);
        let on_corner = corners.iter().map(|&(x, y)| tab_at(x, y, area)).find(|r| free(r, &taken));
        let tab = match on_corner {
            Some(rect) => Tab { rect, on_frame: true },
            None => {
                // The free place nearest the first corner, on a grid of STEP pixels.
                let nx = ((area.width() - SIDE) / STEP).floor().max(0.0) as usize;
                let ny = ((area.height() - SIDE) / STEP).floor().max(0.0) as usize;
                let mut best: Option<(f64, Rect)> = None;
                for i in 0..=nx {
                    for j in 0..=ny {
                        let r = tab_at(area.x0 + i as f64 * STEP, area.y0 + j as f64 * STEP, area);
                        let d = (r.x0 - first.x0).hypot(r.y0 - first.y0);
                        let nearer = match best {
                            None => true,
                            Some((b, _)) => d < b,
                        };
                        if nearer && free(&r, &taken) {
                            best = Some((d, r));
                        }
                    }
                }
                match best {
                    Some((_, rect)) => Tab { rect, on_frame: false },
                    // No room at all (an overview smaller than its tabs): the first corner.
                    None => Tab { rect: first, on_frame: true },
                }
            }
        };
        taken.push(tab.rect);
        tabs.push(tab);
    }
    tabs
}

/// The point of `frame`'s border nearest to `p`, where a leader line from a tab ends.
pub(super) fn nearest_on_border(frame: &Rect, p: [f64; 2]) -> [f64; 2] {
    let x = p[0].clamp(frame.x0, frame.x1);
    let y = p[1].clamp(frame.y0, frame.y1);
    if x > frame.x0 && x < frame.x1 && y > frame.y0 && y < frame.y1 {
        // Inside: to the nearest side.
        let d = [x - frame.x0, frame.x1 - x, y - frame.y0, frame.y1 - y];
        let k = (0..4).min_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap_or(0);
        return match k {
            0 => [frame.x0, y],
            1 => [frame.x1, y],
            2 => [x, frame.y0],
            _ => [x, frame.y1],
        };
    }
    [x, y]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(tabs: &[Tab], area: &Rect, obstacles: &[Rect]) {
        for (i, a) in tabs.iter().enumerate() {
            let r = a.rect;
            assert!(r.x0 >= area.x0 && r.y0 >= area.y0 && r.x1 <= area.x1 && r.y1 <= area.y1);
            for b in &tabs[i + 1..] {
                assert!(!overlaps(&r, &b.rect), "{r:?} and {:?} overlap", b.rect);
            }
            for o in obstacles {
                assert!(!overlaps(&r, o), "{r:?} covers {o:?}");
            }
        }
    }

    #[test]
    fn nested_frames_get_tabs_apart() {
        // The AGARD01 overview at 1200 px: four windows on the leading edge within a few
        // pixels of each other, inside a larger one.
        let area = Rect::new(20.0, 60.0, 1180.0, 600.0);
        let frames = [
            Rect::new(477.9, 338.5, 722.0, 521.6),
            Rect::new(574.8, 411.1, 625.3, 448.9),
            Rect::new(573.2, 404.8, 630.3, 447.6),
            Rect::new(572.2, 412.6, 623.9, 451.4),
            Rect::new(588.3, 409.0, 752.9, 448.1),
        ];
        let bar = [Rect::new(30.0, 560.0, 120.0, 590.0)];
        let tabs = place(&frames, &area, &bar);
        check(&tabs, &area, &bar);
        // The first keeps the top-left corner; those that find no corner say so.
        assert_eq!(tabs[0].rect, Rect::new(477.9, 323.5, 492.9, 338.5));
        assert!(tabs[0].on_frame);
    }

    #[test]
    fn many_identical_frames_and_a_corner_of_the_area() {
        let area = Rect::new(0.0, 0.0, 300.0, 200.0);
        let frames = vec![Rect::new(0.0, 0.0, 20.0, 20.0); 12];
        let tabs = place(&frames, &area, &[]);
        check(&tabs, &area, &[]);
        assert!(tabs.iter().any(|t| !t.on_frame));
        let p = nearest_on_border(&frames[0], tabs[11].rect.centre());
        assert!(p[0] == 20.0 || p[1] == 20.0, "{p:?}");
    }
}
