//! The three turbine distributors of thesis 6.3.1 (`examples/distributor`): a stay vane
//! and a guide vane in one periodic pitch of a distributor unrolled into a 2D cascade,
//! the guide vane changing between the variants, the topology and tags not.
//!
//! The geometry is that of `examples/make_examples.py`, computed in the same order of
//! operations so that the written `.poly` files are the committed ones byte for byte but
//! the line naming the writer (checked by `tests/variants.rs`): the channel's periodic
//! sides are piecewise linear (thesis 6.3.2.4), the stay vane a round nose, straight
//! flanks and circular arcs tangent to them down to a blunt trailing edge, the guide vane
//! a camber line (circular arc or S-shaped cubic) carrying a NACA 4-digit thickness
//! thickened linearly to a blunt trailing edge that stays at the same place in every
//! variant. Tags: curves 301 Inlet, 302-304 and 306-308 the periodic sides, 305 Outlet,
//! 101-107 the stay vane, 201-203 the guide vane; points 1-7 on the stay vane, 11-13 on
//! the guide vane, 21-28 the channel's corners; face 1000 Fluid.

use std::f64::consts::PI;

use super::{format_g, naca::COEFFICIENTS, Pslg};
use crate::geometry::segment::Point2;

/// One pitch of the cascade.
const PITCH: f64 = 30.0;
/// Lower periodic side, inlet to outlet; the upper one is shifted by [`PITCH`].
const PERIODIC: [Point2; 4] = [[-100.0, -16.0], [-72.0, -22.0], [-24.0, -36.0], [0.0, -44.0]];
/// Stay vane: trailing edge centre, chord, stagger (degrees), nose radius, half
/// thickness of the blunt trailing edge, (upper flank length, angle, lower flank
/// length, angle).
const SV_TE: Point2 = [-50.0, -12.8];
const SV_CHORD: f64 = 20.0;
const SV_STAGGER: f64 = -13.5;
const SV_NOSE: f64 = 1.6;
const SV_TE_HALF: f64 = 0.3;
const SV_FLANK: (f64, f64, f64, f64) = (9.0, -2.0, 8.0, 3.0);
/// Guide vane: trailing edge and its half thickness, the same in every variant.
const GV_TE: Point2 = [-26.0, -20.0];
const GV_TE_HALF: f64 = 0.2;
/// Vertex spacing on the channel's sides, and the largest on the blades.
const DIST_H: f64 = 1.5;
const BLADE_H: f64 = 0.25;

/// The camber line of a guide vane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Camber {
    /// A circular arc (a parabola, 4 m s (1 − s)).
    Arc,
    /// S-shaped: positive camber in front, negative behind (a cubic).
    S,
}

/// A guide vane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuideVane {
    /// The variant's name (its folder in `examples/distributor`).
    pub name: &'static str,
    /// Leading edge.
    pub leading_edge: Point2,
    /// NACA thickness over chord.
    pub thickness: f64,
    /// Camber line.
    pub camber_kind: Camber,
    /// Camber over chord.
    pub camber: f64,
    /// What it shows.
    pub what: &'static str,
}

/// The three variants of thesis 6.3.1.
pub const VARIANTS: [GuideVane; 3] = [
    GuideVane {
        name: "1-narrow",
        leading_edge: [-42.0, -14.2],
        thickness: 0.06,
        camber_kind: Camber::Arc,
        camber: 0.04,
        what: "a narrow guide vane: strong curvature at its leading edge (thesis 6.3.1.1)",
    },
    GuideVane {
        name: "2-thick",
        leading_edge: [-38.5, -15.8],
        thickness: 0.22,
        camber_kind: Camber::Arc,
        camber: 0.03,
        what: "a thick guide vane and a larger gap to the stay vane (thesis 6.3.1.2)",
    },
    GuideVane {
        name: "3-s-shaped",
        leading_edge: [-46.5, -13.6],
        thickness: 0.08,
        camber_kind: Camber::S,
        camber: 0.05,
        what: "a thin S-shaped guide vane and a very small gap to the stay vane (thesis 6.3.1.3)",
    },
];

fn dist(p: Point2, q: Point2) -> f64 {
    (q[0] - p[0]).hypot(q[1] - p[1])
}

/// Points strictly between p and q, at most `h` apart.
fn straight(p: Point2, q: Point2, h: f64) -> Vec<Point2> {
    let n = ((dist(p, q) / h).ceil() as usize).max(1);
    (1..n)
        .map(|k| {
            let k = k as f64;
            let n = n as f64;
            [p[0] + (q[0] - p[0]) * k / n, p[1] + (q[1] - p[1]) * k / n]
        })
        .collect()
}

/// Points strictly between angles a0 and a1 on a circle, at most `h` apart.
fn arc(cx: f64, cy: f64, r: f64, a0: f64, a1: f64, h: f64) -> Vec<Point2> {
    let n = (((a1 - a0).abs() * r / h).ceil() as usize).max(2);
    (1..n)
        .map(|k| {
            let a = a0 + (a1 - a0) * k as f64 / n as f64;
            [cx + r * a.cos(), cy + r * a.sin()]
        })
        .collect()
}

/// Python's `%` on floats: the result has the divisor's sign.
fn py_mod(x: f64, y: f64) -> f64 {
    let m = x % y;
    if m != 0.0 {
        if (y < 0.0) != (m < 0.0) {
            m + y
        } else {
            m
        }
    } else {
        0.0f64.copysign(y)
    }
}

/// Points strictly between s and e on the circle tangent to direction t at s that
/// passes through e.
fn tangent_arc(s: Point2, t: Point2, e: Point2, h: f64) -> Vec<Point2> {
    let n = [-t[1], t[0]];
    let d = [e[0] - s[0], e[1] - s[1]];
    let rho = (d[0].powf(2.0) + d[1].powf(2.0)) / (2.0 * (d[0] * n[0] + d[1] * n[1]));
    let (cx, cy) = (s[0] + rho * n[0], s[1] + rho * n[1]);
    let a0 = (s[1] - cy).atan2(s[0] - cx);
    let a1 = (e[1] - cy).atan2(e[0] - cx);
    let da = py_mod(a1 - a0 + PI, 2.0 * PI) - PI;
    arc(cx, cy, rho.abs(), a0, a0 + da, h)
}

fn rotate(p: Point2, ang: f64, origin: Point2) -> Point2 {
    let (c, s) = (ang.cos(), ang.sin());
    [origin[0] + c * p[0] - s * p[1], origin[1] + s * p[0] + c * p[1]]
}

/// The NACA half thickness (the standard coefficients) at x for thickness t.
fn half_thickness(x: f64, t: f64) -> f64 {
    let [a0, a1, a2, a3, a4] = COEFFICIENTS;
    5.0 * t * (a0 * x.sqrt() + a1 * x + a2 * x * x + a3 * x.powf(3.0) + a4 * x.powf(4.0))
}

/// The seven curves of the stay vane in its chord frame (leading edge at the origin):
/// its seven points and, for each curve, its tag, name and inner points.
type Curves = Vec<(i64, &'static str, Vec<Point2>)>;

fn stay_vane_local(h: f64) -> ([Point2; 7], Curves) {
    let (a, l, b) = (SV_NOSE, SV_CHORD, SV_TE_HALF);
    let (lu, au, ll, al) = SV_FLANK;
    let (au, al) = (au.to_radians(), al.to_radians());
    let tu = [au.cos(), au.sin()];
    let tl = [al.cos(), al.sin()];
    let p2 = [a - a * tu[1], a * tu[0]];
    let p7 = [a + a * tl[1], -a * tl[0]];
    let p3 = [p2[0] + lu * tu[0], p2[1] + lu * tu[1]];
    let p6 = [p7[0] + ll * tl[0], p7[1] + ll * tl[1]];
    let (p1, p4, p5) = ([0.0, 0.0], [l, b], [l, -b]);
    let ang2 = p2[1].atan2(p2[0] - a);
    let ang7 = p7[1].atan2(p7[0] - a);
    let rev = |mut v: Vec<Point2>| {
        v.reverse();
        v
    };
    let curves = vec![
        (101, "StayVaneNoseUpper", arc(a, 0.0, a, PI, ang2, h / 4.0)),
        (102, "StayVaneUpperFlank", straight(p2, p3, h)),
        (103, "StayVaneUpperTail", tangent_arc(p3, tu, p4, h)),
        (104, "StayVaneTrailingEdge", straight(p4, p5, h / 4.0)),
        (105, "StayVaneLowerTail", rev(tangent_arc(p6, tl, p5, h))),
        (106, "StayVaneLowerFlank", rev(straight(p7, p6, h))),
        (107, "StayVaneNoseLower", arc(a, 0.0, a, ang7, -PI, h / 4.0)),
    ];
    ([p1, p2, p3, p4, p5, p6, p7], curves)
}

/// Upper and lower sides of a guide vane of chord `chord` in its chord frame, from the
/// leading edge, `n + 1` cosine-spaced stations.
fn guide_vane_local(chord: f64, v: &GuideVane, n: usize) -> (Vec<Point2>, Vec<Point2>) {
    let (mut up, mut lo) = (Vec::new(), Vec::new());
    let camber = v.camber;
    for k in 0..=n {
        let s = (1.0 - (PI * k as f64 / n as f64).cos()) / 2.0;
        let (yc, dyc) = match v.camber_kind {
            Camber::Arc => (4.0 * camber * s * (1.0 - s), 4.0 * camber * (1.0 - 2.0 * s)),
            Camber::S => (
                6.0 * camber * s * (1.0 - s) * (1.0 - 2.0 * s) * 1.3,
                6.0 * camber * 1.3 * (1.0 - 6.0 * s + 6.0 * s * s),
            ),
        };
        let yt = half_thickness(s, v.thickness)
            + s * (GV_TE_HALF / chord - half_thickness(1.0, v.thickness));
        let th = dyc.atan();
        up.push([chord * (s - yt * th.sin()), chord * (yc + yt * th.cos())]);
        lo.push([chord * (s + yt * th.sin()), chord * (yc - yt * th.cos())]);
    }
    (up, lo)
}

/// The geometry of one variant.
pub fn geometry(v: &GuideVane) -> Pslg {
    let first = v.name.chars().next().unwrap_or('?');
    let mut g = Pslg::new(format!("Distributor {first}: a stay vane and {}", v.what));
    let low = PERIODIC;
    let up = PERIODIC.map(|p| [p[0], p[1] + PITCH]);
    let c_in_up = g.add_point(up[0], 21, "InletUpper");
    let c_in_lo = g.add_point(low[0], 22, "InletLower");
    let c_lo1 = g.add_point(low[1], 23, "LowerPeriodic1");
    let c_lo2 = g.add_point(low[2], 24, "LowerPeriodic2");
    let c_out_lo = g.add_point(low[3], 25, "OutletLower");
    let c_out_up = g.add_point(up[3], 26, "OutletUpper");
    let c_up2 = g.add_point(up[2], 27, "UpperPeriodic2");
    let c_up1 = g.add_point(up[1], 28, "UpperPeriodic1");
    let h = DIST_H;
    g.add_curve(301, "Inlet", c_in_up, &straight(up[0], low[0], h), c_in_lo);
    g.add_curve(302, "LowerPeriodic1", c_in_lo, &straight(low[0], low[1], h), c_lo1);
    g.add_curve(303, "LowerPeriodic2", c_lo1, &straight(low[1], low[2], h), c_lo2);
    g.add_curve(304, "LowerPeriodic3", c_lo2, &straight(low[2], low[3], h), c_out_lo);
    g.add_curve(305, "Outlet", c_out_lo, &straight(low[3], up[3], h), c_out_up);
    g.add_curve(306, "UpperPeriodic3", c_out_up, &straight(up[3], up[2], h), c_up2);
    g.add_curve(307, "UpperPeriodic2", c_up2, &straight(up[2], up[1], h), c_up1);
    g.add_curve(308, "UpperPeriodic1", c_up1, &straight(up[1], up[0], h), c_in_up);

    // Stay vane: points 1..7, curves 101..107.
    let ang = SV_STAGGER.to_radians();
    let sv_le = [SV_TE[0] - SV_CHORD * ang.cos(), SV_TE[1] - SV_CHORD * ang.sin()];
    let (pts, curves) = stay_vane_local(BLADE_H);
    let place = |p: Point2| rotate(p, ang, sv_le);
    const SV_NAMES: [&str; 7] = [
        "StayVaneLeadingEdge",
        "StayVaneUpperNoseEnd",
        "StayVaneUpperTailStart",
        "StayVaneTrailingEdgeUpper",
        "StayVaneTrailingEdgeLower",
        "StayVaneLowerTailStart",
        "StayVaneLowerNoseEnd",
    ];
    let ids: Vec<usize> =
        (0..7).map(|k| g.add_point(place(pts[k]), k as i64 + 1, SV_NAMES[k])).collect();
    for (k, (tag, name, inner)) in curves.iter().enumerate() {
        let placed: Vec<Point2> = inner.iter().map(|&p| place(p)).collect();
        g.add_curve(*tag, name, ids[k], &placed, ids[(k + 1) % 7]);
    }
    g.add_hole(place([(pts[2][0] + pts[5][0]) / 2.0, (pts[2][1] + pts[5][1]) / 2.0]));

    // Guide vane: points 13 (leading edge), 11 and 12 (trailing edge corners), curves
    // 201 (upper side, 13 to 11), 202 (trailing edge, 11 to 12), 203 (lower side, 12 to
    // 13).
    let le = v.leading_edge;
    let chord = dist(le, GV_TE);
    let gang = (GV_TE[1] - le[1]).atan2(GV_TE[0] - le[0]);
    let n = 80;
    let (upl, lol) = guide_vane_local(chord, v, n);
    let gp = |p: Point2| rotate(p, gang, le);
    let g13 = g.add_point(gp(upl[0]), 13, "GuideVaneLeadingEdge");
    let g11 = g.add_point(gp(upl[n]), 11, "GuideVaneTrailingEdgeUpper");
    let g12 = g.add_point(gp(lol[n]), 12, "GuideVaneTrailingEdgeLower");
    let upper: Vec<Point2> = upl[1..n].iter().map(|&p| gp(p)).collect();
    g.add_curve(201, "GuideVaneUpperSide", g13, &upper, g11);
    let te = straight(gp(upl[n]), gp(lol[n]), BLADE_H / 4.0);
    g.add_curve(202, "GuideVaneTrailingEdge", g11, &te, g12);
    let lower: Vec<Point2> = lol[1..n].iter().rev().map(|&p| gp(p)).collect();
    g.add_curve(203, "GuideVaneLowerSide", g12, &lower, g13);
    let m = n / 2;
    g.add_hole(gp([(upl[m][0] + lol[m][0]) / 2.0, (upl[m][1] + lol[m][1]) / 2.0]));
    g.set_face([-90.0, 0.0], 1000, "Fluid");

    let f = |x: f64| format_g(x, 6);
    let (lu, au, ll, al) = SV_FLANK;
    g.notes = vec![
        format!(
            "One pitch ({}) of a distributor unrolled into a 2D cascade, flow along +x. Periodic sides:",
            f(PITCH)
        ),
        format!(
            "lower {}, upper the same shifted by {} in y.",
            PERIODIC.iter().map(|p| format!("({}, {})", f(p[0]), f(p[1]))).collect::<Vec<_>>().join(" "),
            f(PITCH)
        ),
        format!(
            "Stay vane: chord {}, stagger {} deg, trailing edge centre ({}, {}), nose radius {}, flanks",
            f(SV_CHORD),
            f(SV_STAGGER),
            f(SV_TE[0]),
            f(SV_TE[1]),
            f(SV_NOSE)
        ),
        format!(
            "(length, angle) upper ({}, {} deg), lower ({}, {} deg), tangent circular arcs to a blunt",
            f(lu),
            f(au),
            f(ll),
            f(al)
        ),
        format!("trailing edge of half thickness {}.", f(SV_TE_HALF)),
        format!(
            "Guide vane: leading edge ({}, {}), trailing edge ({}, {}), NACA thickness {}, {} camber {},",
            f(le[0]),
            f(le[1]),
            f(GV_TE[0]),
            f(GV_TE[1]),
            f(v.thickness),
            match v.camber_kind {
                Camber::Arc => "circular-arc",
                Camber::S => "S-shaped (cubic)",
            },
            f(v.camber)
        ),
        format!("blunt trailing edge of half thickness {}.", f(GV_TE_HALF)),
    ];
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn python_float_modulo() {
        assert_eq!(py_mod(5.0, 3.0), 2.0);
        assert_eq!(py_mod(-1.0, 3.0), 2.0);
        assert_eq!(py_mod(1.0, -3.0), -2.0);
        assert_eq!(py_mod(-3.0, 3.0), 0.0);
    }

    #[test]
    fn every_variant_is_a_valid_graph_with_the_same_tags() {
        let tags = |g: &Pslg| g.names.clone();
        let first = geometry(&VARIANTS[0]);
        first.check().unwrap();
        for v in &VARIANTS[1..] {
            let g = geometry(v);
            g.check().unwrap();
            assert_eq!(tags(&g), tags(&first));
        }
    }
}
