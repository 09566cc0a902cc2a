//! Making room for the skin: the triangles in its way are removed, and the band between
//! the outer front of the skin and the rest of the mesh is triangulated again (a
//! constrained Delaunay triangulation, spade's, of the front, the skin's open sides, the
//! edges where the kept mesh meets the removed zone, and the boundary and interface edges
//! inside the zone).
//!
//! A triangle is removed when it has a wall vertex, a vertex a side of the skin replaces,
//! when it overlaps a cell of the skin or comes closer to one than a quarter of that cell's
//! shortest edge, or when one of its free vertices (inside a face, on no curve) lies
//! inside the skin or nearer to its outline than half the outline's local edge length.
//! Free vertices of the removed zone that are far enough from the skin stay, so the band
//! keeps the sizes the mesh had there.
//!
//! Invariants: the band's triangles are exactly the faces of the triangulation reached
//! from the band side of the front and of the kept mesh's edges without crossing a
//! constrained edge; each takes the face tags of the side it was reached from; no vertex
//! is added (spade's constraints are refused rather than split when they cross).

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::skin::Skin;
use super::LayerError;
use crate::geometry::plane::{
    convex_overlap, inside_convex, norm, segment_distance, sub, Bbox, BoxIndex, P,
};
use crate::topology::{Classification, Topology};

/// The band: which input triangles go, and the triangles that replace them.
pub(super) struct Band {
    /// Removed flag per surface cell.
    pub removed: Vec<bool>,
    /// New triangles (point ids into the skin's `pts`) with their tags.
    pub triangles: Vec<([usize; 3], (i32, i32))>,
    /// Mesh vertices the skin's sides replace.
    pub side_removed: BTreeSet<usize>,
    /// Boundary edges the skin's sides replace (their line cells go).
    pub side_edges: BTreeSet<[usize; 2]>,
    /// New line cells along the sides (point ids) with their tags.
    pub lines: Vec<([usize; 2], (i32, i32))>,
}

fn key(a: usize, b: usize) -> [usize; 2] {
    [a.min(b), a.max(b)]
}

/// Builds the band around `skin` in the mesh of `topo` (triangles only).
pub(super) fn build(
    skin: &Skin,
    topo: &Topology,
    cell_tags: &[(i32, i32)],
    line_tags: &BTreeMap<[usize; 2], (i32, i32)>,
    listed: &[bool],
) -> Result<Band, LayerError> {
    let sides = sides(skin, topo);
    let shapes = Shapes::of(skin);
    let (dropped, removed) = removed_zone(skin, topo, listed, &shapes, &sides.side_removed);
    let zone = Zone { removed: &removed, dropped: &dropped, sides: &sides };
    let Constraints { constraints, seeds, verts } =
        band_constraints(skin, topo, cell_tags, line_tags, &zone, &shapes)?;
    let triangles = triangulate(&skin.pts, &verts, constraints, seeds)?;
    let Sides { side_removed, side_edges, lines, .. } = sides;
    Ok(Band { removed, triangles, side_removed, side_edges, lines })
}

/// What the skin's open sides replace and add.
struct Sides {
    /// Mesh vertices the sides replace.
    side_removed: BTreeSet<usize>,
    /// Boundary edges the sides replace.
    side_edges: BTreeSet<[usize; 2]>,
    /// New line cells along the sides.
    lines: Vec<([usize; 2], (i32, i32))>,
    /// Edges from each side's last point to where it joins the kept boundary.
    bridges: Vec<[usize; 2]>,
}

/// First what every side replaces, then where each side's last point joins the kept
/// boundary: the first vertex past it that no side replaces, or, when two sides share
/// one boundary run between two walls, the other side's last point.
fn sides(skin: &Skin, topo: &Topology) -> Sides {
    let pts = &skin.pts;
    let n = skin.layers;
    let mut side_removed = BTreeSet::new();
    let mut lines = Vec::new();
    let mut bridges: Vec<[usize; 2]> = Vec::new();
    let mut side_edges = BTreeSet::new();
    for col in &skin.columns {
        let Some(side) = &col.side else { continue };
        let top = col.ids[n];
        let reach = norm(sub(pts[top], pts[col.base]));
        let last_h = norm(sub(pts[top], pts[col.ids[n - 1]]));
        for (i, &v) in side.path.iter().enumerate().skip(1) {
            let stop = matches!(topo.vertex_class[v], Classification::Point(_)) || skin.wall[v];
            if side.arc[i] < reach + 0.5 * last_h && !stop && i + 1 < side.path.len() {
                side_removed.insert(v);
            } else {
                break;
            }
        }
    }
    for (c, col) in skin.columns.iter().enumerate() {
        let Some(side) = &col.side else { continue };
        let top = col.ids[n];
        let Some(&q) = side.path.iter().skip(1).find(|v| !side_removed.contains(v)) else {
            continue;
        };
        for w in side.path.windows(2) {
            side_edges.insert(key(w[0], w[1]));
            if w[1] == q {
                break;
            }
        }
        // The other side of the same run, if `q` is its wall vertex.
        let facing = skin.columns.iter().enumerate().find(|(o, oc)| {
            *o != c && oc.base == q && oc.side.as_ref().is_some_and(|s| s.path.contains(&col.base))
        });
        let end = match facing {
            Some((o, _)) if o < c => continue,
            Some((_, oc)) => oc.ids[n],
            None => q,
        };
        if let Some(tags) = side.tags {
            for k in 0..n {
                lines.push(([col.ids[k], col.ids[k + 1]], tags));
            }
            lines.push(([top, end], tags));
        }
        bridges.push([top, end]);
    }
    // The facing sides' own lines (skipped above with their shared bridge).
    for (c, col) in skin.columns.iter().enumerate() {
        let Some(side) = &col.side else { continue };
        let Some(&q) = side.path.iter().skip(1).find(|v| !side_removed.contains(v)) else {
            continue;
        };
        let facing_first = skin.columns.iter().enumerate().any(|(o, oc)| {
            o < c && oc.base == q && oc.side.as_ref().is_some_and(|s| s.path.contains(&col.base))
        });
        if facing_first {
            if let Some(tags) = side.tags {
                for k in 0..n {
                    lines.push(([col.ids[k], col.ids[k + 1]], tags));
                }
            }
        }
    }
    Sides { side_removed, side_edges, lines, bridges }
}

/// The shortest edge of polygon `cell`.
fn shortest_edge(cell: &[P]) -> f64 {
    (0..cell.len())
        .map(|i| norm(sub(cell[(i + 1) % cell.len()], cell[i])))
        .fold(f64::INFINITY, f64::min)
}

/// The skin's cells and outline, indexed for the removal tests.
struct Shapes {
    /// The skin's cells as polygons.
    cells: Vec<Vec<P>>,
    /// The cells' boxes, grown by the margin of the overlap test.
    cgrid: BoxIndex,
    /// The skin's outline: fronts, open sides (with the clearance each asks).
    outline: Vec<([usize; 2], f64)>,
    /// The outline's boxes, grown by their clearance.
    ogrid: BoxIndex,
    /// The columns at the ends of open chains.
    end_cols: Vec<usize>,
}

impl Shapes {
    fn of(skin: &Skin) -> Shapes {
        let pts = &skin.pts;
        let n = skin.layers;
        let mut cells: Vec<Vec<P>> = Vec::new();
        for g in 0..skin.gaps.len() {
            for k in 0..n {
                cells.push(skin.cell(g, k).iter().map(|&v| pts[v]).collect());
            }
        }
        // Grown by the margin of the overlap test below (a quarter of the shortest edge).
        let cboxes: Vec<Bbox> =
            cells.iter().map(|c| Bbox::of(c).grown(0.5 * shortest_edge(c))).collect();
        let cgrid = BoxIndex::new(&cboxes);
        let mut outline: Vec<([usize; 2], f64)> = Vec::new();
        for gap in &skin.gaps {
            let (a, b) = (skin.columns[gap.cols[0]].ids[n], skin.columns[gap.cols[1]].ids[n]);
            outline.push(([a, b], 0.5 * norm(sub(pts[b], pts[a]))));
        }
        let mut end_cols: Vec<usize> = Vec::new();
        for ch in &skin.chains {
            if !ch.closed {
                end_cols.push(ch.cols[0]);
                end_cols.push(*ch.cols.last().expect("a chain has columns"));
            }
        }
        for &c in &end_cols {
            let ids = &skin.columns[c].ids;
            for k in 0..n {
                let l = norm(sub(pts[ids[k + 1]], pts[ids[k]]));
                outline.push(([ids[k], ids[k + 1]], 0.5 * l));
            }
        }
        let oboxes: Vec<Bbox> =
            outline.iter().map(|(s, c)| Bbox::of(&[pts[s[0]], pts[s[1]]]).grown(*c)).collect();
        let ogrid = BoxIndex::new(&oboxes);
        Shapes { cells, cgrid, outline, ogrid, end_cols }
    }
}

/// The free vertices dropped (inside the skin or too near its outline), and the removed
/// flag of each surface cell.
fn removed_zone(
    skin: &Skin,
    topo: &Topology,
    listed: &[bool],
    shapes: &Shapes,
    side_removed: &BTreeSet<usize>,
) -> (Vec<bool>, Vec<bool>) {
    let pts = &skin.pts;
    let Shapes { cells, cgrid, outline, ogrid, .. } = shapes;
    let free = |v: usize| matches!(topo.vertex_class[v], Classification::Face(_)) && !listed[v];
    let mut dropped = vec![false; skin.base_points];
    for v in 0..skin.base_points {
        if !free(v) {
            continue;
        }
        let p = pts[v];
        let b = Bbox::of(&[p]);
        let near = ogrid.query(b).into_iter().any(|o| {
            let (s, c) = outline[o as usize];
            segment_distance(p, pts[s[0]], pts[s[1]]) < c
        });
        let inside = cgrid.query(b).into_iter().any(|c| inside_convex(p, &cells[c as usize], 0.0));
        dropped[v] = near || inside;
    }
    let mut removed = vec![false; topo.surface_cells.len()];
    for (t, sc) in topo.surface_cells.iter().enumerate() {
        let vs = sc.vertices();
        if vs.iter().any(|&v| skin.wall[v] || side_removed.contains(&v) || dropped[v]) {
            removed[t] = true;
            continue;
        }
        let poly: Vec<P> = vs.iter().map(|&v| pts[v]).collect();
        let b = Bbox::of(&poly);
        for c in cgrid.query(b) {
            let cell = &cells[c as usize];
            if convex_overlap(&poly, cell, 0.25 * shortest_edge(cell)) {
                removed[t] = true;
                break;
            }
        }
    }
    (dropped, removed)
}

/// What leaves the mesh (removed cells, dropped vertices) and what the sides replace.
struct Zone<'a> {
    removed: &'a [bool],
    dropped: &'a [bool],
    sides: &'a Sides,
}

/// A directed edge with the band on its left, and the tags of the band there.
type Seed = ([usize; 2], (i32, i32));

/// What the band's triangulation is made of.
struct Constraints {
    /// The constrained edges.
    constraints: Vec<[usize; 2]>,
    /// Where the flood of the band starts.
    seeds: Vec<Seed>,
    /// The vertices.
    verts: BTreeSet<usize>,
}

/// The constrained edges of the band's triangulation, its seeds, and its vertices.
fn band_constraints(
    skin: &Skin,
    topo: &Topology,
    cell_tags: &[(i32, i32)],
    line_tags: &BTreeMap<[usize; 2], (i32, i32)>,
    zone: &Zone,
    shapes: &Shapes,
) -> Result<Constraints, LayerError> {
    let n = skin.layers;
    let Zone { removed, dropped, sides } = *zone;
    let Sides { side_removed, side_edges, bridges, .. } = sides;
    // Edges of the removed zone, and what is on the other side of each.
    let mut owners: BTreeMap<[usize; 2], Vec<(usize, [usize; 2])>> = BTreeMap::new();
    for (t, sc) in topo.surface_cells.iter().enumerate() {
        let vs = sc.vertices();
        for i in 0..vs.len() {
            let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
            owners.entry(key(a, b)).or_default().push((t, [a, b]));
        }
    }
    let mut constraints: Vec<[usize; 2]> = Vec::new();
    // (directed edge with the band on its left, tags)
    let mut seeds: Vec<Seed> = Vec::new();
    let mut verts: BTreeSet<usize> = BTreeSet::new();
    for (k, own) in &owners {
        let rem: Vec<&(usize, [usize; 2])> = own.iter().filter(|o| removed[o.0]).collect();
        if rem.is_empty() {
            continue;
        }
        let kept: Vec<&(usize, [usize; 2])> = own.iter().filter(|o| !removed[o.0]).collect();
        if let Some(&&(_, [a, b])) = kept.first() {
            // The band is on the left of b→a.
            constraints.push(*k);
            seeds.push(([b, a], cell_tags[rem[0].0]));
            verts.insert(a);
            verts.insert(b);
            continue;
        }
        let [a, b] = *k;
        if skin.wall_edges.contains(k)
            || side_edges.contains(k)
            || side_removed.contains(&a)
            || side_removed.contains(&b)
        {
            continue;
        }
        let boundary = own.len() == 1;
        let interface = line_tags.contains_key(k)
            || (own.len() == 2 && cell_tags[own[0].0] != cell_tags[own[1].0]);
        if boundary || interface {
            // A boundary edge from a chain end stays (the end column starts there); an
            // interface reaching the wall would cross the skin.
            if (skin.wall[a] || skin.wall[b]) && interface && !boundary {
                return Err(LayerError::Bad(format!(
                    "an interface or curve inside the domain meets the wall at vertex {}; a skin across it is not supported",
                    if skin.wall[a] { a } else { b }
                )));
            }
            constraints.push(*k);
            verts.insert(a);
            verts.insert(b);
        }
    }
    for (t, sc) in topo.surface_cells.iter().enumerate() {
        if removed[t] {
            for &v in sc.vertices() {
                if !skin.wall[v] && !side_removed.contains(&v) && !dropped[v] {
                    verts.insert(v);
                }
            }
        }
    }
    for gap in &skin.gaps {
        let (a, b) = (skin.columns[gap.cols[0]].ids[n], skin.columns[gap.cols[1]].ids[n]);
        constraints.push(key(a, b));
        seeds.push(([a, b], gap.tags));
        verts.insert(a);
        verts.insert(b);
    }
    for &c in &shapes.end_cols {
        let ids = &skin.columns[c].ids;
        for k in 0..n {
            constraints.push(key(ids[k], ids[k + 1]));
            verts.insert(ids[k]);
        }
        verts.insert(ids[n]);
    }
    for &[a, b] in bridges {
        constraints.push(key(a, b));
        verts.insert(a);
        verts.insert(b);
    }
    Ok(Constraints { constraints, seeds, verts })
}

/// A triangle (point ids) with its tags.
type TaggedTriangle = ([usize; 3], (i32, i32));

/// Triangulates `verts` with `constraints` and keeps the faces flooded from `seeds`
/// without crossing a constraint, each with the tags of its seed.
fn triangulate(
    pts: &[P],
    verts: &BTreeSet<usize>,
    mut constraints: Vec<[usize; 2]>,
    seeds: Vec<Seed>,
) -> Result<Vec<TaggedTriangle>, LayerError> {
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> = Default::default();
    let mut handle: BTreeMap<usize, FixedVertexHandle> = BTreeMap::new();
    let mut back: BTreeMap<usize, usize> = BTreeMap::new();
    for &v in verts {
        let p = pts[v];
        let h = cdt.insert(Point2::new(p[0], p[1])).map_err(|_| {
            LayerError::Bad(format!("point {v} at ({}, {}) is not finite", p[0], p[1]))
        })?;
        if let Some(&other) = back.get(&h.index()) {
            return Err(LayerError::CannotFit { at: [pts[other][0], pts[other][1]] });
        }
        back.insert(h.index(), v);
        handle.insert(v, h);
    }
    constraints.sort_unstable();
    constraints.dedup();
    for &[a, b] in &constraints {
        let (ha, hb) = (handle[&a], handle[&b]);
        if cdt.get_edge_from_neighbors(ha, hb).is_some_and(|e| e.is_constraint_edge()) {
            continue;
        }
        if cdt.try_add_constraint(ha, hb).is_empty() {
            return Err(LayerError::CannotFit { at: pts[a] });
        }
        if cdt.get_edge_from_neighbors(ha, hb).is_none() {
            // A vertex lay on the edge and split it: the mesh would hang there.
            return Err(LayerError::CannotFit { at: pts[a] });
        }
    }
    // Flood the band from its seeds.
    let mut tag_of: BTreeMap<usize, (i32, i32)> = BTreeMap::new();
    let mut queue = VecDeque::new();
    for ([a, b], tags) in seeds {
        let Some(e) = cdt.get_edge_from_neighbors(handle[&a], handle[&b]) else {
            return Err(LayerError::CannotFit { at: pts[a] });
        };
        if let Some(f) = e.face().as_inner() {
            let id = f.fix().index();
            if let std::collections::btree_map::Entry::Vacant(s) = tag_of.entry(id) {
                s.insert(tags);
                queue.push_back(f.fix());
            }
        }
    }
    while let Some(f) = queue.pop_front() {
        let tags = tag_of[&f.index()];
        for e in cdt.face(f).adjacent_edges() {
            if e.is_constraint_edge() {
                continue;
            }
            if let Some(o) = e.rev().face().as_inner() {
                let id = o.fix().index();
                if let std::collections::btree_map::Entry::Vacant(s) = tag_of.entry(id) {
                    s.insert(tags);
                    queue.push_back(o.fix());
                }
            }
        }
    }
    let mut triangles = Vec::with_capacity(tag_of.len());
    for f in cdt.inner_faces() {
        if let Some(&tags) = tag_of.get(&f.fix().index()) {
            let vs = f.vertices().map(|v| back[&v.fix().index()]);
            triangles.push((vs, tags));
        }
    }
    Ok(triangles)
}
