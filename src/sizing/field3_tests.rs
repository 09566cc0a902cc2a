//! The 3D driver on small meshes made here: UNIFORM on surfaces and volumes, the bounds,
//! the gradation, and the refusal of an algorithm that does not size in space.

use smartmesh_formats::TaggedMesh;
use smartmesh_test_support::grid::kuhn_box;

use super::*;
use crate::sizing::algorithms::{
    Algorithm, Arguments, Around, Declaration, EntitySet, SizingAlgorithm, Uniform, Work,
};
use crate::sizing::plan::Step;

/// The topology of `mesh` and the plan of `steps` with the given bounds.
pub(super) fn plan(steps: Vec<Algorithm>, h_max: Option<f64>) -> SizingPlan {
    SizingPlan {
        h_max,
        steps: steps
            .into_iter()
            .enumerate()
            .map(|(i, algorithm)| Step { label: format!("step {i}"), algorithm, names: vec![] })
            .collect(),
        ..SizingPlan::default()
    }
}

/// Runs `plan` on `mesh`.
pub(super) fn run(mesh: &TaggedMesh, plan: &SizingPlan) -> Result<SizeField3, SizingError> {
    let topology = Topology::from_mesh(mesh);
    let space = SpaceMesh::new(mesh, &topology).unwrap();
    compute_size_field3(&space, &topology, plan, &mut |_| {})
}

/// The face (surface) of `tag`.
pub(super) fn face(mesh: &TaggedMesh, tag: i32) -> usize {
    let t = Topology::from_mesh(mesh);
    t.faces.iter().position(|f| f.tag == tag).unwrap()
}

fn uniform(size: f64, on: EntitySet) -> Algorithm {
    Algorithm::Uniform(Uniform { size, on })
}

/// UNIFORM on the bottom of a box (z = 0, tag 15): every vertex of it gets the size, every
/// other vertex the default h_max; on the volume, every vertex.
#[test]
fn uniform_gives_every_vertex_of_its_regions_the_size() {
    let mesh = kuhn_box(4, [1.0, 1.0, 1.0]);
    let bottom = EntitySet { faces: vec![face(&mesh, 15)], ..EntitySet::default() };
    let f = run(&mesh, &plan(vec![uniform(0.05, bottom)], Some(0.5))).unwrap();
    assert_eq!(f.tensors.len(), mesh.points.len());
    for (v, p) in mesh.points.iter().enumerate() {
        let h = if p[2] == 0.0 { 0.05 } else { 0.5 };
        assert_eq!(f.tensors[v].sizes(), [h; 3], "vertex {v} at {p:?}");
        assert_eq!(f.reached[v], p[2] == 0.0);
    }
    assert_eq!(f.steps[0].vertices_reached, 25);
    let volume = EntitySet { volumes: vec![0], ..EntitySet::default() };
    let f = run(&mesh, &plan(vec![uniform(0.2, volume)], None)).unwrap();
    assert!(f.tensors.iter().all(|t| t.sizes() == [0.2; 3]));
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
}

/// Two steps intersect (the smaller size wins whatever the order); h_min and h_max
/// clamp; the default is the box diagonal with a warning when there is no h_max.
#[test]
fn steps_intersect_and_bounds_clamp() {
    let mesh = kuhn_box(2, [1.0, 2.0, 2.0]);
    let bottom = EntitySet { faces: vec![face(&mesh, 15)], ..EntitySet::default() };
    let all = EntitySet { volumes: vec![0], ..EntitySet::default() };
    let mut p = plan(vec![uniform(0.01, bottom.clone()), uniform(0.3, all.clone())], None);
    let f = run(&mesh, &p).unwrap();
    for (v, x) in mesh.points.iter().enumerate() {
        let h = if x[2] == 0.0 { 0.01 } else { 0.3 };
        assert!(f.tensors[v].sizes().iter().all(|s| (s - h).abs() < 1e-15), "{v}");
    }
    p.h_min = Some(0.02);
    p.h_max = Some(0.25);
    let f = run(&mesh, &p).unwrap();
    for (v, x) in mesh.points.iter().enumerate() {
        let h = if x[2] == 0.0 { 0.02 } else { 0.25 };
        assert!(f.tensors[v].sizes().iter().all(|s| (s - h).abs() < 1e-15), "{v}");
    }
    let f = run(&mesh, &plan(vec![uniform(0.1, bottom)], None)).unwrap();
    assert_eq!(f.default_size, 3.0);
    assert!(f.warnings.iter().any(|w| w.contains("bounding-box diagonal 3")), "{:?}", f.warnings);
}

/// The maximum aspect ratio shrinks the larger sizes of an anisotropic tensor to the
/// smallest times the ratio, keeping the frame; the gradation bounds the growth across
/// every edge (T_q ⊆ g^ℓ T_p to the pass's slack) and keeps h_min.
#[test]
fn aspect_and_gradation_apply() {
    let mesh = kuhn_box(6, [1.0, 1.0, 1.0]);
    let bottom = EntitySet { faces: vec![face(&mesh, 15)], ..EntitySet::default() };
    let mut p = plan(vec![uniform(0.005, bottom)], Some(0.5));
    p.gradation = Some(1.05);
    p.h_min = Some(0.001);
    let f = run(&mesh, &p).unwrap();
    let g = f.gradation.unwrap();
    assert!(g.converged && g.updates > 0, "{g:?}");
    let topology = Topology::from_mesh(&mesh);
    let space = SpaceMesh::new(&mesh, &topology).unwrap();
    for v in 0..mesh.points.len() {
        for &q in space.neighbours(v) {
            let (a, b) = (mesh.points[v], mesh.points[q as usize]);
            let edge = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let t = crate::metric::gradate_edge3(&f.tensors[v], &f.tensors[q as usize], edge, 1.05);
            if let Some(t) = t {
                // Only rounding left: the tensor is within the slack of its bound.
                let r = t.h_max() / f.tensors[q as usize].h_max();
                assert!(r > 1.0 - 1e-8, "{v} -> {q}: {r}");
            }
        }
    }
    // Vertices one layer up (z = 1/6) are bounded by 0.005 · 1.05^(1/6 / 0.005) ≈ 0.026.
    let up = mesh.points.iter().position(|p| p == &[0.0, 0.0, 1.0 / 6.0]).unwrap();
    assert!(f.tensors[up].h_max() < 0.03, "{:?}", f.tensors[up]);
    assert!(f.tensors.iter().all(|t| t.h_min() >= 0.001 * (1.0 - 1e-12)));
    // Aspect: a tensor 1 × 1 × 0.01 with aspect 10 becomes 0.1 × 0.1 × 0.01.
    let bounds = SizeBounds::try_new(1e-6, 10.0, 10.0).unwrap();
    let t = SizeTensor3::new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.01]);
    let mut tensors = vec![t];
    finish(&mut tensors, &[true], t, Some(&bounds));
    assert!(tensors[0].sizes().iter().zip([0.1, 0.1, 0.01]).all(|(a, b)| (a - b).abs() < 1e-15));
    assert_eq!(tensors[0].frame(), t.frame());
}

/// An algorithm with no 3D work, as every one is until it says otherwise.
struct Flat;

impl SizingAlgorithm for Flat {
    const DECLARATION: Declaration =
        Declaration { keyword: "FLAT", name: "flat", doc: "Test.", parameters: &[] };
    type Tensor<'a> = std::convert::Infallible;
    fn from_arguments(_: &mut Arguments) -> Option<Flat> {
        Some(Flat)
    }
    fn entity_sets(&self) -> Vec<&EntitySet> {
        vec![]
    }
    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        None
    }
    fn work<'a>(
        &'a self,
        _: &'a crate::mesh_graph::MeshGraph,
        _: &'a Topology,
    ) -> Result<Work<Self::Tensor<'a>>, Failure> {
        Err(Failure::NoSource)
    }
}

/// By default an algorithm refuses a mesh in space, naming its keyword and the step.
#[test]
fn an_algorithm_without_3d_work_is_refused_by_name() {
    let mesh = kuhn_box(1, [1.0, 1.0, 1.0]);
    let topology = Topology::from_mesh(&mesh);
    let space = SpaceMesh::new(&mesh, &topology).unwrap();
    let e = Flat.work_in_space(&space, &topology).err().unwrap();
    assert_eq!(e, Failure::NotInSpace { keyword: "FLAT" });
    const { assert!(!Flat::IN_SPACE) };
    let msg = e.at(2, "algorithm 3 (FLAT)").to_string();
    assert_eq!(msg, "step 2 (algorithm 3 (FLAT)): FLAT is not available on a mesh in space yet");
}

/// The mesh's edges: a Kuhn box of one cube has the 12 cube edges, 6 face diagonals and
/// the long diagonal.
#[test]
fn the_space_mesh_has_every_edge_once() {
    let mesh = kuhn_box(1, [1.0, 1.0, 1.0]);
    let topology = Topology::from_mesh(&mesh);
    let space = SpaceMesh::new(&mesh, &topology).unwrap();
    assert_eq!(space.num_edges(), 19);
    assert_eq!(space.neighbours(0), &[1, 2, 3, 4, 5, 6, 7]);
}
