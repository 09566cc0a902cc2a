//! What the command-line tests of meshes in space share: the unit cube Gmsh meshes with
//! named surfaces, curve, point and volume; the public box-cylinder; `size` and then
//! `remesh` through `mmg3d_O3` with the field as given; and the measures the tests take
//! apart from the library (signed volumes of tetrahedra, the edges of a mesh's cells,
//! metric lengths by quadrature, a median).
//!
//! The skips are those of [`crate::cli::program`], [`crate::formats::python_with`] and
//! [`crate::require_public_fixtures`]: a test calls them (or [`gmsh_and_mmg3d`]) first
//! and returns on a skip; under CI the missing tool or fixture fails it instead. The
//! binary is named by the caller, as in [`crate::cli`].

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Output;

use smartmesh_formats::{read_path, CellKind, TaggedMesh};

use crate::cli::{program, run, streams};
use crate::formats::{public_fixture, python_with, run_python};

/// The public box-cylinder (the box [0, 2] × [0, 1]², less the cylinder of radius 0.2
/// about the z axis through (0.6, 0.5); 634 vertices, named surfaces and volume); a test
/// calls [`crate::require_public_fixtures`] first.
pub fn box_cyl_path() -> PathBuf {
    public_fixture("3d/box_cyl.v41_ascii.msh")
}

/// [`box_cyl_path`] as a string, for a command's arguments.
pub fn box_cyl() -> String {
    box_cyl_path().display().to_string()
}

/// The Python interpreter that imports `gmsh`, with `mmg3d_O3` on PATH; else `None`,
/// after saying that the test skips (Python's `gmsh` is looked for first), or failing it
/// under `SMARTMESH_REQUIRE_INTEROP=1`.
pub fn gmsh_and_mmg3d() -> Option<String> {
    let py = python_with(&["gmsh"])?;
    program("mmg3d_O3")?;
    Some(py)
}

/// The unit cube meshed by Gmsh (`python -c GMSH_CUBE OUT MAX_SIZE`) with physical
/// surfaces Left (x = 0, 1), Right (x = 1, 2), Walls (the others, 3), the volume Solid
/// (10), the curve Rim (the four edges of the face x = 0, 20) and the point Origin (30).
const GMSH_CUBE: &str = r#"
import sys, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("box")
gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
gmsh.model.occ.synchronize()
left, right, walls = [], [], []
for d, t in gmsh.model.getEntities(2):
    x = gmsh.model.occ.getCenterOfMass(d, t)[0]
    (left if x < 1e-9 else right if x > 1 - 1e-9 else walls).append(t)
gmsh.model.addPhysicalGroup(2, left, 1, "Left")
gmsh.model.addPhysicalGroup(2, right, 2, "Right")
gmsh.model.addPhysicalGroup(2, walls, 3, "Walls")
gmsh.model.addPhysicalGroup(3, [1], 10, "Solid")
rim = [t for d, t in gmsh.model.getBoundary([(2, left[0])], oriented=False)]
gmsh.model.addPhysicalGroup(1, rim, 20, "Rim")
origin = [t for d, t in gmsh.model.getEntities(0)
          if max(abs(c) for c in gmsh.model.getValue(0, t, [])) < 1e-9]
gmsh.model.addPhysicalGroup(0, origin, 30, "Origin")
gmsh.option.setNumber("Mesh.MeshSizeMax", float(sys.argv[2]))
gmsh.model.mesh.generate(3)
gmsh.write(sys.argv[1])
gmsh.finalize()
"#;

/// Writes the Gmsh cube (see `GMSH_CUBE`) at `path`, its elements at most `max_size`
/// (Gmsh's `Mesh.MeshSizeMax`), through the interpreter `py` of [`gmsh_and_mmg3d`].
pub fn write_gmsh_cube(py: &str, path: &Path, max_size: f64) {
    // `{}` prints the shortest decimal that reads back as the same double.
    run_python(py, GMSH_CUBE, &[path.to_str().unwrap(), &max_size.to_string()]);
}

/// A wall layer on box_cyl's cylinder (DISTANCE_TO_BORDER): across the wall 0.02
/// growing to 0.15 at 0.3 away, along it 0.06 to 0.15; h_max 0.15, then the lines
/// `global` (each ending in a newline) in the recipe's `[global]` table.
pub fn cylinder_wall_recipe(global: &str) -> String {
    format!("\n[global]\nh_max = 0.15\n{global}{CYLINDER_WALL_STEPS}")
}

/// The regions, functions and step of [`cylinder_wall_recipe`].
const CYLINDER_WALL_STEPS: &str = r#"
[regions]
cyl = ["Cylinder"]

[functions.perp]
kind = "distance"
size_at_source = 0.02
size_at_max_distance = 0.15
max_distance = 0.3
exponent = 1.0

[functions.par]
kind = "distance"
size_at_source = 0.06
size_at_max_distance = 0.15
max_distance = 0.3
exponent = 1.0

[[algorithms]]
type = "distance_to_border"
regions = ["cyl"]
perpendicular = "perp"
parallel = "par"
"#;

/// `bin remesh MESH --metric FIELD -o OUT --hgrad -1 EXTRA…` (the field as given, no
/// gradation: a mesh in space goes to `mmg3d_O3`), asserting exit 0; its output.
pub fn remesh_as_given(bin: &str, mesh: &str, field: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args =
        vec!["remesh", mesh, "--metric", field.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend(["--hgrad", "-1"]);
    args.extend(extra);
    let o = run(bin, &args, None);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    o
}

/// `bin size` box_cyl with `recipe` into `dir/SOL`, then [`remesh_as_given`] box_cyl to
/// it into `dir/adapted.msh`; the adapted mesh.
pub fn size_then_mmg3d(bin: &str, dir: &Path, recipe: &Path, sol: &str) -> TaggedMesh {
    let sol = dir.join(sol);
    let (mesh, r, s) = (box_cyl(), recipe.to_str().unwrap(), sol.to_str().unwrap());
    let o = run(bin, &["size", &mesh, "--recipe", r, "-o", s], None);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let out = dir.join("adapted.msh");
    remesh_as_given(bin, &mesh, &sol, &out, &[]);
    read_path(&out, None).unwrap()
}

/// Six times the signed volume of a tetrahedron (positive when the fourth corner sees
/// the first three counter-clockwise).
pub fn volume6(p: [[f64; 3]; 4]) -> f64 {
    let d = |i: usize| [p[i][0] - p[0][0], p[i][1] - p[0][1], p[i][2] - p[0][2]];
    let (a, b, c) = (d(1), d(2), d(3));
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// The volume of `mesh`'s tetrahedra, asserting that each has a volume above `floor`.
pub fn positive_volume(mesh: &TaggedMesh, floor: f64) -> f64 {
    let mut volume = 0.0;
    for (k, n, _, _) in mesh.cells() {
        if k == CellKind::Tetra {
            let v = volume6(std::array::from_fn(|i| mesh.points[n[i] as usize])) / 6.0;
            assert!(v > floor, "tetrahedron {n:?} has volume {v}");
            volume += v;
        }
    }
    volume
}

/// The edges of `mesh`'s cells of `kind` (tetrahedra or triangles), as sorted vertex
/// pairs.
pub fn edges(mesh: &TaggedMesh, kind: CellKind) -> BTreeSet<(u32, u32)> {
    let pairs: &[(usize, usize)] = match kind {
        CellKind::Tetra => &[(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)],
        CellKind::Triangle => &[(0, 1), (1, 2), (2, 0)],
        _ => panic!("edges of {kind:?} are not listed here"),
    };
    let mut out = BTreeSet::new();
    for (k, n, _, _) in mesh.cells() {
        if k == kind {
            for &(i, j) in pairs {
                out.insert((n[i].min(n[j]), n[i].max(n[j])));
            }
        }
    }
    out
}

/// The length of the segment a–b in the metric field `metric`, by the midpoint rule on
/// 16 pieces.
pub fn metric_length(a: [f64; 3], b: [f64; 3], metric: impl Fn([f64; 3]) -> [[f64; 3]; 3]) -> f64 {
    let n = 16;
    let e = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    (0..n)
        .map(|k| {
            let t = (k as f64 + 0.5) / n as f64;
            let m = metric([a[0] + t * e[0], a[1] + t * e[1], a[2] + t * e[2]]);
            let q: f64 = (0..3).map(|i| (0..3).map(|j| e[i] * m[i][j] * e[j]).sum::<f64>()).sum();
            q.sqrt() / n as f64
        })
        .sum()
}

/// The lengths `length(p, q)` of `edges` of `mesh`, in increasing order.
pub fn edge_lengths(
    mesh: &TaggedMesh,
    edges: &BTreeSet<(u32, u32)>,
    length: impl Fn([f64; 3], [f64; 3]) -> f64,
) -> Vec<f64> {
    let mut l: Vec<f64> = edges
        .iter()
        .map(|&(a, b)| length(mesh.points[a as usize], mesh.points[b as usize]))
        .collect();
    l.sort_by(f64::total_cmp);
    l
}

/// The median of lengths in increasing order (the upper one of an even count).
pub fn median(sorted: &[f64]) -> f64 {
    sorted[sorted.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::kuhn_box;

    #[test]
    fn volumes_and_edges_of_a_kuhn_box_are_counted_by_hand() {
        // The corner tetrahedron (0, x, y, z) has volume 1/6; swapping two corners flips it.
        let o = [0.0; 3];
        let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(volume6([o, x, y, z]), 1.0);
        assert_eq!(volume6([o, y, x, z]), -1.0);
        let cube = kuhn_box(1, [1.0; 3]);
        assert!((positive_volume(&cube, 0.0) - 1.0).abs() < 1e-12);
        assert!((positive_volume(&kuhn_box(3, [1.0, 2.0, 3.0]), 0.0) - 6.0).abs() < 1e-12);
        // One cube: its 12 edges, a diagonal on each of its 6 faces, the long diagonal.
        assert_eq!(edges(&cube, CellKind::Tetra).len(), 19);
        assert_eq!(edges(&cube, CellKind::Triangle).len(), 18);
    }

    #[test]
    fn a_constant_metric_scales_lengths_and_the_median_is_the_middle() {
        let m = |_: [f64; 3]| [[4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 4.0]];
        assert!((metric_length([0.0; 3], [1.0, 2.0, 2.0], m) - 6.0).abs() < 1e-12);
        let cube = kuhn_box(1, [1.0; 3]);
        let euclid = |p: [f64; 3], q: [f64; 3]| {
            metric_length(p, q, |_| {
                std::array::from_fn(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))))
            })
        };
        let l = edge_lengths(&cube, &edges(&cube, CellKind::Tetra), euclid);
        // 12 edges of length 1, 6 face diagonals of √2, the long diagonal √3, in order.
        let want: Vec<f64> = [(12, 1.0), (6, 2.0), (1, 3.0)]
            .iter()
            .flat_map(|&(n, l2): &(usize, f64)| std::iter::repeat_n(l2.sqrt(), n))
            .collect();
        assert!(l.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-12), "{l:?}");
        assert_eq!(l.len(), want.len());
        assert_eq!(median(&[1.0, 2.0, 7.0]), 2.0);
        assert_eq!(median(&[1.0, 2.0, 7.0, 9.0]), 7.0);
    }
}
