//! A metric field written as Gmsh's parsed post-processing format (`.pos`): one view of
//! tensor records, the form `gmsh -bgm` and the Gmsh GUI read ([`super::pos_view`] reads
//! it back).
//!
//! Format (Gmsh reference manual, "Post-processing scripting / parsed format"): a view is
//! `View "name" { ... };` holding one record per element, `TT(x1,y1,z1,x2,y2,z2,x3,y3,z3)
//! {t1..t9 at node 1, t1..t9 at node 2, t1..t9 at node 3};` for a triangle with a tensor
//! (9 components, row-major) at each node, and `TQ(...)` for a quadrangle. Second-order
//! cells are written as their corner triangle or quadrangle (a background mesh needs no
//! more). Cells of other dimensions carry no record: a background field lives on faces.
//!
//! Numbers are shortest round-trip decimals, which Gmsh's `strtod` reads back exactly.

use smartmesh_formats::text::push_f64;
use smartmesh_formats::{CellKind, DataArray, Error, ErrorKind, TaggedMesh};

/// The bytes of a `.pos` file holding one view `name` of the 9-component point array
/// `tensor` on the triangles and quadrangles of `mesh`.
pub fn write_tensor_view(
    mesh: &TaggedMesh,
    tensor: &DataArray,
    name: &str,
) -> Result<Vec<u8>, Error> {
    let cannot = |reason: String| {
        Error::new(ErrorKind::CannotWrite { format: "Gmsh post-processing view", reason })
    };
    if tensor.components != 9 || tensor.values.len() != 9 * mesh.points.len() {
        return Err(cannot(format!(
            "a view needs 9 components per mesh vertex ({} vertices, {} values)",
            mesh.points.len(),
            tensor.values.len()
        )));
    }
    if name.contains('"') || name.contains('\n') {
        return Err(cannot(format!("view name {name:?} holds a quote or a newline")));
    }
    let faces = mesh.blocks.iter().filter(|b| face_corners(b.kind).is_some());
    let records: usize = faces.clone().map(|b| b.len()).sum();
    if records == 0 {
        return Err(cannot("the mesh has no triangle or quadrangle to carry the view".into()));
    }
    let mut out = Vec::with_capacity(64 + records * 3 * 230);
    out.extend_from_slice(b"View \"");
    out.extend_from_slice(name.as_bytes());
    out.extend_from_slice(b"\" {\n");
    for block in faces {
        let (tag, corners): (&[u8], usize) = face_corners(block.kind).expect("filtered on faces");
        for cell in block.cells() {
            let cell = &cell[..corners];
            out.extend_from_slice(tag);
            out.push(b'(');
            for (k, &v) in cell.iter().enumerate() {
                for (c, &x) in mesh.points[v as usize].iter().enumerate() {
                    if k + c > 0 {
                        out.push(b',');
                    }
                    push_f64(&mut out, x);
                }
            }
            out.extend_from_slice(b"){");
            for (k, &v) in cell.iter().enumerate() {
                let v = v as usize;
                for (c, &x) in tensor.values[9 * v..9 * v + 9].iter().enumerate() {
                    if k + c > 0 {
                        out.push(b',');
                    }
                    push_f64(&mut out, x);
                }
            }
            out.extend_from_slice(b"};\n");
        }
    }
    out.extend_from_slice(b"};\n");
    Ok(out)
}

/// The record tag and number of corners of a face kind, `None` for other kinds.
fn face_corners(kind: CellKind) -> Option<(&'static [u8], usize)> {
    match kind {
        CellKind::Triangle | CellKind::Triangle6 => Some((b"TT", 3)),
        CellKind::Quad | CellKind::Quad8 | CellKind::Quad9 => Some((b"TQ", 4)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::CellBlock;

    fn square() -> TaggedMesh {
        let mut m = TaggedMesh {
            points: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            ..TaggedMesh::new()
        };
        let mut b = CellBlock::new(CellKind::Triangle);
        b.push(&[0, 1, 2], 1, 1);
        b.push(&[0, 2, 3], 1, 1);
        m.blocks.push(b);
        let mut l = CellBlock::new(CellKind::Line);
        l.push(&[0, 1], 5, 5);
        m.blocks.push(l);
        m
    }

    #[test]
    fn one_record_per_triangle_with_nine_values_per_node() {
        let m = square();
        let t = DataArray::new(9, (0..36).map(|k| k as f64 / 4.0).collect());
        let text = String::from_utf8(write_tensor_view(&m, &t, "metric").unwrap()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "View \"metric\" {");
        assert_eq!(lines.len(), 4);
        assert!(lines[1].starts_with("TT(0.0,0.0,0.0,1.0,0.0,0.0,1.0,1.0,0.0){0.0,0.25,"));
        let values = lines[2].split('{').nth(1).unwrap().trim_end_matches("};");
        let v: Vec<f64> = values.split(',').map(|s| s.parse().unwrap()).collect();
        // Nodes 0, 2, 3 of the second triangle.
        let expect: Vec<f64> = [0usize, 2, 3]
            .iter()
            .flat_map(|&n| (9 * n..9 * n + 9).map(|k| k as f64 / 4.0))
            .collect();
        assert_eq!(v, expect);
        assert_eq!(lines[3], "};");
    }

    #[test]
    fn wrong_sizes_are_errors() {
        let m = square();
        assert!(write_tensor_view(&m, &DataArray::new(9, vec![1.0; 27]), "m").is_err());
        assert!(write_tensor_view(&m, &DataArray::new(3, vec![1.0; 12]), "m").is_err());
        assert!(write_tensor_view(&m, &DataArray::new(9, vec![1.0; 36]), "a\"b").is_err());
    }
}
