//! The constrained Delaunay triangulation of the graph (spade's bulk loader) and its
//! quality refinement (spade's Ruppert/Chew `refine`), with the two things spade's
//! refinement cannot do by itself done around it:
//!
//! - **Which faces to leave alone.** spade's `exclude_outer_faces` decides inside from
//!   outside by the parity of the segments crossed, which is right for a boundary with
//!   holes but wrong as soon as a segment has the domain on both sides (an interface
//!   between two regions, a crack): faces of the domain would be skipped. So we first ask
//!   spade which faces it would exclude (a `refine` call allowed no new vertex, which
//!   returns that set and changes nothing) and use the exclusion only when every one of
//!   them is carved by our own flood fill ([`super::domain`]). Otherwise every face is
//!   refined and the outside carved afterwards; that costs time outside the domain, and
//!   points inserted in holes can split hole boundaries a little finer than needed.
//! - **Per-region area bounds** (the fourth number of a `.poly` region line). spade takes
//!   one global bound. After it has refined, every domain triangle larger than its
//!   region's bound gets its centroid inserted (inside that triangle, so inside its
//!   region), and spade refines again for angles; this repeats until no triangle is too
//!   large. The same pass also catches any triangle spade left above the global bound.
//!
//! Before any of that, the vertices the area bounds ask for are estimated from the
//! unrefined triangulation (each domain triangle's area over its bound,
//! [`expected_vertices`]) and a graph asking for more than the limit is refused
//! ([`MeshError::TooManyVertices`]): `--size 1e-4` on a unit square would otherwise
//! insert 10⁸ vertices before failing.

use spade::{AngleLimit, Point2, RefinementParameters, Triangulation};

use super::domain::{classify, CARVED};
use super::pslg::Pslg;
use super::{Cdt, MeshError, MeshOptions, DEFAULT_MAX_VERTICES};

/// Rounds of the region-bound pass before giving up (each round at least thirds the
/// area of every triangle that is too large, so 60 rounds cover a factor of 3^60).
const MAX_ROUNDS: usize = 60;

/// Builds the constrained Delaunay triangulation of `pslg`'s vertices and segments.
pub(crate) fn build(pslg: &Pslg) -> Result<Cdt, MeshError> {
    let vertices: Vec<Point2<f64>> = pslg.points.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let edges: Vec<[usize; 2]> = pslg.segments.iter().map(|s| [s.a, s.b]).collect();
    let mut conflicts: Vec<[usize; 2]> = Vec::new();
    let cdt = Cdt::try_bulk_load_cdt(vertices, edges, |e| conflicts.push(e))
        .map_err(|e| MeshError::Coordinates { reason: format!("{e:?}") })?;
    if cdt.num_vertices() != pslg.points.len() {
        // Exact duplicates were refused before; spade merging others means coordinates
        // it cannot tell apart.
        return Err(MeshError::Coordinates { reason: "spade merged vertices that differ".into() });
    }
    if let Some(&[a, b]) = conflicts.iter().min() {
        let segment = pslg
            .segments
            .iter()
            .position(|s| (s.a, s.b) == (a, b) || (s.a, s.b) == (b, a))
            .unwrap_or(0);
        let other = crossing_partner(pslg, segment);
        return Err(MeshError::SegmentsCross { segment: segment + 1, other: other.map(|o| o + 1) });
    }
    Ok(cdt)
}

/// The first segment that `k` crosses, for the error message (a linear scan: this runs
/// once, on the way out).
fn crossing_partner(pslg: &Pslg, k: usize) -> Option<usize> {
    let p = |i: usize| pslg.points[i];
    let orient = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let s = pslg.segments[k];
    let (a, b) = (p(s.a), p(s.b));
    pslg.segments.iter().enumerate().position(|(j, t)| {
        if j == k || t.a == s.a || t.a == s.b || t.b == s.a || t.b == s.b {
            return false;
        }
        let (c, d) = (p(t.a), p(t.b));
        let (o1, o2, o3, o4) = (orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b));
        o1 * o2 <= 0.0 && o3 * o4 <= 0.0
    })
}

/// The area bound of a face with label `label`: the smaller of the global bound and
/// its region's, `None` when neither is set.
fn bound_of(label: u32, global: Option<f64>, pslg: &Pslg) -> Option<f64> {
    let region = pslg.seeds.get(label as usize).and_then(|s| s.max_area);
    match (global, region) {
        (Some(g), Some(r)) => Some(g.min(r)),
        (g, r) => g.or(r),
    }
}

/// spade's `refine`, with a panic (spade gives up with one when a circumcentre cannot be
/// inserted for loss of precision) turned into an error.
fn spade_refine(
    cdt: &mut Cdt,
    params: RefinementParameters<f64>,
) -> Result<spade::RefinementResult, MeshError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| cdt.refine(params))).map_err(|e| {
        let why = e
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| e.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        MeshError::Internal { reason: format!("spade's refinement failed: {why}") }
    })
}

/// A triangle of the domain (spade vertex indices, counter-clockwise) and its label.
pub(crate) type Labelled = ([usize; 3], u32);

/// The triangles of the domain, counter-clockwise (spade vertex indices), with their
/// labels; and the centroids of those larger than their area bound. One pass over the
/// faces, which [`super::assemble`] reuses when nothing is too large.
fn domain_triangles(
    cdt: &Cdt,
    labels: &[u32],
    global: Option<f64>,
    pslg: &Pslg,
) -> (Vec<Labelled>, Vec<Point2<f64>>) {
    let coords: Vec<[f64; 2]> = cdt.vertices().map(|v| [v.position().x, v.position().y]).collect();
    let mut kept = Vec::with_capacity(cdt.num_inner_faces());
    let mut too_large = Vec::new();
    for f in cdt.inner_faces() {
        let l = labels[f.fix().index()];
        if l == CARVED {
            continue;
        }
        let t = f.vertices().map(|v| v.fix().index());
        if let Some(bound) = bound_of(l, global, pslg) {
            let (a, b, c) = (coords[t[0]], coords[t[1]], coords[t[2]]);
            if crate::quality::signed_area(a, b, c) > bound {
                too_large.push(Point2::new((a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0));
            }
        }
        kept.push((t, l));
    }
    (kept, too_large)
}

/// Vertices per unit of area over area bound in a refined mesh (measured on the
/// fixtures: refinement to an area bound leaves triangles of about half the bound, two
/// triangles per vertex).
const VERTICES_PER_BOUND: f64 = 1.0;

/// The vertices the area bounds ask for: the area of each domain triangle of the
/// unrefined triangulation over its bound, summed (`None` when no bound applies).
pub(crate) fn expected_vertices(
    cdt: &Cdt,
    labels: &[u32],
    global: Option<f64>,
    pslg: &Pslg,
) -> Option<f64> {
    let mut sum = 0.0;
    let mut any = false;
    for f in cdt.inner_faces() {
        let l = labels[f.fix().index()];
        if l == CARVED {
            continue;
        }
        if let Some(bound) = bound_of(l, global, pslg) {
            any = true;
            sum += f.area() / bound;
        }
    }
    any.then_some(VERTICES_PER_BOUND * sum + cdt.num_vertices() as f64)
}

/// Refines `cdt` as `opts` asks and returns the domain's triangles with their labels.
pub(crate) fn refine(
    cdt: &mut Cdt,
    pslg: &Pslg,
    opts: &MeshOptions,
) -> Result<Vec<Labelled>, MeshError> {
    let initial = classify(cdt, pslg, opts.keep_convex_hull)?;
    let global = opts.area_bound();
    // The memory guard: the default limit, or the caller's when higher (a lower one is a
    // budget that refinement stops at, below).
    let limit = opts.max_vertices.map_or(DEFAULT_MAX_VERTICES, |m| m.max(DEFAULT_MAX_VERTICES));
    if let Some(estimate) = expected_vertices(cdt, &initial, global, pslg) {
        if crate::metric::complexity::exceeds(estimate, limit) {
            return Err(MeshError::TooManyVertices { estimate, limit });
        }
    }
    let any_region_bound = pslg.seeds.iter().any(|s| s.max_area.is_some());
    if opts.min_angle_deg == 0.0 && global.is_none() && !any_region_bound {
        return Ok(domain_triangles(cdt, &initial, None, pslg).0);
    }

    let exclude = !opts.keep_convex_hull && {
        let dry = spade_refine(
            cdt,
            RefinementParameters::<f64>::new()
                .exclude_outer_faces(true)
                .with_max_additional_vertices(0),
        )?;
        dry.excluded_faces.iter().all(|f| initial[f.index()] == CARVED)
    };

    let hull_area: f64 = cdt.inner_faces().map(|f| f.area()).sum();
    let smallest_bound =
        pslg.seeds.iter().filter_map(|s| s.max_area).chain(global).fold(f64::INFINITY, f64::min);
    let budget = |cdt: &Cdt| -> usize {
        match opts.max_vertices {
            Some(m) => m.saturating_sub(cdt.num_vertices()),
            None => {
                let by_area = if smallest_bound.is_finite() {
                    (4.0 * hull_area / smallest_bound).min(1e12) as usize
                } else {
                    0
                };
                (10 * cdt.num_vertices() + by_area + 10_000).min(DEFAULT_MAX_VERTICES)
            }
        }
    };
    let params = |cdt: &Cdt| {
        let mut p = RefinementParameters::<f64>::new()
            .with_angle_limit(AngleLimit::from_deg(opts.min_angle_deg))
            .exclude_outer_faces(exclude)
            .with_max_additional_vertices(budget(cdt));
        if let Some(a) = global {
            p = p.with_max_allowed_area(a);
        }
        p
    };

    let p = params(cdt);
    let result = spade_refine(cdt, p)?;
    if !result.refinement_complete {
        return Err(MeshError::RefinementIncomplete { vertices: cdt.num_vertices() });
    }
    for _ in 0..MAX_ROUNDS {
        let labels = classify(cdt, pslg, opts.keep_convex_hull)?;
        let (kept, centroids) = domain_triangles(cdt, &labels, global, pslg);
        if centroids.is_empty() {
            return Ok(kept);
        }
        if opts.max_vertices.is_some_and(|m| cdt.num_vertices() + centroids.len() > m) {
            return Err(MeshError::RefinementIncomplete { vertices: cdt.num_vertices() });
        }
        for c in centroids {
            cdt.insert(c).map_err(|e| MeshError::Coordinates { reason: format!("{e:?}") })?;
        }
        let p = params(cdt);
        let result = spade_refine(cdt, p)?;
        if !result.refinement_complete {
            return Err(MeshError::RefinementIncomplete { vertices: cdt.num_vertices() });
        }
    }
    Err(MeshError::RefinementIncomplete { vertices: cdt.num_vertices() })
}
