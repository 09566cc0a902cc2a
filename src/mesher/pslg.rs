//! The planar straight-line graph a mesh is made from, taken out of a [`TaggedMesh`] and
//! checked before any triangulation starts.
//!
//! Two kinds of input give a PSLG:
//! - a Triangle `.poly` (no surface cells): every point is a vertex of the graph (isolated
//!   points too, as Triangle inserts them), the Line cells are the segments, holes and
//!   region seeds come from the file;
//! - any other mesh (a `.msh`, a `.mesh`...): only its Line cells (and Vertex cells) and the
//!   points they use. Its triangles are not meshed again; instead the centroid of every
//!   surface cell becomes a region seed with the cell's tag, and the parts of the plane
//!   bounded by segments that hold no surface cell are carved away (a cylinder's inside is a
//!   hole without anybody saying so).
//!
//! The checks are those that the triangulation cannot survive, or would silently get
//! wrong: non-planar or non-finite coordinates, two points at the same place, zero-length
//! and repeated segments. Crossing segments are found
//! while the constrained triangulation is built (spade reports them), see
//! [`super::refine`].

use std::collections::HashMap;

use smartmesh_formats::{CellKind, TaggedMesh};

use super::MeshError;

/// One segment of the graph: compact point indices and the tags of its Line cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Segment {
    pub a: usize,
    pub b: usize,
    pub physical: i32,
    pub geometrical: i32,
}

/// A region seed with the face tag it gives, its regional attribute and its own area
/// bound (`None`: unbounded).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Seed {
    pub point: [f64; 2],
    pub tag: i32,
    /// Triangle's regional attribute, a real (the tag when every attribute is an integer).
    pub attribute: f64,
    pub max_area: Option<f64>,
    /// 1-based number of the region in the input (for messages); 0 for seeds derived
    /// from surface cells.
    pub number: usize,
}

/// The checked planar straight-line graph.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Pslg {
    /// Vertex coordinates, compact.
    pub points: Vec<[f64; 2]>,
    /// The input point index of each compact vertex.
    pub source: Vec<usize>,
    /// Segments in input order.
    pub segments: Vec<Segment>,
    /// Input Vertex cells: compact vertex and tags.
    pub listed: Vec<(usize, i32, i32)>,
    /// Hole points.
    pub holes: Vec<[f64; 2]>,
    /// Region seeds, in input order (a later seed wins where two flood one region).
    pub seeds: Vec<Seed>,
    /// Whether parts of the domain reached by no seed are carved (mesh input).
    pub seeded_only: bool,
    /// Whether the regional attributes are reals that are not all integers: then they
    /// are no face tags (every tag is 0) and travel as a cell field instead, as the
    /// Triangle reader treats the attributes of an `.ele`.
    pub real_attributes: bool,
}

/// Topological points named by Triangle vertex markers (point data `triangle:marker`) in
/// a file with no Vertex cell: a vertex whose marker is not 0 and differs from the
/// markers of all its segments. Triangle itself gives every vertex on a segment that
/// segment's marker, so such a marker only says "on this boundary"; a marker of its own
/// names a point (a leading edge, a corner a recipe refines toward, an isolated source
/// inside the domain) and becomes a Vertex cell with that tag.
fn marked_points(
    mesh: &TaggedMesh,
    compact: &[usize],
    segments: &[Segment],
) -> Vec<(usize, i32, i32)> {
    let Some(markers) = mesh
        .point_data
        .get(smartmesh_formats::triangle::MARKER)
        .filter(|a| a.components == 1 && a.len() == mesh.points.len())
    else {
        return Vec::new();
    };
    if mesh.blocks.iter().any(|b| b.kind == CellKind::Vertex && !b.is_empty()) {
        return Vec::new();
    }
    let tag_of =
        |v: f64| (v != 0.0 && v.fract() == 0.0 && v.abs() <= i32::MAX as f64).then_some(v as i32);
    // Compact vertices that lie on a segment carrying their own marker.
    let mut on_own_segment = vec![false; compact.len()];
    let mut input_of = vec![usize::MAX; compact.iter().filter(|&&c| c != usize::MAX).count()];
    for (i, &c) in compact.iter().enumerate() {
        if c != usize::MAX {
            input_of[c] = i;
        }
    }
    for s in segments {
        for v in [s.a, s.b] {
            if tag_of(markers.values[input_of[v]]) == Some(s.physical) {
                on_own_segment[input_of[v]] = true;
            }
        }
    }
    let mut out = Vec::new();
    for (i, &m) in markers.values.iter().enumerate() {
        match tag_of(m) {
            Some(tag) if compact[i] != usize::MAX && !on_own_segment[i] => {
                out.push((compact[i], tag, tag))
            }
            _ => {}
        }
    }
    out
}

/// Takes the graph out of `mesh` and checks it.
pub(crate) fn extract(mesh: &TaggedMesh) -> Result<Pslg, MeshError> {
    // Meshed in (x, y): the caller puts the result back in the input's plane.
    crate::planar::plane(mesh).map_err(MeshError::NotPlanar)?;
    let n = mesh.points.len();
    let has_surface = mesh.blocks.iter().any(|b| b.kind.dim() == 2 && !b.is_empty());
    let mut compact = vec![usize::MAX; n];
    let mut source = Vec::new();
    let mut take = |i: usize, compact: &mut Vec<usize>| -> Result<usize, MeshError> {
        if i >= n {
            return Err(MeshError::BadIndex { index: i, points: n });
        }
        if compact[i] == usize::MAX {
            compact[i] = source.len();
            source.push(i);
        }
        Ok(compact[i])
    };
    if !has_surface {
        for i in 0..n {
            take(i, &mut compact)?;
        }
    }
    let mut segments = Vec::new();
    let mut listed = Vec::new();
    for (kind, nodes, physical, geometrical) in mesh.cells() {
        match kind {
            CellKind::Line | CellKind::Line3 => {
                let (a, b) = (
                    take(nodes[0] as usize, &mut compact)?,
                    take(nodes[1] as usize, &mut compact)?,
                );
                segments.push(Segment { a, b, physical, geometrical });
            }
            CellKind::Vertex => {
                listed.push((take(nodes[0] as usize, &mut compact)?, physical, geometrical))
            }
            _ => {}
        }
    }
    listed.extend(marked_points(mesh, &compact, &segments));
    let mut points = Vec::with_capacity(source.len());
    for &i in &source {
        let p = mesh.points[i];
        if !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()) {
            return Err(MeshError::NonFinite { point: i });
        }
        points.push([p[0], p[1]]);
    }
    check_duplicate_points(&points, &source)?;
    check_segments(&segments, &source)?;

    // Triangle's regional attributes are reals (`la.poly` has 0.05); they are face tags
    // only when all are integers.
    let integral = |a: f64| a.fract() == 0.0 && a >= i32::MIN as f64 && a <= i32::MAX as f64;
    let real_attributes = !mesh.regions.iter().all(|r| integral(r.attribute));
    let mut seeds = Vec::new();
    for (k, r) in mesh.regions.iter().enumerate() {
        let a = r.attribute;
        if !(r.point[0].is_finite() && r.point[1].is_finite() && a.is_finite()) {
            return Err(MeshError::NonFiniteSeed { what: "region", number: k + 1 });
        }
        let max_area = (r.max_area > 0.0 && r.max_area.is_finite()).then_some(r.max_area);
        let tag = if real_attributes { 0 } else { a as i32 };
        seeds.push(Seed { point: r.point, tag, attribute: a, max_area, number: k + 1 });
    }
    let seeded_only = has_surface && mesh.regions.is_empty() && mesh.holes.is_empty();
    if seeded_only {
        for (kind, nodes, physical, geometrical) in mesh.cells() {
            if kind.dim() != 2 {
                continue;
            }
            let k = match kind {
                CellKind::Triangle | CellKind::Triangle6 => 3,
                _ => 4,
            };
            let (mut x, mut y) = (0.0, 0.0);
            for &v in &nodes[..k] {
                let v = v as usize;
                let p = mesh.points.get(v).ok_or(MeshError::BadIndex { index: v, points: n })?;
                x += p[0];
                y += p[1];
            }
            let tag = if physical != 0 { physical } else { geometrical };
            seeds.push(Seed {
                point: [x / k as f64, y / k as f64],
                tag,
                attribute: tag as f64,
                max_area: None,
                number: 0,
            });
        }
    }
    for (k, h) in mesh.holes.iter().enumerate() {
        if !(h[0].is_finite() && h[1].is_finite()) {
            return Err(MeshError::NonFiniteSeed { what: "hole", number: k + 1 });
        }
    }
    Ok(Pslg {
        points,
        source,
        segments,
        listed,
        holes: mesh.holes.clone(),
        seeds,
        seeded_only,
        real_attributes,
    })
}

/// Two vertices at the same place would be merged by the triangulation and every segment
/// through one of them would lose its end: refuse them. Sorting finds them in O(n log n).
fn check_duplicate_points(points: &[[f64; 2]], source: &[usize]) -> Result<(), MeshError> {
    // `+ 0.0` turns -0.0 into 0.0, so that total_cmp sorts the two together.
    let key = |i: usize| (points[i][0] + 0.0, points[i][1] + 0.0);
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_unstable_by(|&i, &j| {
        let (p, q) = (key(i), key(j));
        p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1)).then(i.cmp(&j))
    });
    for w in order.windows(2) {
        let (p, q) = (points[w[0]], points[w[1]]);
        if p[0] == q[0] && p[1] == q[1] {
            let (a, b) = (source[w[0]].min(source[w[1]]), source[w[0]].max(source[w[1]]));
            return Err(MeshError::DuplicatePoint { first: a, second: b, at: p });
        }
    }
    Ok(())
}

/// Zero-length segments have no direction to mesh along, and a segment listed twice
/// would give two Line cells with possibly different tags on every edge: refuse both.
fn check_segments(segments: &[Segment], source: &[usize]) -> Result<(), MeshError> {
    let mut seen: HashMap<(usize, usize), usize> = HashMap::with_capacity(segments.len());
    for (k, s) in segments.iter().enumerate() {
        if s.a == s.b {
            return Err(MeshError::ZeroLengthSegment { segment: k + 1, point: source[s.a] });
        }
        let key = (s.a.min(s.b), s.a.max(s.b));
        if let Some(&first) = seen.get(&key) {
            return Err(MeshError::DuplicateSegment { first: first + 1, second: k + 1 });
        }
        seen.insert(key, k);
    }
    Ok(())
}
