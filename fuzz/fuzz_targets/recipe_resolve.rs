//! Fuzz target: a recipe (libconfig, TOML or JSON: the first byte chooses) resolved
//! against a small mesh whose tags clash across dimensions must give Ok or Err, never
//! panic, and a plan whose entity indices all exist in the topology.
#![no_main]

use std::path::Path;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use smartmesh::formats::{CellBlock, CellKind, TaggedMesh};
use smartmesh::recipe::{ReadOptions, Recipe, RecipeFormat};
use smartmesh::sizing::EntitySet;
use smartmesh::Topology;

/// A unit square in two triangles (face tag 1 "Plate", face tag 3 on the second), its
/// bottom line tag 1 "Bottom", its right line tag 2, vertex cells tag 2 and tag 5
/// "Corner": tag 1 is a face and a curve, tag 2 a curve and a point.
fn topology() -> &'static Topology {
    static TOPOLOGY: OnceLock<Topology> = OnceLock::new();
    TOPOLOGY.get_or_init(|| {
        let mut m = TaggedMesh::new();
        m.points = vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
        let mut t = CellBlock::new(CellKind::Triangle);
        t.push(&[0, 1, 2], 1, 1);
        t.push(&[0, 2, 3], 3, 3);
        let mut l = CellBlock::new(CellKind::Line);
        l.push(&[0, 1], 1, 1);
        l.push(&[1, 2], 2, 2);
        let mut v = CellBlock::new(CellKind::Vertex);
        v.push(&[2], 2, 2);
        v.push(&[0], 5, 5);
        m.blocks = vec![v, l, t];
        m.tag_names.insert((2, 1), "Plate".into());
        m.tag_names.insert((1, 1), "Bottom".into());
        m.tag_names.insert((0, 5), "Corner".into());
        Topology::from_mesh(&m)
    })
}

fn within(set: &EntitySet, topo: &Topology) -> bool {
    set.points.iter().all(|&i| i < topo.points.len())
        && set.curves.iter().all(|&i| i < topo.curves.len())
        && set.faces.iter().all(|&i| i < topo.faces.len())
}

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else { return };
    let Ok(text) = std::str::from_utf8(rest) else { return };
    let (format, name) = match first % 3 {
        0 => (RecipeFormat::Libconfig, "fuzz.cfg"),
        1 => (RecipeFormat::Toml, "fuzz.toml"),
        _ => (RecipeFormat::Json, "fuzz.json"),
    };
    let options = ReadOptions::untrusted();
    let Ok(recipe) = Recipe::from_str_with(text, format, Path::new(name), &options) else {
        return;
    };
    let topo = topology();
    let Ok(resolved) = recipe.resolve(topo) else { return };
    assert_eq!(resolved.regions.len(), recipe.regions.len());
    assert_eq!(resolved.plan.steps.len(), recipe.algorithms.len());
    for step in &resolved.plan.steps {
        let sets = step.algorithm.entity_sets();
        assert!(sets.iter().all(|s| within(s, topo)), "{}", step.label);
    }
});
