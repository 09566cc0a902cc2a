//! The triangulated sheet of DISTANCE_TO_IMAGINARY_SURFACE (a wake, a shock surface):
//! read, when the recipe is resolved, from the file its `FILE` key names, through the
//! formats crate's own readers (any format it reads that holds triangles: `.stl`,
//! `.obj`, `.mesh`, `.msh`, `.vtk`/`.vtu`, …).
//!
//! The path is relative to the recipe file that wrote the key (an included file's own
//! folder for a key written there), absolute paths as they are; it is data: opened as a
//! file, never given to a shell or a program. Only regular files are read (a FIFO or a
//! device would block or never end). The sheet is the file's triangles, quads split
//! along their 0–2 diagonal, second-order cells by their corners; its other cells
//! (lines, vertices, volume cells) are left out, and so are the points no triangle uses.
//! A file with no triangle is an error, as is a triangle with a non-finite corner.

use std::path::{Path, PathBuf};

use smartmesh_formats::{read_path, CellKind};

use crate::sizing::algorithms::Sheet;

/// The sheet the recipe file `recipe` names as `written`; why not, in words naming the
/// path as resolved and the reader's error.
pub(crate) fn read_sheet(recipe: Option<&Path>, written: &str) -> Result<Sheet, String> {
    if written.is_empty() {
        return Err("no file named: FILE takes the path of a triangulated surface".into());
    }
    let given = Path::new(written);
    let path: PathBuf = match recipe.and_then(Path::parent) {
        Some(dir) if given.is_relative() => dir.join(given),
        _ => given.to_path_buf(),
    };
    let shown = path.display();
    match std::fs::metadata(&path) {
        Err(e) => return Err(format!("cannot read {shown}: {e}")),
        Ok(m) if !m.is_file() => return Err(format!("{shown} is not a regular file")),
        Ok(_) => {}
    }
    let mesh = read_path(&path, None).map_err(|e| format!("cannot read {shown}: {e}"))?;
    let n = mesh.points.len();
    let mut local = vec![u32::MAX; n];
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for block in &mesh.blocks {
        let kind = block.kind.linear();
        let splits: &[[usize; 3]] = match kind {
            CellKind::Triangle => &[[0, 1, 2]],
            CellKind::Quad => &[[0, 1, 2], [0, 2, 3]],
            _ => continue,
        };
        for cell in block.cells() {
            for split in splits {
                let mut t = [0u32; 3];
                for (k, &c) in split.iter().enumerate() {
                    let v = cell[c] as usize;
                    let p = *mesh.points.get(v).ok_or_else(|| {
                        format!("{shown}: a cell names point {v}, but the file has {n}")
                    })?;
                    if !p.iter().all(|x| x.is_finite()) {
                        return Err(format!("{shown}: point {v} has a non-finite coordinate"));
                    }
                    if local[v] == u32::MAX {
                        local[v] = points.len() as u32;
                        points.push(p);
                    }
                    t[k] = local[v];
                }
                triangles.push(t);
            }
        }
    }
    if triangles.is_empty() {
        return Err(format!(
            "{shown} holds no triangle: a sheet is a triangulated surface (.stl, .obj, .mesh, .msh, …)"
        ));
    }
    Ok(Sheet { path, points, triangles })
}
