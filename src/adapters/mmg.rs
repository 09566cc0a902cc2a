//! MMG's remeshers as an [`Adapter`]: `mmg2d_O3` for planar meshes ([`Adapter::adapt`]),
//! `mmg3d_O3` for tetrahedral meshes and `mmgs_O3` for triangulated surfaces in space
//! ([`Adapter::adapt_space`]). One [`Tool`] per program; everything else is shared.
//!
//! One run, in a temporary directory that is removed afterwards (also when smartmesh is
//! interrupted: the program is stopped, see [`super::tool`]):
//! 1. the mesh is [prepared](super::prepare) and written as `in.mesh` (Medit ASCII) with
//!    the metric in `in.sol` (type 3: m11 m12 m22 in 2D; m11 m12 m22 m13 m23 m33 in 3D,
//!    the Medit file order, which MMG's reader turns into its own);
//! 2. `PROGRAM -in in.mesh -sol in.sol -out out.mesh -v 1 [-hgrad G] [-hausd D]
//!    [-hmin H] [-hmax H] [-ar A] [-nr] [-nosurf] [extra arguments…]` runs (`-nosurf`
//!    not for mmgs, which has none); a non-zero exit is an error quoting its output;
//! 3. `out.mesh` is read back and its tags restored.
//!
//! Tags. Medit keeps one reference per element, MMG carries references through
//! remeshing. Each distinct (physical, geometrical) pair of a dimension gets its own
//! reference (1, 2, … in sorted order), so that both tags come back exactly and the
//! boundaries between Gmsh entities of one physical group stay where they are. Every
//! topological point — the vertex cells, the ends and junctions of curves, and where the
//! reference changes along a curve — is written as a `Corners` and `RequiredVertices`
//! entry: MMG keeps it in place, and the vertex cells are put back on it by position.
//! In 3D the triangle references are those of the boundary surfaces (Gmsh's physical
//! surfaces), the tetrahedron references those of the volumes; the curves given as
//! lines are kept by MMG as reference edges.
//!
//! MMG moves new boundary points onto a smooth reconstruction of curved boundaries
//! (DESIGN.md); `-nosurf` leaves the boundary as it is, which also keeps it from being
//! refined. Edges MMG writes with reference 0 (boundary pieces that had no line cell,
//! and in 3D the ridges it found by angle) are left out, as they were in the input; in
//! 3D so are triangles of reference 0 (boundary MMG closed where the input gave no
//! triangle). Any other reference smartmesh did not write is an error.

use std::collections::BTreeMap;
use std::path::Path;

use smartmesh_formats::{
    read_path, CellBlock, CellKind, DataArray, Format, TaggedMesh, WriteOptions,
};

use super::prepare::{prepare, prepare_space, Prepared, Shape};
use super::restore::{attach_names, ensure_tags_kept, place_point_cells};
use super::tool::{find_program, run};
use super::{Adapted, Adapter, AdapterError, AdapterOptions};
use crate::metric::{Sym2, Sym3};
use crate::metric_field::MetricField;
use crate::topology::Topology;

/// The program looked up on `PATH` for mmg2d.
pub(crate) const PROGRAM: &str = "mmg2d_O3";

/// One of MMG's three remeshers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Tool {
    /// `mmg2d_O3`: planar triangle meshes.
    Mmg2d,
    /// `mmg3d_O3`: tetrahedral meshes.
    Mmg3d,
    /// `mmgs_O3`: triangulated surfaces in space.
    Mmgs,
}

impl Tool {
    /// The adapter's name (`--adapter`, `history.json`).
    pub(crate) fn name(self) -> &'static str {
        match self {
            Tool::Mmg2d => "mmg2d",
            Tool::Mmg3d => "mmg3d",
            Tool::Mmgs => "mmgs",
        }
    }

    /// The program looked up on `PATH`.
    pub(crate) fn program(self) -> &'static str {
        match self {
            Tool::Mmg2d => PROGRAM,
            Tool::Mmg3d => "mmg3d_O3",
            Tool::Mmgs => "mmgs_O3",
        }
    }

    fn hint(self) -> &'static str {
        match self {
            Tool::Mmg2d => "install MMG (`pip install mmgpy` puts mmg2d_O3 on PATH) or name the executable with --adapter-program",
            Tool::Mmg3d => "install MMG (`pip install mmgpy` puts mmg3d_O3 on PATH) or name the executable with --adapter-program",
            Tool::Mmgs => "install MMG (`pip install mmgpy` puts mmgs_O3 on PATH) or name the executable with --adapter-program",
        }
    }

    /// The meshes it takes.
    fn shape(self) -> Shape {
        match self {
            Tool::Mmg2d => Shape::Planar,
            Tool::Mmg3d => Shape::Volume,
            Tool::Mmgs => Shape::Surface,
        }
    }
}

/// An MMG program with its options.
#[derive(Debug, Clone)]
pub(crate) struct MmgAdapter {
    tool: Tool,
    program: std::path::PathBuf,
    options: AdapterOptions,
}

impl MmgAdapter {
    /// Finds the program (`options.program`, else the tool's on `PATH`); refuses the
    /// options the tool does not have (mmgs has no `-nosurf`).
    pub(crate) fn new(tool: Tool, options: AdapterOptions) -> Result<MmgAdapter, AdapterError> {
        if tool == Tool::Mmgs && options.nosurf {
            return Err(AdapterError::Kind(
                "--nosurf: mmgs_O3 has no -nosurf (a surface remesher changes the surface); use --adapter-arg -noinsert or -nomove to restrict it".into(),
            ));
        }
        let program = find_program(tool.program(), options.program.as_deref(), tool.hint())?;
        Ok(MmgAdapter { tool, program, options })
    }

    /// The arguments after the file names.
    fn option_args(&self) -> Vec<String> {
        let mut a = vec!["-v".to_string(), "1".to_string()];
        let o = &self.options;
        for (flag, value) in [
            ("-hgrad", o.hgrad),
            ("-hausd", o.hausd),
            ("-hmin", o.hmin),
            ("-hmax", o.hmax),
            ("-ar", o.ridge_angle),
        ] {
            if let Some(v) = value {
                a.extend([flag.to_string(), v.to_string()]);
            }
        }
        if o.no_ridges {
            a.push("-nr".to_string());
        }
        if o.nosurf {
            a.push("-nosurf".to_string());
        }
        a.extend(o.extra_args.iter().cloned());
        a
    }

    /// Runs the tool on `prepared` (coded as `coded`) with the solution file `sol`, and
    /// reads its result back with the input's tags, names and entities.
    fn run_on(
        &self,
        prepared: &Prepared,
        coded: &Coded,
        sol: &[u8],
    ) -> Result<TaggedMesh, AdapterError> {
        let dir = tempfile::Builder::new()
            .prefix(&format!("smartmesh-{}-", self.tool.name()))
            .tempdir()
            .map_err(|source| AdapterError::Io {
                what: "creating a temporary directory".into(),
                source,
            })?;
        write_input(dir.path(), prepared, coded, sol)?;
        let mut args: Vec<String> = ["-in", "in.mesh", "-sol", "in.sol", "-out", "out.mesh"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        args.extend(self.option_args());
        run(&self.program, &args, dir.path())?;
        let out = read_path(&dir.path().join("out.mesh"), Some(Format::Medit))?;
        let mut result = coded.decode(self.name(), &out, self.tool != Tool::Mmg2d)?;
        place_point_cells(self.name(), &prepared.mesh, &mut result)?;
        attach_names(&prepared.mesh, &mut result);
        result.entities = prepared.mesh.entities.clone();
        result.holes = prepared.mesh.holes.clone();
        result.regions = prepared.mesh.regions.clone();
        ensure_tags_kept(self.name(), &prepared.mesh, &result)?;
        Ok(result)
    }
}

impl Adapter for MmgAdapter {
    fn name(&self) -> &str {
        self.tool.name()
    }

    fn adapt(
        &self,
        mesh: &TaggedMesh,
        _topology: &Topology,
        metric: &[Sym2],
    ) -> Result<Adapted, AdapterError> {
        if self.tool != Tool::Mmg2d {
            return Err(AdapterError::Kind(format!(
                "{} remeshes meshes in space to a 3D metric; a planar mesh with a 2D metric goes to mmg2d (--adapter mmg2d)",
                self.tool.name()
            )));
        }
        let prepared = prepare(mesh, metric)?;
        let coded = Coded::new(&prepared.mesh);
        let sol = MetricField::new(prepared.metric(metric), "the metric").sol_bytes(false)?;
        let result = self.run_on(&prepared, &coded, &sol)?;
        Ok(Adapted { mesh: result, stats: None })
    }

    fn adapt_space(&self, mesh: &TaggedMesh, metric: &[Sym3]) -> Result<Adapted, AdapterError> {
        if self.tool == Tool::Mmg2d {
            return Err(AdapterError::Kind(
                "mmg2d remeshes planar meshes; a tetrahedral mesh goes to mmg3d, a surface in space to mmgs, either to Gmsh (--adapter mmg3d|mmgs|gmsh)".into(),
            ));
        }
        let prepared = prepare_space(mesh, metric.len(), self.tool.shape())?;
        if prepared.mesh.points.iter().all(|p| p[2] == 0.0) {
            // The Medit writer writes such a mesh as `Dimension 2`, which mmg3d and mmgs
            // refuse: it is a planar mesh.
            return Err(AdapterError::Kind(format!(
                "{}: every vertex has z = 0, a planar mesh: it goes to mmg2d or the native remesher with a 2D metric",
                self.tool.name()
            )));
        }
        let coded = Coded::new(&prepared.mesh);
        let values: Vec<f64> =
            prepared.metric(metric).iter().flat_map(|m| m.to_row_major()).collect();
        let array = DataArray::new(9, values);
        let sol = smartmesh_formats::medit::write_sol(&[("metric", &array)], 3, false)?;
        let result = self.run_on(&prepared, &coded, &sol)?;
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
    /// Tetrahedron references, the same way.
    tetrahedra: Vec<(i32, i32)>,
}

impl Coded {
    /// Numbers the tag pairs of `mesh`'s lines and triangles in sorted order.
    pub(crate) fn new(mesh: &TaggedMesh) -> Coded {
        let pairs = |kind: CellKind| -> Vec<(i32, i32)> {
            let set: std::collections::BTreeSet<(i32, i32)> =
                mesh.cells().filter(|c| c.0 == kind).map(|c| (c.2, c.3)).collect();
            set.into_iter().collect()
        };
        Coded {
            lines: pairs(CellKind::Line),
            triangles: pairs(CellKind::Triangle),
            tetrahedra: pairs(CellKind::Tetra),
        }
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
                CellKind::Tetra => &self.tetrahedra,
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
    /// left out, and in `space` (mmg3d, mmgs) triangles of reference 0 too; any other
    /// unknown reference is an error. In `space` the coordinates are kept, else put on
    /// z = 0.
    pub(crate) fn decode(
        &self,
        program: &str,
        out: &TaggedMesh,
        space: bool,
    ) -> Result<TaggedMesh, AdapterError> {
        let mut mesh = TaggedMesh::new();
        mesh.points = if space {
            out.points.clone()
        } else {
            out.points.iter().map(|p| [p[0], p[1], 0.0]).collect()
        };
        let mut lines = CellBlock::new(CellKind::Line);
        let mut triangles = CellBlock::new(CellKind::Triangle);
        let mut tetrahedra = CellBlock::new(CellKind::Tetra);
        for (kind, nodes, r, _) in out.cells() {
            let (table, block) = match kind {
                CellKind::Line => (&self.lines, &mut lines),
                CellKind::Triangle => (&self.triangles, &mut triangles),
                CellKind::Tetra if space => (&self.tetrahedra, &mut tetrahedra),
                other => {
                    return Err(AdapterError::Lost {
                        program: program.into(),
                        what: format!("{} cells, which smartmesh did not give it", other.name()),
                    })
                }
            };
            if r == 0 && (kind == CellKind::Line || (space && kind == CellKind::Triangle)) {
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
        for b in [lines, triangles, tetrahedra] {
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
    let mut req = required_vertices_space(mesh);
    req.extend(Topology::from_mesh(mesh).points.iter().map(|p| p.vertex));
    req.sort_unstable();
    req.dedup();
    req
}

/// The vertices MMG must keep in a mesh in space: vertex cells, the ends and junctions
/// of the curves given as lines, and where the line reference changes along a curve,
/// sorted. (The planar [`required_vertices`] adds the planar topology's points, which
/// recovers the same points from the lines.)
pub(crate) fn required_vertices_space(mesh: &TaggedMesh) -> Vec<usize> {
    let mut req: Vec<usize> =
        mesh.cells().filter(|c| c.0 == CellKind::Vertex).map(|c| c.1[0] as usize).collect();
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
    sol: &[u8],
) -> Result<(), AdapterError> {
    let mut medit = coded.encode(&prepared.mesh);
    let volume = prepared.mesh.blocks.iter().any(|b| b.kind.dim() == 3);
    let space = volume || prepared.mesh.points.iter().any(|p| p[2] != 0.0);
    let required = if space {
        required_vertices_space(&prepared.mesh)
    } else {
        required_vertices(&prepared.mesh)
    };
    medit.point_sets.insert("Corners".into(), required.clone());
    medit.point_sets.insert("RequiredVertices".into(), required);
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
    std::fs::write(dir.join("in.sol"), sol).map_err(|e| io("in.sol", e))?;
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
        let back = coded.decode("mmg2d", &encoded, false).unwrap();
        let tags: Vec<(i32, i32)> = back.cells().map(|c| (c.2, c.3)).collect();
        assert_eq!(tags, [(4, 5), (4, 6), (3, 1), (10, 1), (10, 1)]);
        let mut bad = encoded.clone();
        bad.blocks[1].physical[0] = 7;
        assert!(coded.decode("mmg2d", &bad, false).is_err());
        // Vertex 1 is where the reference changes inside physical curve 4, 0 and 3 are
        // curve ends, 2 a junction of two tags.
        assert_eq!(required_vertices(&m), [0, 1, 2, 3]);
    }
}
