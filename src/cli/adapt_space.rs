//! `adapt` on a mesh in space: a tetrahedral mesh through `mmg3d_O3`, a triangulated
//! surface through `mmgs_O3` (or either through Gmsh: `--adapter gmsh`), each mesh
//! sized by the recipe's 3D engine ([`smartmesh::adapt::space`]). The result files, the
//! progress, Ctrl-C, the end of the run, the solver (`--solver`) and the vertex budget
//! (`--complexity`, or the recipe's own complexity with `--solver` alone) are the planar
//! command's (`adapt.rs`); this file only checks what the loop in space cannot do, picks
//! the remesher, gives the recipe's own complexity in space and starts the loop.

use std::path::Path;
use std::time::Instant;

use smartmesh::adapt::files::ResultFiles;
use smartmesh::adapt::space::{
    run_space_with_solver, RecipeInSpace, SURFACE_BUDGET, SURFACE_SOLVER,
};
use smartmesh::adapt::{AdaptOptions, Tolerances};
use smartmesh::expected_vertices;
use smartmesh::formats::{CellKind, Format, TaggedMesh};
use smartmesh::metric::SizeTensor3;
use smartmesh::recipe::size_mesh_in_space;
use smartmesh::Topology;
use smartmesh::{adapter, AdapterKind, AdapterOptions};

use super::{finish, handle_interrupts, is_stdio, ui, AdaptArgs, AdapterArg, CliError, Progress};

/// The remesher of a mesh in space: the one asked for (mmg3d, mmgs, gmsh), else mmg3d
/// for a mesh with tetrahedra and mmgs for a surface.
fn remesher(args: &AdaptArgs, tetrahedra: bool) -> Result<AdapterKind, CliError> {
    match args.adapter {
        AdapterArg::Mmg3d => Ok(AdapterKind::Mmg3d),
        AdapterArg::Mmgs => Ok(AdapterKind::Mmgs),
        AdapterArg::Gmsh if args.hausd.is_some() => Err(CliError::usage(format!(
            "{}: a mesh in space; --hausd with --adapter gmsh bounds a planar metric only (in space it is MMG's -hausd: --adapter mmg3d|mmgs)",
            crate::cli::input_name(&args.input)
        ))),
        AdapterArg::Gmsh => Ok(AdapterKind::Gmsh),
        AdapterArg::Native if tetrahedra => Ok(AdapterKind::Mmg3d),
        AdapterArg::Native => Ok(AdapterKind::Mmgs),
        AdapterArg::Mmg2d => Err(CliError::usage(format!(
            "{}: a mesh in space; --adapter mmg2d remeshes planar meshes: a tetrahedral mesh goes to mmg3d or gmsh, a surface in space to mmgs or gmsh (the default picks mmg3d or mmgs)",
            crate::cli::input_name(&args.input),
        ))),
    }
}

/// The options of the planar loop that the loop in space has not, refused before any
/// work (see [`smartmesh::adapt::space`] for why).
fn planar_only(args: &AdaptArgs, recipe: &smartmesh::Recipe) -> Result<(), CliError> {
    let planar = [
        ("--layer", args.layer),
        ("the recipe's LAYER section", recipe.layer.is_some() && !args.no_layer),
        ("the recipe's periodic sides", !recipe.periodic_pairs().is_empty()),
        ("--split-quads", args.split_quads),
        ("--coarsen-geometry", args.coarsen_geometry),
    ];
    if let Some((what, _)) = planar.iter().find(|o| o.1) {
        return Err(CliError::usage(format!(
            "{}: a mesh in space; {what} works on planar meshes only (the loop in space sizes with the recipe, remeshes with mmg3d or mmgs and measures as the UGAWG does)",
            crate::cli::input_name(&args.input)
        )));
    }
    Ok(())
}

/// What a surface in space cannot take: a budget (no volume cell to take the complexity
/// over) and a solver (no tetrahedra to recover its Hessian on).
fn volume_only(args: &AdaptArgs) -> Result<(), CliError> {
    let needs = [
        ("--complexity", args.solution.complexity.is_some(), SURFACE_BUDGET),
        ("--solver", args.solver.is_some(), SURFACE_SOLVER),
        ("--error", args.solution.error.is_some(), SURFACE_SOLVER),
        ("--field", !args.solution.field.is_empty(), SURFACE_SOLVER),
    ];
    if let Some((what, _, why)) = needs.iter().find(|o| o.1) {
        return Err(CliError::usage(format!(
            "{}: a surface in space (no volume cell); {what}: {why}",
            crate::cli::input_name(&args.input)
        )));
    }
    Ok(())
}

/// The recipe's own complexity on the mesh in space `mesh` (over its volume cells): the
/// budget of `--solver` without `--complexity` or `--error`, as in the plane.
fn recipe_vertices(
    args: &AdaptArgs,
    mesh: &TaggedMesh,
    recipe: &smartmesh::Recipe,
) -> Result<Option<f64>, CliError> {
    if !super::own_budget(args, recipe)? {
        return Ok(None);
    }
    let topology = Topology::from_mesh(mesh);
    let sized = size_mesh_in_space(mesh, &topology, recipe, &[], &mut |_| {})
        .map_err(|e| CliError::context(format!("{e} (input {})", args.input.display()), e))?;
    let metric: Vec<_> = sized.field.tensors.iter().map(SizeTensor3::to_metric).collect();
    Ok(Some(expected_vertices(mesh, &metric)))
}

/// Runs `adapt` on the mesh in space at `args.input`, with the recipe read and the
/// output checked (`format`).
pub(super) fn run(
    args: &AdaptArgs,
    recipe: &smartmesh::Recipe,
    format: Format,
    t0: Instant,
) -> Result<(), CliError> {
    planar_only(args, recipe)?;
    if is_stdio(&args.input) {
        return Err(CliError::usage(
            "a mesh in space on stdin: the loop in space reads its input from a file",
        ));
    }
    let from = args.from.or_else(|| Format::from_path(&args.input));
    let (mesh, read_notes) = crate::cli::read_linear_mesh_noted(&args.input, from)?;
    for n in &read_notes {
        ui::note(&format!("{}: {n}", args.input.display()));
    }
    let tetrahedra = mesh.num_cells_of(CellKind::Tetra) > 0;
    let kind = remesher(args, tetrahedra)?;
    if !tetrahedra {
        volume_only(args)?;
    }
    // The input is checked whole before any tool is looked for: a recipe that names tags
    // the mesh does not have is bad input (2) whether or not the remesher is installed.
    recipe
        .resolve(&Topology::from_mesh(&mesh))
        .map_err(|e| CliError::context(format!("{e} (input {})", args.input.display()), e))?;
    let own = recipe_vertices(args, &mesh, recipe)?;
    let solver = super::solver_loop(args, &mesh, recipe, own)?;
    let budget = super::budget(args, own);
    if let Some(b) = budget.as_ref().filter(|_| own.is_some()) {
        ui::note(&format!("vertex budget: {}", b.from));
    }
    let options = AdapterOptions {
        program: args.adapter_program.clone(),
        // Under a budget the recipe's gradation acts inside the normalisation: MMG's own
        // (1.3 by default) would grade the field again and spend vertices off the budget
        // (measured on box_cyl with a wall layer: 2 to 3.5 times the count asked, not
        // 1.4 to 1.6), so it is off unless --hgrad asks for it.
        // Gmsh drives MMG3D with its own gradation, which its command line cannot turn off
        // (adapters/gmsh_space.rs): --hgrad is then the recipe's gradation alone.
        hgrad: args.controls.hgrad.or(budget.as_ref().map(|_| -1.0)).filter(|_| kind.is_mmg()),
        hausd: args.hausd,
        nosurf: args.nosurf,
        // The loop's --hmin/--hmax bound the recipe's field, which MMG then follows.
        extra_args: args.adapter_args.clone(),
        ..AdapterOptions::default()
    };
    let remesher = adapter(kind, options)?;
    let opts = AdaptOptions {
        max_iterations: args.max_iterations,
        tolerances: Tolerances { vertices: args.tol_vertices, conformity: args.tol_conformity },
        max_vertices: Some(args.max_vertices),
        max_growth: (args.max_growth > 0.0).then_some(args.max_growth),
        budget,
        ..AdaptOptions::default()
    };
    let to_stdout = is_stdio(&args.output);
    let mesh_file = if to_stdout { Path::new("stdout.msh") } else { args.output.as_path() };
    let progress = Progress {
        files: ResultFiles::new(
            mesh_file,
            args.history.as_deref(),
            args.output_format.write_options(&args.output),
        )
        .with_format(format),
        to_stdout,
        bar: ui::progress_bar(opts.max_iterations as u64, "{bar:30} {pos}/{len} {msg} [{elapsed}]"),
        adapter: remesher.name().to_string(),
        printed: 0,
        plane_z: None,
    };
    let mut progress = progress;
    handle_interrupts();
    let input = args.input.display().to_string();
    let result = run_space_with_solver(
        mesh,
        &RecipeInSpace(recipe),
        solver.as_ref(),
        remesher.as_ref(),
        &opts,
        &input,
        &args.recipe.label(),
        &mut progress,
    );
    finish(args, result, progress, &read_notes, format, None, t0)
}
