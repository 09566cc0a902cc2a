//! The boundary-layer skin of a mixed mesh in a report: zoom windows on it, and the
//! columns that `layer` thinned or stopped marked where they stand.
//!
//! The skin's thickness is the sum of its layers' mean heights, found from the quads
//! alone ([`crate::layer::stats::quad_quality`]), so any mixed mesh gets its window: a
//! square 2.5 thicknesses wide (kept between 0.02 % and 30 % of the domain's diagonal)
//! centred on the quad of smallest scaled Jacobian, where the skin is hardest (a corner,
//! a trailing edge). The thinned columns come from the record `layer` writes,
//! [`crate::layer::THICKNESS_SHARE`] (a share below 1 at a column's points); when there
//! are some, a second window is centred on the thinnest, and every point of a thinned
//! column is drawn as a red dot, in the overview and in every zoom.

use crate::layer::stats::{quad_figures, quad_quality};
use crate::layer::THICKNESS_SHARE;
use smartmesh_formats::{CellKind, TaggedMesh};

use super::svg::{num, Svg};
use super::view::{Rect, View};
use super::windows::ZoomWindow;

/// Colour of the thinned columns' dots.
pub(super) const THINNED: &str = "#d32f2f";

/// The skin as a report shows it.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct SkinMarks {
    /// Points of thinned columns, with the share of the thickness their column took.
    pub thinned: Vec<([f64; 2], f64)>,
    /// Zoom windows on the skin.
    pub windows: Vec<ZoomWindow>,
}

/// The skin of `mesh` (none without quads), its windows kept inside `domain`'s scale.
pub(super) fn skin_marks(mesh: &TaggedMesh, domain: &Rect) -> SkinMarks {
    let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let thinned: Vec<([f64; 2], f64)> = match mesh.point_data.get(THICKNESS_SHARE) {
        Some(a) if a.components == 1 && a.values.len() == pts.len() => pts
            .iter()
            .zip(&a.values)
            .filter(|(_, &s)| s < 1.0 - 1e-9)
            .map(|(&p, &s)| (p, s))
            .collect(),
        _ => Vec::new(),
    };
    let Some(q) = quad_quality(mesh) else { return SkinMarks { thinned, windows: Vec::new() } };
    let thickness: f64 = q.layers.iter().map(|l| l.height[1]).sum();
    let diag = domain.diagonal();
    let half = (1.25 * thickness).clamp(1e-4 * diag, 0.15 * diag);
    let square = |c: [f64; 2]| Rect::new(c[0] - half, c[1] - half, c[0] + half, c[1] + half);
    let mut windows = Vec::new();
    // The worst quad; the first of equals, so the choice is the same every run.
    let worst = mesh
        .blocks
        .iter()
        .filter(|b| b.kind == CellKind::Quad)
        .flat_map(|b| b.cells())
        .map(|c| {
            let corners = [0, 1, 2, 3].map(|k| pts[c[k] as usize]);
            (quad_figures(corners).0, corners)
        })
        .fold(None::<(f64, [[f64; 2]; 4])>, |best, x| match best {
            Some(b) if b.0 <= x.0 => Some(b),
            _ => Some(x),
        });
    if let Some((sj, c)) = worst {
        let centre = [
            (c[0][0] + c[1][0] + c[2][0] + c[3][0]) / 4.0,
            (c[0][1] + c[1][1] + c[2][1] + c[3][1]) / 4.0,
        ];
        let region = square(centre);
        windows.push(ZoomWindow {
            region,
            label: format!(
                "boundary layer: {} layers, {} thick; worst quad, scaled Jacobian {}",
                q.layers.len(),
                super::fmt_sig(thickness),
                num(sj, 3)
            ),
            steps: Vec::new(),
            shown: region,
        });
    }
    if let Some(&(p, s)) = thinned.iter().min_by(|a, b| a.1.total_cmp(&b.1)) {
        let region = square(p);
        let count = thinned.len();
        windows.push(ZoomWindow {
            region,
            label: if s <= 0.0 {
                format!("layer stopped here ({count} points of thinned columns in red)")
            } else {
                format!(
                    "layer thinned to {}% here ({count} points of thinned columns in red)",
                    num(100.0 * s, 0)
                )
            },
            steps: Vec::new(),
            shown: region,
        });
    }
    SkinMarks { thinned, windows }
}

/// Draws the thinned columns' points.
pub(super) fn draw(svg: &mut Svg, view: &View, marks: &SkinMarks, radius: f64) {
    if marks.thinned.is_empty() {
        return;
    }
    svg.open("g", &[("class", "layer-thinned"), ("fill", THINNED)]);
    for &(p, _) in &marks.thinned {
        if !view.world.contains(p) {
            continue;
        }
        let [x, y] = view.to_px(p);
        svg.element("circle", &[("cx", &num(x, 1)), ("cy", &num(y, 1)), ("r", &num(radius, 1))]);
    }
    svg.close();
}
