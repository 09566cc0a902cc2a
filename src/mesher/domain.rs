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
//! Labels are per spade face index (face 0 is spade's outer face). O(triangles).

use spade::handles::{FixedFaceHandle, InnerTag};
use spade::{PositionInTriangulation, Triangulation};

use super::pslg::Pslg;
use super::{Cdt, MeshError};

type Face = FixedFaceHandle<InnerTag>;

/// Label of a carved triangle (outside, in a hole, or reached by no seed of a mesh).
pub(crate) const CARVED: u32 = u32::MAX;
/// Label of a triangle of the domain that no region seed reached.
pub(crate) const NO_REGION: u32 = u32::MAX - 1;

/// Floods from `start` across non-segment edges into faces for which `enter` holds,
/// setting their label to `label`.
fn flood(cdt: &Cdt, labels: &mut [u32], start: Face, label: u32, enter: impl Fn(u32) -> bool, stack: &mut Vec<Face>) {
    if !enter(labels[start.index()]) {
        return;
    }
    labels[start.index()] = label;
    stack.clear();
    stack.push(start);
    while let Some(f) = stack.pop() {
        for e in cdt.face(f).adjacent_edges() {
            if e.is_constraint_edge() {
                continue;
            }
            if let Some(g) = e.rev().face().as_inner() {
                let gi = g.fix().index();
                if enter(labels[gi]) {
                    labels[gi] = label;
                    stack.push(g.fix());
                }
            }
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
                Located::Faces([e.face(), e.rev().face()].iter().filter_map(|f| f.as_inner()).map(|f| f.fix()).collect())
            }
        }
        PositionInTriangulation::OnVertex(v) => {
            // A point inserted by refinement may land exactly on a seed; off every
            // segment, all its faces are in one region.
            let v = cdt.vertex(v);
            if v.out_edges().any(|e| e.is_constraint_edge()) {
                Located::OnSegment
            } else {
                Located::Faces(v.out_edges().filter_map(|e| e.face().as_inner()).map(|f| f.fix()).collect())
            }
        }
        PositionInTriangulation::OutsideOfConvexHull(_) | PositionInTriangulation::NoTriangulation => Located::OutsideHull,
    }
}

/// Labels every face of `cdt`: [`CARVED`], [`NO_REGION`] or the index of the seed of
/// `pslg.seeds` whose region it is in.
pub(crate) fn classify(cdt: &Cdt, pslg: &Pslg, keep_convex_hull: bool) -> Result<Vec<u32>, MeshError> {
    let mut labels = vec![NO_REGION; cdt.num_all_faces()];
    labels[0] = CARVED;
    let mut stack = Vec::new();
    let domain = |l: u32| l != CARVED;
    if !keep_convex_hull {
        let starts: Vec<Face> =
            cdt.convex_hull().map(|e| e.rev()).filter(|e| !e.is_constraint_edge()).filter_map(|e| e.face().as_inner().map(|f| f.fix())).collect();
        for f in starts {
            flood(cdt, &mut labels, f, CARVED, domain, &mut stack);
        }
    }
    for (k, &h) in pslg.holes.iter().enumerate() {
        match locate(cdt, h) {
            Located::Faces(fs) => {
                for f in fs {
                    flood(cdt, &mut labels, f, CARVED, domain, &mut stack);
                }
            }
            Located::OnSegment => return Err(MeshError::SeedOnSegment { what: "hole", number: k + 1, point: h }),
            // Triangle ignores holes outside the triangulation; so do we.
            Located::OutsideHull => {}
        }
    }
    if labels.iter().all(|&l| l == CARVED) {
        return Err(MeshError::NothingToMesh);
    }
    for (k, s) in pslg.seeds.iter().enumerate() {
        let k = k as u32;
        let derived = s.number == 0;
        let faces = match locate(cdt, s.point) {
            Located::Faces(fs) => fs,
            _ if derived => continue,
            Located::OnSegment => return Err(MeshError::SeedOnSegment { what: "region", number: s.number, point: s.point }),
            Located::OutsideHull => return Err(MeshError::RegionOutside { region: s.number, point: s.point }),
        };
        for f in faces {
            if derived {
                flood(cdt, &mut labels, f, k, |l| l == NO_REGION, &mut stack);
            } else if labels[f.index()] == CARVED {
                return Err(MeshError::RegionOutside { region: s.number, point: s.point });
            } else {
                flood(cdt, &mut labels, f, k, |l| l != CARVED && l != k, &mut stack);
            }
        }
    }
    if pslg.seeded_only {
        for l in labels.iter_mut() {
            if *l == NO_REGION {
                *l = CARVED;
            }
        }
        if labels.iter().all(|&l| l == CARVED) {
            return Err(MeshError::NothingToMesh);
        }
    }
    Ok(labels)
}
