//! One parser per file of Triangle's set (`.node`, `.ele`, `.poly`, `.edge`, `.area`),
//! each into a small record of what the file lists; nothing here looks at another file.

use crate::error::{Error, ErrorKind, Result};
use crate::text::{check_count, Tokens};
use crate::{CellKind, NodeIndex, RegionSeed, MAX_POINTS};

use super::record::{fast, start, Rec, FAST_ATTRIBUTES};

/// A vertex list (`.node`, or the first section of a `.poly`).
#[derive(Debug, Default)]
pub(super) struct NodeList {
    pub(super) xy: Vec<[f64; 2]>,
    pub(super) nattr: usize,
    /// `nattr` values per vertex.
    pub(super) attrs: Vec<f64>,
    pub(super) markers: Option<Vec<i32>>,
    /// Number of the first vertex: 0 or 1.
    pub(super) base: i64,
}

/// Segments or edges, and the rays of a Voronoi `.edge`.
#[derive(Debug, Default)]
pub(super) struct Lines {
    pub(super) nodes: Vec<NodeIndex>,
    pub(super) tags: Vec<i32>,
    /// `(origin, marker, direction)`.
    pub(super) rays: Vec<(NodeIndex, i32, [f64; 2])>,
}

/// What a `.poly` lists besides its vertices.
#[derive(Debug, Default)]
pub(super) struct PolyRest {
    pub(super) segments: Lines,
    pub(super) holes: Vec<[f64; 2]>,
    pub(super) regions: Vec<RegionSeed>,
}

/// Triangles of a `.ele`, 0-based and already in smartmesh's node order.
#[derive(Debug)]
pub(super) struct Ele {
    pub(super) kind: CellKind,
    pub(super) nodes: Vec<NodeIndex>,
    pub(super) nattr: usize,
    pub(super) attrs: Vec<f64>,
}

impl Ele {
    pub(super) fn len(&self) -> usize {
        self.nodes.len() / self.kind.nodes_per_cell()
    }
}

// ---------------------------------------------------------------------------------------
// One parser per file
// ---------------------------------------------------------------------------------------

/// The vertex list: `<n> [<dim> [<#attributes> [<#markers>]]]`, then one vertex a line.
pub(super) fn parse_nodes(t: &mut Tokens<'_>, file: &str) -> Result<NodeList> {
    let line = start(t, || {
        format!(
            "the header of the {file} file (number of vertices, dimension, attributes, markers)"
        )
    })?;
    let mut r = Rec::new(t, line, "header", 0);
    // A vertex record is at least "1 0 0\n".
    let n = r.count("number of vertices", 6)?;
    if n > MAX_POINTS {
        return Err(Error::at_line(line, crate::mesh::past_max_points("vertices", n)));
    }
    let dim = r.opt_int("dimension", 2)?;
    if dim != 2 {
        return Err(Error::expected(
            line,
            "dimension 2 (Triangle is two-dimensional)",
            dim.to_string(),
        ));
    }
    let nattr = r.opt_int("number of attributes", 0)?;
    // Attributes may be left out of the records (they are then 0), so the check is that
    // the file could be this big at all, not that each record holds them.
    let nattr = r.check_count("number of attributes", nattr, 1)?;
    check_count(n.saturating_mul(nattr), r.t.remaining().len(), 1, "vertex attributes")
        .map_err(|k| Error::at_line(line, k))?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    if !(0..=1).contains(&nmarkers) {
        return Err(Error::expected(line, "0 or 1 boundary markers", nmarkers.to_string()));
    }
    r.end();
    let mut list = NodeList {
        xy: Vec::with_capacity(n),
        nattr,
        attrs: Vec::with_capacity(n * nattr),
        markers: (nmarkers == 1).then(|| Vec::with_capacity(n)),
        base: 1,
    };
    let mut i = 0;
    while i < n {
        if i > 0 {
            i += fast(
                t,
                n - i,
                |s| {
                    let (x, y) = (s.next_f64()?, s.next_f64()?);
                    let mut a = [0.0; FAST_ATTRIBUTES];
                    for slot in a.iter_mut().take(nattr) {
                        *slot = s.next_f64()?;
                    }
                    let m = if nmarkers == 1 { Some(s.next_i32()?) } else { None };
                    Some((x, y, a, m))
                },
                |(x, y, a, m)| {
                    list.xy.push([x, y]);
                    list.attrs.extend_from_slice(&a[..nattr]);
                    if let (Some(ms), Some(m)) = (list.markers.as_mut(), m) {
                        ms.push(m);
                    }
                },
                nattr <= FAST_ATTRIBUTES,
            );
            if i == n {
                break;
            }
        }
        let line = start(t, || format!("vertex {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "vertex", i + 1);
        let number = r.number()?;
        if i == 0 {
            list.base = match number {
                0 | 1 => number,
                _ => {
                    return Err(Error::expected(
                        line,
                        "0 or 1 as the number of the first vertex",
                        number.to_string(),
                    ))
                }
            };
        }
        let x = r.f64("x coordinate")?;
        let y = r.f64("y coordinate")?;
        list.xy.push([x, y]);
        for _ in 0..nattr {
            let a = r.opt_f64("attribute", 0.0)?;
            list.attrs.push(a);
        }
        if let Some(m) = list.markers.as_mut() {
            m.push(r.opt_marker()?);
        }
        r.end();
        i += 1;
    }
    Ok(list)
}

/// The triangles: `<n> [<nodes per triangle> [<#attributes>]]`, then one triangle a line.
pub(super) fn parse_ele(t: &mut Tokens<'_>, nv: usize, base: i64) -> Result<Ele> {
    let line = start(t, || {
        "the header of the .ele file (number of triangles, nodes per triangle, attributes)".into()
    })?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count("number of triangles", 8)?;
    let corners = r.opt_int("nodes per triangle", 3)?;
    let kind = match corners {
        3 => CellKind::Triangle,
        6 => CellKind::Triangle6,
        _ => {
            return Err(Error::at_line(
                line,
                ErrorKind::Unsupported(format!(
                    "triangles with {corners} nodes (Triangle writes 3, or 6 with -o2)"
                )),
            ))
        }
    };
    let nattr = r.opt_int("number of attributes", 0)?;
    let nattr = r.check_count("number of attributes", nattr, 1)?;
    check_count(n.saturating_mul(nattr), r.t.remaining().len(), 1, "triangle attributes")
        .map_err(|k| Error::at_line(line, k))?;
    r.end();
    let k = kind.nodes_per_cell();
    let mut ele =
        Ele { kind, nodes: Vec::with_capacity(n * k), nattr, attrs: Vec::with_capacity(n * nattr) };
    let mut v = [0 as NodeIndex; 6];
    let mut i = 0;
    while i < n {
        i += fast(
            t,
            n - i,
            |s| {
                let mut w = [0 as NodeIndex; 6];
                for slot in w.iter_mut().take(k) {
                    *slot = s.next_index(base, nv)?;
                }
                let mut a = [0.0; FAST_ATTRIBUTES];
                for slot in a.iter_mut().take(nattr) {
                    *slot = s.next_f64()?;
                }
                Some((w, a))
            },
            |(w, a)| {
                if k == 6 {
                    ele.nodes.extend_from_slice(&[w[0], w[1], w[2], w[5], w[3], w[4]]);
                } else {
                    ele.nodes.extend_from_slice(&w[..3]);
                }
                ele.attrs.extend_from_slice(&a[..nattr]);
            },
            nattr <= FAST_ATTRIBUTES,
        );
        if i == n {
            break;
        }
        let line = start(t, || format!("triangle {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "triangle", i + 1);
        r.number()?;
        for slot in v.iter_mut().take(k) {
            *slot = r.index("vertex", base, nv)?;
        }
        if k == 6 {
            // Triangle: nodes 4, 5, 6 lie opposite corners 1, 2, 3 (on edges 2-3, 3-1,
            // 1-2); smartmesh (as Gmsh) wants edges 1-2, 2-3, 3-1.
            ele.nodes.extend_from_slice(&[v[0], v[1], v[2], v[5], v[3], v[4]]);
        } else {
            ele.nodes.extend_from_slice(&v[..3]);
        }
        for _ in 0..nattr {
            let a = r.opt_f64("attribute", 0.0)?;
            ele.attrs.push(a);
        }
        r.end();
        i += 1;
    }
    Ok(ele)
}

/// Segments: `<n> [<#markers>]`, then `<#> <end> <end> [marker]`.
pub(super) fn parse_segments(
    t: &mut Tokens<'_>,
    nv: usize,
    base: i64,
    file: &str,
) -> Result<Lines> {
    let line = start(t, || {
        format!("the segment header of the {file} file (number of segments, markers)")
    })?;
    let mut r = Rec::new(t, line, "segment header", 0);
    let n = r.count("number of segments", 6)?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    if !(0..=1).contains(&nmarkers) {
        return Err(Error::expected(line, "0 or 1 boundary markers", nmarkers.to_string()));
    }
    r.end();
    let mut lines =
        Lines { nodes: Vec::with_capacity(2 * n), tags: Vec::with_capacity(n), rays: Vec::new() };
    let mut i = 0;
    while i < n {
        i += fast(
            t,
            n - i,
            |s| {
                let (a, b) = (s.next_index(base, nv)?, s.next_index(base, nv)?);
                let m = if nmarkers == 1 { s.next_i32()? } else { 0 };
                Some((a, b, m))
            },
            |(a, b, m)| {
                lines.nodes.extend_from_slice(&[a, b]);
                lines.tags.push(m);
            },
            true,
        );
        if i == n {
            break;
        }
        let line = start(t, || format!("segment {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "segment", i + 1);
        r.number()?;
        let a = r.index("first endpoint", base, nv)?;
        let b = r.index("second endpoint", base, nv)?;
        let m = if nmarkers == 1 { r.opt_marker()? } else { 0 };
        r.end();
        lines.nodes.extend_from_slice(&[a, b]);
        lines.tags.push(m);
        i += 1;
    }
    Ok(lines)
}

/// Holes: `<n>`, then `<#> <x> <y>`.
pub(super) fn parse_holes(t: &mut Tokens<'_>, file: &str) -> Result<Vec<[f64; 2]>> {
    let line = start(t, || format!("the number of holes in the {file} file"))?;
    let mut r = Rec::new(t, line, "hole header", 0);
    let n = r.count("number of holes", 6)?;
    r.end();
    let mut holes = Vec::with_capacity(n);
    for i in 0..n {
        let line = start(t, || format!("hole {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "hole", i + 1);
        r.number()?;
        let x = r.f64("x coordinate")?;
        let y = r.f64("y coordinate")?;
        r.end();
        holes.push([x, y]);
    }
    Ok(holes)
}

/// Regions (optional section): `<n>`, then `<#> <x> <y> <attribute> [<max area>]`; a
/// missing area takes the attribute's value, as Triangle reads it.
pub(super) fn parse_regions(t: &mut Tokens<'_>) -> Result<Vec<RegionSeed>> {
    t.skip_space();
    if t.remaining().is_empty() {
        return Ok(Vec::new());
    }
    let line = t.line();
    let mut r = Rec::new(t, line, "region header", 0);
    let n = r.count("number of regions", 8)?;
    r.end();
    let mut regions = Vec::with_capacity(n);
    for i in 0..n {
        let line = start(t, || format!("region {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "region", i + 1);
        r.number()?;
        let x = r.f64("x coordinate")?;
        let y = r.f64("y coordinate")?;
        let attribute = r.f64("regional attribute or area constraint")?;
        let max_area = r.opt_f64("maximum area", attribute)?;
        r.end();
        regions.push(RegionSeed { point: [x, y], attribute, max_area });
    }
    Ok(regions)
}

/// What follows the vertex list of a `.poly`: segments, holes and the optional regions.
/// Anything after the regions is ignored, as Triangle ignores it.
pub(super) fn parse_poly_rest(t: &mut Tokens<'_>, nv: usize, base: i64) -> Result<PolyRest> {
    let segments = parse_segments(t, nv, base, ".poly")?;
    let holes = parse_holes(t, ".poly")?;
    let regions = parse_regions(t)?;
    Ok(PolyRest { segments, holes, regions })
}

/// Edges: `<n> [<#markers>]`, then `<#> <end> <end> [marker]`, or for the infinite rays
/// of a Voronoi diagram `<#> <end> -1 <dx> <dy> [marker]`.
pub(super) fn parse_edges(t: &mut Tokens<'_>, nv: usize, base: i64) -> Result<Lines> {
    let line = start(t, || "the header of the .edge file (number of edges, markers)".into())?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count("number of edges", 6)?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    if !(0..=1).contains(&nmarkers) {
        return Err(Error::expected(line, "0 or 1 boundary markers", nmarkers.to_string()));
    }
    r.end();
    let mut lines =
        Lines { nodes: Vec::with_capacity(2 * n), tags: Vec::with_capacity(n), rays: Vec::new() };
    let mut i = 0;
    while i < n {
        // Rays (second endpoint -1) are left to the general path.
        i += fast(
            t,
            n - i,
            |s| {
                let (a, b) = (s.next_index(base, nv)?, s.next_index(base, nv)?);
                let m = if nmarkers == 1 { s.next_i32()? } else { 0 };
                Some((a, b, m))
            },
            |(a, b, m)| {
                lines.nodes.extend_from_slice(&[a, b]);
                lines.tags.push(m);
            },
            true,
        );
        if i == n {
            break;
        }
        let line = start(t, || format!("edge {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "edge", i + 1);
        r.number()?;
        let a = r.index("first endpoint", base, nv)?;
        // -1 is never a vertex (numbering starts at 0 or 1): it marks a ray.
        let save = r.t.clone();
        let second = r.int("second endpoint")?;
        if second == -1 {
            let dx = r.f64("ray direction x")?;
            let dy = r.f64("ray direction y")?;
            let m = if nmarkers == 1 { r.opt_marker()? } else { 0 };
            r.end();
            lines.rays.push((a, m, [dx, dy]));
            i += 1;
            continue;
        }
        *r.t = save;
        let b = r.index("second endpoint", base, nv)?;
        let m = if nmarkers == 1 { r.opt_marker()? } else { 0 };
        r.end();
        lines.nodes.extend_from_slice(&[a, b]);
        lines.tags.push(m);
        i += 1;
    }
    Ok(lines)
}

/// Area bounds: `<n>`, then `<#> [<area>]` (no area, or a negative one: no bound).
pub(super) fn parse_area(t: &mut Tokens<'_>, ntri: usize) -> Result<Vec<f64>> {
    let line = start(t, || "the number of triangles in the .area file".into())?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count("number of triangles", 4)?;
    if n != ntri {
        return Err(Error::at_line(
            line,
            ErrorKind::Inconsistent(format!(
                "the .area file lists {n} triangles, the .ele file {ntri}"
            )),
        ));
    }
    r.end();
    let mut areas = Vec::with_capacity(n);
    let mut i = 0;
    while i < n {
        i += fast(t, n - i, |s| s.next_f64(), |a| areas.push(a), true);
        if i == n {
            break;
        }
        let line = start(t, || format!("triangle {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "triangle", i + 1);
        r.number()?;
        areas.push(r.opt_f64("maximum area", -1.0)?);
        r.end();
        i += 1;
    }
    Ok(areas)
}

pub(crate) fn tokens(bytes: &[u8]) -> Tokens<'_> {
    Tokens::with_comments(bytes, b'#')
}
