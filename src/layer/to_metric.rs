//! The band of a skin remeshed to a metric: where a metric is given on the mesh the skin
//! was inserted into (the adaptation loop's last field, or `layer --metric`), the band
//! between the skin's outer front and the kept mesh, triangulated by [`super::insert`]
//! to conform to both, is remeshed by the native remesher to that metric, with the skin
//! and the kept mesh frozen ([`crate::remesh::remesh_keeping`]). The metric at the
//! skin's new points is interpolated (Log-Euclidean) in the input's triangles, where
//! they lie, and so is the whole field the result carries ([`carry_field`]).
//!
//! Invariants: every cell outside the band (skin, kept triangles) comes back with the
//! same vertices, coordinates and tags; the band's boundary edges are never split, so
//! the result conforms to them; the result passes [`crate::check_mesh`] (the
//! remesher checks it) or the call fails.

use super::{LayerError, Layered};
use crate::metric::{SizeTensor, Sym2};
use crate::metric_field::{interpolate, MetricField};
use crate::remesh::{remesh_keeping, RemeshOptions};
use crate::topology::Topology;
use smartmesh_formats::TaggedMesh;

/// `layered`, inserted into `input`, with its band remeshed to `metric` (one SPD tensor
/// per point of `input`). Returns the mesh (its `metric` point data the field on it) and
/// the number of band triangles after the remeshing.
pub fn band_to_metric(
    input: &TaggedMesh,
    metric: &[Sym2],
    layered: Layered,
    opts: &RemeshOptions,
) -> Result<Layered, LayerError> {
    if !layered.band.iter().any(|&b| b) {
        let mut layered = layered;
        carry_field(&mut layered.mesh, input, metric)?;
        return Ok(layered);
    }
    let pts: Vec<[f64; 2]> = layered.mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let field = interpolate::interpolate(input, metric, &pts)
        .map_err(|e| LayerError::Bad(format!("the metric: {e}")))?;
    let keep: Vec<bool> = layered.band.iter().map(|&b| !b).collect();
    let kept_cells = keep.iter().filter(|&&k| k).count();
    let topo = Topology::from_mesh(&layered.mesh);
    let out = remesh_keeping(&layered.mesh, &topo, &field, opts, &keep, &mut |_| {})
        .map_err(|e| LayerError::Invalid(format!("remeshing the band to the metric: {e}")))?;
    let mut mesh = out.mesh;
    // The remesher writes the remeshed triangles first, then the kept ones.
    let surface: usize = mesh.blocks.iter().filter(|b| b.kind.dim() == 2).map(|b| b.len()).sum();
    let band_now = surface - kept_cells;
    let mut band = vec![false; surface];
    band[..band_now].iter_mut().for_each(|b| *b = true);
    // The record of thinned columns, carried to the same (frozen) points.
    if let Some(a) = layered.mesh.point_data.get(super::THICKNESS_SHARE) {
        let at: std::collections::BTreeMap<[u64; 2], f64> = layered
            .mesh
            .points
            .iter()
            .zip(&a.values)
            .filter(|(_, &v)| v != 1.0)
            .map(|(p, &v)| ([p[0].to_bits(), p[1].to_bits()], v))
            .collect();
        let values = mesh
            .points
            .iter()
            .map(|p| at.get(&[p[0].to_bits(), p[1].to_bits()]).copied().unwrap_or(1.0))
            .collect();
        mesh.point_data.insert(
            super::THICKNESS_SHARE.to_string(),
            smartmesh_formats::DataArray { components: 1, values, layout: Default::default() },
        );
    }
    let mut report = layered.report;
    if !layered.mesh.point_sets.is_empty() {
        report.notes.push("point sets dropped by the band's remeshing".to_string());
    }
    mesh.holes = layered.mesh.holes.clone();
    mesh.regions = layered.mesh.regions.clone();
    report.notes.push(format!(
        "band remeshed to the metric: {} triangles (were {})",
        band_now, report.band_triangles
    ));
    report.band_triangles = band_now;
    carry_field(&mut mesh, input, metric)?;
    Ok(Layered { mesh, band, report })
}

/// Sets the field arrays of `mesh` (`metric`, and the sizes written beside it:
/// `size_tensor`, `h1`, `h2`, `anisotropy`, `axis1`, `axis2`) to `metric` (one tensor
/// per point of `input`) interpolated (Log-Euclidean) at its points, so that the result
/// carries the field as the input did, consistent at every point: the remesher keeps
/// only `metric`, and the skin's new points had copies of their wall vertex's sizes.
pub fn carry_field(
    mesh: &mut TaggedMesh,
    input: &TaggedMesh,
    metric: &[Sym2],
) -> Result<(), LayerError> {
    let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let at = interpolate::interpolate(input, metric, &pts)
        .map_err(|e| LayerError::Bad(format!("the metric on the skinned mesh: {e}")))?;
    let sizes = at
        .iter()
        .map(SizeTensor::try_from_metric)
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| LayerError::Invalid(format!("the metric on the skinned mesh: {e}")))?;
    mesh.point_data.extend(MetricField::from_sizes(&sizes, "the metric").arrays());
    Ok(())
}
