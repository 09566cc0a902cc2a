//! MMG's 2D remesher, `mmg2d_O3`, as an [`Adapter`].
//!
//! One run, in a temporary directory that is removed afterwards (also when smartmesh is
//! interrupted: the program is stopped, see [`super::tool`]):
//! 1. the mesh is [prepared](super::prepare) and written as `in.mesh` (Medit ASCII) with
//!    the metric in `in.sol` (type 3, m11 m12 m22);
//! 2. `mmg2d_O3 -in in.mesh -sol in.sol -out out.mesh -v 1 [-hgrad G] [-hausd D]
//!    [-nosurf] [extra arguments…]` runs; a non-zero exit is an error quoting its output;
//! 3. `out.mesh` is read back and its tags restored.
//!
//! Tags. Medit keeps one reference per element, MMG carries references through
//! remeshing. Each distinct (physical, geometrical) pair of a dimension gets its own
//! reference (1, 2, … in sorted order), so that both tags come back exactly and the
//! boundaries between Gmsh entities of one physical group stay where they are. Every
//! topological point — the vertex cells, the ends and junctions of curves, and where the
//! reference changes along a curve — is written as a `Corners` and `RequiredVertices`
//! entry: MMG keeps it in place, and the vertex cells are put back on it by position.
//!
//! MMG moves new boundary points onto a smooth reconstruction of curved boundaries
//! (DESIGN.md); `-nosurf` leaves the boundary as it is, which also keeps it from being
//! refined. Edges MMG writes with reference 0 (boundary pieces that had no line cell)
//! are left out, as they were in the input.

use std::collections::BTreeMap;
use std::path::Path;

use smartmesh_formats::{read_path, CellBlock, CellKind, Format, TaggedMesh, WriteOptions};

use super::prepare::{prepare, Prepared};
use super::restore::{attach_names, ensure_tags_kept, place_point_cells};
use super::tool::{find_program, run};
use super::{Adapted, Adapter, AdapterError, AdapterOptions};
use crate::metric::Sym2;
use crate::metric_field::MetricField;
use crate::topology::Topology;

/// The program looked up on `PATH`.
pub(crate) const PROGRAM: &str = "mmg2d_O3";

const HINT: &str = "install MMG (`pip install mmgpy` puts mmg2d_O3 on PATH) or name the executable with --adapter-program";

/// `mmg2d_O3` with its options.
#[derive(Debug, Clone)]
pub(crate) struct MmgAdapter {
    program: std::path::PathBuf,
    options: AdapterOptions,
}

impl MmgAdapter {
    /// Finds the program (`options.program`, else `mmg2d_O3` on `PATH`).
    pub(crate) fn new(options: AdapterOptions) -> Result<MmgAdapter, AdapterError> {
        let program = find_program(PROGRAM, options.program.as_deref(), HINT)?;
        Ok(MmgAdapter { program, options })
    }

    /// The arguments after the file names.
    fn option_args(&self) -> Vec<String> {
        let mut a = vec!["-v".to_string(), "1".to_string()];
        if let Some(g) = self.options.hgrad {
            a.extend(["-hgrad".to_string(), g.to_string()]);
        }
        if let Some(d) = self.options.hausd {
            a.extend(["-hausd".to_string(), d.to_string()]);
        }
        if self.options.nosurf {
            a.push("-nosurf".to_string());
        }
        a.extend(self.options.extra_args.iter().cloned());
        a
    }
}

impl Adapter for MmgAdapter {
    fn name(&self) -> &str {
        "mmg2d"
    }

    fn adapt(
        &self,
        mesh: &TaggedMesh,
        _topology: &Topology,
        metric: &[Sym2],
    ) -> Result<Adapted, AdapterError> {
        let prepared = prepare(mesh, metric)?;
        let coded = Coded::new(&prepared.mesh);
        let dir =
            tempfile::Builder::new().prefix("smartmesh-mmg2d-").tempdir().map_err(|source| {
                AdapterError::Io { what: "creating a temporary directory".into(), source }
            })?;
        write_input(dir.path(), &prepared, &coded, metric)?;
        let mut args: Vec<String> = ["-in", "in.mesh", "-sol", "in.sol", "-out", "out.mesh"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        args.extend(self.option_args());
        run(&self.program, &args, dir.path())?;
        let out = read_path(&dir.path().join("out.mesh"), Some(Format::Medit))?;
        let mut result = coded.decode(self.name(), &out)?;
        place_point_cells(self.name(), &prepared.mesh, &mut result)?;
        attach_names(&prepared.mesh, &mut result);
        result.entities = prepared.mesh.entities.clone();
        result.holes = prepared.mesh.holes.clone();
        result.regions = prepared.mesh.regions.clone();
        ensure_tags_kept(self.name(), &prepared.mesh, &result)?;
        Ok(Adapted { mesh: result, stats: None })
    }
}

/// The Medit references of a prepared mesh: one per (dimension, physical, geometrical).
#[derive(Debug, Clone)]
pub(crate) struct Coded {
    /// Edge references: `lines[r - 1]` is the (physical, geometrical) pair of reference r.
    lines: Vec<(i32, i32)>,
    /// Triangle references, the same way.
    triangles: Vec<(i32, i32)>,
}

impl Coded {
    /// Numbers the tag pairs of `mesh`'s lines and triangles in sorted order.
    pub(crate) fn new(mesh: &TaggedMesh) -> Coded {
        let pairs = |kind: CellKind| -> Vec<(i32, i32)> {
            let set: std::collections::BTreeSet<(i32, i32)> =
                mesh.cells().filter(|c| c.0 == kind).map(|c| (c.2, c.3)).collect();
            set.into_iter().collect()
        };
        Coded { lines: pairs(CellKind::Line), triangles: pairs(CellKind::Triangle) }
    }

    fn code(table: &[(i32, i32)], pair: (i32, i32)) -> i32 {
        // Every pair was numbered from this mesh, so the search succeeds.
        table.binary_search(&pair).map_or(0, |i| i as i32 + 1)
    }

    /// The mesh with references for tags, as written for MMG.
    pub(crate) fn encode(&self, mesh: &TaggedMesh) -> TaggedMesh {
        let mut out = TaggedMesh::new();
        out.points = mesh.points.clone();
        for b in &mesh.blocks {
            let table = match b.kind {
                CellKind::Line => &self.lines,
                CellKind::Triangle => &self.triangles,
                _ => continue,
            };
            let mut block = CellBlock::new(b.kind);
            for (i, cell) in b.cells().enumerate() {
                let r = Coded::code(table, (b.physical[i], b.geometrical[i]));
                block.push(cell, r, r);
            }
            out.blocks.push(block);
        }
        out
    }

    /// MMG's result with the tags its references stand for. Edges of reference 0 are
    /// left out; any other unknown reference is an error.
    pub(crate) fn decode(
        &self,
        program: &str,
        out: &TaggedMesh,
    ) -> Result<TaggedMesh, AdapterError> {
        let mut mesh = TaggedMesh::new();
        mesh.points = out.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let mut lines = CellBlock::new(CellKind::Line);
        let mut triangles = CellBlock::new(CellKind::Triangle);
        for (kind, nodes, r, _) in out.cells() {
            let (table, block) = match kind {
                CellKind::Line => (&self.lines, &mut lines),
                CellKind::Triangle => (&self.triangles, &mut triangles),
                other => {
                    return Err(AdapterError::Lost {
                        program: program.into(),
                        what: format!("{} cells, which smartmesh did not give it", other.name()),
                    })
                }
            };
            if kind == CellKind::Line && r == 0 {
                continue;
            }
            match usize::try_from(r).ok().and_then(|r| r.checked_sub(1)).and_then(|i| table.get(i))
            {
                Some(&(p, g)) => block.push(nodes, p, g),
                None => {
                    return Err(AdapterError::Lost {
                        program: program.into(),
                        what: format!(
                            "a {} with reference {r}, which smartmesh did not write",
                            kind.name()
                        ),
                    })
                }
            }
        }
        for b in [lines, triangles] {
            if !b.is_empty() {
                mesh.blocks.push(b);
            }
        }
        Ok(mesh)
    }
}

/// The vertices MMG must keep: vertex cells, the topological points of the mesh (curve
/// ends and junctions), and the vertices where the line reference changes, sorted.
pub(crate) fn required_vertices(mesh: &TaggedMesh) -> Vec<usize> {
    let mut req: Vec<usize> =
        mesh.cells().filter(|c| c.0 == CellKind::Vertex).map(|c| c.1[0] as usize).collect();
    req.extend(Topology::from_mesh(mesh).points.iter().map(|p| p.vertex));
    let mut around: BTreeMap<usize, Vec<(i32, i32)>> = BTreeMap::new();
    for (kind, n, p, g) in mesh.cells() {
        if kind == CellKind::Line {
            around.entry(n[0] as usize).or_default().push((p, g));
            around.entry(n[1] as usize).or_default().push((p, g));
        }
    }
    for (v, pairs) in around {
        if pairs.len() != 2 || pairs[0] != pairs[1] {
            req.push(v);
        }
    }
    req.sort_unstable();
    req.dedup();
    req
}

fn write_input(
    dir: &Path,
    prepared: &Prepared,
    coded: &Coded,
    metric: &[Sym2],
) -> Result<(), AdapterError> {
    let mut medit = coded.encode(&prepared.mesh);
    let required = required_vertices(&prepared.mesh);
    medit.point_sets.insert("Corners".into(), required.clone());
    medit.point_sets.insert("RequiredVertices".into(), required);
    let sol = MetricField::new(prepared.metric(metric), "the metric").sol_bytes(false)?;
    let written = smartmesh_formats::write_bytes(
        Format::Medit,
        &medit,
        &WriteOptions { main_name: Some("in.mesh".into()), ..WriteOptions::default() },
    )?;
    let io = |what: &str, source| AdapterError::Io {
        what: format!("writing {what} in {}", dir.display()),
        source,
    };
    std::fs::write(dir.join("in.mesh"), &written.main).map_err(|e| io("in.mesh", e))?;
    std::fs::write(dir.join("in.sol"), &sol).map_err(|e| io("in.sol", e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_round_trip_both_tags() {
        let mut m = TaggedMesh::new();
        m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        m.block_mut(CellKind::Line).push(&[0, 1], 4, 5);
        m.block_mut(CellKind::Line).push(&[1, 2], 4, 6);
        m.block_mut(CellKind::Line).push(&[2, 3], 3, 1);
        m.block_mut(CellKind::Triangle).push(&[0, 1, 2], 10, 1);
        m.block_mut(CellKind::Triangle).push(&[0, 2, 3], 10, 1);
        let coded = Coded::new(&m);
        let encoded = coded.encode(&m);
        let refs: Vec<i32> = encoded.cells().map(|c| c.2).collect();
        assert_eq!(refs, [2, 3, 1, 1, 1]);
        let back = coded.decode("mmg2d", &encoded).unwrap();
        let tags: Vec<(i32, i32)> = back.cells().map(|c| (c.2, c.3)).collect();
        assert_eq!(tags, [(4, 5), (4, 6), (3, 1), (10, 1), (10, 1)]);
        let mut bad = encoded.clone();
        bad.blocks[1].physical[0] = 7;
        assert!(coded.decode("mmg2d", &bad).is_err());
        // Vertex 1 is where the reference changes inside physical curve 4, 0 and 3 are
        // curve ends, 2 a junction of two tags.
        assert_eq!(required_vertices(&m), [0, 1, 2, 3]);
    }
}
