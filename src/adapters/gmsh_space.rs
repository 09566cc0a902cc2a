//! Gmsh's 3D path ([`super::gmsh::GmshAdapter`]'s `adapt_space`): a tetrahedral mesh
//! remeshed by MMG3D inside Gmsh (`Mesh.Algorithm3D` 7) after BAMG (`Mesh.Algorithm`
//! 7) has remeshed its boundary surfaces, or a triangulated surface in space remeshed
//! by BAMG alone, both to a background `.pos` view of the 3D metric.
//!
//! Which Gmsh algorithms honour the field in 3D, measured with Gmsh 4.15.2 on the
//! discrete model of a smartmesh mesh (the [`VOLUME_SCRIPT`] below, UGAWG measures of
//! `smartmesh info --metric` against the recipe's field sized on each result):
//! - MMG3D (7) follows it: the Gmsh-made unit cube (341 vertices) with a wall layer on
//!   one face (normal size 0.02 → 0.3, tangential 0.15 → 0.3 over 0.5): 49.5 % of the
//!   edges in [1/√2, √2] before, 72.8 % after (2524 tetrahedra, longest edge 2.56,
//!   metric mean ratio 0.78); box_cyl with the cylinder's wall layer: 48.6 % → 54.9 %
//!   (35 387 tetrahedra, longest 2.34, mean ratio 0.79). `mmg3d_O3` on the same input
//!   and `.sol`: 30.2 % (cube) and 64.7 % (box_cyl) with its default gradation, 83.3 %
//!   and 73.9 % with `-hgrad -1`. Gmsh drives MMG3D with its own settings (gradation
//!   1.3, the boundary frozen: `-nosurf`), which the command line cannot change: its
//!   meshes are finer than the field asks (mean metric length 0.78 to 0.90);
//! - Delaunay (1), Frontal (4) and HXT (10) find no size in a tensor view (Gmsh's
//!   warning "No vector or scalar value found in PostView field") and fill the volume
//!   from the surface mesh: longest edges 7.8 to 9.7 in the metric, mean ratio 0.51;
//! - on a surface in space BAMG follows the view: box_cyl's boundary, 81.0 % → 87.4 %
//!   (longest 4.46 → 1.49), where `mmgs_O3` made 62.8 % (69.0 % with `-hgrad -1`);
//! - several volumes sharing a surface: Gmsh's one MMG3D call for them fails
//!   ("Mmg3d: unable to set mesh size"), the first volume alone meshed; such a mesh is
//!   refused ([`one_volume`]).
//!
//! One run, in a temporary directory that is removed afterwards (also when smartmesh is
//! interrupted), as the planar path does: the mesh [prepared](super::prepare) as
//! `in.msh` — without the input's Gmsh entities, which Gmsh 4.15.2's `CreateTopology`
//! crashed on (a segmentation fault on box_cyl's own `$Entities`, whose bounding curves
//! have no elements); the writer makes one entity per tag pair — and the metric as
//! `bgm.pos` (`TS` records on the tetrahedra, `TT` on a surface's triangles), then
//! `gmsh remesh.geo -setnumber Mesh.Algorithm 7 -setnumber Mesh.Algorithm3D 7
//! -setnumber Mesh.MeshSizeExtendFromBoundary 0 -setnumber Mesh.MeshSizeFromPoints 0
//! -setnumber Mesh.MeshSizeFromCurvature 0 [extra arguments…] -v 2 -nopopup
//! -parse_and_exit`, and `out.msh` read back: the physical tags and names as the planar
//! path brings them, the vertex cells put back on their points by position (Gmsh keeps
//! a discrete model's points, renumbering their entities).

use smartmesh_formats::{CellKind, Format, TaggedMesh, WriteOptions};

use super::gmsh::{run_script, PROGRAM};
use super::prepare::{prepare_space, Shape};
use super::restore::{attach_names, ensure_tags_kept, place_point_cells};
use super::{Adapted, AdapterError};
use crate::metric::Sym3;
use crate::metric_field::MetricField;

/// The script for a tetrahedral mesh. Line by line:
/// - `Merge "in.msh"`: the mesh, its physical groups in `$Entities`;
/// - `CreateTopology`: the discrete entities' boundaries (curves and points where
///   surfaces meet), so that each surface can be meshed on its own;
/// - `CreateGeometry`: a parametrisation of each discrete curve and surface, which BAMG
///   meshes in (the discrete volume is then the region they bound);
/// - `Merge "bgm.pos"; Background Mesh View[0]`: the metric as the size field;
/// - `Mesh 3`: curves, then surfaces (BAMG), then the volume (Delaunay, refined by MMG3D
///   to the view);
/// - `Mesh.MshFileVersion = 4.1; Save "out.msh"`: the elements of physical groups.
pub(crate) const VOLUME_SCRIPT: &str =
    "// Written by smartmesh: remesh in.msh to the background view bgm.pos (BAMG, MMG3D).
Merge \"in.msh\";
CreateTopology;
CreateGeometry;
Merge \"bgm.pos\";
Background Mesh View[0];
Mesh 3;
Mesh.MshFileVersion = 4.1;
Save \"out.msh\";
";

/// The script for a surface in space: the planar path's own ([`VOLUME_SCRIPT`] with
/// `Mesh 2`, BAMG alone), which meshes each discrete surface in its parametrisation.
pub(crate) const SURFACE_SCRIPT: &str = super::gmsh::SCRIPT;

/// The settings on Gmsh's command line, before the user's extra arguments (which may
/// override them).
pub(crate) const SETTINGS: [(&str, &str); 5] = [
    ("Mesh.Algorithm", "7"),
    ("Mesh.Algorithm3D", "7"),
    ("Mesh.MeshSizeExtendFromBoundary", "0"),
    ("Mesh.MeshSizeFromPoints", "0"),
    ("Mesh.MeshSizeFromCurvature", "0"),
];

/// The whole command line after the program.
fn args(extra: &[String]) -> Vec<String> {
    let mut a = vec!["remesh.geo".to_string()];
    for (name, value) in SETTINGS {
        a.extend(["-setnumber".to_string(), name.to_string(), value.to_string()]);
    }
    a.extend(extra.iter().cloned());
    a.extend(["-v", "2", "-nopopup", "-parse_and_exit"].iter().map(|s| s.to_string()));
    a
}

/// Remeshes `mesh` (tetrahedra with their boundary, or a surface in space) to `metric`
/// with the Gmsh at `program`, `extra` on its command line.
pub(crate) fn adapt_space(
    program: &std::path::Path,
    extra: &[String],
    mesh: &TaggedMesh,
    metric: &[Sym3],
) -> Result<Adapted, AdapterError> {
    let volume = mesh.blocks.iter().any(|b| b.kind.dim() == 3 && !b.is_empty());
    let shape = if volume { Shape::Volume } else { Shape::Surface };
    let mut prepared = prepare_space(mesh, metric.len(), shape)?;
    if prepared.mesh.points.iter().all(|p| p[2] == 0.0) {
        return Err(AdapterError::Kind(
            "gmsh: every vertex has z = 0, a planar mesh: it goes to the planar loop (`adapt --adapter gmsh`) with a 2D metric".into(),
        ));
    }
    prepared.mesh.entities.clear();
    if volume {
        one_volume(&mut prepared.mesh)?;
    }
    let dir = tempfile::Builder::new().prefix("smartmesh-gmsh3d-").tempdir().map_err(|source| {
        AdapterError::Io { what: "creating a temporary directory".into(), source }
    })?;
    let field = MetricField::new(prepared.metric(metric), "the metric");
    let pos = smartmesh_formats::gmsh::pos::write_tensor_view(
        &prepared.mesh,
        &field.to_array_3d(),
        crate::metric_field::METRIC,
    )?;
    let msh =
        smartmesh_formats::write_bytes(Format::Gmsh, &prepared.mesh, &WriteOptions::default())?;
    let script = if volume { VOLUME_SCRIPT } else { SURFACE_SCRIPT };
    let inputs =
        [("in.msh", &msh.main[..]), ("bgm.pos", &pos[..]), ("remesh.geo", script.as_bytes())];
    let (kind, what) =
        if volume { (CellKind::Tetra, "tetrahedron") } else { (CellKind::Triangle, "triangle") };
    let mut result = run_script(program, &args(extra), dir.path(), &inputs, kind, what)?;
    result.point_data.clear();
    result.cell_data.clear();
    // Gmsh gives the points of the discrete model entities of its own numbering: they are
    // put back as the input had them.
    result.blocks.retain(|b| b.kind != CellKind::Vertex);
    place_point_cells(PROGRAM, &prepared.mesh, &mut result)?;
    attach_names(&prepared.mesh, &mut result);
    ensure_tags_kept(PROGRAM, &prepared.mesh, &result)?;
    Ok(Adapted { mesh: result, stats: None })
}

/// Makes the tetrahedra of `mesh` one Gmsh volume entity (their elementary tag the
/// physical one: Gmsh numbers the discrete entities anew anyway), or refuses a mesh of
/// several physical volumes: Gmsh 4.15.2 meshes several volumes that share a surface
/// with one MMG3D call that fails ("Mmg3d: unable to set mesh size") and saves the
/// first volume alone — seen on two boxes sharing a face, as smartmesh's discrete model
/// and as Gmsh's own OpenCASCADE model meshed with `Mesh.Algorithm3D` 7.
fn one_volume(mesh: &mut TaggedMesh) -> Result<(), AdapterError> {
    let mut volumes = std::collections::BTreeSet::new();
    for b in mesh.blocks.iter_mut().filter(|b| b.kind == CellKind::Tetra) {
        for (g, &p) in b.geometrical.iter_mut().zip(&b.physical) {
            if p != 0 {
                *g = p;
            }
            volumes.insert((p, *g));
        }
    }
    if volumes.len() > 1 {
        let named: Vec<String> = volumes
            .iter()
            .map(|&(p, g)| match (p, mesh.tag_name(3, p)) {
                (0, _) => format!("untagged (elementary {g})"),
                (_, Some(name)) => format!("{p} \"{name}\""),
                (_, None) => p.to_string(),
            })
            .collect();
        return Err(AdapterError::Kind(format!(
            "gmsh: the tetrahedra make {} volumes ({}); Gmsh 4.15.2 meshes volumes that share a surface with one MMG3D call, which fails (\"Mmg3d: unable to set mesh size\") and leaves all but the first empty: a mesh of several volumes goes to mmg3d (--adapter mmg3d)",
            volumes.len(),
            named.join(", ")
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_come_first_and_the_users_arguments_override_them() {
        let a = args(&["-setnumber".into(), "Mesh.Algorithm3D".into(), "1".into()]);
        let at = |s: &str| a.iter().rposition(|x| x == s).unwrap();
        assert_eq!(a[0], "remesh.geo");
        // The user's Algorithm3D comes after smartmesh's, so Gmsh takes it.
        assert_eq!(a[at("Mesh.Algorithm3D") + 1], "1");
        assert!(at("Mesh.Algorithm3D") > at("Mesh.MeshSizeFromCurvature"));
        assert_eq!(a[a.len() - 1], "-parse_and_exit");
        assert!(VOLUME_SCRIPT.contains("Mesh 3;") && SURFACE_SCRIPT.contains("Mesh 2;"));
    }

    #[test]
    fn one_physical_volume_becomes_one_entity_and_two_are_refused() {
        let mut m = TaggedMesh::new();
        m.points = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        m.block_mut(CellKind::Tetra).push(&[0, 1, 2, 3], 10, 1);
        m.block_mut(CellKind::Tetra).push(&[0, 1, 2, 3], 10, 2);
        m.block_mut(CellKind::Triangle).push(&[0, 2, 1], 4, 7);
        one_volume(&mut m).unwrap();
        let tags: Vec<(i32, i32)> = m.cells().map(|c| (c.2, c.3)).collect();
        assert_eq!(tags, [(10, 10), (10, 10), (4, 7)]);
        m.tag_names.insert((3, 11), "B".into());
        m.block_mut(CellKind::Tetra).push(&[0, 1, 2, 3], 11, 3);
        let e = one_volume(&mut m).unwrap_err().to_string();
        assert!(e.contains("2 volumes (10, 11 \"B\")") && e.contains("mmg3d"), "{e}");
    }
}
