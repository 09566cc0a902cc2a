//! Writing a mesh and its solution file (see the module documentation of `medit`).

use super::*;

/// What the writers serialise: the mesh with its choices made.
pub(super) struct Out<'m> {
    pub(super) dim: u8,
    pub(super) points: &'m [[f64; 3]],
    pub(super) refs: Option<Vec<i32>>,
    /// Element keyword and the blocks written under it.
    pub(super) elements: Vec<(usize, Vec<&'m CellBlock>)>,
    /// Set keyword and its 1-based numbers.
    pub(super) sets: Vec<(usize, Vec<usize>)>,
}

impl Out<'_> {
    pub(super) fn count(&self, code: usize) -> usize {
        self.elements
            .iter()
            .filter(|(c, _)| *c == code)
            .flat_map(|(_, b)| b.iter())
            .map(|b| b.len())
            .sum()
    }
}

fn integral_i32(v: f64) -> Option<i32> {
    (v.fract() == 0.0 && v >= i32::MIN as f64 && v <= i32::MAX as f64).then_some(v as i32)
}

/// How to write Medit files (the `medit` group of [`WriteOptions`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MeditWrite {
    /// `.meshb`/`.solb` rather than ASCII when the main file name does not tell.
    pub binary: bool,
}

/// Writes a mesh as Medit, with its solution file beside it (see the module documentation).
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    write_into(mesh, opts, Vec::new())
}

/// [`write`], a `.meshb` built in `spare`'s memory (cleared first; reused memory is not
/// faulted in again).
pub(crate) fn write_into(
    mesh: &TaggedMesh,
    opts: &WriteOptions,
    spare: Vec<u8>,
) -> Result<Written> {
    let binary = match opts
        .main_name
        .as_deref()
        .and_then(|n| Path::new(n).extension())
        .and_then(|e| e.to_str())
    {
        Some(e) if e.eq_ignore_ascii_case("meshb") => true,
        Some(e) if e.eq_ignore_ascii_case("mesh") => false,
        _ => opts.medit.binary,
    };
    let mut report = WriteReport::default();
    // One pass over the points for the dimension and for what `validate` checks of
    // them; the node numbers are checked where the elements are written.
    let (has_z, finite) = mesh.points.iter().fold((false, true), |(z, f), p| {
        (z | (p[2] != 0.0), f & p[0].is_finite() & p[1].is_finite() & p[2].is_finite())
    });
    if !finite || !mesh.lengths_agree() {
        return Err(refused(Format::Medit, mesh));
    }
    let dim =
        if has_z || mesh.blocks.iter().any(|b| b.kind.dim() == 3 && !b.is_empty()) { 3 } else { 2 };

    let refs = match mesh.point_data.get(REF) {
        Some(a) if a.components == 1 => {
            let r: Option<Vec<i32>> = a.values.iter().map(|&v| integral_i32(v)).collect();
            if r.is_none() {
                report.drop(format!("point data `{REF}`: not integers, so not vertex references"));
            }
            r
        }
        Some(a) => {
            report.drop(format!(
                "point data `{REF}` ({}): a vertex has one reference",
                crate::words::components(a.components)
            ));
            None
        }
        None => None,
    };

    // Elements, and the global index → element number maps the sets need.
    let mut elements = Vec::new();
    let mut number: BTreeMap<CellKind, Vec<(usize, usize)>> = BTreeMap::new(); // kind → [(first global, len)]
    let mut offset = 0;
    let mut geo_differs = 0;
    let mut topological: Vec<usize> = Vec::new();
    let mut point_tags = 0;
    for b in &mesh.blocks {
        if let Some(&(code, _)) = ELEMENTS.iter().find(|(_, k)| *k == b.kind) {
            match elements.iter_mut().find(|(c, _): &&mut (usize, Vec<&CellBlock>)| *c == code) {
                Some((_, list)) => list.push(b),
                None => elements.push((code, vec![b])),
            }
            number.entry(b.kind).or_default().push((offset, b.len()));
            geo_differs += b.tags_differ();
        } else if b.kind == CellKind::Vertex {
            // Topological points: MMG keeps them where they are as corners and required
            // vertices (what the mmg2d adapter writes too).
            topological.extend(b.nodes.iter().map(|&v| v as usize));
            point_tags += b.physical.iter().filter(|&&t| t != 0).count();
        } else if !b.is_empty() {
            report.drop(format!(
                "{} {} cells: Medit has no serendipity elements (8-node quadrilaterals, 20-node hexahedra, 15-node prisms, 13-node pyramids)",
                b.len(),
                b.kind.name()
            ));
        }
        offset += b.len();
    }
    // File order as MMG writes it: edges, triangles, quadrilaterals, then volumes.
    elements.sort_by_key(|(code, _)| ELEMENTS.iter().position(|(c, _)| c == code));
    if geo_differs > 0 {
        report.drop(format!(
            "geometrical tags of {geo_differs} cells differ from the physical ones: Medit keeps one reference (the physical tag)"
        ));
    }

    if !topological.is_empty() {
        report.drop(format!(
            "{} point cells: written as Corners and RequiredVertices entries, which are not cells (the file has {0} cells fewer)",
            topological.len()
        ));
    }
    if point_tags > 0 {
        report.drop(format!(
            "the tags of {point_tags} point cells: written as Corners and RequiredVertices, which have no references"
        ));
    }

    // Sets; the Vertex cells' points join Corners and RequiredVertices.
    let mut sets = Vec::new();
    let mut point_sets: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    if !topological.is_empty() {
        for name in ["Corners", "RequiredVertices"] {
            point_sets.insert(name, topological.clone());
        }
    }
    for (name, items) in &mesh.point_sets {
        point_sets.entry(name.as_str()).or_default().extend(items);
    }
    for (name, mut items) in point_sets {
        match lookup(name.as_bytes()).filter(|&c| set_target(c) == Some(None)) {
            Some(code) => {
                if !topological.is_empty() {
                    items.sort_unstable();
                    items.dedup();
                }
                sets.push((code, items.iter().map(|&v| v + 1).collect()))
            }
            None => report
                .drop(format!("point set `{name}`: Medit keeps only Corners and RequiredVertices")),
        }
    }
    for (name, items) in &mesh.cell_sets {
        let Some((code, kind)) =
            lookup(name.as_bytes()).and_then(|c| set_target(c).flatten().map(|k| (c, k)))
        else {
            report.drop(format!("cell set `{name}`: Medit keeps only Ridges, RequiredEdges, RequiredTriangles and RequiredQuadrilaterals"));
            continue;
        };
        // Global cell index → number among the elements of `kind`, in writing order.
        let ranges = number.get(&kind).map(Vec::as_slice).unwrap_or(&[]);
        let mut numbers = Vec::with_capacity(items.len());
        let mut lost = 0;
        for &g in items {
            let mut before = 0;
            let mut found = None;
            for &(first, len) in ranges {
                if g >= first && g < first + len {
                    found = Some(before + g - first + 1);
                    break;
                }
                before += len;
            }
            match found {
                Some(n) => numbers.push(n),
                None => lost += 1,
            }
        }
        if lost > 0 {
            report.drop(format!(
                "{lost} entries of cell set `{name}`: they are not {} cells",
                kind.name()
            ));
        }
        sets.push((code, numbers));
    }
    sets.sort_by_key(|(code, _)| SETS.iter().position(|(c, _)| c == code));

    if !mesh.tag_names.is_empty() {
        report.drop(format!("{} tag names: Medit references have no names", mesh.tag_names.len()));
    }
    if !mesh.entities.is_empty() {
        report.drop(format!("{} Gmsh entities: Medit has none", mesh.entities.len()));
    }
    if !mesh.holes.is_empty() || !mesh.regions.is_empty() {
        report.drop(format!(
            "{} holes and {} regions: Medit meshes have no PSLG seeds",
            mesh.holes.len(),
            mesh.regions.len()
        ));
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({}): the Medit writer keeps point data only (SolAtVertices)",
            crate::words::components(a.components)
        ));
    }

    // The solution MMG reads: the metric, else the size.
    let metric = mesh.point_data.get("metric").filter(|a| a.is_tensor());
    let size = mesh.point_data.get("size").filter(|a| a.components == 1);
    let chosen = match (metric, size) {
        (Some(m), _) => Some(("metric", m)),
        (None, Some(s)) => Some(("size", s)),
        _ => None,
    };
    for (name, a) in &mesh.point_data {
        if name == REF || chosen.is_some_and(|(c, _)| c == name) {
            continue;
        }
        let why = if name == "metric" {
            "a metric needs 9 components".to_string()
        } else if chosen.is_some() {
            format!("MMG reads one solution, `{}` was written", chosen.map_or("", |c| c.0))
        } else {
            "only `metric` (tensor) or `size` (scalar) go to the solution file".into()
        };
        report.drop(format!(
            "point data `{name}` ({}): {why}",
            crate::words::components(a.expanded_components())
        ));
    }

    let out = Out { dim, points: &mesh.points, refs, elements, sets };
    // Node numbers: checked in the pass that writes the binary elements; in a pass of
    // their own for ASCII and for the blocks Medit does not hold.
    let bound = |b: &CellBlock| b.nodes.iter().fold(0, |m, &v| m.max(v as usize + 1));
    let (main, written_bound) =
        if binary { binary::write_mesh(&out, spare) } else { (ascii::write_mesh(&out), 0) };
    let held = |b: &CellBlock| ELEMENTS.iter().any(|(_, k)| *k == b.kind);
    let rest_bound =
        mesh.blocks.iter().filter(|b| !binary || !held(b)).map(bound).max().unwrap_or(0);
    if written_bound.max(rest_bound) > mesh.points.len() {
        return Err(refused(Format::Medit, mesh));
    }
    let mut written = Written { main, siblings: Vec::new(), report };
    if let Some((name, a)) = chosen {
        let sol = write_sol(&[(name, a)], dim, binary)?;
        written.siblings.push((if binary { "solb" } else { "sol" }.to_string(), sol));
    }
    Ok(written)
}

/// Writes a solution file (`.solb` when `binary`, else `.sol`) with one `SolAtVertices`
/// holding every array in order: 1 component → scalar (type 1), 2 or 3 → vector (type 2),
/// 9 or packed symmetric 2D → symmetric tensor (type 3, m11 m12 m22 in 2D, m11 m12 m22
/// m13 m23 m33 in 3D; off-diagonal terms of 9-component ones averaged).
/// `dim` is 2 or 3; every array must cover the same number of vertices.
pub fn write_sol(arrays: &[(&str, &DataArray)], dim: u8, binary: bool) -> Result<Vec<u8>> {
    let cannot =
        |reason: String| Error::new(ErrorKind::CannotWrite { format: "Medit solution", reason });
    if dim != 2 && dim != 3 {
        return Err(cannot(format!("dimension {dim}: Medit solutions are 2D or 3D")));
    }
    let Some(&(_, first)) = arrays.first() else {
        return Err(cannot("no array to write".into()));
    };
    let n = first.len();
    let mut types = Vec::with_capacity(arrays.len());
    for &(name, a) in arrays {
        if a.len() != n {
            return Err(cannot(format!(
                "array `{name}` covers {} vertices, `{}` {n}",
                a.len(),
                arrays[0].0
            )));
        }
        types.push(match a.components {
            _ if a.is_tensor() => 3,
            1 => 1u32,
            2 | 3 => 2,
            c => {
                return Err(cannot(format!("array `{name}` has {c} components; a solution is a scalar, a vector or a 9-component tensor")))
            }
        });
    }
    let stride: usize = types.iter().map(|&t| sol_size(t, dim).unwrap_or(0)).sum();
    let sol = SolOut { dim, n, types: &types, stride, arrays };
    Ok(if binary { binary::write_sol(&sol) } else { ascii::write_sol(&sol) })
}

/// A `SolAtVertices` to serialise: `n` vertices of `stride` reals, taken from `arrays`
/// one vertex row at a time (no intermediate copy of the whole solution).
pub(super) struct SolOut<'a> {
    pub(super) dim: u8,
    pub(super) n: usize,
    pub(super) types: &'a [u32],
    pub(super) stride: usize,
    pub(super) arrays: &'a [(&'a str, &'a DataArray)],
}

/// A solution file's single array, in a layout with a fixed-size record.
pub(super) enum Single<'a> {
    /// A scalar.
    Scalar(&'a DataArray),
    /// A 2D symmetric tensor kept packed (`m11 m12 m22`).
    Packed(&'a DataArray),
    /// A 2D metric as a full 9-component tensor (its symmetric part is written).
    Tensor2(&'a DataArray),
}

impl<'a> SolOut<'a> {
    /// The one array of a 2D solution file, when its record has a fixed layout
    /// ([`SolOut::row`] writes the same reals).
    pub(super) fn single(&self) -> Option<Single<'a>> {
        match self.arrays {
            [(_, a)] if self.dim == 2 => match (a.layout, a.components) {
                (Layout::Symmetric2, _) => Some(Single::Packed(a)),
                (_, 1) => Some(Single::Scalar(a)),
                (_, 9) => Some(Single::Tensor2(a)),
                _ => None,
            },
            _ => None,
        }
    }

    /// The file's reals for vertex `v`, in `row` (cleared first).
    #[inline]
    pub(super) fn row(&self, v: usize, row: &mut Vec<f64>) {
        row.clear();
        let d = self.dim as usize;
        for &(_, a) in self.arrays {
            let s = a.item(v);
            if a.layout == Layout::Symmetric2 {
                row.extend_from_slice(s);
                if d == 3 {
                    row.extend_from_slice(&[0.0, 0.0, 1.0]);
                }
                continue;
            }
            match (a.components, d) {
                (1, _) => row.push(s[0]),
                (2, 2) | (3, 2) => row.extend_from_slice(&s[..2]),
                (2, _) => row.extend_from_slice(&[s[0], s[1], 0.0]),
                (3, _) => row.extend_from_slice(s),
                (_, 2) => {
                    let (m11, m12, m22) = tensor9_to_sym2(s);
                    row.extend_from_slice(&[m11, m12, m22]);
                }
                (_, _) => row.extend_from_slice(&[
                    s[0],
                    0.5 * (s[1] + s[3]),
                    s[4],
                    0.5 * (s[2] + s[6]),
                    0.5 * (s[5] + s[7]),
                    s[8],
                ]),
            }
        }
    }
}
