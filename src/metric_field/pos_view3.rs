//! A Gmsh `.pos` view read as a 3D metric on a mesh in space: the tensor records of the
//! file's **last** view (the one `gmsh -bgm` uses), `TS` on tetrahedra and `TT` on
//! triangles in space and every other tensor element alike, at their first time step.
//!
//! A view gives tensors at positions. Here they are taken at the view's nodes, joined by
//! their exact (x, y, z) (−0 read as +0), the first record in the file giving a node that
//! several share; every node's tensor must be a 3D metric (finite, symmetric, positive
//! definite, with the record's line in the error). Each vertex a cell of the mesh uses
//! must be a node of the view, bit for bit, as `smartmesh size -o X.pos` writes the
//! mesh's own vertices in shortest round-trip decimals; a vertex that is not is an error
//! that names it. Interpolating between a view's nodes in tetrahedra (the 2D reader does
//! it in triangles, [`super::pos_view`]) is not done in 3D yet: it needs a point location
//! in tetrahedra, which `geometry` does not offer today.

use std::collections::BTreeMap;
use std::path::Path;

use crate::metric::Sym3;
use smartmesh_formats::gmsh::pos::{self, Field, Item};
use smartmesh_formats::{Error, ErrorKind, TaggedMesh, MAX_POINTS};

use super::tensor::not_a_metric3;

type Key = (u64, u64, u64);

fn key(p: [f64; 3]) -> Key {
    ((p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits(), (p[2] + 0.0).to_bits())
}

/// One view being read: its name, its line and its nodes' tensors.
#[derive(Debug)]
struct Nodes {
    name: String,
    line: u64,
    at: BTreeMap<Key, Sym3>,
}

/// The last view of `bytes`: its name, the line of its `View` and its nodes' tensors.
fn parse(bytes: &[u8]) -> Result<Nodes, Error> {
    let (mut current, mut last): (Option<Nodes>, Option<Nodes>) = (None, None);
    pos::read_bytes(bytes, &mut |item| {
        match item {
            Item::View { name, line } => {
                current = Some(Nodes { name: name.to_string(), line, at: BTreeMap::new() })
            }
            Item::Record(r) => {
                let Some(nodes) = current.as_mut() else { return Ok(()) };
                if r.field != Field::Tensor {
                    return Ok(());
                }
                for k in 0..r.element.nodes() {
                    let p = [r.coords[3 * k], r.coords[3 * k + 1], r.coords[3 * k + 2]];
                    let t: [f64; 9] = std::array::from_fn(|j| r.values[9 * k + j]);
                    if let Some(why) = not_a_metric3(&t) {
                        return Err(Error::at_line(
                            r.line,
                            ErrorKind::Inconsistent(format!(
                                "the tensor at node {} of the record is not a 3D metric: {t:?} (row-major) is {why}",
                                k + 1
                            )),
                        ));
                    }
                    if nodes.at.len() >= MAX_POINTS {
                        return Err(Error::at_line(
                            r.line,
                            ErrorKind::Unsupported(format!(
                                "a view of more than {MAX_POINTS} distinct nodes"
                            )),
                        ));
                    }
                    nodes.at.entry(key(p)).or_insert_with(|| Sym3::from_row_major(&t));
                }
            }
            Item::EndView => last = current.take(),
        }
        Ok(())
    })?;
    let Some(nodes) = last else {
        return Err(Error::at_line(
            1,
            ErrorKind::Inconsistent(
                "no view: a metric view is `View \"name\" { TS(...){...}; ... };`".into(),
            ),
        ));
    };
    if nodes.at.is_empty() {
        return Err(Error::at_line(
            nodes.line,
            ErrorKind::Inconsistent(format!(
                "view `{}` (the last of the file, the one `gmsh -bgm` uses) holds no tensor record (TS, TT, ...): a scalar or vector view is not a metric",
                nodes.name
            )),
        ));
    }
    Ok(nodes)
}

/// The last view of the `.pos` file at `path` at the vertices of `mesh` (see the module
/// documentation): its name and one tensor per vertex, the identity where no cell uses
/// the vertex and the view has no node.
pub(crate) fn read_at(path: &Path, mesh: &TaggedMesh) -> Result<(String, Vec<Sym3>), Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::from(e).with_path(path))?;
    let nodes = parse(&bytes).map_err(|e| e.with_path(path))?;
    at_vertices(nodes, mesh).map_err(|e| e.with_path(path))
}

fn at_vertices(nodes: Nodes, mesh: &TaggedMesh) -> Result<(String, Vec<Sym3>), Error> {
    let mut used = vec![false; mesh.points.len()];
    for (_, cell, _, _) in mesh.cells() {
        for &n in cell {
            if let Some(u) = used.get_mut(n as usize) {
                *u = true;
            }
        }
    }
    let mut out = Vec::with_capacity(mesh.points.len());
    for (v, (p, &in_use)) in mesh.points.iter().zip(&used).enumerate() {
        match nodes.at.get(&key(*p)) {
            Some(&m) => out.push(m),
            None if !in_use => out.push(Sym3::IDENTITY),
            None => {
                return Err(Error::at_line(
                    nodes.line,
                    ErrorKind::Inconsistent(format!(
                        "vertex {v} (0-based) of the mesh, at {p:?}, is no node of view `{}`: a 3D view is read at its nodes, which must be the mesh's own vertices (interpolation inside a view's tetrahedra is not done)",
                        nodes.name
                    )),
                ))
            }
        }
    }
    Ok((nodes.name, out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::CellKind;

    fn tet() -> TaggedMesh {
        let mut mesh = TaggedMesh::new();
        mesh.points = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        mesh.block_mut(CellKind::Tetra).push(&[0, 1, 2, 3], 1, 1);
        mesh
    }

    const ID: &str = "1,0,0,0,1,0,0,0,1";

    #[test]
    fn a_tetrahedron_view_gives_each_vertex_its_node() {
        let aniso = "4,1,0.5,1,3,-0.25,0.5,-0.25,2";
        let text = format!(
            "View \"metric\" {{\nTS(0,0,0,1,0,0,0,1,0,0,0,1){{{aniso},{ID},{ID},{ID}}};\nSS(0,0,0,1,0,0,0,1,0,0,0,1){{1,2,3,4}};\n}};\n"
        );
        let nodes = parse(text.as_bytes()).unwrap();
        let (name, at) = at_vertices(nodes, &tet()).unwrap();
        assert_eq!(name, "metric");
        assert_eq!(at[0], Sym3 { xx: 4.0, xy: 1.0, yy: 3.0, xz: 0.5, yz: -0.25, zz: 2.0 });
        assert_eq!(at[3], Sym3::IDENTITY);
    }

    #[test]
    fn bad_views_name_the_line_or_the_vertex() {
        let bad = "1,0,0.9,0,1,0.9,0.9,0.9,1";
        let text =
            format!("View \"m\" {{\n\nTS(0,0,0,1,0,0,0,1,0,0,0,1){{{ID},{bad},{ID},{ID}}};}};");
        let e = parse(text.as_bytes()).unwrap_err();
        assert!(e.to_string().contains("node 2") && e.to_string().contains("positive definite"));
        assert_eq!(e.at, Some(smartmesh_formats::Position::Line(3)));
        let moved =
            format!("View \"m\" {{\nTS(0,0,0,2,0,0,0,1,0,0,0,1){{{ID},{ID},{ID},{ID}}};}};");
        let e = at_vertices(parse(moved.as_bytes()).unwrap(), &tet()).unwrap_err().to_string();
        assert!(e.contains("vertex 1 (0-based)") && e.contains("no node of view `m`"), "{e}");
        let scalar = "View \"s\" {\nSS(0,0,0,1,0,0,0,1,0,0,0,1){1,2,3,4};\n};";
        let e = parse(scalar.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("no tensor record"), "{e}");
    }
}
