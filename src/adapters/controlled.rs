//! A remesher with size controls applied to every metric it is given: `--hausd` for the
//! remeshers that have no such option of their own (the native one and Gmsh's BAMG).
//! The controls themselves are [`SizeControls`]'s, which know no remesher.

use smartmesh_formats::TaggedMesh;

use super::{Adapted, Adapter, AdapterError};
use crate::metric::{Sym2, Sym3};
use crate::size_controls::SizeControls;
use crate::topology::Topology;

/// `inner` given every metric with `controls` applied.
pub(crate) struct Controlled {
    /// The remesher.
    pub inner: Box<dyn Adapter>,
    /// The controls.
    pub controls: SizeControls,
}

impl Adapter for Controlled {
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn adapt(
        &self,
        mesh: &TaggedMesh,
        topology: &Topology,
        metric: &[Sym2],
    ) -> Result<Adapted, AdapterError> {
        let mut metric = metric.to_vec();
        self.controls
            .apply(mesh, &mut metric)
            .map_err(|e| AdapterError::Input(format!("applying --hausd: {e}")))?;
        self.inner.adapt(mesh, topology, &metric)
    }

    /// The controls bound a planar metric (curves of a planar boundary): a mesh in space
    /// is refused before any work, naming the remeshers that bound it themselves.
    fn adapt_space(&self, mesh: &TaggedMesh, metric: &[Sym3]) -> Result<Adapted, AdapterError> {
        let _ = (mesh, metric);
        Err(AdapterError::Input(format!(
            "--hausd with the {} adapter bounds a planar metric by the curvature of its boundary curves; in space it is MMG's -hausd (--adapter mmg3d|mmgs)",
            self.inner.name()
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::{CellBlock, CellKind};

    /// A regular 64-gon of radius 2 as a fan of triangles, its boundary as Line cells.
    fn polygon() -> TaggedMesh {
        let n = 64;
        let mut mesh = TaggedMesh::default();
        mesh.points.push([0.0, 0.0, 0.0]);
        for k in 0..n {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            mesh.points.push([2.0 * t.cos(), 2.0 * t.sin(), 0.0]);
        }
        let ring = |k: usize| 1 + k % n;
        let mut tri = CellBlock::new(CellKind::Triangle);
        let mut lines = CellBlock::new(CellKind::Line);
        for k in 0..n {
            tri.push(&[0, ring(k), ring(k + 1)], 2, 2);
            lines.push(&[ring(k), ring(k + 1)], 1, 1);
        }
        mesh.blocks.push(tri);
        mesh.blocks.push(lines);
        mesh
    }

    /// A remesher that returns its input and keeps the metric it was given.
    struct Recorder(std::rc::Rc<std::cell::RefCell<Vec<Sym2>>>);

    impl Adapter for Recorder {
        fn name(&self) -> &str {
            "recorder"
        }

        fn adapt(
            &self,
            mesh: &TaggedMesh,
            _topology: &Topology,
            metric: &[Sym2],
        ) -> Result<Adapted, AdapterError> {
            *self.0.borrow_mut() = metric.to_vec();
            Ok(Adapted { mesh: mesh.clone(), stats: None })
        }
    }

    #[test]
    fn a_controlled_remesher_is_given_the_bounded_metric() {
        let mesh = polygon();
        let metric = vec![Sym2::new(1.0, 0.0, 1.0); mesh.points.len()];
        let seen = std::rc::Rc::new(std::cell::RefCell::new(Vec::new()));
        let controls = SizeControls { hausd: Some(1e-3), ..Default::default() };
        let controlled = Controlled { inner: Box::new(Recorder(seen.clone())), controls };
        assert_eq!(controlled.name(), "recorder");
        let topology = Topology::from_mesh(&mesh);
        controlled.adapt(&mesh, &topology, &metric).unwrap();
        let mut expected = metric.clone();
        controls.apply(&mesh, &mut expected).unwrap();
        assert_ne!(expected, metric);
        assert_eq!(*seen.borrow(), expected);
    }
}
