//! Periodic sides in a Fluent mesh: the narrow distributor written with its recipe's
//! PERIODIC pair (302, 303, 304 onto 308, 307, 306 by (0, 30)) holds a `periodic` zone
//! (bc-type 12), a `periodic-shadow` zone (8) and a `(18 ...)` section pairing their
//! faces. A twin written here from the file's own text checks every pair: the shadow
//! face is the periodic face moved by (0, 30) (to 1e-8: the file's coordinates are
//! rounded at 1e-9), each face of both zones exactly once.
//! smartmesh reads the file back with the pair count; meshio's `ansys` reader reads it
//! (it skips section 18). OpenFOAM cannot check the pairing: `fluentMeshToFoam` stops
//! at a `periodic` zone ("fluent patch type periodic not recognised", its list of
//! types has none) and `fluent3DMeshToFoam` (3D only) makes such zones plain patches
//! and skips section 18 (its periodic matching is commented out in its source).

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use smartmesh_test_support::formats::{python_with, run_python};
use support::{ok, run, stderr};

fn distributor(dir: &Path) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let input = root.join("examples/distributor/1-narrow/start.msh");
    let recipe = root.join("examples/distributor/recipe.cfg");
    let file = dir.join("distributor.fluent.msh");
    let o = run(&[
        "convert",
        input.to_str().unwrap(),
        file.to_str().unwrap(),
        "--recipe",
        recipe.to_str().unwrap(),
    ]);
    ok(&o);
    assert!(stderr(&o).contains("periodic and periodic-shadow zones"), "{}", stderr(&o));
    file
}

fn hex(s: &str) -> usize {
    usize::from_str_radix(s, 16).unwrap()
}

/// The sections the twin needs, parsed from the text as the Fluent User's Guide gives
/// them: 2D nodes, each face zone's (bc-type, faces as node lists), the face pairs.
struct Parsed {
    nodes: Vec<[f64; 2]>,
    zones: BTreeMap<usize, (usize, Vec<Vec<usize>>)>,
    first_face: BTreeMap<usize, usize>,
    pairs: Vec<Section18>,
}

/// The periodic zone, the shadow zone, the face pairs.
type Section18 = (usize, usize, Vec<(usize, usize)>);

fn parse(text: &str) -> Parsed {
    let mut p = Parsed {
        nodes: Vec::new(),
        zones: BTreeMap::new(),
        first_face: BTreeMap::new(),
        pairs: Vec::new(),
    };
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let head: Vec<&str> = line.split(['(', ')', ' ']).filter(|s| !s.is_empty()).collect();
        let body = line.ends_with("(");
        match (head.first().copied(), body) {
            (Some("10"), true) => {
                for l in lines.by_ref().take_while(|l| *l != "))") {
                    let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
                    p.nodes.push([v[0], v[1]]);
                }
            }
            (Some("13"), true) => {
                let (id, first, bc) = (hex(head[1]), hex(head[2]), hex(head[4]));
                let faces = lines
                    .by_ref()
                    .take_while(|l| *l != "))")
                    .map(|l| l.split_whitespace().take(2).map(hex).collect())
                    .collect();
                p.zones.insert(id, (bc, faces));
                p.first_face.insert(id, first);
            }
            (Some("18"), true) => {
                let pairs = lines
                    .by_ref()
                    .take_while(|l| *l != "))")
                    .map(|l| {
                        let v: Vec<usize> = l.split_whitespace().map(hex).collect();
                        (v[0], v[1])
                    })
                    .collect();
                p.pairs.push((hex(head[3]), hex(head[4]), pairs));
            }
            _ => {}
        }
    }
    p
}

#[test]
fn periodic_zones_pair_each_face_with_its_image() {
    let dir = tempfile::tempdir().unwrap();
    let file = distributor(dir.path());
    let text = std::fs::read_to_string(&file).unwrap();
    let p = parse(&text);
    assert_eq!(p.pairs.len(), 1, "one (18 ...) section");
    let (pz, sz, pairs) = &p.pairs[0];
    assert_eq!(p.zones[pz].0, 12, "the periodic zone's bc-type");
    assert_eq!(p.zones[sz].0, 8, "the shadow zone's bc-type");
    assert!(text.contains(&format!("({pz} periodic LowerPeriodic1_LowerPeriodic2_LowerPeriodic3)")));
    assert!(text
        .contains(&format!("({sz} periodic-shadow UpperPeriodic1_UpperPeriodic2_UpperPeriodic3)")));
    assert_eq!(pairs.len(), 71);
    let mid = |zone: usize, face: usize| {
        let f = &p.zones[&zone].1[face - p.first_face[&zone]];
        let (a, b) = (p.nodes[f[0] - 1], p.nodes[f[1] - 1]);
        [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
    };
    let (mut seen_p, mut seen_s) = (BTreeSet::new(), BTreeSet::new());
    for &(f, s) in pairs {
        let (a, b) = (mid(*pz, f), mid(*sz, s));
        assert!(
            (b[0] - a[0]).abs() < 1e-8 && (b[1] - a[1] - 30.0).abs() < 1e-8,
            "face {f:x} at {a:?}, its shadow {s:x} at {b:?}"
        );
        seen_p.insert(f);
        seen_s.insert(s);
    }
    assert_eq!((seen_p.len(), seen_s.len()), (71, 71), "every face of both zones once");
    assert_eq!(p.zones[pz].1.len(), 71);
    assert_eq!(p.zones[sz].1.len(), 71);

    // Read back: the pair counted, the zones named boundary tags.
    let back = dir.path().join("back.msh");
    let o = run(&["convert", file.to_str().unwrap(), back.to_str().unwrap()]);
    ok(&o);
    assert!(stderr(&o).contains("71 face pairs"), "{}", stderr(&o));
    let gmsh = std::fs::read_to_string(&back).unwrap();
    assert!(gmsh.contains("\"UpperPeriodic1_UpperPeriodic2_UpperPeriodic3\""));

    // A pair naming a face of another zone: refused at the section's line.
    let line = text.lines().position(|l| l.starts_with("(18 ")).unwrap() + 1;
    let first = &text.lines().nth(line).unwrap().to_string();
    let broken = text.replacen(&format!("\n{first}\n"), "\n1 2\n", 1);
    let bad = dir.path().join("bad.fluent.msh");
    std::fs::write(&bad, broken).unwrap();
    let o = run(&["info", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains(&format!(":{line}:")), "{}", stderr(&o));
}

#[test]
fn meshio_reads_a_mesh_with_periodic_zones() {
    let Some(py) = python_with(&["meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let file = distributor(dir.path());
    let script = r#"
import sys, meshio
m = meshio.read(sys.argv[1], file_format="ansys")
print(len(m.points), sum(len(c.data) for c in m.cells), sum(len(c.data) == 71 for c in m.cells))
"#;
    let out = run_python(&py, script, &[file.to_str().unwrap()]);
    let text = std::fs::read_to_string(&file).unwrap();
    let faces = hex(text.lines().find(|l| l.starts_with("(13 (0 1 ")).unwrap()[9..]
        .split(' ')
        .next()
        .unwrap());
    // Every node and face, the two periodic zones of 71 faces among them.
    assert_eq!(out.trim(), format!("2050 {faces} 2"), "{out}");
}
