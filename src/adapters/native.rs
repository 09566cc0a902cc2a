//! smartmesh's own remesher ([`crate::remesh`]) behind the [`Adapter`] trait: the
//! default of `smartmesh adapt`. It keeps tags, tag names, entities and topological
//! points by construction; the same [`ensure_tags_kept`] check as the external tools
//! guards the loop all the same.

use smartmesh_formats::TaggedMesh;

use super::restore::ensure_tags_kept;
use super::{Adapted, Adapter, AdapterError};
use crate::metric::Sym2;
use crate::remesh::{remesh_with_topology, RemeshOptions};
use crate::topology::Topology;

/// The native remesher with its options.
#[derive(Debug, Clone, Default)]
pub(crate) struct NativeAdapter {
    /// How to remesh.
    pub options: RemeshOptions,
}

impl Adapter for NativeAdapter {
    fn name(&self) -> &str {
        "native"
    }

    fn adapt(
        &self,
        mesh: &TaggedMesh,
        topology: &Topology,
        metric: &[Sym2],
    ) -> Result<Adapted, AdapterError> {
        let remeshed = remesh_with_topology(mesh, topology, metric, &self.options, &mut |_| {})
            .map_err(|e| {
                if e.is_limit() {
                    AdapterError::Limit(e.to_string())
                } else {
                    AdapterError::Input(e.to_string())
                }
            })?;
        let stats = Some(remeshed.stats.counts());
        let mut out = remeshed.mesh;
        // The loop sizes each new mesh with the recipe; the interpolated field is not the
        // next iteration's metric, so it does not travel with the result.
        out.point_data.remove(crate::metric_field::METRIC);
        ensure_tags_kept(self.name(), mesh, &out)?;
        Ok(Adapted { mesh: out, stats })
    }
}
