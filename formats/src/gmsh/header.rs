//! Writing: the header sections both versions share (`$MeshFormat`, `$PhysicalNames`)
//! and the quoting of names.

use crate::text;
use crate::{TaggedMesh, WriteReport};

pub(super) fn write_mesh_format(out: &mut Vec<u8>, version: &str, binary: bool) {
    out.extend_from_slice(b"$MeshFormat\n");
    out.extend_from_slice(version.as_bytes());
    out.extend_from_slice(if binary { b" 1 8\n" } else { b" 0 8\n" });
    if binary {
        out.extend_from_slice(&1i32.to_le_bytes());
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndMeshFormat\n");
}

/// A name as a quoted MSH string: Gmsh's reader stops at the next quote and at the end
/// of the line, and keeps 127 characters of a physical name.
pub(super) fn quote_name(
    name: &str,
    what: &str,
    max_len: Option<usize>,
    report: &mut WriteReport,
) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c == '"' {
                '\''
            } else if c == '\n' || c == '\r' {
                ' '
            } else {
                c
            }
        })
        .collect();
    if s != name {
        report.drop(format!("{what} `{name}`: double quotes and line breaks cannot stand in an MSH name; written as `{s}`"));
    }
    if let Some(max) = max_len {
        if s.len() > max {
            let mut cut = max;
            while !s.is_char_boundary(cut) {
                cut -= 1;
            }
            s.truncate(cut);
            report.drop(format!("{what} `{name}`: MSH names hold {max} characters; cut to `{s}`"));
        }
    }
    s
}

pub(super) fn write_physical_names(out: &mut Vec<u8>, mesh: &TaggedMesh, report: &mut WriteReport) {
    let names: Vec<_> = mesh.tag_names.iter().filter(|((d, _), _)| *d <= 3).collect();
    for ((d, t), n) in &mesh.tag_names {
        if *d > 3 {
            report.drop(format!(
                "name `{n}` of tag {t} of dimension {d}: MSH physical groups have dimension 0 to 3"
            ));
        }
    }
    if names.is_empty() {
        return;
    }
    out.extend_from_slice(b"$PhysicalNames\n");
    text::push_int(out, names.len());
    out.push(b'\n');
    for ((d, t), n) in names {
        let q = quote_name(n, "physical name", Some(127), report);
        text::push_int(out, *d);
        out.push(b' ');
        text::push_int(out, *t);
        out.extend_from_slice(b" \"");
        out.extend_from_slice(q.as_bytes());
        out.extend_from_slice(b"\"\n");
    }
    out.extend_from_slice(b"$EndPhysicalNames\n");
}
