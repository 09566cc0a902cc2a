//! Where to zoom: one window around the source entities of each step of a sizing plan
//! (their bounding box grown by the distance over which the step's size function acts,
//! or, for a source as large as the domain, a window around where the step asks for its
//! finest sizes), or, without a recipe, around the vertices where the metric asks for the
//! smallest sizes.

use crate::metric::SizeTensor;
use crate::sizing::algorithms::Around;
use crate::sizing::plan::{Algorithm, EntitySet, SizingPlan, Step};
use crate::sizing::Contribution;
use crate::topology::{Classification, Topology};

use super::view::Rect;

/// At most this many zoom windows.
pub(super) const MAX_WINDOWS: usize = 6;

/// One zoom window: the part of the plane it shows and why.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ZoomWindow {
    /// The region of the plane, before it is grown to the panel's aspect.
    pub region: Rect,
    /// What the window shows (short step captions, or "smallest sizes").
    pub label: String,
    /// The full labels of the plan steps it shows (empty without a recipe).
    pub steps: Vec<String>,
    /// What the panel shows: the region grown to the panel's aspect and moved inside
    /// the domain (set when the report is laid out; the region until then).
    pub shown: Rect,
}

fn entity_points(topo: &Topology, points: &[[f64; 2]], set: &EntitySet) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for &p in &set.points {
        if let Some(tp) = topo.points.get(p) {
            out.push(points[tp.vertex]);
        }
    }
    for &c in &set.curves {
        if let Some(tc) = topo.curves.get(c) {
            out.extend(tc.polylines.iter().flat_map(|pl| pl.vertices.iter().map(|&v| points[v])));
        }
    }
    for &f in &set.faces {
        if let Some(tf) = topo.faces.get(f) {
            out.extend(
                tf.cells
                    .iter()
                    .flat_map(|&c| topo.surface_cells[c].vertices().iter().map(|&v| points[v])),
            );
        }
    }
    out
}

/// The source points of a step and the distance over which it acts; `None` for steps
/// without a localised source (UNIFORM, which covers whole regions).
fn step_sources(
    topo: &Topology,
    points: &[[f64; 2]],
    a: &Algorithm,
) -> Option<(Vec<[f64; 2]>, f64)> {
    let (around, reach) = a.zoom()?;
    let pts = match around {
        Around::Entities(set) => entity_points(topo, points, &set),
        Around::Points(p) => p.to_vec(),
    };
    Some((pts, reach))
}

fn entity_names(topo: &Topology, set: &EntitySet) -> Vec<String> {
    let name = |tag: Option<i32>, name: &Option<String>| {
        name.clone().or_else(|| tag.map(|t| t.to_string())).unwrap_or_else(|| "untagged".into())
    };
    let mut v: Vec<String> = set
        .points
        .iter()
        .filter_map(|&i| topo.points.get(i))
        .map(|p| name(p.tag, &p.name))
        .collect();
    v.extend(set.curves.iter().filter_map(|&i| topo.curves.get(i)).map(|c| name(c.tag, &c.name)));
    v.extend(
        set.faces.iter().filter_map(|&i| topo.faces.get(i)).map(|f| name(Some(f.tag), &f.name)),
    );
    v
}

/// A short caption for a step: its keyword in words and its sources by the recipe's
/// names, e.g. "distance to border: Airfoil, Wake"; for a plan made in code, by the
/// names (or tags) of its entities, or the number of points of its polyline.
pub(super) fn describe(step: &Step, topo: &Topology) -> String {
    let a = &step.algorithm;
    let words = a.keyword().to_ascii_lowercase().replace('_', " ").replace("imaginary ", "");
    let names = if !step.names.is_empty() {
        step.names.clone()
    } else {
        match a.zoom() {
            Some((Around::Points(p), _)) => vec![format!("{} points", p.len())],
            Some((Around::Entities(set), _)) => entity_names(topo, &set),
            None => a.entity_sets().into_iter().flat_map(|s| entity_names(topo, s)).collect(),
        }
    };
    let mut shown: Vec<String> = names.iter().take(3).cloned().collect();
    if names.len() > 3 {
        shown.push(format!("{} more", names.len() - 3));
    }
    if shown.is_empty() {
        words
    } else {
        format!("{words}: {}", shown.join(", "))
    }
}

/// How far a window reaches beyond its sources: the step's reach, within [2 %, 10 %] of
/// the domain's diagonal.
fn margin(reach: f64, diag: f64) -> f64 {
    reach.clamp(0.02 * diag, 0.1 * diag)
}

/// Whether `region`, grown to the aspect of the panel it would get (4:3, or up to 5:1
/// for a wide one), shows at least three quarters of the domain both ways: no zoom.
pub(super) fn is_whole_domain(region: &Rect, domain: &Rect) -> bool {
    let aspect = region.width() / region.height().max(1e-300);
    let target = if aspect > super::layout::WIDE { aspect.min(5.0) } else { 4.0 / 3.0 };
    let shown = region.with_aspect(target);
    shown.width() >= 0.75 * domain.width() && shown.height() >= 0.75 * domain.height()
}

/// One window per step of `plan` that has sources: their bounding box grown by the
/// step's reach (within [2 %, 10 %] of the domain's diagonal) and cut to the domain grown
/// by 2 %. A source so large that this window would show the whole domain (a wall around
/// it, a wake down its length) is framed instead around the point `focus(step)` gives
/// (where the step asks for its finest sizes), twice the reach each way (within [2 %,
/// 12 %] of the diagonal); without one, around the source point nearest the sources'
/// centre. Steps with the same window share it; at most [`MAX_WINDOWS`].
pub(super) fn from_plan(
    plan: &SizingPlan,
    topo: &Topology,
    points: &[[f64; 2]],
    domain: &Rect,
    focus: &mut dyn FnMut(usize) -> Option<[f64; 2]>,
) -> Vec<ZoomWindow> {
    let diag = domain.diagonal();
    let frame = domain.inflate(0.02 * diag);
    let mut out: Vec<ZoomWindow> = Vec::new();
    for (k, step) in plan.steps.iter().enumerate() {
        let Some((pts, reach)) = step_sources(topo, points, &step.algorithm) else { continue };
        let Some(bb) = Rect::bounding(pts.iter().copied()) else { continue };
        let Some(mut region) = bb.inflate(margin(reach, diag)).intersect(&frame) else {
            continue;
        };
        if is_whole_domain(&region, domain) {
            let c = bb.centre();
            let nearest = || {
                pts.iter().copied().min_by(|a, b| {
                    let da = (a[0] - c[0]).hypot(a[1] - c[1]);
                    let db = (b[0] - c[0]).hypot(b[1] - c[1]);
                    da.total_cmp(&db)
                })
            };
            if let Some(p) = focus(k).or_else(nearest) {
                let half = (2.0 * reach).clamp(0.02 * diag, 0.12 * diag);
                let square = Rect::new(p[0] - half, p[1] - half, p[0] + half, p[1] + half);
                if let Some(r) = square.intersect(&frame) {
                    region = r;
                }
            }
        }
        let caption = describe(step, topo);
        if let Some(w) = out.iter_mut().find(|w| same_region(&w.region, &region, diag)) {
            w.label.push_str("; ");
            w.label.push_str(&caption);
            w.steps.push(step.label.clone());
        } else if out.len() < MAX_WINDOWS {
            out.push(ZoomWindow {
                region,
                label: caption,
                steps: vec![step.label.clone()],
                shown: region,
            });
        }
    }
    out
}

/// Where a step asks for its finest sizes: the vertex of its contribution whose size
/// ellipse is smallest (h1 · h2; ties to the lower vertex index), e.g. the tightest bend
/// of a wall for CURVATURE_OF_BORDER, the start of a wake.
pub(super) fn finest(contribution: &Contribution, points: &[[f64; 2]]) -> Option<[f64; 2]> {
    contribution
        .vertices
        .iter()
        .zip(&contribution.tensors)
        .map(|(&v, t)| (t.h1() * t.h2(), v as usize))
        .filter(|(a, v)| a.is_finite() && *v < points.len())
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map(|(_, v)| points[v])
}

fn same_region(a: &Rect, b: &Rect, diag: f64) -> bool {
    let tol = 1e-3 * diag;
    (a.x0 - b.x0).abs() <= tol
        && (a.x1 - b.x1).abs() <= tol
        && (a.y0 - b.y0).abs() <= tol
        && (a.y1 - b.y1).abs() <= tol
}

/// Up to `max` windows around the vertices with the smallest metric size: the smallest
/// first (ties by vertex index), each next one outside the windows already chosen and
/// asking for less than half the median size. A window's half-width is 8 times the
/// largest size at its vertex, within [2 %, 15 %] of the domain's diagonal. Vertices
/// that no cell uses are ignored.
pub(super) fn from_sizes(
    sizes: &[Option<SizeTensor>],
    topo: &Topology,
    points: &[[f64; 2]],
    domain: &Rect,
    max: usize,
) -> Vec<ZoomWindow> {
    let diag = domain.diagonal();
    let mut order: Vec<(f64, usize)> = sizes
        .iter()
        .enumerate()
        .filter(|(v, _)| !matches!(topo.vertex_class.get(*v), Some(Classification::Unused) | None))
        .filter_map(|(v, t)| t.map(|t| (t.h_min(), v)))
        .collect();
    if order.is_empty() {
        return Vec::new();
    }
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let median = order[order.len() / 2].0;
    let mut out: Vec<ZoomWindow> = Vec::new();
    for &(h, v) in &order {
        if out.len() >= max || (!out.is_empty() && h >= 0.5 * median) {
            break;
        }
        let p = points[v];
        if out.iter().any(|w| w.region.inflate(0.5 * w.region.width()).contains(p)) {
            continue;
        }
        let hmax = sizes[v].map_or(h, |t| t.h_max());
        let half = (8.0 * hmax).clamp(0.02 * diag, 0.15 * diag);
        let region = Rect::new(p[0] - half, p[1] - half, p[0] + half, p[1] + half);
        out.push(ZoomWindow {
            region,
            label: format!("smallest sizes: h = {} at vertex {v}", super::fmt_sig(h)),
            steps: Vec::new(),
            shown: region,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::{CellKind, TaggedMesh};

    /// A strip of `n` unit squares along x, two triangles each.
    fn strip(n: usize) -> (Topology, Vec<[f64; 2]>) {
        let mut m = TaggedMesh::new();
        for i in 0..=n {
            m.points.push([i as f64, 0.0, 0.0]);
            m.points.push([i as f64, 1.0, 0.0]);
        }
        let b = m.block_mut(CellKind::Triangle);
        for i in 0..n {
            let (a, c) = (2 * i as u32, 2 * i as u32 + 2);
            b.push(&[a, c, c + 1], 1, 1);
            b.push(&[a, c + 1, a + 1], 1, 1);
        }
        let pts = m.points.iter().map(|p| [p[0], p[1]]).collect();
        (Topology::from_mesh(&m), pts)
    }

    #[test]
    fn captions_use_the_recipe_names_of_a_step() {
        use crate::sizing::{DistanceFunction, DistanceToBorder};
        let mut m = TaggedMesh::new();
        for p in [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] {
            m.points.push([p[0], p[1], 0.0]);
        }
        m.block_mut(CellKind::Triangle).push(&[0, 1, 2], 1, 1);
        m.block_mut(CellKind::Line).push(&[0, 1], 7, 7);
        m.block_mut(CellKind::Line).push(&[1, 2], 8, 8);
        let topo = Topology::from_mesh(&m);
        let f = DistanceFunction::try_new(0.1, 1.0, 1.0, 1.0).unwrap();
        let curves = EntitySet { curves: vec![0, 1], ..EntitySet::default() };
        let algorithm = Algorithm::DistanceToBorder(DistanceToBorder {
            perpendicular: f,
            parallel: f,
            borders: curves,
        });
        let mut step = Step { label: "border".into(), algorithm, names: Vec::new() };
        // Without a recipe: the tags of the entities.
        assert_eq!(describe(&step, &topo), "distance to border: 7, 8");
        // From a recipe: its region names.
        step.names = vec!["Airfoil".into(), "Wake".into()];
        assert_eq!(describe(&step, &topo), "distance to border: Airfoil, Wake");
    }

    #[test]
    fn size_windows_start_at_the_smallest_and_skip_ordinary_sizes() {
        let (topo, pts) = strip(20);
        let mut sizes: Vec<Option<SizeTensor>> = vec![Some(SizeTensor::isotropic(1.0)); pts.len()];
        // Two refined spots far apart (vertices 4 and 36), a third one that is not
        // refined enough (0.6 of the median) to earn a window.
        sizes[36] = Some(SizeTensor::isotropic(0.01));
        sizes[4] = Some(SizeTensor::isotropic(0.02));
        sizes[20] = Some(SizeTensor::isotropic(0.6));
        let domain = Rect::bounding(pts.iter().copied()).unwrap();
        let w = from_sizes(&sizes, &topo, &pts, &domain, 3);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].region.contains(pts[36]) && w[1].region.contains(pts[4]));
        assert!(w[0].label.contains("vertex 36"));
        // Same input, same windows.
        assert_eq!(w, from_sizes(&sizes, &topo, &pts, &domain, 3));
    }
}
