//! The solution field of a mesh: a scalar point-data array, of the mesh itself or of
//! another file on the same vertices (a solver's output), found by name or, unnamed, as
//! the file's only scalar point array, checked and attached to the mesh under its name so
//! that the sizing step (SOLUTION_HESSIAN) reads it from there.
//!
//! A Medit solution alone (`.sol`, `.solb`, as MMG pairs it with its mesh) is taken in
//! the mesh's vertex order: its scalar arrays are named `size`, `size_2`, … as the Medit
//! reader names them ([`read_solution`]). A Gmsh data-only `.msh` (views without a mesh)
//! is taken likewise, node tag t at vertex t − 1, its views named as Gmsh names them.
//!
//! Checks: the other file has the mesh's vertex count and its vertices at the same
//! positions (up to 1e-9 of the mesh's extent, what a text file's rounding leaves); the
//! array has one component and one item per vertex, and its values are finite.

use std::path::Path;

use smartmesh_formats::gmsh::MshContent;
use smartmesh_formats::{read_path, ErrorKind, Format, TaggedMesh};

/// The solution file `path` as a mesh to take a field from: a mesh file as read; a Medit
/// `.sol`/`.solb` alone as `mesh`'s vertices (when it has as many) with its arrays.
pub fn read_solution(
    path: &Path,
    mesh: &TaggedMesh,
) -> Result<TaggedMesh, smartmesh_formats::Error> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    if Format::from_path(path) == Some(Format::Gmsh) {
        return read_msh_solution(path, &ext, mesh);
    }
    if ext != "sol" && ext != "solb" {
        return read_path(path, None);
    }
    let bytes =
        std::fs::read(path).map_err(|e| smartmesh_formats::Error::from(e).with_path(path))?;
    let Some((n, arrays)) =
        smartmesh_formats::medit::read_sol_alone(&bytes).map_err(|e| e.with_path(path))?
    else {
        return Err(smartmesh_formats::Error::new(ErrorKind::Inconsistent(
            "no SolAtVertices: the file holds no solution at vertices".into(),
        ))
        .with_path(path));
    };
    let mut other = TaggedMesh::new();
    // Another count keeps its own, so that `attach` names both.
    other.points = if n == mesh.points.len() { mesh.points.clone() } else { vec![[0.0; 3]; n] };
    other.point_data = arrays;
    Ok(other)
}

/// A `.msh` solution file: a mesh as read, or a Gmsh data-only file (`$NodeData` alone,
/// as `gmsh.view.write` or a solver writes it beside the mesh, which `--metric` takes
/// too) as `mesh`'s vertices, node tag t at vertex t − 1, with its views as point data
/// (a vertex a view gives nothing for is NaN, which the field's check refuses, naming
/// it). Views up to another count keep their own, so that `attach` names both.
fn read_msh_solution(
    path: &Path,
    ext: &str,
    mesh: &TaggedMesh,
) -> Result<TaggedMesh, smartmesh_formats::Error> {
    let bytes =
        std::fs::read(path).map_err(|e| smartmesh_formats::Error::from(e).with_path(path))?;
    let ctx = smartmesh_formats::ReadContext::alone(ext);
    match smartmesh_formats::gmsh::read_mesh_or_data(&bytes, &ctx).map_err(|e| e.with_path(path))? {
        MshContent::Mesh(m) => Ok(m),
        MshContent::NodeData(data) => {
            let n = data.arrays.values().map(|a| a.len()).max().unwrap_or(0);
            let mut other = TaggedMesh::new();
            // Views of other lengths are padded to the longest, NaN where they give nothing.
            other.point_data = data
                .arrays
                .into_iter()
                .map(|(name, mut a)| {
                    a.values.resize(n * a.components, f64::NAN);
                    (name, a)
                })
                .collect();
            other.points =
                if n == mesh.points.len() { mesh.points.clone() } else { vec![[0.0; 3]; n] };
            Ok(other)
        }
    }
}

/// Why a solution field could not be had.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FieldError {
    /// No array of that name.
    #[error("{path}: no point data `{name}` (its point arrays: {available})")]
    Missing {
        /// The file.
        path: String,
        /// The name asked for.
        name: String,
        /// The arrays it has.
        available: String,
    },
    /// No name was given and the file has no scalar point array, or several.
    #[error("{path}: {why}; name the field with --field")]
    Ambiguous {
        /// The file.
        path: String,
        /// What it holds.
        why: String,
    },
    /// The array is not a scalar.
    #[error(
        "{path}: point data `{name}` has {components} components; a solution field is a scalar (1)"
    )]
    NotScalar {
        /// The file.
        path: String,
        /// The array.
        name: String,
        /// Its components.
        components: usize,
    },
    /// Another vertex count than the mesh.
    #[error("{path}: {items} values of `{name}` for the {vertices} vertices of {mesh} (the solution must live on the mesh's own vertices)")]
    Count {
        /// The file.
        path: String,
        /// The array.
        name: String,
        /// Its items (or the file's points).
        items: usize,
        /// The mesh.
        mesh: String,
        /// The mesh's vertices.
        vertices: usize,
    },
    /// The same count, other positions.
    #[error("{path}: vertex {vertex} (0-based) is at {at:?}, but vertex {vertex} of {mesh} is at {expected:?}; the solution must live on the mesh's own vertices")]
    Moved {
        /// The file.
        path: String,
        /// The first vertex that differs.
        vertex: usize,
        /// Where the file has it.
        at: [f64; 2],
        /// The mesh.
        mesh: String,
        /// Where the mesh has it.
        expected: [f64; 2],
    },
    /// A NaN or infinite value.
    #[error("{path}: `{name}` at vertex {vertex} (0-based) is {value}, not a finite number")]
    NotFinite {
        /// The file.
        path: String,
        /// The array.
        name: String,
        /// The vertex.
        vertex: usize,
        /// The value.
        value: f64,
    },
}

/// The name of the field to take from `other` (read from `path`): `name` when given and
/// present, else its only scalar point array.
pub fn field_name(
    other: &TaggedMesh,
    path: &Path,
    name: Option<&str>,
) -> Result<String, FieldError> {
    let shown = path.display().to_string();
    let list = |m: &TaggedMesh| {
        if m.point_data.is_empty() {
            "none".to_string()
        } else {
            m.point_data.keys().cloned().collect::<Vec<_>>().join(", ")
        }
    };
    if let Some(name) = name {
        return if other.point_data.contains_key(name) {
            Ok(name.to_string())
        } else {
            Err(FieldError::Missing { path: shown, name: name.into(), available: list(other) })
        };
    }
    let scalars: Vec<&String> =
        other.point_data.iter().filter(|(_, a)| a.components == 1).map(|(n, _)| n).collect();
    match scalars.as_slice() {
        [one] => Ok((*one).clone()),
        [] => Err(FieldError::Ambiguous {
            path: shown,
            why: format!("no scalar point data (its point arrays: {})", list(other)),
        }),
        many => Err(FieldError::Ambiguous {
            path: shown,
            why: format!(
                "several scalar point arrays ({})",
                many.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
            ),
        }),
    }
}

/// The names of the fields to take from `other` (read from `path`): each of `names`, in
/// order, when present (the first missing one is the error, listing the file's arrays);
/// without names, its only scalar point array.
pub fn field_names(
    other: &TaggedMesh,
    path: &Path,
    names: &[String],
) -> Result<Vec<String>, FieldError> {
    if names.is_empty() {
        return Ok(vec![field_name(other, path, None)?]);
    }
    names.iter().map(|n| field_name(other, path, Some(n))).collect()
}

/// Attaches field `name` of `other` (read from `other_path`) to `mesh` (read from
/// `mesh_path`) under the same name, after the checks of the module documentation.
/// `other` may be `mesh` itself (pass a clone), then only the array is checked.
pub fn attach(
    mesh: &mut TaggedMesh,
    mesh_path: &Path,
    other: &TaggedMesh,
    other_path: &Path,
    name: &str,
) -> Result<(), FieldError> {
    let path = other_path.display().to_string();
    let mesh_shown = mesh_path.display().to_string();
    let Some(array) = other.point_data.get(name) else {
        return Err(field_name(other, other_path, Some(name)).unwrap_err());
    };
    if array.components != 1 {
        return Err(FieldError::NotScalar {
            path,
            name: name.into(),
            components: array.components,
        });
    }
    let n = mesh.points.len();
    for items in [other.points.len(), array.len()] {
        if items != n {
            return Err(FieldError::Count {
                path,
                name: name.into(),
                items,
                mesh: mesh_shown,
                vertices: n,
            });
        }
    }
    if let Some(v) = crate::metric_field::first_moved_vertex(mesh, other) {
        return Err(FieldError::Moved {
            path,
            vertex: v,
            at: [other.points[v][0], other.points[v][1]],
            mesh: mesh_shown,
            expected: [mesh.points[v][0], mesh.points[v][1]],
        });
    }
    if let Some(v) = array.values.iter().position(|x| !x.is_finite()) {
        return Err(FieldError::NotFinite {
            path,
            name: name.into(),
            vertex: v,
            value: array.values[v],
        });
    }
    mesh.point_data.insert(name.to_string(), array.clone());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::{CellKind, DataArray};

    fn mesh() -> TaggedMesh {
        let mut m = TaggedMesh::new();
        m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        m.block_mut(CellKind::Triangle).push(&[0, 1, 2], 1, 1);
        m
    }

    #[test]
    fn a_medit_solution_alone_is_read_in_the_mesh_vertex_order() {
        let dir = tempfile::tempdir().unwrap();
        let sol = dir.path().join("u.sol");
        let text = |rows: &[&str]| {
            format!(
                "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n{}\n1 1\n{}\nEnd\n",
                rows.len(),
                rows.join("\n")
            )
        };
        std::fs::write(&sol, text(&["1.5", "2.5", "3.5"])).unwrap();
        let other = read_solution(&sol, &mesh()).unwrap();
        assert_eq!(field_name(&other, &sol, None).unwrap(), "size");
        let mut m = mesh();
        attach(&mut m, Path::new("m.mesh"), &other, &sol, "size").unwrap();
        assert_eq!(m.point_data["size"].values, vec![1.5, 2.5, 3.5]);
        std::fs::write(&sol, text(&["1.5", "2.5"])).unwrap();
        let other = read_solution(&sol, &mesh()).unwrap();
        let e = attach(&mut mesh(), Path::new("m.mesh"), &other, &sol, "size").unwrap_err();
        assert!(e.to_string().contains("2 values of `size` for the 3 vertices"), "{e}");
        std::fs::write(&sol, "MeshVersionFormatted 2\nDimension 2\nEnd\n").unwrap();
        let e = read_solution(&sol, &mesh()).unwrap_err().to_string();
        assert!(e.contains("u.sol") && e.contains("no SolAtVertices"), "{e}");
    }

    #[test]
    fn a_field_is_found_checked_and_attached() {
        let (mp, sp) = (Path::new("m.msh"), Path::new("s.vtu"));
        let mut other = mesh();
        other.point_data.insert("u".into(), DataArray::new(1, vec![1.0, 2.0, 3.0]));
        other.point_data.insert("v".into(), DataArray::new(3, vec![0.0; 9]));
        assert_eq!(field_name(&other, sp, None).unwrap(), "u");
        let e = field_name(&other, sp, Some("w")).unwrap_err().to_string();
        assert!(e.contains("s.vtu") && e.contains("`w`") && e.contains("u, v"), "{e}");
        let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(field_names(&other, sp, &[]).unwrap(), ["u"]);
        assert_eq!(field_names(&other, sp, &names(&["v", "u"])).unwrap(), ["v", "u"]);
        let e = field_names(&other, sp, &names(&["u", "w", "x"])).unwrap_err().to_string();
        assert_eq!(e, "s.vtu: no point data `w` (its point arrays: u, v)");
        let mut m = mesh();
        attach(&mut m, mp, &other, sp, "u").unwrap();
        assert_eq!(m.point_data["u"].values, vec![1.0, 2.0, 3.0]);
        let e = attach(&mut mesh(), mp, &other, sp, "v").unwrap_err();
        assert!(matches!(e, FieldError::NotScalar { components: 3, .. }), "{e}");

        other.point_data.insert("t".into(), DataArray::new(1, vec![0.0, f64::NAN, 0.0]));
        let e = field_name(&other, sp, None).unwrap_err().to_string();
        assert!(e.contains("several scalar point arrays (t, u)") && e.contains("--field"), "{e}");
        let e = attach(&mut mesh(), mp, &other, sp, "t").unwrap_err();
        assert!(matches!(e, FieldError::NotFinite { vertex: 1, .. }), "{e}");

        let mut moved = other.clone();
        moved.points[2][0] = 0.5;
        let e = attach(&mut mesh(), mp, &moved, sp, "u").unwrap_err();
        assert!(matches!(e, FieldError::Moved { vertex: 2, .. }), "{e}");
        let mut short = other.clone();
        short.points.pop();
        short.point_data.insert("u".into(), DataArray::new(1, vec![1.0, 2.0]));
        let e = attach(&mut mesh(), mp, &short, sp, "u").unwrap_err().to_string();
        assert!(e.contains("2 values of `u` for the 3 vertices of m.msh"), "{e}");
        let e = field_name(&mesh(), sp, None).unwrap_err().to_string();
        assert!(e.contains("no scalar point data (its point arrays: none)"), "{e}");
    }
}
