//! Layer: a structured skin of quadrilaterals along chosen curves of a triangle mesh
//! (thesis 5.4.2), pushing the triangles away; optionally each quad split in two
//! triangles.
//!
//! Steps, one module each:
//! - [`growth`]: the layer heights from any three of first height, ratio, count and
//!   thickness (or the first height from a target y⁺);
//! - `skin`: wall chains, columns of points (mitred normals, fans at convex corners,
//!   leaning near concave ones, sides sliding along the boundary a wall ends on), the
//!   thickness each column may take (thinned in gaps and where fronts collide), the cells;
//! - `band`: the triangles in the skin's way removed and the band between the front and
//!   the kept mesh triangulated again, conforming to both;
//! - [`to_metric`]: where a metric is given, the band remeshed to it by the native
//!   remesher with the skin and the kept mesh frozen;
//! - [`stats`]: the quality of a skin as built (per-layer heights and ratios, scaled
//!   Jacobians, skewness, aspect ratios).
//!
//! What it shares with the remesher lives below both: the plane geometry of the skin
//! (`geometry::plane`), the pairs of segments or cells that may meet
//! (`geometry::near_pairs`) and the validity of a mixed mesh ([`crate::check_mesh`]).
//!
//! Invariants of [`insert`]'s output: every input point used by a kept cell keeps its
//! index order (points only go: the removed ones), skin points follow; every line cell,
//! vertex cell, tag name and face tag of the input stays (line cells along a side of the
//! skin are replaced by lines of the same tags along the side); skin cells take the
//! tags of the triangle they replace at the wall (their geometrical tag may be set
//! apart); the result passes [`crate::check_mesh`] or [`insert`] fails.

mod band;
pub mod growth;
mod skin;
pub mod stats;
pub mod to_metric;

use std::collections::BTreeMap;

use smartmesh_formats::{CellKind, DataArray, TaggedMesh};

pub use growth::{first_height_for_y_plus, Growth, GrowthError};

use crate::topology::{cell_tag, EntityRef, Topology};

/// The point data in which [`insert`] records, at the points of each column, the share
/// of its nominal thickness the column took (1 where it was not thinned, 0 where it was
/// stopped), and 1 at every other point; `report` marks the thinned columns from it.
pub const THICKNESS_SHARE: &str = "layer_thickness_share";

/// Why a skin could not be inserted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LayerError {
    /// Bad input or options.
    #[error("{0}")]
    Bad(String),
    /// The layer heights.
    #[error(transparent)]
    Growth(#[from] GrowthError),
    /// No thinning made the skin fit.
    #[error("the skin does not fit near ({x}, {y}) even thinned; try fewer or thinner layers", x = at[0], y = at[1])]
    CannotFit {
        /// Where.
        at: [f64; 2],
    },
    /// The first height is below what the skin can tell from its wall edge: no thinning
    /// helps (it brings the fronts closer).
    #[error("the first height {height:e} is too small for the wall edge of length {edge:.3e} near ({x:.6}, {y:.6}): a skin's first layer must be at least 1e-5 of the wall's edges (here {bound:.3e}); give a larger first height, or refine the wall", x = at[0], y = at[1])]
    FirstHeightTooSmall {
        /// Where (the middle of the wall edge).
        at: [f64; 2],
        /// The first height asked for.
        height: f64,
        /// The wall edge's length.
        edge: f64,
        /// The smallest first height that edge allows.
        bound: f64,
    },
    /// The result failed its own check (a bug; the message lists what failed).
    #[error("the mesh with its skin is not valid: {0}")]
    Invalid(String),
}

impl LayerError {
    /// Whether the input or the options are at fault (exit 2) rather than the work.
    pub fn is_input_error(&self) -> bool {
        matches!(
            self,
            LayerError::Bad(_) | LayerError::Growth(_) | LayerError::FirstHeightTooSmall { .. }
        )
    }
}

/// One curve's layers.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveLayers {
    /// A curve tag or name.
    pub curve: EntityRef,
    /// Its growth.
    pub growth: Growth,
}

/// How to build the skin.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerOptions {
    /// The curves and their growth (every curve the same layer count).
    pub curves: Vec<CurveLayers>,
    /// Largest angle between two columns of a fan at a convex corner, degrees; convex
    /// corners turning more get a fan.
    pub fan_angle_deg: f64,
    /// Largest share of the gap in front of a wall the skin fills (snappyHexMesh's
    /// thickness-to-medial ratio is half of it).
    pub gap_ratio: f64,
    /// Write each quad as two triangles.
    pub split: bool,
    /// Geometrical tag of the skin's cells (their physical tag stays the face's).
    pub tag: Option<i32>,
}

impl Default for LayerOptions {
    fn default() -> Self {
        LayerOptions {
            curves: Vec::new(),
            fan_angle_deg: 30.0,
            gap_ratio: 0.4,
            split: false,
            tag: None,
        }
    }
}

/// A column thinned below its nominal thickness.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Thinned {
    /// The wall vertex (input numbering).
    pub vertex: usize,
    /// Where.
    pub at: [f64; 2],
    /// Share of the nominal thickness kept.
    pub factor: f64,
    /// Thickness built.
    pub thickness: f64,
    /// Thickness asked.
    pub nominal: f64,
    /// Why: `gap`, `front collision`, `side ends at a topological point`.
    pub reason: String,
}

/// What [`insert`] did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LayerReport {
    /// Wall vertices.
    pub wall_vertices: usize,
    /// Columns (a fan corner has several).
    pub columns: usize,
    /// Layers.
    pub layers: usize,
    /// Quads built (0 with `split`).
    pub quads: usize,
    /// Triangles of the skin (fan corners, and split quads).
    pub skin_triangles: usize,
    /// Input triangles removed.
    pub removed_triangles: usize,
    /// Triangles of the band triangulated again.
    pub band_triangles: usize,
    /// Columns thinned, where and by how much.
    pub thinned: Vec<Thinned>,
    /// Things the output does not carry over.
    pub notes: Vec<String>,
}

/// The mesh with its skin.
#[derive(Debug, Clone)]
pub struct Layered {
    /// The mesh.
    pub mesh: TaggedMesh,
    /// Whether each surface cell of `mesh` ([`TaggedMesh::cells`] order) is a triangle
    /// of the band, triangulated again between the skin's front and the kept mesh.
    pub band: Vec<bool>,
    /// What was done.
    pub report: LayerReport,
}

/// The topological curves `e` names ([`Topology::resolve_curves`]), or an error listing
/// the tagged ones.
pub fn resolve_curve(topo: &Topology, e: &EntityRef) -> Result<Vec<usize>, LayerError> {
    topo.resolve_curves(e).map_err(|e| LayerError::Bad(e.to_string()))
}

/// Inserts a skin into the triangle mesh `mesh`.
pub fn insert(mesh: &TaggedMesh, opts: &LayerOptions) -> Result<Layered, LayerError> {
    if mesh.num_cells_of(CellKind::Quad)
        + mesh.num_cells_of(CellKind::Quad8)
        + mesh.num_cells_of(CellKind::Quad9)
        > 0
    {
        return Err(LayerError::Bad(
            "the mesh already has quads; a skin is inserted into a triangle mesh".into(),
        ));
    }
    if mesh.blocks.iter().any(|b| b.kind.is_second_order()) {
        return Err(LayerError::Bad(
            "the mesh has second-order cells; a skin needs a first-order triangle mesh".into(),
        ));
    }
    if !(opts.fan_angle_deg > 1.0 && opts.fan_angle_deg <= 180.0) {
        return Err(LayerError::Bad(format!(
            "fan angle {}: expected 1 to 180 degrees",
            opts.fan_angle_deg
        )));
    }
    if !(opts.gap_ratio > 0.0 && opts.gap_ratio < 1.0) {
        return Err(LayerError::Bad(format!(
            "gap ratio {}: expected between 0 and 1",
            opts.gap_ratio
        )));
    }
    if let Some(p) = mesh.validate().first() {
        return Err(LayerError::Bad(format!("the mesh is not consistent: {p}")));
    }
    let topo = Topology::from_mesh(mesh);
    let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let mut cell_tags = Vec::new();
    let mut line_tags: BTreeMap<[usize; 2], (i32, i32)> = BTreeMap::new();
    let mut listed = vec![false; pts.len()];
    for (kind, nodes, p, g) in mesh.cells() {
        match kind.dim() {
            2 => cell_tags.push((p, g)),
            1 => {
                let (a, b) = (nodes[0] as usize, nodes[1] as usize);
                line_tags.entry([a.min(b), a.max(b)]).or_insert((p, g));
            }
            _ => listed[nodes[0] as usize] = true,
        }
    }
    let mut growth: BTreeMap<usize, Growth> = BTreeMap::new();
    for cl in &opts.curves {
        for c in resolve_curve(&topo, &cl.curve)? {
            growth.insert(c, cl.growth);
        }
    }
    if growth.is_empty() {
        return Err(LayerError::Bad("no curve selected".into()));
    }
    let inp = skin::SkinInput {
        pts: &pts,
        topo: &topo,
        cell_tags: &cell_tags,
        line_tags: &line_tags,
        growth: &growth,
        fan_step: opts.fan_angle_deg.to_radians(),
        gap_ratio: opts.gap_ratio,
    };
    let sk = skin::Skin::build(&inp)?;
    let band = band::build(&sk, &topo, &cell_tags, &line_tags, &listed)?;
    let (out, in_band, mut report) = assemble(mesh, &sk, &band, opts);
    let v = crate::validity::check_mesh(&out);
    if !v.is_valid() {
        return Err(LayerError::Invalid(v.problems().join("; ")));
    }
    report.thinned = sk.thinned();
    Ok(Layered { mesh: out, band: in_band, report })
}

/// Writes the output mesh: kept cells, the skin, the band; points renumbered.
fn assemble(
    mesh: &TaggedMesh,
    sk: &skin::Skin,
    band: &band::Band,
    opts: &LayerOptions,
) -> (TaggedMesh, Vec<bool>, LayerReport) {
    let n = sk.layers;
    let np = sk.pts.len();
    // Surface cells, tagged (nodes in the skin's numbering).
    let mut tris: Vec<([usize; 3], (i32, i32))> = Vec::new();
    let mut quads: Vec<([usize; 4], (i32, i32))> = Vec::new();
    let mut si = 0;
    let mut lines: Vec<([usize; 2], (i32, i32))> = Vec::new();
    let mut vertices: Vec<(usize, (i32, i32))> = Vec::new();
    for (kind, nodes, p, g) in mesh.cells() {
        let nd: Vec<usize> = nodes.iter().map(|&v| v as usize).collect();
        match kind.dim() {
            2 => {
                if !band.removed[si] {
                    tris.push(([nd[0], nd[1], nd[2]], (p, g)));
                }
                si += 1;
            }
            1 => {
                let k = [nd[0].min(nd[1]), nd[0].max(nd[1])];
                if !band.side_edges.contains(&k)
                    && !band.side_removed.contains(&nd[0])
                    && !band.side_removed.contains(&nd[1])
                {
                    lines.push(([nd[0], nd[1]], (p, g)));
                }
            }
            _ => vertices.push((nd[0], (p, g))),
        }
    }
    lines.extend(band.lines.iter().copied());
    let removed_triangles = band.removed.iter().filter(|&&r| r).count();
    let band_triangles = band.triangles.len();
    let band_from = tris.len();
    tris.extend(band.triangles.iter().copied());
    let mut skin_triangles = 0;
    let mut nquads = 0;
    for (g, gap) in sk.gaps.iter().enumerate() {
        let tags = (gap.tags.0, opts.tag.unwrap_or(gap.tags.1));
        for k in 0..n {
            let c = sk.cell(g, k);
            if c.len() == 3 {
                tris.push(([c[0], c[1], c[2]], tags));
                skin_triangles += 1;
            } else {
                quads.push(([c[0], c[1], c[2], c[3]], tags));
                nquads += 1;
            }
        }
    }
    // Points: every input point still used, or used by nothing in the input either
    // (kept as they were), then the skin's.
    let mut used_before = vec![false; mesh.points.len()];
    for (_, nodes, _, _) in mesh.cells() {
        for &v in nodes {
            used_before[v as usize] = true;
        }
    }
    let mut used = vec![false; np];
    for (c, _) in &tris {
        c.iter().for_each(|&v| used[v] = true);
    }
    for (c, _) in &quads {
        c.iter().for_each(|&v| used[v] = true);
    }
    for (c, _) in &lines {
        c.iter().for_each(|&v| used[v] = true);
    }
    for (v, _) in &vertices {
        used[*v] = true;
    }
    let mut map = vec![usize::MAX; np];
    let mut out = TaggedMesh::new();
    out.coordinate_dim = mesh.coordinate_dim;
    let mut source: Vec<usize> = Vec::new(); // input point each output point copies data from
    for v in 0..np {
        let keep = if v < mesh.points.len() { used[v] || !used_before[v] } else { used[v] };
        if keep {
            map[v] = out.points.len();
            if v < mesh.points.len() {
                out.points.push(mesh.points[v]);
                source.push(v);
            } else {
                out.points.push([sk.pts[v][0], sk.pts[v][1], 0.0]);
                source.push(usize::MAX);
            }
        }
    }
    // New points take the data of their column's wall vertex.
    for col in &sk.columns {
        for &id in &col.ids[1..] {
            if map[id] != usize::MAX {
                source[map[id]] = col.base;
            }
        }
    }
    let mut notes = Vec::new();
    for (name, a) in &mesh.point_data {
        let c = a.components;
        let mut vals = Vec::with_capacity(out.points.len() * c);
        for &s in &source {
            vals.extend_from_slice(a.item(s));
        }
        out.point_data
            .insert(name.clone(), DataArray { components: c, values: vals, layout: a.layout });
    }
    if !mesh.point_data.is_empty() {
        notes.push("point data on the skin's new points copied from their wall vertex".to_string());
    }
    // The share of its nominal thickness each column took, at its points (a wall vertex
    // with a fan takes its thinnest column's), 1 elsewhere.
    let mut share = vec![1.0f64; out.points.len()];
    for col in &sk.columns {
        for &id in &col.ids {
            if map[id] != usize::MAX {
                share[map[id]] = share[map[id]].min(col.factor);
            }
        }
    }
    out.point_data.insert(
        THICKNESS_SHARE.to_string(),
        DataArray { components: 1, values: share, layout: Default::default() },
    );
    if !mesh.cell_data.is_empty() {
        let names: Vec<&str> = mesh.cell_data.keys().map(String::as_str).collect();
        notes.push(format!("cell data dropped: {}", names.join(", ")));
    }
    if !mesh.cell_sets.is_empty() {
        notes.push("cell sets dropped".to_string());
    }
    for (name, set) in &mesh.point_sets {
        let kept: Vec<usize> =
            set.iter().filter_map(|&v| (map[v] != usize::MAX).then_some(map[v])).collect();
        out.point_sets.insert(name.clone(), kept);
    }
    let b = out.block_mut(CellKind::Vertex);
    for (v, (p, g)) in &vertices {
        b.push(&[map[*v]], *p, *g);
    }
    let b = out.block_mut(CellKind::Line);
    for (c, (p, g)) in &lines {
        b.push(&[map[c[0]], map[c[1]]], *p, *g);
    }
    let b = out.block_mut(CellKind::Triangle);
    for (c, (p, g)) in &tris {
        b.push(&c.map(|v| map[v]), *p, *g);
    }
    if !quads.is_empty() {
        let b = out.block_mut(CellKind::Quad);
        for (c, (p, g)) in &quads {
            b.push(&c.map(|v| map[v]), *p, *g);
        }
    }
    out.blocks.retain(|b| !b.is_empty());
    out.tag_names = mesh.tag_names.clone();
    out.entities = mesh.entities.clone();
    if let Some(t) = opts.tag {
        let phys: std::collections::BTreeSet<i32> =
            sk.gaps.iter().map(|g| g.tags.0).filter(|&p| p != 0).collect();
        if !mesh.entities.is_empty() {
            out.entities.insert((2, t), phys.into_iter().collect());
        }
    }
    out.holes = mesh.holes.clone();
    out.regions = mesh.regions.clone();
    if opts.split {
        let n = out.split_quads();
        skin_triangles += 2 * n;
        nquads = 0;
    }
    // Triangles (kept, band, skin) then the quads, or the triangles of the split quads.
    // The triangle block (kept, band, skin triangles) comes first, then the quads (or
    // the triangles of the split quads).
    let surface = out.blocks.iter().filter(|b| b.kind.dim() == 2).map(|b| b.len()).sum();
    let mut in_band = vec![false; surface];
    in_band[band_from..band_from + band_triangles].iter_mut().for_each(|b| *b = true);
    let report = LayerReport {
        wall_vertices: sk.wall.iter().filter(|&&w| w).count(),
        columns: sk.columns.len(),
        layers: n,
        quads: nquads,
        skin_triangles,
        removed_triangles,
        band_triangles,
        thinned: Vec::new(),
        notes,
    };
    let _ = cell_tag;
    (out, in_band, report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesher::{triangulate, MeshOptions};
    use crate::validity;

    /// A triangle mesh of the polygon `pts` with segment tags `tags`.
    fn mesh_of(pts: &[[f64; 2]], tags: &[i32], size: f64) -> TaggedMesh {
        let mut m = TaggedMesh::new();
        m.points = pts.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let b = m.block_mut(CellKind::Line);
        for (i, &t) in tags.iter().enumerate() {
            b.push(&[i as u32, ((i + 1) % pts.len()) as u32], t, t);
        }
        triangulate(&m, &MeshOptions { size: Some(size), ..Default::default() }).unwrap()
    }

    fn opts(curves: &[&str], g: Growth) -> LayerOptions {
        LayerOptions {
            curves: curves.iter().map(|&c| CurveLayers { curve: c.into(), growth: g }).collect(),
            ..Default::default()
        }
    }

    /// Skins whose fitting finds bad strips (fronts colliding in a slot, fans at convex
    /// corners, a slanted wall whose sides slide): every call of the crossing test is
    /// checked against its all-pairs twin (under test, `bad_gaps` asserts they agree),
    /// and the result against the all-pairs check of the mixed mesh.
    #[test]
    fn the_crossing_test_and_the_check_agree_with_their_all_pairs_twins() {
        let slot =
            mesh_of(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.05], [0.0, 0.05]], &[1, 2, 3, 4], 0.03);
        let g = Growth::solve(Some(0.002), None, Some(5), Some(0.06)).unwrap();
        let square = mesh_of(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], &[1, 1, 1, 1], 0.1);
        let h = Growth::solve(Some(0.01), Some(1.2), Some(6), None).unwrap();
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let rot = |x: f64, y: f64| [c * x - s * y, s * x + c * y];
        let slanted = mesh_of(
            &[rot(0.0, 0.0), rot(1.0, 0.0), rot(1.0, 0.3), rot(0.0, 0.3)],
            &[1, 2, 3, 4],
            0.05,
        );
        let k = Growth::solve(Some(1e-4), Some(1.0), Some(40), None).unwrap();
        for (m, o) in
            [(&slot, opts(&["1", "3"], g)), (&square, opts(&["1"], h)), (&slanted, opts(&["1"], k))]
        {
            let out = insert(m, &o).unwrap();
            let pts: Vec<[f64; 2]> = out.mesh.points.iter().map(|p| [p[0], p[1]]).collect();
            let cells = validity::surface_cells(&out.mesh);
            assert_eq!(
                validity::check_cells(&pts, &cells),
                validity::check_cells_brute(&pts, &cells)
            );
        }
    }
}
