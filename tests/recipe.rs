//! Recipes: the libconfig syntax, cpp, the spelling variants of the thesis, TOML and
//! JSON, suggestions, resolution against a mesh and its dimension rule, round trips.

use std::path::{Path, PathBuf};

use smartmesh::formats::read_path;
use smartmesh::recipe::{AlgorithmSpec, EntityRef, FunctionSpec, Recipe, RecipeErrorKind, RecipeFormat};
use smartmesh::sizing::{Algorithm, DistanceFunction};
use smartmesh::topology::Topology;

fn appendix_example() -> PathBuf {
    let p = std::env::var("SMARTMESH_SHARED").map(PathBuf::from).unwrap_or_else(|_| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared"));
    p.join("reference/appendix-a-example.cfg")
}

fn distributor() -> Topology {
    let mesh = read_path(&Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/distributor.msh"), None).unwrap();
    Topology::from_mesh(&mesh)
}

fn cfg(text: &str) -> Result<Recipe, smartmesh::RecipeError> {
    Recipe::from_str(text, RecipeFormat::Libconfig, Path::new("recipe.cfg"))
}

fn has_cpp() -> bool {
    std::process::Command::new("cpp").arg("--version").output().is_ok_and(|o| o.status.success())
}

#[test]
fn appendix_example_parses_and_resolves_on_the_distributor() {
    if !has_cpp() {
        eprintln!("skipped: no cpp (the example uses #define)");
        return;
    }
    let r = Recipe::from_path(&appendix_example()).unwrap();
    let resolved = r.resolve(&distributor()).unwrap();
    for s in &resolved.plan.steps {
        println!("{}", s.label);
    }
    for rr in &resolved.regions {
        println!("{rr:?}");
    }
}
