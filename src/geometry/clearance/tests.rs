//! The clearance index against brute-force twins: exact clearances, the cone bounds
//! and the covering of points by their closest feature.

use super::*;
use crate::geometry::test_support::{brute, Rng};

/// Closed or open polylines as segments with their links.
fn polyline(points: &[Point2], closed: bool) -> (Vec<SegmentGeom>, Vec<Links>) {
    let k = points.len();
    let count = if closed { k } else { k - 1 };
    let geoms: Vec<SegmentGeom> =
        (0..count).map(|i| SegmentGeom::new(points[i], points[(i + 1) % k])).collect();
    let links = (0..count)
        .map(|i| {
            let prev = if i > 0 {
                Some(i as u32 - 1)
            } else if closed {
                Some(count as u32 - 1)
            } else {
                None
            };
            let next = if i + 1 < count {
                Some(i as u32 + 1)
            } else if closed {
                Some(0)
            } else {
                None
            };
            (prev, next)
        })
        .collect();
    (geoms, links)
}

/// `n` points at angles a round the origin (a turn when closed, `0..open_span` when
/// open) at radius `radius(k, a)`, as segments with their links.
fn radial_curve(
    n: usize,
    closed: bool,
    open_span: f64,
    mut radius: impl FnMut(usize, f64) -> f64,
) -> (Vec<SegmentGeom>, Vec<Links>) {
    let points: Vec<Point2> = (0..n)
        .map(|k| {
            let a = if closed {
                2.0 * std::f64::consts::PI * k as f64 / n as f64
            } else {
                open_span * k as f64 / n as f64
            };
            let r = radius(k, a);
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    polyline(&points, closed)
}

/// The cone's clearance from its two segments' (the module header's "vertex from its
/// segments") against its definition: never above `G` at 65 points of every
/// segment outside the cone's window, on closed and open curves, smooth or jagged
/// (a random phase per point gives turns from nearly none to sharp corners), at
/// every tier. And of use: at least half the cone's own search for most cones.
#[test]
fn cone_bound_from_segments_is_below_g_everywhere() {
    let mut rng = Rng(11);
    let (mut checked, mut useful) = (0usize, 0usize);
    for case in 0..30 {
        let n = 12 + (rng.unit() * 120.0) as usize;
        let closed = case % 2 == 0;
        let (geoms, links) = radial_curve(n, closed, 4.0, |_, a| {
            0.6 + 0.2 * (3.0 * a + rng.unit()).cos()
                + if case % 3 == 1 { 0.15 * rng.unit() } else { 0.0 }
        });
        let clearance = Clearance::new(&geoms, &links, 1.0, 8.0);
        for s in 0..geoms.len() {
            let Some(shape) = clearance.cone[s] else { continue };
            let next = links[s].1.unwrap();
            let window = [links[s].0, Some(s as u32), Some(next), links[next as usize].1];
            let v = geoms[s].b;
            let mut g_min = f64::INFINITY;
            for (o, h) in geoms.iter().enumerate() {
                if window.contains(&Some(o as u32)) {
                    continue;
                }
                for k in 0..=64 {
                    let t = k as f64 / 64.0;
                    let q = [h.a[0] + t * h.d[0], h.a[1] + t * h.d[1]];
                    let e = [q[0] - v[0], q[1] - v[1]];
                    let support = shape.sector.support(e);
                    if support > 0.0 {
                        g_min = g_min.min((e[0] * e[0] + e[1] * e[1]) / (2.0 * support));
                    }
                }
            }
            for t in 0..clearance.caps.len() {
                let derived = clearance.cone_derived_value(s, &shape, t);
                assert!(derived <= g_min, "case {case}, vertex at the end of {s}, tier {t}: {derived} above the smallest G {g_min}");
                checked += 1;
                useful += usize::from(derived >= 0.5 * clearance.cone_value(s, t));
            }
        }
    }
    eprintln!(
        "{useful} of {checked} cone bounds from the segments at least half the cone's own search"
    );
    assert!(
        checked > 1000 && useful * 2 > checked,
        "{useful} of {checked}: too few cones, or bounds too weak to be of use"
    );
}

/// The clearance's promise, checked directly against a scan of every segment: where
/// a segment (or a vertex) says it covers a point, no segment outside its window is
/// as close as it. Wavy closed curves, open ones with corners and hairpins, and
/// points near and far, including past the medial axis.
#[test]
fn covered_points_have_their_closest_segment_in_the_window() {
    let mut rng = Rng(5);
    // Of the pairs where the segment (or vertex) is the closest one: how many covered.
    let (mut covered, mut asked) = (0usize, 0usize);
    for case in 0..40 {
        let n = 20 + (rng.unit() * 300.0) as usize;
        let closed = case % 2 == 0;
        let modes: Vec<(f64, f64, f64)> = (0..3)
            .map(|m| (rng.unit() * 0.3 / (m + 1) as f64, (m + 2) as f64, rng.unit() * 6.3))
            .collect();
        let (geoms, links) = radial_curve(n, closed, 5.0, |k, a| {
            let r = 0.6 + modes.iter().map(|&(amp, f, ph)| amp * (f * a + ph).cos()).sum::<f64>();
            // Corners: every seventh point of some curves pushed out.
            if case % 3 == 1 && k % 7 == 0 {
                r * 1.1
            } else {
                r
            }
        });
        let clearance = Clearance::new(&geoms, &links, 1.0, 8.0);
        let window_of = |s: u32| -> Vec<u32> {
            let mut w = vec![s];
            let (mut b, mut f) = (s, s);
            for _ in 0..WINDOW {
                if let Some(x) = links[b as usize].0 {
                    b = x;
                    w.push(x);
                }
                if let Some(x) = links[f as usize].1 {
                    f = x;
                    w.push(x);
                }
            }
            w
        };
        for _ in 0..400 {
            let p = [3.0 * rng.unit() - 1.5, 3.0 * rng.unit() - 1.5];
            let want = brute(&geoms, p);
            for (s, g) in geoms.iter().enumerate() {
                let s = s as u32;
                let pr = g.project(p);
                let d = pr.distance();
                let closest = s == want.segment
                    || (want.projection.foot == pr.foot
                        && want.projection.distance_squared == pr.distance_squared);
                if pr.t > 0.0 && pr.t < 1.0 {
                    asked += usize::from(closest);
                    if clearance.covers_segment(s, p, d) {
                        covered += usize::from(closest);
                        // Nothing outside the window is as close as `s`.
                        for (o, h) in geoms.iter().enumerate() {
                            if !window_of(s).contains(&(o as u32)) {
                                assert!(h.project(p).distance_squared > pr.distance_squared, "case {case}: segment {o} outside the window of {s} is as close to {p:?}");
                            }
                        }
                    }
                } else if pr.t == 1.0 && links[s as usize].1.is_some() {
                    asked += usize::from(closest);
                    if clearance.covers_vertex(s, p, d) {
                        covered += usize::from(closest);
                        let next = links[s as usize].1.unwrap();
                        let window =
                            [links[s as usize].0, Some(s), Some(next), links[next as usize].1];
                        for (o, h) in geoms.iter().enumerate() {
                            if !window.contains(&Some(o as u32)) {
                                assert!(h.project(p).distance_squared > pr.distance_squared, "case {case}: segment {o} outside the window of vertex {s} is as close to {p:?}");
                            }
                        }
                    }
                }
            }
        }
    }
    eprintln!(
        "{covered} of {asked} points covered by the clearance of their closest segment or vertex"
    );
    assert!(
        covered * 10 >= asked * 3,
        "{covered} of {asked} covered: the clearances are too small to be of use"
    );
}
