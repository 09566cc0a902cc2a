//! glTF 2.0 writer: a mesh for viewers (web, Blender, three.js), coloured by a field.
//!
//! Source: Khronos, *glTF 2.0 Specification* (registry.khronos.org/glTF/specs/2.0):
//! §3.6 buffers and buffer views (4-byte alignment, exact `byteLength`, data URIs),
//! §3.7 accessors (POSITION needs `min`/`max`; indices must not use the largest
//! value of their type), §3.7.2.1 mesh attributes (POSITION FLOAT VEC3, COLOR_0 FLOAT
//! VEC3 in linear colour space), §4 GLB (12-byte header, JSON chunk padded with
//! spaces, BIN chunk padded with zeros); `KHR_materials_unlit` for the material. The
//! JSON is built with `gltf-json`, the GLB container with `gltf::binary::Glb`.
//!
//! What is written: one scene, one node, one mesh with
//! - a TRIANGLES primitive of every triangle and quad (a quad `a b c d` as `a b c` and
//!   `a c d`, reported), when there are any;
//! - a LINES primitive of every Line cell, when there are any;
//! - POSITION (coordinates rounded to `f32`, reported when that changes one) with its
//!   exact `min`/`max`, indices as UNSIGNED_INT;
//! - COLOR_0 from a point field: `WriteOptions::color_field`, else the first scalar
//!   point field (in name order), else none. Scalars are used as they are, 2- or
//!   3-component vectors by their magnitude, 9-component tensors by the finest size
//!   `h = 1/sqrt(λmax)` of their 2D part (a metric's smallest edge length), mapped
//!   through viridis between the field's finite min and max (sRGB stops, stored
//!   linear as COLOR_0 must be); values that are not finite (or a tensor that is not
//!   positive) are drawn grey. The field, the quantity and its min/max are in the
//!   mesh's `extras`. A coloured mesh uses an unlit material so that viewers show the
//!   colour map as it is; otherwise a grey, non-metallic, double-sided PBR material.
//!
//! Output: `.glb` when [`GltfWrite::glb`] is set or `main_name` ends in `.glb`;
//! otherwise `.gltf` JSON with a `bin` sibling named after `main_name` (its stem +
//! `.bin`, percent-encoded in the URI), or, with no `main_name` (stdout), the buffer
//! embedded as a base64 data URI so that one file suffices.
//!
//! Not written (and reported): tags and tag names, other point data, cell data, Vertex
//! cells, sets, holes, regions, entities; second-order cells are drawn by their
//! corners. A mesh with volume cells is drawn by its boundary (the faces of one volume
//! cell only, outward, see `skin`), as ParaView's *Extract Surface* draws it;
//! the report says so. glTF is not read: smartmesh writes it for viewers only.

use std::collections::BTreeMap;

use base64::Engine as _;
use gltf_json as json;
use json::validation::{Checked, USize64};

use crate::{
    mesh::DataArray, tensor9_to_sym2, CellKind, Error, ErrorKind, Result, TaggedMesh, WriteOptions,
    WriteReport, Written,
};

/// Viridis (matplotlib's default colour map, perceptually uniform), sampled at
/// 0, 1/8, ..., 1 from matplotlib's table; sRGB in [0, 1].
const VIRIDIS: [[f64; 3]; 9] = [
    [0.267004, 0.004874, 0.329415],
    [0.278826, 0.175490, 0.483397],
    [0.229739, 0.322361, 0.545706],
    [0.172719, 0.448791, 0.557885],
    [0.127568, 0.566949, 0.550556],
    [0.157851, 0.683765, 0.501686],
    [0.369214, 0.788888, 0.382914],
    [0.678489, 0.863742, 0.189503],
    [0.993248, 0.906157, 0.143936],
];

/// Linear-light grey for values that cannot be coloured.
const NO_VALUE: [f32; 3] = [0.2, 0.2, 0.2];

/// sRGB transfer function inverse (IEC 61966-2-1): COLOR_0 is linear.
fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Viridis at `t` in [0, 1], interpolated in sRGB between the stops, returned linear.
pub(crate) fn viridis_linear(t: f64) -> [f32; 3] {
    let x = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mut out = [0.0f32; 3];
    for k in 0..3 {
        out[k] = srgb_to_linear(a[k] + (b[k] - a[k]) * f) as f32;
    }
    out
}

/// What a colour field contributes per vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Quantity {
    Value,
    Magnitude,
    FinestSize,
}

impl Quantity {
    fn describe(self) -> &'static str {
        match self {
            Quantity::Value => "value",
            Quantity::Magnitude => "magnitude",
            Quantity::FinestSize => "finest size h = 1/sqrt(largest eigenvalue of the 2D part)",
        }
    }
}

/// The finest size of a 2D metric: `1/sqrt(λmax)`, NaN when the tensor is not positive.
fn finest_size(t: &[f64]) -> f64 {
    let (a, b, c) = tensor9_to_sym2(t);
    let half_trace = 0.5 * (a + c);
    let radius = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let lmax = half_trace + radius;
    if lmax > 0.0 && lmax.is_finite() {
        1.0 / lmax.sqrt()
    } else {
        f64::NAN
    }
}

/// The field that colours the vertices, `None` when there is none to use.
fn colour_field<'a>(
    mesh: &'a TaggedMesh,
    opts: &WriteOptions,
) -> Result<Option<(&'a str, &'a DataArray, Quantity)>> {
    let quantity = |a: &DataArray| match a.components {
        _ if a.is_tensor() => Some(Quantity::FinestSize),
        1 => Some(Quantity::Value),
        2 | 3 => Some(Quantity::Magnitude),
        _ => None,
    };
    match &opts.gltf.color_field {
        Some(name) => {
            let cannot =
                |reason: String| Error::new(ErrorKind::CannotWrite { format: "glTF", reason });
            let Some((key, a)) = mesh.point_data.get_key_value(name.as_str()) else {
                let known: Vec<&str> = mesh.point_data.keys().map(String::as_str).collect();
                let also = if mesh.cell_data.contains_key(name) {
                    " (it is cell data; glTF colours vertices)"
                } else {
                    ""
                };
                return Err(cannot(format!(
                    "no point field `{name}` to colour by{also}; point fields: {}",
                    if known.is_empty() { "none".to_string() } else { known.join(", ") }
                )));
            };
            match quantity(a) {
                Some(q) => Ok(Some((key.as_str(), a, q))),
                None => Err(cannot(format!(
                    "point field `{name}` has {} components; colours come from a scalar, a 2- or 3-vector or a 9-component tensor",
                    a.components
                ))),
            }
        }
        None => Ok(mesh
            .point_data
            .iter()
            .find(|(_, a)| a.components == 1)
            .map(|(k, a)| (k.as_str(), a, Quantity::Value))),
    }
}

/// Appends an accessor on a new buffer view over `bytes` (already in `buffer`).
#[allow(clippy::too_many_arguments)]
fn accessor(
    root: &mut json::Root,
    range: std::ops::Range<usize>,
    target: json::buffer::Target,
    count: usize,
    component: json::accessor::ComponentType,
    ty: json::accessor::Type,
    minmax: Option<(serde_json::Value, serde_json::Value)>,
    name: &str,
) -> json::Index<json::Accessor> {
    let view = root.push(json::buffer::View {
        buffer: json::Index::new(0),
        byte_length: USize64::from(range.len()),
        byte_offset: Some(USize64::from(range.start)),
        byte_stride: None,
        name: None,
        target: Some(Checked::Valid(target)),
        extensions: None,
        extras: Default::default(),
    });
    let (min, max) = match minmax {
        Some((a, b)) => (Some(a), Some(b)),
        None => (None, None),
    };
    root.push(json::Accessor {
        buffer_view: Some(view),
        byte_offset: None,
        count: USize64::from(count),
        component_type: Checked::Valid(json::accessor::GenericComponentType(component)),
        extensions: None,
        extras: Default::default(),
        type_: Checked::Valid(ty),
        min,
        max,
        name: Some(name.to_string()),
        normalized: false,
        sparse: None,
    })
}

/// Percent-encodes a file name for a relative URI (RFC 3986: unreserved kept).
fn uri_encode(name: &str) -> String {
    let mut s = String::with_capacity(name.len());
    for b in name.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'.' | b'_' | b'~') {
            s.push(b as char);
        } else {
            s.push_str(&format!("%{b:02X}"));
        }
    }
    s
}

fn cannot(reason: impl Into<String>) -> Error {
    Error::new(ErrorKind::CannotWrite { format: "glTF", reason: reason.into() })
}

/// glTF is written only; its writer leaves validation to `write_bytes`.
pub(crate) const CHECKS: crate::Checks = crate::Checks::NONE;

/// How to write glTF (the `gltf` group of [`WriteOptions`]).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct GltfWrite {
    /// The point field whose values colour the vertices (the first scalar if unset).
    pub color_field: Option<String>,
    /// One `.glb` rather than `.gltf` + `.bin` (also chosen by a main name in `.glb`).
    pub glb: bool,
}

/// Writes a mesh.
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let mut report = WriteReport::default();
    // A volume mesh is drawn by its boundary faces, as ParaView's Extract Surface does.
    let skinned = crate::skin::skin(mesh, "glTF", &mut report);
    let mesh: &TaggedMesh = &skinned;
    let n = mesh.points.len();
    // u32::MAX is the primitive-restart value that indices must not contain (§3.7.2.1).
    if n >= u32::MAX as usize {
        return Err(cannot(format!("{n} points: glTF UNSIGNED_INT indices reach 4294967294")));
    }

    let (tris, lines) = indices(mesh, &mut report)?;
    report_unheld(mesh, &mut report);

    // Positions, rounded to f32, with their exact bounds.
    let mut buffer: Vec<u8> = Vec::with_capacity(n * 24 + 4 * (tris.len() + lines.len()));
    let (lo, hi) = push_positions(mesh, &mut buffer, &mut report)?;
    let pos_range = 0..buffer.len();

    let (colour_range, extras) = push_colours(mesh, opts, &mut buffer, &mut report)?;

    let tri_range = buffer.len()..buffer.len() + 4 * tris.len();
    for v in &tris {
        buffer.extend_from_slice(&v.to_le_bytes());
    }
    let line_range = buffer.len()..buffer.len() + 4 * lines.len();
    for v in &lines {
        buffer.extend_from_slice(&v.to_le_bytes());
    }
    debug_assert_eq!(buffer.len() % 4, 0);

    // The JSON document.
    use json::accessor::{ComponentType, Type};
    use json::buffer::Target;
    let glb = opts.gltf.glb
        || opts.main_name.as_deref().is_some_and(|m| m.to_ascii_lowercase().ends_with(".glb"));
    let mut root = json::Root {
        asset: json::Asset {
            copyright: None,
            extensions: None,
            extras: Default::default(),
            generator: Some(format!("smartmesh-formats {}", env!("CARGO_PKG_VERSION"))),
            min_version: None,
            version: "2.0".into(),
        },
        ..Default::default()
    };
    let uri = if glb {
        None
    } else {
        match &opts.main_name {
            Some(main) => {
                let stem = std::path::Path::new(main)
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("mesh");
                Some(uri_encode(&format!("{stem}.bin")))
            }
            None => Some(format!(
                "data:application/octet-stream;base64,{}",
                base64::engine::general_purpose::STANDARD.encode(&buffer)
            )),
        }
    };
    root.push(json::Buffer {
        byte_length: USize64::from(buffer.len()),
        name: None,
        uri,
        extensions: None,
        extras: Default::default(),
    });
    let bounds = |a: [f32; 3]| {
        serde_json::Value::from(a.iter().map(|&x| f64::from(x)).collect::<Vec<f64>>())
    };
    let position = accessor(
        &mut root,
        pos_range,
        Target::ArrayBuffer,
        n,
        ComponentType::F32,
        Type::Vec3,
        Some((bounds(lo), bounds(hi))),
        "POSITION",
    );
    let colour = colour_range.map(|r| {
        accessor(
            &mut root,
            r,
            Target::ArrayBuffer,
            n,
            ComponentType::F32,
            Type::Vec3,
            None,
            "COLOR_0",
        )
    });
    let material = {
        let mut m = json::Material {
            double_sided: true,
            name: Some(if colour.is_some() { "colour map (unlit)" } else { "grey" }.into()),
            ..Default::default()
        };
        m.pbr_metallic_roughness.metallic_factor = json::material::StrengthFactor(0.0);
        if colour.is_some() {
            // The extension struct's fields depend on which gltf-json features are on.
            #[allow(clippy::needless_update)]
            let unlit = json::extensions::material::Material {
                unlit: Some(json::extensions::material::Unlit {}),
                ..Default::default()
            };
            m.extensions = Some(unlit);
            root.extensions_used.push("KHR_materials_unlit".into());
        } else {
            m.pbr_metallic_roughness.base_color_factor =
                json::material::PbrBaseColorFactor([0.6, 0.6, 0.6, 1.0]);
        }
        root.push(m)
    };
    let mut attributes = BTreeMap::new();
    attributes.insert(Checked::Valid(json::mesh::Semantic::Positions), position);
    if let Some(c) = colour {
        attributes.insert(Checked::Valid(json::mesh::Semantic::Colors(0)), c);
    }
    let mut primitives = Vec::new();
    for (indices, range, mode, name) in [
        (&tris, tri_range, json::mesh::Mode::Triangles, "triangles"),
        (&lines, line_range, json::mesh::Mode::Lines, "lines"),
    ] {
        if indices.is_empty() {
            continue;
        }
        let acc = accessor(
            &mut root,
            range,
            Target::ElementArrayBuffer,
            indices.len(),
            ComponentType::U32,
            Type::Scalar,
            None,
            name,
        );
        primitives.push(json::mesh::Primitive {
            attributes: attributes.clone(),
            extensions: None,
            extras: Default::default(),
            indices: Some(acc),
            material: Some(material),
            mode: Checked::Valid(mode),
            targets: None,
        });
    }
    let mesh_index = root.push(json::Mesh {
        extensions: None,
        extras,
        name: Some("smartmesh".into()),
        primitives,
        weights: None,
    });
    let node = root.push(json::Node {
        mesh: Some(mesh_index),
        name: Some("smartmesh".into()),
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    root.scene = Some(scene);

    if glb {
        let json_bytes = root.to_vec().map_err(|e| cannot(e.to_string()))?;
        let total = 12 + 8 + json_bytes.len().next_multiple_of(4) + 8 + buffer.len();
        if total > u32::MAX as usize {
            return Err(cannot(format!("a GLB file holds at most 4 GiB; this one would take {total} bytes (write .gltf + .bin)")));
        }
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header { magic: *b"glTF", version: 2, length: total as u32 },
            json: std::borrow::Cow::Owned(json_bytes),
            bin: Some(std::borrow::Cow::Owned(buffer)),
        };
        let main = glb.to_vec().map_err(|e| cannot(e.to_string()))?;
        Ok(Written { main, siblings: Vec::new(), report })
    } else {
        let mut main = root.to_vec_pretty().map_err(|e| cannot(e.to_string()))?;
        main.push(b'\n');
        let siblings =
            if opts.main_name.is_some() { vec![("bin".to_string(), buffer)] } else { Vec::new() };
        Ok(Written { main, siblings, report })
    }
}

/// What glTF cannot hold at all.
fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    let tagged: usize = mesh
        .blocks
        .iter()
        .map(|b| {
            b.physical.iter().zip(&b.geometrical).filter(|(p, g)| **p != 0 || **g != 0).count()
        })
        .sum();
    if tagged > 0 {
        report.drop(format!("physical and geometrical tags of {tagged} cells: glTF holds no tags"));
    }
    if !mesh.tag_names.is_empty() {
        let names: Vec<&str> = mesh.tag_names.values().map(String::as_str).collect();
        report.drop(format!("tag names ({}): glTF holds no tags", names.join(", ")));
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({}): glTF holds no fields",
            crate::words::components(a.components)
        ));
    }
    if !mesh.entities.is_empty() {
        report.drop(format!("the entity table ({} entities): glTF has none", mesh.entities.len()));
    }
    for name in mesh.point_sets.keys() {
        report.drop(format!("point set `{name}`: glTF holds no sets"));
    }
    for name in mesh.cell_sets.keys() {
        report.drop(format!("cell set `{name}`: glTF holds no sets"));
    }
    if !mesh.holes.is_empty() {
        report.drop(format!("{} hole points: glTF holds none", mesh.holes.len()));
    }
    if !mesh.regions.is_empty() {
        report.drop(format!("{} region seeds: glTF holds none", mesh.regions.len()));
    }
}

/// The cells as triangle and line index lists (quads as two triangles, second-order
/// cells by their corners), and what that changes in the report.
fn indices(mesh: &TaggedMesh, report: &mut WriteReport) -> Result<(Vec<u32>, Vec<u32>)> {
    let n = mesh.points.len();
    let mut tris: Vec<u32> = Vec::with_capacity(
        3 * (mesh.num_cells_of(CellKind::Triangle) + 2 * mesh.num_cells_of(CellKind::Quad)),
    );
    let mut lines: Vec<u32> = Vec::with_capacity(2 * mesh.num_cells_of(CellKind::Line));
    let mut counts: BTreeMap<CellKind, usize> = BTreeMap::new();
    for b in &mesh.blocks {
        *counts.entry(b.kind).or_insert(0) += b.len();
        for c in b.cells() {
            let i = |k: usize| -> Result<u32> {
                c.get(k).copied().filter(|&v| (v as usize) < n).ok_or_else(|| {
                    cannot(format!(
                        "a {} cell refers to a point that does not exist",
                        b.kind.name()
                    ))
                })
            };
            match b.kind {
                CellKind::Vertex => {}
                CellKind::Line | CellKind::Line3 => lines.extend_from_slice(&[i(0)?, i(1)?]),
                CellKind::Triangle | CellKind::Triangle6 => {
                    tris.extend_from_slice(&[i(0)?, i(1)?, i(2)?])
                }
                CellKind::Quad | CellKind::Quad8 | CellKind::Quad9 => {
                    let (a, b1, c1, d) = (i(0)?, i(1)?, i(2)?, i(3)?);
                    tris.extend_from_slice(&[a, b1, c1, a, c1, d]);
                }
                _ => {
                    return Err(cannot(format!(
                        "{} cells left after the skin: glTF draws surfaces, not volumes",
                        b.kind.name()
                    )))
                }
            }
        }
    }
    if tris.is_empty() && lines.is_empty() {
        return Err(cannot("the mesh has no triangles, quads or lines to draw"));
    }
    for (&kind, &count) in &counts {
        match kind {
            CellKind::Quad if count > 0 => report.drop(format!(
                "{count} quad cells split into 2 triangles each (glTF draws triangles)"
            )),
            CellKind::Vertex if count > 0 => report.drop(format!(
                "{count} vertex cells not drawn (the glTF writer draws triangles and lines)"
            )),
            k if k.is_second_order() && count > 0 => report.drop(format!(
                "{count} {} cells drawn by their corners{}: glTF has no second-order elements",
                k.name(),
                if k.dim() == 2 && k != CellKind::Triangle6 { ", as 2 triangles each" } else { "" }
            )),
            _ => {}
        }
    }
    Ok((tris, lines))
}

/// Appends the positions, rounded to f32, to `buffer`; returns their exact bounds.
fn push_positions(
    mesh: &TaggedMesh,
    buffer: &mut Vec<u8>,
    report: &mut WriteReport,
) -> Result<([f32; 3], [f32; 3])> {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    let mut largest_change = 0.0f64;
    for (pi, p) in mesh.points.iter().enumerate() {
        for k in 0..3 {
            let v = p[k] as f32;
            if !v.is_finite() {
                return Err(cannot(format!(
                    "point {pi} has coordinate {} that is not a finite 32-bit float",
                    p[k]
                )));
            }
            largest_change = largest_change.max((v as f64 - p[k]).abs());
            lo[k] = lo[k].min(v);
            hi[k] = hi[k].max(v);
            buffer.extend_from_slice(&v.to_le_bytes());
        }
    }
    if largest_change > 0.0 {
        report.drop(format!("coordinates rounded to 32-bit floats (glTF POSITION is FLOAT); largest change {largest_change:.3e}"));
    }
    Ok((lo, hi))
}

/// Where the vertex colours are in the buffer, and the mesh extras that name their field.
type Colours = (Option<std::ops::Range<usize>>, Option<Box<json::extras::RawValue>>);

/// Appends the vertex colours of the colour field (if any) to `buffer`; returns where
/// they are and the mesh extras that record the field and its range.
fn push_colours(
    mesh: &TaggedMesh,
    opts: &WriteOptions,
    buffer: &mut Vec<u8>,
    report: &mut WriteReport,
) -> Result<Colours> {
    let n = mesh.points.len();
    let field = colour_field(mesh, opts)?;
    let mut extras = None;
    let mut colour_range = None;
    if let Some((name, array, quantity)) = field {
        let q: Vec<f64> = (0..n)
            .map(|i| {
                let item = array.item(i);
                match quantity {
                    Quantity::Value => item[0],
                    Quantity::Magnitude => item.iter().map(|x| x * x).sum::<f64>().sqrt(),
                    Quantity::FinestSize => finest_size(&array.tensor9(i)),
                }
            })
            .collect();
        let (mut qmin, mut qmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for &v in q.iter().filter(|v| v.is_finite()) {
            qmin = qmin.min(v);
            qmax = qmax.max(v);
        }
        let bad = q.iter().filter(|v| !v.is_finite()).count();
        let start = buffer.len();
        for &v in &q {
            let c = if !v.is_finite() {
                NO_VALUE
            } else if qmax > qmin {
                viridis_linear((v - qmin) / (qmax - qmin))
            } else {
                viridis_linear(0.5)
            };
            for x in c {
                buffer.extend_from_slice(&x.to_le_bytes());
            }
        }
        colour_range = Some(start..buffer.len());
        let finite = qmin <= qmax;
        report.drop(format!(
            "point data `{name}` ({}) written only as vertex colours: its {} through viridis{}",
            crate::words::components(array.expanded_components()),
            quantity.describe(),
            if finite {
                format!(
                    " from {} to {} (recorded in the mesh extras)",
                    crate::words::number(qmin),
                    crate::words::number(qmax)
                )
            } else {
                String::new()
            }
        ));
        if bad > 0 {
            report.drop(format!(
                "{bad} vertices of `{name}` have no finite {} and are drawn grey",
                quantity.describe()
            ));
        }
        let num =
            |v: f64| if finite { serde_json::Value::from(v) } else { serde_json::Value::Null };
        let value = serde_json::json!({
            "color_field": name,
            "color_quantity": quantity.describe(),
            "color_min": num(qmin),
            "color_max": num(qmax),
            "colormap": "viridis",
        });
        extras = Some(
            json::extras::RawValue::from_string(value.to_string())
                .map_err(|e| cannot(e.to_string()))?,
        );
    }
    for (name, a) in &mesh.point_data {
        if field.map(|f| f.0) != Some(name.as_str()) {
            let why = match field {
                Some((f, _, _)) => format!("the vertices are coloured by `{f}` alone"),
                None if opts.gltf.color_field.is_none() => "glTF holds no fields, and only a scalar colours the vertices unless --color-field names another".to_string(),
                None => "glTF holds no fields".to_string(),
            };
            report.drop(format!(
                "point data `{name}` ({}): {why}",
                crate::words::components(a.expanded_components())
            ));
        }
    }
    Ok((colour_range, extras))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_middle() {
        let to_srgb = |c: f32| {
            let c = c as f64;
            if c <= 0.0031308 {
                12.92 * c
            } else {
                1.055 * c.powf(1.0 / 2.4) - 0.055
            }
        };
        for (t, stop) in [
            (0.0, VIRIDIS[0]),
            (0.5, VIRIDIS[4]),
            (1.0, VIRIDIS[8]),
            (-3.0, VIRIDIS[0]),
            (7.0, VIRIDIS[8]),
        ] {
            let c = viridis_linear(t);
            for k in 0..3 {
                assert!((to_srgb(c[k]) - stop[k]).abs() < 1e-6, "t={t}");
            }
        }
    }

    #[test]
    fn finest_size_of_a_metric() {
        // M = diag(1/0.1², 1/0.01²): the finest size is 0.01.
        let t = crate::sym2_to_tensor9(100.0, 0.0, 10000.0, 1.0);
        assert!((finest_size(&t) - 0.01).abs() < 1e-15);
        // Rotated by 45°: same eigenvalues.
        let (a, c) = (100.0, 10000.0);
        let t = crate::sym2_to_tensor9(0.5 * (a + c), 0.5 * (a - c), 0.5 * (a + c), 1.0);
        assert!((finest_size(&t) - 0.01).abs() < 1e-12);
        assert!(finest_size(&crate::sym2_to_tensor9(-1.0, 0.0, -2.0, 1.0)).is_nan());
    }

    #[test]
    fn uri_names_are_percent_encoded() {
        assert_eq!(uri_encode("my mesh#1.bin"), "my%20mesh%231.bin");
        assert_eq!(uri_encode("naca-0012_v2.bin"), "naca-0012_v2.bin");
    }
}
