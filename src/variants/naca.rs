//! NACA 4-digit airfoils in a circular far field, with the tags and names of the bundled
//! NACA 0012 example (`examples/naca0012-agard01`): points 11 LeadingEdge and 12
//! TrailingEdge, curves 1 Upper, 2 Lower, 3 FarField, face 100 Fluid. So the example's
//! recipe adapts every member of a family.
//!
//! The profile is the NACA 4-digit definition (Abbott & von Doenhoff, *Theory of Wing
//! Sections*, 6.4): half thickness `yt = 5 t (0.2969 √x − 0.1260 x − 0.3516 x² +
//! 0.2843 x³ − 0.1015 x⁴)` about the camber line `yc = m/p² (2 p x − x²)` for `x < p`,
//! `m/(1−p)² (1 − 2p + 2 p x − x²)` after, each surface offset perpendicular to the camber
//! line: `(x ∓ yt sin θ, yc ± yt cos θ)`, `θ = atan(dyc/dx)`. The standard coefficients
//! leave the trailing edge open (`yt(1) = 0.0126 t/0.12`); the two closed forms, which
//! keep one trailing-edge point so that the tags stay those of the example:
//! - [`TrailingEdge::Extended`]: the standard formulas taken to the root of the
//!   thickness, x = 1.008930…, where the surfaces meet (the chord of 1.00893 of thesis
//!   6.2.4 and of the bundled example: with t = 0.12 and no camber the vertices are the
//!   example's, digit for digit);
//! - [`TrailingEdge::Closed`]: the last coefficient −0.1036 instead of −0.1015, so that
//!   `yt(1) = 0` and the chord is 1.
//!
//! Stations are cosine-spaced from the leading edge, `x = c (1 − cos β)/2`, β uniform in
//! [0, π]; the far field is a circle about mid-chord. The hole point is on the camber
//! line at mid-chord, the face point half a radius above mid-chord.

use super::{format_g, Pslg};
use crate::geometry::segment::Point2;

/// The standard thickness coefficients a0..a4.
pub const COEFFICIENTS: [f64; 5] = [0.2969, -0.1260, -0.3516, 0.2843, -0.1015];
/// a4 of the closed trailing edge.
pub const CLOSED_A4: f64 = -0.1036;

/// How the trailing edge is closed (module header).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrailingEdge {
    /// The standard formula to the root of the thickness (chord 1.008930…).
    Extended,
    /// a4 = −0.1036 (chord 1).
    Closed,
}

/// One NACA 4-digit profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Naca4 {
    /// Largest thickness over chord, t (0.12 for a NACA xx12).
    pub thickness: f64,
    /// Largest camber over chord, m (0.02 for a NACA 2xxx).
    pub camber: f64,
    /// Where the largest camber is, p, over chord (0.4 for a NACA x4xx); unused when
    /// `camber` is 0.
    pub position: f64,
    /// How the trailing edge closes.
    pub trailing_edge: TrailingEdge,
}

/// The far field and the discretisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// Segments per side of the airfoil (vertices per side: one more).
    pub per_side: usize,
    /// Radius of the far-field circle.
    pub far_radius: f64,
    /// Vertices on the far-field circle.
    pub far_points: usize,
}

/// The thinnest profile offered, over chord. At the first cosine station of the default
/// layout the surfaces are `~0.01 t` apart; `mesh` tells apart gaps down to about 1e-12
/// of the far field's radius (`t = 1e-12` fails, `1e-9` meshes), so 1e-4 keeps six
/// orders of margin and every real airfoil.
pub const MIN_THICKNESS: f64 = 1e-4;

/// Most members of one family.
pub const MAX_MEMBERS: usize = 100_000;

/// Most vertices of all the members of one family together (all are held, as text, until
/// they are written as one set: about 30 bytes each).
pub const MAX_FAMILY_VERTICES: u64 = 20_000_000;

impl Default for Layout {
    /// The bundled example's: 100 segments a side, radius 25, 48 vertices.
    fn default() -> Layout {
        Layout { per_side: 100, far_radius: 25.0, far_points: 48 }
    }
}

impl Layout {
    /// Checks the layout: 8 to 100000 segments a side and far-field vertices, a radius of
    /// 3 to 1e6 chords.
    pub fn check(&self) -> Result<(), String> {
        if self.per_side < 8 || self.per_side > 100_000 {
            return Err(format!("{} segments a side: expected 8 to 100000", self.per_side));
        }
        if self.far_points < 8 || self.far_points > 100_000 {
            return Err(format!("{} far-field vertices: expected 8 to 100000", self.far_points));
        }
        if !(self.far_radius >= 3.0 && self.far_radius <= 1e6) {
            return Err(format!("far-field radius {}: expected 3 to 1e6 chords", self.far_radius));
        }
        Ok(())
    }

    /// Vertices of one member (an upper bound: both sides and the far field).
    pub fn vertices(&self) -> u64 {
        2 * self.per_side as u64 + self.far_points as u64
    }
}

impl Naca4 {
    /// Checks the parameters: `MIN_THICKNESS <= t <= 0.5`, `|m| <= 0.2`, `0 < p < 1` when
    /// `m != 0`.
    pub fn check(&self) -> Result<(), String> {
        let t = self.thickness;
        if !(MIN_THICKNESS..=0.5).contains(&t) {
            return Err(format!(
                "thickness {t}: expected {MIN_THICKNESS} <= t <= 0.5 (of the chord); a thinner \
                 profile's surfaces come closer than `mesh` can tell apart in the far field"
            ));
        }
        if self.camber.is_nan() || self.camber.abs() > 0.2 {
            return Err(format!("camber {}: expected |m| <= 0.2 (of the chord)", self.camber));
        }
        if self.camber != 0.0 && !(self.position > 0.0 && self.position < 1.0) {
            return Err(format!(
                "camber position {}: expected 0 < p < 1 (of the chord)",
                self.position
            ));
        }
        Ok(())
    }

    fn a4(&self) -> f64 {
        match self.trailing_edge {
            TrailingEdge::Extended => COEFFICIENTS[4],
            TrailingEdge::Closed => CLOSED_A4,
        }
    }

    /// The half thickness yt at x (written as the bundled example's script evaluates
    /// it, so that the digits agree).
    pub fn half_thickness(&self, x: f64) -> f64 {
        let [a0, a1, a2, a3, _] = COEFFICIENTS;
        5.0 * self.thickness
            * (a0 * x.sqrt() + a1 * x + a2 * x * x + a3 * x.powf(3.0) + self.a4() * x.powf(4.0))
    }

    /// Where the surfaces meet: the root of the thickness beyond x = 1 (by bisection, to
    /// the last bit) or 1.
    pub fn chord(&self) -> f64 {
        match self.trailing_edge {
            TrailingEdge::Closed => 1.0,
            TrailingEdge::Extended => {
                let (mut lo, mut hi) = (1.0f64, 1.1f64);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if self.half_thickness(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                0.5 * (lo + hi)
            }
        }
    }

    /// The camber line yc and its slope at x.
    pub fn camber_line(&self, x: f64) -> (f64, f64) {
        let (m, p) = (self.camber, self.position);
        if m == 0.0 {
            (0.0, 0.0)
        } else if x < p {
            (m / (p * p) * (2.0 * p * x - x * x), 2.0 * m / (p * p) * (p - x))
        } else {
            let q = (1.0 - p) * (1.0 - p);
            (m / q * (1.0 - 2.0 * p + 2.0 * p * x - x * x), 2.0 * m / q * (p - x))
        }
    }

    /// The upper and lower surface points of station x.
    pub fn surface(&self, x: f64) -> (Point2, Point2) {
        let yt = self.half_thickness(x);
        let (yc, slope) = self.camber_line(x);
        let th = slope.atan();
        let (s, c) = (th.sin(), th.cos());
        ([x - yt * s, yc + yt * c], [x + yt * s, yc - yt * c])
    }

    /// The name of a family member: `naca-t0.12-m0.02-p0.4` (`naca-t0.12-m0` without
    /// camber), values to 6 significant digits.
    pub fn name(&self) -> String {
        let g = |v: f64| format_g(v, 6);
        if self.camber == 0.0 {
            format!("naca-t{}-m0", g(self.thickness))
        } else {
            format!("naca-t{}-m{}-p{}", g(self.thickness), g(self.camber), g(self.position))
        }
    }

    /// The 4-digit designation when m, p and t are whole digits (`2412`).
    pub fn designation(&self) -> Option<String> {
        let digits = |v: f64, scale: f64, max: f64| {
            let d = (v * scale).round();
            ((v * scale - d).abs() < 1e-9 && (0.0..=max).contains(&d)).then_some(d as u32)
        };
        let m = digits(self.camber, 100.0, 9.0)?;
        let p = if m == 0 { 0 } else { digits(self.position, 10.0, 9.0)? };
        let t = digits(self.thickness, 100.0, 99.0)?;
        Some(format!("{m}{p}{t:02}"))
    }

    /// The airfoil in its far field, as a tagged graph (module header).
    pub fn geometry(&self, layout: &Layout) -> Result<Pslg, String> {
        self.check()?;
        layout.check()?;
        let c = self.chord();
        let (n, r, nf) = (layout.per_side, layout.far_radius, layout.far_points);
        let what = match self.designation() {
            Some(d) => format!("NACA {d}"),
            None => format!(
                "NACA 4-digit airfoil (t = {}, m = {}, p = {})",
                format_g(self.thickness, 6),
                format_g(self.camber, 6),
                format_g(self.position, 6)
            ),
        };
        let mut g = Pslg::new(format!("{what} in a far field of radius {} chords", format_g(r, 6)));
        let a4 = format_g(self.a4(), 6).replace('-', "");
        g.notes = vec![
            format!(
                "Thickness yt = 5 t (0.2969 sqrt(x) - 0.1260 x - 0.3516 x^2 + 0.2843 x^3 - {a4} x^4), t = {},",
                format_g(self.thickness, 10)
            ),
            format!(
                "camber line m = {}, p = {} (NACA 4-digit), surfaces offset across it; 0 <= x <= {}",
                format_g(self.camber, 10),
                format_g(self.position, 10),
                format_g(c, 7)
            ),
            match self.trailing_edge {
                TrailingEdge::Extended => {
                    "(the root of yt: closed trailing edge, the standard coefficients).".to_string()
                }
                TrailingEdge::Closed => {
                    "(closed trailing edge by the coefficient -0.1036).".to_string()
                }
            },
            format!(
                "{} vertices a side, cosine spacing x = c (1 - cos b) / 2, b uniform in [0, pi].",
                n + 1
            ),
            format!(
                "Far field: circle of radius {} about ({}, 0), {nf} vertices. The chord lies on the x axis.",
                format_g(r, 6),
                format_g(c / 2.0, 6)
            ),
        ];
        let le = g.add_point([0.0, 0.0], 11, "LeadingEdge");
        let te = g.add_point([c, self.camber_line(c).0], 12, "TrailingEdge");
        let stations: Vec<f64> = (1..n)
            .map(|k| c * (1.0 - (std::f64::consts::PI * k as f64 / n as f64).cos()) / 2.0)
            .collect();
        let (upper, lower): (Vec<Point2>, Vec<Point2>) =
            stations.iter().map(|&x| self.surface(x)).unzip();
        g.add_curve(1, "Upper", le, &upper, te);
        g.add_curve(2, "Lower", le, &lower, te);
        let circle: Vec<Point2> = (0..nf)
            .map(|k| {
                let b = 2.0 * std::f64::consts::PI * k as f64 / nf as f64;
                [c / 2.0 + r * b.cos(), r * b.sin()]
            })
            .collect();
        g.add_closed_curve(3, "FarField", &circle);
        g.add_hole([c / 2.0, self.camber_line(c / 2.0).0]);
        g.set_face([c / 2.0, r / 2.0], 100, "Fluid");
        Ok(g)
    }
}

/// `values` without repeats, in the order of their first occurrence (-0 and 0 are one).
fn distinct(values: &[f64]) -> Vec<f64> {
    let mut seen = std::collections::BTreeSet::new();
    values.iter().copied().filter(|v| seen.insert((v + 0.0).to_bits())).collect()
}

/// How many members [`family`] gives for these values, computed without building them,
/// so that a cap is checked before any work (saturating: 10^15 combinations is no
/// overflow).
pub fn family_size(thickness: &[f64], camber: &[f64], position: &[f64]) -> usize {
    let (t, m, p) = (distinct(thickness), distinct(camber), distinct(position));
    let cambered = m.iter().filter(|&&v| v != 0.0).count();
    let per_thickness = cambered
        .saturating_mul(p.len())
        .saturating_add(usize::from(cambered < m.len() && !p.is_empty()));
    t.len().saturating_mul(per_thickness)
}

/// The members of a family: every combination of the values, in the order thickness,
/// then camber, then position (the last changing fastest); a member without camber is
/// listed once, whatever the positions. A repeated value gives no second member: the
/// first occurrence of each combination is where its values first occur, so iterating
/// the distinct values gives the same order. Check [`family_size`] first.
pub fn family(
    thickness: &[f64],
    camber: &[f64],
    position: &[f64],
    trailing_edge: TrailingEdge,
) -> Vec<Naca4> {
    let (t, m, p) = (distinct(thickness), distinct(camber), distinct(position));
    let mut out: Vec<Naca4> = Vec::with_capacity(family_size(&t, &m, &p).min(MAX_MEMBERS));
    for &t in &t {
        for &m in &m {
            let positions: &[f64] = if m == 0.0 { &p[..p.len().min(1)] } else { &p };
            for &p in positions {
                let position = if m == 0.0 { 0.0 } else { p };
                out.push(Naca4 { thickness: t, camber: m, position, trailing_edge });
            }
        }
    }
    out
}

/// The all-combinations twin of [`family`]: the quadratic search for repeats.
#[cfg(test)]
fn family_brute(
    thickness: &[f64],
    camber: &[f64],
    position: &[f64],
    trailing_edge: TrailingEdge,
) -> Vec<Naca4> {
    let mut out: Vec<Naca4> = Vec::new();
    for &t in thickness {
        for &m in camber {
            for &p in position {
                let v = Naca4 {
                    thickness: t,
                    camber: m,
                    position: if m == 0.0 { 0.0 } else { p },
                    trailing_edge,
                };
                if !out.contains(&v) {
                    out.push(v);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn naca(t: f64, m: f64, p: f64) -> Naca4 {
        Naca4 { thickness: t, camber: m, position: p, trailing_edge: TrailingEdge::Extended }
    }

    #[test]
    fn ordinates_are_those_tabulated_for_the_naca_0012() {
        // Abbott & von Doenhoff, appendix I: NACA 0012 half thickness in % of chord.
        let table = [
            (0.0125, 1.894),
            (0.025, 2.615),
            (0.05, 3.555),
            (0.1, 4.683),
            (0.2, 5.737),
            (0.3, 6.002),
            (0.4, 5.803),
            (0.5, 5.294),
            (0.6, 4.563),
            (0.8, 2.623),
            (0.9, 1.448),
            (1.0, 0.126),
        ];
        let a = naca(0.12, 0.0, 0.0);
        for (x, y) in table {
            assert!((100.0 * a.half_thickness(x) - y).abs() < 6e-4, "{x}: {}", a.half_thickness(x));
        }
        let closed = Naca4 { trailing_edge: TrailingEdge::Closed, ..a };
        assert!(closed.half_thickness(1.0).abs() < 1e-15);
        assert_eq!(closed.chord(), 1.0);
        let c = a.chord();
        assert!((c - 1.008930411).abs() < 1e-9, "{c}");
        assert!(a.half_thickness(c).abs() < 1e-15);
        // The root does not depend on the thickness.
        assert_eq!(naca(0.21, 0.0, 0.0).chord(), c);
    }

    #[test]
    fn the_camber_line_peaks_at_p_with_m_and_surfaces_are_offset_across_it() {
        let a = naca(0.12, 0.02, 0.4);
        assert_eq!(a.designation().as_deref(), Some("2412"));
        assert_eq!(a.camber_line(0.4), (0.02, 0.0));
        let (up, lo) = a.surface(0.4);
        assert_eq!(up, [0.4, 0.02 + a.half_thickness(0.4)]);
        assert_eq!(lo, [0.4, 0.02 - a.half_thickness(0.4)]);
        // Camber 0 at both ends, continuous slope at p, and the slope is the derivative.
        assert_eq!(a.camber_line(0.0).0, 0.0);
        assert!(a.camber_line(1.0).0.abs() < 1e-17);
        for x in [0.1, 0.3, 0.39, 0.41, 0.7, 0.95] {
            let h = 1e-6;
            let d = (a.camber_line(x + h).0 - a.camber_line(x - h).0) / (2.0 * h);
            assert!((d - a.camber_line(x).1).abs() < 1e-8, "{x}");
        }
        // Every surface point is yt away from its camber point, across the line.
        for x in [0.05, 0.2, 0.6, 0.9] {
            let (up, lo) = a.surface(x);
            let (yc, s) = a.camber_line(x);
            for q in [up, lo] {
                let d = (q[0] - x).hypot(q[1] - yc);
                assert!((d - a.half_thickness(x)).abs() < 1e-15);
                assert!(((q[0] - x) + s * (q[1] - yc)).abs() < 1e-15, "not across");
            }
        }
    }

    /// The family and its size agree with the quadratic twin, repeats, -0 and camber 0
    /// (positions collapse) included; the size of 10^15 combinations is computed at once.
    #[test]
    fn families_agree_with_the_quadratic_twin_and_are_counted_before_built() {
        let lists: [&[f64]; 5] =
            [&[0.1], &[0.1, 0.12, 0.1], &[0.0, 0.02, -0.0, 0.02], &[0.3, 0.4, 0.3], &[]];
        for t in lists {
            for m in lists {
                for p in lists {
                    let fast = family(t, m, p, TrailingEdge::Closed);
                    assert_eq!(
                        fast,
                        family_brute(t, m, p, TrailingEdge::Closed),
                        "{t:?} {m:?} {p:?}"
                    );
                    assert_eq!(family_size(t, m, p), fast.len(), "{t:?} {m:?} {p:?}");
                }
            }
        }
        let many: Vec<f64> = (0..100_000).map(|k| 0.1 + k as f64 * 1e-7).collect();
        let start = std::time::Instant::now();
        assert_eq!(family_size(&many, &many[..10_000], &many), 100_000 * 10_000 * 100_000);
        assert!(start.elapsed().as_secs_f64() < 2.0, "{:?}", start.elapsed());
    }

    #[test]
    fn names_and_families() {
        assert_eq!(naca(0.12, 0.0, 0.4).name(), "naca-t0.12-m0");
        assert_eq!(naca(0.1, 0.02, 0.4).name(), "naca-t0.1-m0.02-p0.4");
        assert_eq!(naca(0.12, 0.0, 0.0).designation().as_deref(), Some("0012"));
        assert_eq!(naca(0.125, 0.0, 0.0).designation(), None);
        let f = family(&[0.1, 0.12], &[0.0, 0.02], &[0.3, 0.4], TrailingEdge::Closed);
        let names: Vec<String> = f.iter().map(Naca4::name).collect();
        assert_eq!(
            names,
            [
                "naca-t0.1-m0",
                "naca-t0.1-m0.02-p0.3",
                "naca-t0.1-m0.02-p0.4",
                "naca-t0.12-m0",
                "naca-t0.12-m0.02-p0.3",
                "naca-t0.12-m0.02-p0.4"
            ]
        );
        assert!(naca(0.0, 0.0, 0.0).geometry(&Layout::default()).is_err());
        assert!(naca(1e-300, 0.0, 0.0).geometry(&Layout::default()).is_err());
        assert!(naca(MIN_THICKNESS, 0.0, 0.0).geometry(&Layout::default()).is_ok());
        assert!(naca(0.1, 0.02, 1.0).geometry(&Layout::default()).is_err());
        assert!(naca(0.1, 0.0, 0.0)
            .geometry(&Layout { far_radius: 1.0, ..Layout::default() })
            .is_err());
    }
}
