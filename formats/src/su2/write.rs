//! Writing SU2 meshes: 2D (`NDIME= 2`, triangles and quads inside, lines as markers)
//! or 3D (`NDIME= 3` when the mesh has volume cells: tetrahedra, hexahedra, prisms and
//! pyramids inside, triangles and quads as markers), in the layout of the
//! documentation's example (see the module header).

use std::collections::BTreeMap;

use super::{generated_tag, su2_order, su2_type};
use crate::text::{push_f64, push_int};
use crate::{CellBlock, CellKind, TaggedMesh, WriteOptions, WriteReport, Written};

/// `name` as one SU2 marker word: blanks and the characters SU2's mesh and
/// configuration files give a meaning (`=`, `%`, parentheses, commas, `;`) become `_`.
fn marker_word(name: &str) -> String {
    name.trim()
        .chars()
        .map(|c| if c.is_whitespace() || c.is_control() || "=%(),;".contains(c) { '_' } else { c })
        .collect()
}

/// The word for a tag of dimension `d` in messages.
fn what(d: u8) -> &'static str {
    if d == 1 {
        "line"
    } else {
        "surface"
    }
}

/// Writes a mesh as an SU2 file.
pub fn write(mesh: &TaggedMesh, _opts: &WriteOptions) -> Result<Written, crate::Error> {
    let mut report = WriteReport::default();
    // A mesh with volume cells is 3D; its interior cells are the volume cells and its
    // markers the surface cells. Otherwise 2D: surface cells inside, lines as markers.
    let ndime: u8 = if mesh.blocks.iter().any(|b| b.kind.dim() == 3) { 3 } else { 2 };
    report_unheld(mesh, ndime, &mut report);
    let mut out = Vec::with_capacity(64 + 36 * mesh.points.len() + 40 * mesh.num_cells());
    out.extend_from_slice(b"% SU2 mesh written by smartmesh\n%\n% Problem dimension\n%\nNDIME= ");
    push_int(&mut out, ndime);
    out.push(b'\n');

    let interior: Vec<&CellBlock> = mesh.blocks.iter().filter(|b| b.kind.dim() == ndime).collect();
    let nelem: usize = interior.iter().map(|b| b.len()).sum();
    out.extend_from_slice(b"%\n% Inner element connectivity\n%\nNELEM= ");
    push_int(&mut out, nelem);
    out.push(b'\n');
    let mut index = 0usize;
    let mut inner_tags = BTreeMap::new();
    for b in &interior {
        let t = su2_type(b.kind.linear()).expect("a linear kind of dimension 2 or 3");
        let order = su2_order(b.kind.linear());
        for (i, c) in b.cells().enumerate() {
            push_int(&mut out, t);
            for &k in order {
                out.push(b' ');
                push_int(&mut out, c[k]);
            }
            out.push(b' ');
            push_int(&mut out, index);
            out.push(b'\n');
            index += 1;
            *inner_tags.entry(b.physical[i]).or_insert(0usize) += 1;
        }
    }
    if inner_tags.keys().any(|&t| t != 1) {
        let list: Vec<String> = inner_tags
            .iter()
            .map(|(&t, n)| match mesh.tag_name(ndime, t) {
                Some(name) => format!("{t} `{name}` ({n} cells)"),
                None => format!("{t} ({n} cells)"),
            })
            .collect();
        report.drop(format!(
            "{} tags {}: SU2 names no volume, so the interior cells read back with tag 1 (zone 1)",
            if ndime == 3 { "volume" } else { "face" },
            list.join(", ")
        ));
    }

    out.extend_from_slice(b"%\n% Node coordinates\n%\nNPOIN= ");
    push_int(&mut out, mesh.points.len());
    out.push(b'\n');
    let mut with_z = 0usize;
    for (i, p) in mesh.points.iter().enumerate() {
        if !p.iter().take(ndime as usize).all(|c| c.is_finite()) {
            return Err(crate::io::refused(crate::Format::Su2, mesh));
        }
        for &c in &p[..ndime as usize] {
            push_f64(&mut out, c);
            out.push(b' ');
        }
        push_int(&mut out, i);
        out.push(b'\n');
        with_z += usize::from(p[2] != 0.0);
    }
    if with_z > 0 && ndime == 2 {
        report.drop(format!(
            "the z coordinates of {with_z} points: a 2D SU2 mesh (NDIME= 2) holds x and y"
        ));
    }

    // Markers: the boundary cells grouped by physical tag, in increasing tag order.
    let d = ndime - 1;
    let mut by_tag: BTreeMap<i32, Vec<(i64, Vec<u32>)>> = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == d) {
        let t = su2_type(b.kind.linear()).expect("a linear kind of dimension 1 or 2");
        let order = su2_order(b.kind.linear());
        for (i, c) in b.cells().enumerate() {
            by_tag
                .entry(b.physical[i])
                .or_default()
                .push((t, order.iter().map(|&k| c[k]).collect()));
        }
    }
    out.extend_from_slice(b"%\n% Boundary elements\n%\nNMARK= ");
    push_int(&mut out, by_tag.len());
    out.push(b'\n');
    let mut used: BTreeMap<String, i32> = BTreeMap::new();
    for (&tag, cells) in &by_tag {
        let name = marker_name(mesh, d, tag, &used, &mut report);
        used.insert(name.clone(), tag);
        out.extend_from_slice(b"MARKER_TAG= ");
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(b"\nMARKER_ELEMS= ");
        push_int(&mut out, cells.len());
        out.push(b'\n');
        for (t, c) in cells {
            push_int(&mut out, *t);
            for &v in c {
                out.push(b' ');
                push_int(&mut out, v);
            }
            out.push(b'\n');
        }
    }
    for (&(dd, t), name) in &mesh.tag_names {
        if dd == d && !by_tag.contains_key(&t) {
            report.drop(format!("tag name `{name}` (dimension {d}, tag {t}) names no {} cell; SU2 keeps a marker only with its elements", what(d)));
        }
    }
    Ok(Written { main: out, siblings: Vec::new(), report })
}

/// The marker name of boundary tag `tag` (dimension `d`), reported when it is not the
/// tag name as it stands.
fn marker_name(
    mesh: &TaggedMesh,
    d: u8,
    tag: i32,
    used: &BTreeMap<String, i32>,
    report: &mut WriteReport,
) -> String {
    let generated = format!("tag{tag}");
    let w = what(d);
    let name = match mesh.tag_name(d, tag) {
        None => {
            report.drop(format!(
                "{w} tag {tag} has no name: written as marker `{generated}` (read back as tag {tag})"
            ));
            generated
        }
        Some(orig) => {
            let word = marker_word(orig);
            if word.is_empty() {
                report.drop(format!(
                    "{w} tag {tag}'s name `{orig}` is blank: written as marker `{generated}`"
                ));
                generated
            } else if generated_tag(&word).is_some_and(|t| t != tag) {
                report.drop(format!("{w} tag {tag}'s name `{orig}` would read back as another tag: written as marker `{generated}`"));
                generated
            } else {
                if word != orig {
                    report.drop(format!("{w} tag {tag}'s name `{orig}` written as marker `{word}`: an SU2 marker name is one word without `=`, `%`, parentheses or commas"));
                }
                word
            }
        }
    };
    if let Some(other) = used.get(&name) {
        let unique = format!("{name}_tag{tag}");
        report.drop(format!(
            "{w} tags {other} and {tag} share the marker name `{name}`: tag {tag} written as `{unique}`"
        ));
        return unique;
    }
    name
}

/// What SU2 cannot hold at all, and what it holds only in part.
fn report_unheld(mesh: &TaggedMesh, ndime: u8, report: &mut WriteReport) {
    for (name, a) in &mesh.point_data {
        report.drop(format!(
            "point data `{name}` ({} components): an SU2 mesh holds no fields",
            a.expanded_components()
        ));
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({} components): an SU2 mesh holds no fields",
            a.expanded_components()
        ));
    }
    let differ: usize =
        mesh.blocks.iter().filter(|b| b.kind.dim() + 1 == ndime).map(|b| b.tags_differ()).sum();
    if differ > 0 {
        report.drop(format!("geometrical tags of {differ} boundary cells: SU2 keeps one marker per boundary element, the physical tag"));
    }
    let mut lower: BTreeMap<CellKind, usize> = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() + 1 < ndime) {
        *lower.entry(b.kind).or_insert(0) += b.len();
    }
    for (kind, n) in lower {
        report.drop(format!(
            "{n} {} cells: a {ndime}D SU2 mesh holds {} cells inside and {} on its markers",
            kind.name(),
            if ndime == 3 { "volume" } else { "triangle and quadrilateral" },
            if ndime == 3 { "triangles and quadrilaterals" } else { "lines" },
        ));
    }
    for kind in CellKind::ALL.into_iter().filter(|k| k.is_second_order() && k.dim() + 1 >= ndime) {
        let n = mesh.num_cells_of(kind);
        if n > 0 {
            report.drop(format!("the mid-edge and mid-face nodes of {n} {} cells: SU2 meshes are first order (written by their corners)", kind.name()));
        }
    }
    if !mesh.entities.is_empty() {
        report.drop(format!("the entity table ({} entities): SU2 has none", mesh.entities.len()));
    }
    for name in mesh.point_sets.keys() {
        report.drop(format!("point set `{name}`: SU2 holds no sets"));
    }
    for name in mesh.cell_sets.keys() {
        report.drop(format!("cell set `{name}`: SU2 holds no sets"));
    }
    if !mesh.holes.is_empty() {
        report.drop(format!("{} hole points: SU2 holds none", mesh.holes.len()));
    }
    if !mesh.regions.is_empty() {
        report.drop(format!("{} region seeds: SU2 holds none", mesh.regions.len()));
    }
}
