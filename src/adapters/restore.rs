//! What every adapter checks on its tool's result before the loop uses it: the physical
//! tags of the input are all there (the recipe names them), their names are attached
//! (Medit has none), and the vertex cells of topological points sit on a vertex of the
//! new mesh (a tool keeps required vertices but has no point elements).

use std::collections::BTreeSet;

use smartmesh_formats::{CellKind, TaggedMesh};

use super::AdapterError;

/// 0 for vertex cells, 1 for lines, 2 for surface cells, 3 for volume cells (the
/// dimension of Gmsh's physical groups, which tags and names are keyed by).
pub(crate) fn dimension(kind: CellKind) -> u8 {
    kind.dim()
}

/// The `(dimension, physical tag)` pairs that have cells, tag 0 (none) left out.
pub fn physical_tags(mesh: &TaggedMesh) -> BTreeSet<(u8, i32)> {
    mesh.cells().filter(|c| c.2 != 0).map(|(kind, _, p, _)| (dimension(kind), p)).collect()
}

/// Fails, naming them, when physical tags of `input` have no cell in `output`.
pub(crate) fn ensure_tags_kept(
    program: &str,
    input: &TaggedMesh,
    output: &TaggedMesh,
) -> Result<(), AdapterError> {
    let have = physical_tags(output);
    let lost: Vec<String> = physical_tags(input)
        .difference(&have)
        .map(|&(d, t)| match input.tag_name(d, t) {
            Some(name) => format!("{d}D tag {t} \"{name}\""),
            None => format!("{d}D tag {t}"),
        })
        .collect();
    if lost.is_empty() {
        Ok(())
    } else {
        Err(AdapterError::Lost {
            program: program.to_string(),
            what: format!("no cell carries {}", lost.join(", ")),
        })
    }
}

/// Gives `output` the tag names of `input` (those it does not name itself).
pub(crate) fn attach_names(input: &TaggedMesh, output: &mut TaggedMesh) {
    for (k, name) in &input.tag_names {
        output.tag_names.entry(*k).or_insert_with(|| name.clone());
    }
}

/// Puts each vertex cell of `input` on the vertex of `output` at the same place (within
/// 10⁻⁹ of the bounding-box diagonal: tools print coordinates with 15 digits; distances
/// in space, which in a planar mesh at z = 0 are the planar ones), and gives
/// that vertex the input's exact coordinates. A vertex cell with no vertex there means
/// the tool moved or removed a required point.
pub(crate) fn place_point_cells(
    program: &str,
    input: &TaggedMesh,
    output: &mut TaggedMesh,
) -> Result<(), AdapterError> {
    let cells: Vec<(usize, i32, i32)> = input
        .cells()
        .filter(|c| c.0 == CellKind::Vertex)
        .map(|(_, n, p, g)| (n[0] as usize, p, g))
        .collect();
    if cells.is_empty() {
        return Ok(());
    }
    let dist = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    let diag = input.bounding_box().map_or(1.0, |(lo, hi)| dist(lo, hi));
    let tol = 1e-9 * diag.max(f64::MIN_POSITIVE);
    let mut placed = Vec::with_capacity(cells.len());
    for (v, p, g) in cells {
        let q = input.points[v];
        let nearest = output
            .points
            .iter()
            .enumerate()
            .map(|(i, o)| (i, dist(*o, q)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match nearest {
            Some((i, d)) if d <= tol => {
                // Back to the exact input coordinates: no drift over iterations.
                output.points[i] = q;
                placed.push((i, p, g))
            }
            _ => {
                return Err(AdapterError::Lost {
                    program: program.to_string(),
                    what: format!(
                    "no vertex at ({}, {}, {}), the topological point of 0D tag {p} (it was required)",
                    q[0], q[1], q[2]
                ),
                })
            }
        }
    }
    let mut block = smartmesh_formats::CellBlock::new(CellKind::Vertex);
    for (i, p, g) in placed {
        if i >= smartmesh_formats::MAX_POINTS {
            return Err(AdapterError::Lost {
                program: program.to_string(),
                what: format!(
                    "vertex {i}: past the {} points a mesh can address",
                    smartmesh_formats::MAX_POINTS
                ),
            });
        }
        block.push(&[i], p, g);
    }
    output.blocks.insert(0, block);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(tag: i32) -> TaggedMesh {
        let mut m = TaggedMesh::new();
        m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        m.block_mut(CellKind::Triangle).push(&[0, 1, 2], tag, tag);
        m
    }

    #[test]
    fn lost_tags_are_named() {
        let mut input = square(5);
        input.tag_names.insert((2, 5), "Fluid".into());
        let e = ensure_tags_kept("mmg2d", &input, &square(6)).unwrap_err();
        assert!(e.to_string().contains("2D tag 5 \"Fluid\""), "{e}");
        assert!(ensure_tags_kept("mmg2d", &input, &square(5)).is_ok());
    }

    #[test]
    fn point_cells_follow_their_coordinates() {
        let mut input = square(1);
        input.block_mut(CellKind::Vertex).push(&[1], 20, 6);
        let mut output = square(1);
        output.points.swap(0, 1);
        place_point_cells("t", &input, &mut output).unwrap();
        assert_eq!(output.cells().find(|c| c.0 == CellKind::Vertex).unwrap().1, &[0]);
        let mut moved = square(1);
        moved.points[1][0] = 1.01;
        assert!(place_point_cells("t", &input, &mut moved).is_err());
    }
}
