//! Which triangles of the constrained triangulation belong to the domain, and to which
//! region: flood fills that never cross a segment, as Triangle's `p` switch does.
//!
//! - Outside: unless the convex hull is kept, every triangle reached from a convex hull
//!   edge that is not a segment (Triangle eats the hull inward until it meets segments).
//! - Holes: every triangle reached from a hole point.
//! - Regions: every triangle reached from a region seed takes the seed's index; a later
//!   seed in the same region wins, as in Triangle. For mesh input the seeds are the
//!   surface cells' centroids, and what no seed reaches is carved.
//!
//! Labels are per spade face index (face 0 is spade's outer face). O(triangles): the
//! floods are done as a union-find of the parts that segments separate.

use spade::handles::{FixedFaceHandle, InnerTag};
use spade::{PositionInTriangulation, Triangulation};

use super::pslg::Pslg;
use super::{Cdt, MeshError};

type Face = FixedFaceHandle<InnerTag>;

/// Label of a carved triangle (outside, in a hole, or reached by no seed of a mesh).
pub(crate) const CARVED: u32 = u32::MAX;
/// Label of a triangle of the domain that no region seed reached.
pub(crate) const NO_REGION: u32 = u32::MAX - 1;

/// The parts of the triangulation that segments separate: faces joined through
/// non-segment edges, by union-find over spade's edge list (one pass in memory order,
/// several times faster on a refined mesh than walking face to face), and which parts
/// touch the convex hull through an edge that is not a segment. A flood fill from any
/// face fills exactly its part, so labelling parts is labelling floods.
struct Parts {
    parent: Vec<u32>,
    touches_hull: Vec<bool>,
}

impl Parts {
    fn new(cdt: &Cdt) -> Parts {
        let n = cdt.num_all_faces();
        let mut parts = Parts { parent: (0..n as u32).collect(), touches_hull: vec![false; n] };
        let mut hull_faces = Vec::new();
        for e in cdt.undirected_edges() {
            if e.is_constraint_edge() {
                continue;
            }
            let d = e.as_directed();
            match (d.face().as_inner(), d.rev().face().as_inner()) {
                (Some(a), Some(b)) => parts.union(a.fix().index(), b.fix().index()),
                (Some(a), None) | (None, Some(a)) => hull_faces.push(a.fix().index()),
                (None, None) => {}
            }
        }
        for f in hull_faces {
            let r = parts.find(f);
            parts.touches_hull[r] = true;
        }
        parts
    }

    fn find(&mut self, mut f: usize) -> usize {
        while self.parent[f] as usize != f {
            let up = self.parent[self.parent[f] as usize];
            self.parent[f] = up;
            f = up as usize;
        }
        f
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // The smaller index becomes the root: deterministic, and shallow enough with
            // path halving.
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.parent[hi] = lo as u32;
        }
    }
}

/// Where a seed point lies: the faces to flood from, or why it cannot be used.
enum Located {
    Faces(Vec<Face>),
    OnSegment,
    OutsideHull,
}

fn locate(cdt: &Cdt, p: [f64; 2]) -> Located {
    match cdt.locate(spade::Point2::new(p[0], p[1])) {
        PositionInTriangulation::OnFace(f) => Located::Faces(vec![f]),
        PositionInTriangulation::OnEdge(e) => {
            let e = cdt.directed_edge(e);
            if e.is_constraint_edge() {
                Located::OnSegment
            } else {
                Located::Faces(
                    [e.face(), e.rev().face()]
                        .iter()
                        .filter_map(|f| f.as_inner())
                        .map(|f| f.fix())
                        .collect(),
                )
            }
        }
        PositionInTriangulation::OnVertex(v) => {
            // A point inserted by refinement may land exactly on a seed; off every
            // segment, all its faces are in one region.
            let v = cdt.vertex(v);
            if v.out_edges().any(|e| e.is_constraint_edge()) {
                Located::OnSegment
            } else {
                Located::Faces(
                    v.out_edges().filter_map(|e| e.face().as_inner()).map(|f| f.fix()).collect(),
                )
            }
        }
        PositionInTriangulation::OutsideOfConvexHull(_)
        | PositionInTriangulation::NoTriangulation => Located::OutsideHull,
    }
}

/// Labels every face of `cdt`: [`CARVED`], [`NO_REGION`] or the index of the seed of
/// `pslg.seeds` whose region it is in.
pub(crate) fn classify(
    cdt: &Cdt,
    pslg: &Pslg,
    keep_convex_hull: bool,
) -> Result<Vec<u32>, MeshError> {
    let mut parts = Parts::new(cdt);
    let n = cdt.num_all_faces();
    // Labels per part root.
    let mut labels = vec![NO_REGION; n];
    labels[0] = CARVED;
    if !keep_convex_hull {
        for (l, &touches) in labels.iter_mut().zip(&parts.touches_hull) {
            if touches {
                *l = CARVED;
            }
        }
    }
    for (k, &h) in pslg.holes.iter().enumerate() {
        match locate(cdt, h) {
            Located::Faces(fs) => {
                for f in fs {
                    let r = parts.find(f.index());
                    labels[r] = CARVED;
                }
            }
            Located::OnSegment => {
                return Err(MeshError::SeedOnSegment { what: "hole", number: k + 1, point: h })
            }
            // Triangle ignores holes outside the triangulation; so do we.
            Located::OutsideHull => {}
        }
    }
    let roots: Vec<usize> = (1..n).filter(|&f| parts.find(f) == f).collect();
    if roots.iter().all(|&r| labels[r] == CARVED) {
        return Err(MeshError::NothingToMesh);
    }
    for (k, s) in pslg.seeds.iter().enumerate() {
        let k = k as u32;
        let derived = s.number == 0;
        let faces = match locate(cdt, s.point) {
            Located::Faces(fs) => fs,
            _ if derived => continue,
            Located::OnSegment => {
                return Err(MeshError::SeedOnSegment {
                    what: "region",
                    number: s.number,
                    point: s.point,
                })
            }
            Located::OutsideHull => {
                return Err(MeshError::RegionOutside { region: s.number, point: s.point })
            }
        };
        for f in faces {
            let r = parts.find(f.index());
            if derived {
                if labels[r] == NO_REGION {
                    labels[r] = k;
                }
            } else if labels[r] == CARVED {
                return Err(MeshError::RegionOutside { region: s.number, point: s.point });
            } else {
                labels[r] = k;
            }
        }
    }
    if pslg.seeded_only {
        for &r in &roots {
            if labels[r] == NO_REGION {
                labels[r] = CARVED;
            }
        }
        if roots.iter().all(|&r| labels[r] == CARVED) {
            return Err(MeshError::NothingToMesh);
        }
    }
    let mut out = vec![CARVED; n];
    for (f, o) in out.iter_mut().enumerate().skip(1) {
        *o = labels[parts.find(f)];
    }
    Ok(out)
}
