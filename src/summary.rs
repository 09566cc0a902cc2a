//! What `smartmesh info` reports about a mesh, as one serialisable value.

use std::collections::BTreeMap;

use serde::Serialize;
use smartmesh_formats::{DataShape, TaggedMesh};

use crate::quality::QualitySummary;
use crate::topology::{cell_tag, CurveOrigin, PointOrigin, Topology};

/// Counts, bounding box, tags, topology, fields and quality of a mesh.
#[derive(Debug, Clone, Serialize)]
pub struct MeshSummary {
    /// Number of points.
    pub points: usize,
    /// Points used by no cell (Gmsh keeps, e.g., a circle's centre).
    pub unused_points: usize,
    /// 2 or 3, as the file stores coordinates.
    pub coordinate_dim: u8,
    /// Cell counts per kind name.
    pub cells: BTreeMap<String, usize>,
    /// `[min, max]` corners of the bounding box (x, y, z).
    pub bounding_box: Option<[[f64; 3]; 2]>,
    /// Whether every point lies in one plane z = const (`crate::planar`); the 2D
    /// commands refuse a mesh that does not, whose lengths and areas here are measured in
    /// space.
    pub planar: bool,
    /// Every physical tag used, with its dimension, name and cell count.
    pub tags: Vec<TagSummary>,
    /// The recovered topology.
    pub topology: TopologySummary,
    /// Point data arrays.
    pub point_data: Vec<FieldSummary>,
    /// Cell data arrays.
    pub cell_data: Vec<FieldSummary>,
    /// Element shape quality, when the mesh has surface cells.
    pub quality: Option<QualitySummary>,
    /// Volumes, their topology and the quality of volume cells, when the mesh has volume
    /// cells (left out of the JSON otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solid: Option<SolidSummary>,
    /// Conformity to a metric and metric quality, when there is a metric (left out of
    /// the JSON otherwise, so that the output without a metric stays as it was).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metric: Option<MetricSummary>,
    /// The bin edges of the histograms above.
    pub histogram_bins: HistogramBins,
}

/// The edges of the bins of the histograms a summary holds: bin `i` counts the values in
/// `[edges[i], edges[i + 1])` (the last quality bin includes 1). A JSON reader needs them
/// to draw or compare the counts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HistogramBins {
    /// Shape quality and metric quality: 11 edges, 0, 0.1, … 1.
    pub quality: Vec<f64>,
    /// Metric edge length: 31 edges, 0, 0.1, … 3, the last bin open (everything from 2.9
    /// on), so the last edge is `null` in JSON (infinite).
    pub metric_edge_length: Vec<f64>,
}

impl HistogramBins {
    /// The bins of [`QualitySummary::histogram`], [`crate::conformity::Conformity`]'s
    /// `quality_histogram` and `edge_length_histogram`.
    pub fn standard() -> HistogramBins {
        let n = crate::conformity::LENGTH_BINS;
        let mut length: Vec<f64> = (0..n).map(|i| i as f64 / 10.0).collect();
        length.push(f64::INFINITY);
        HistogramBins {
            quality: (0..=10).map(|i| i as f64 / 10.0).collect(),
            metric_edge_length: length,
        }
    }
}

/// What `info` adds for a mesh with volume cells.
#[derive(Debug, Clone, Serialize)]
pub struct SolidSummary {
    /// Cells of dimension 0, 1, 2 and 3.
    pub cells_per_dim: [usize; 4],
    /// The sum of the volume cells' signed volumes ([`crate::signed_volume`]).
    pub volume: f64,
    /// The volume kinds measured through their corners (second-order kinds but the
    /// tetrahedron), by name; empty when the volume is exact.
    pub volume_by_corners: Vec<String>,
    /// The topological volumes and the surfaces bounding each.
    pub volumes: Vec<crate::solid_topology::TopoVolume>,
    /// Shape quality of the volume cells.
    pub quality: Option<crate::quality3d::VolumeQuality>,
}

impl SolidSummary {
    /// The 3D figures of `mesh`, whose topology is `topo`; `None` when it has no volume
    /// cell.
    pub fn of(mesh: &TaggedMesh, topo: &Topology) -> Option<SolidSummary> {
        let quality = crate::quality3d::VolumeQuality::of(mesh)?;
        let mut cells_per_dim = [0; 4];
        for b in &mesh.blocks {
            cells_per_dim[b.kind.dim() as usize] += b.len();
        }
        let volumes = crate::solid_topology::volumes(mesh, topo);
        let mut volume_by_corners: Vec<String> = mesh
            .blocks
            .iter()
            .filter(|b| b.kind.dim() == 3 && !crate::quality3d::exact_volume(b.kind))
            .map(|b| b.kind.name().to_string())
            .collect();
        volume_by_corners.sort();
        volume_by_corners.dedup();
        Some(SolidSummary {
            cells_per_dim,
            volume_by_corners,
            volume: volumes.iter().map(|v| v.volume).sum(),
            volumes,
            quality: Some(quality),
        })
    }
}

/// How the mesh conforms to a metric field.
#[derive(Debug, Clone, Serialize)]
pub struct MetricSummary {
    /// Where the metric came from, in words.
    pub source: String,
    /// The figures; `None` when the mesh has no triangle or quad to measure (and for a
    /// 3D metric, measured by [`MetricSummary::ugawg`] alone).
    pub conformity: Option<crate::conformity::Conformity>,
    /// The UGAWG measures: always for a 3D metric, for a 2D one when asked
    /// ([`MeshSummary::with_ugawg`]); `None` when there is no cell to measure or they were
    /// not asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ugawg: Option<crate::conformity::Ugawg>,
    /// The vertex count of a unit mesh of the metric ([`crate::expected_vertices`]), for a
    /// 3D metric on volume cells.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_vertices: Option<f64>,
}

/// One tag, as the topology and the recipes know it ([`crate::topology::cell_tag`]).
#[derive(Debug, Clone, Serialize)]
pub struct TagSummary {
    /// Topological dimension of the cells carrying it.
    pub dim: u8,
    /// The tag: the physical tag, or the geometrical (elementary) one of cells that have
    /// no physical tag, so that the tag listed is the one a recipe names.
    pub tag: i32,
    /// Whether `tag` is the cells' geometrical tag because they have no physical one.
    pub elementary: bool,
    /// Its name, if the file names it.
    pub name: Option<String>,
    /// Number of cells carrying it.
    pub cells: usize,
}

/// One named data array.
#[derive(Debug, Clone, Serialize)]
pub struct FieldSummary {
    /// Array name.
    pub name: String,
    /// Components per item.
    pub components: usize,
    /// Scalar, vector, tensor or other.
    pub shape: DataShape,
    /// Smallest and largest value over all components, NaN left out (`None` if empty
    /// or all NaN).
    pub range: Option<[f64; 2]>,
    /// Items with a NaN component (a Gmsh view that covers part of the mesh, a solver's
    /// missing values): kept as they are, refused only where the array is used.
    pub nan_items: usize,
}

/// Topological entities found from the tags.
#[derive(Debug, Clone, Serialize)]
pub struct TopologySummary {
    /// Topological points.
    pub points: Vec<PointSummary>,
    /// Topological curves.
    pub curves: Vec<CurveSummary>,
    /// Topological faces.
    pub faces: Vec<FaceSummary>,
    /// In a mesh in space, the ridge angle (degrees) the ridges were found with; left out
    /// of the JSON for a planar mesh (as every other figure of a mesh in space).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ridge_angle_deg: Option<f64>,
    /// In a mesh in space, the line cells the file lists as ridges (Medit `Ridges`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file_ridge_edges: Option<usize>,
}

/// One topological point.
#[derive(Debug, Clone, Serialize)]
pub struct PointSummary {
    /// Tag of the vertex cell listing it, if any.
    pub tag: Option<i32>,
    /// Name, if any.
    pub name: Option<String>,
    /// Mesh vertex (0-based).
    pub vertex: usize,
    /// Listed, curve end or junction.
    pub origin: PointOrigin,
}

/// One topological curve.
#[derive(Debug, Clone, Serialize)]
pub struct CurveSummary {
    /// Tag, `None` for a curve derived from untagged boundary or interface edges.
    pub tag: Option<i32>,
    /// Name, if any.
    pub name: Option<String>,
    /// Mesh edges on it.
    pub edges: usize,
    /// Number of polyline pieces, and how many of them are closed.
    pub pieces: usize,
    /// Closed pieces.
    pub closed_pieces: usize,
    /// Whether every edge is a boundary edge; `None` when the mesh has no surface cell
    /// (a `.poly`, a set of lines), where boundary and interior are not told yet, and in
    /// a 3D mesh, whose curves lie where surfaces meet.
    pub on_boundary: Option<bool>,
    /// Length of the curve.
    pub length: f64,
    /// In a mesh in space: tagged, derived (where surfaces meet, or a surface's free
    /// boundary) or ridge.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub origin: Option<CurveOrigin>,
}

/// One topological face.
#[derive(Debug, Clone, Serialize)]
pub struct FaceSummary {
    /// Tag.
    pub tag: i32,
    /// Name, if any.
    pub name: Option<String>,
    /// Surface cells in it.
    pub cells: usize,
    /// Area (quads split along a diagonal; each triangle measured in its own plane).
    pub area: f64,
    /// In a mesh in space: connected sets of its cells.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub patches: Option<usize>,
    /// In a mesh in space: its boundary loops, in order (closed, or open where the
    /// boundary touches itself).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub boundary_loops: Option<Vec<LoopSummary>>,
    /// In a mesh in space: the curves its boundary lies on (indices into `curves`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub boundary_curves: Option<Vec<usize>>,
}

/// One boundary loop of a surface in space.
#[derive(Debug, Clone, Serialize)]
pub struct LoopSummary {
    /// Mesh edges along it.
    pub edges: usize,
    /// Whether it closes on itself.
    pub closed: bool,
    /// Its mesh vertices in order (0-based; a closed loop's first is not repeated).
    pub vertices: Vec<usize>,
}

/// Points that no cell uses, by any of its nodes (a second-order cell's mid-edge nodes
/// are used, though the topology sees its corners alone).
fn unused_points(mesh: &TaggedMesh) -> usize {
    let mut used = vec![false; mesh.points.len()];
    for b in &mesh.blocks {
        for &v in &b.nodes {
            used[v as usize] = true;
        }
    }
    used.iter().filter(|&&u| !u).count()
}

impl MeshSummary {
    /// Summarises `mesh`, whose topology is `topo`.
    pub fn of(mesh: &TaggedMesh, topo: &Topology) -> MeshSummary {
        let mut cells = BTreeMap::new();
        let mut tags: BTreeMap<(u8, i32, bool), usize> = BTreeMap::new();
        for (kind, _, p, g) in mesh.cells() {
            *cells.entry(kind.name().to_string()).or_insert(0) += 1;
            *tags.entry((kind.dim(), cell_tag(p, g), p == 0 && g != 0)).or_insert(0) += 1;
        }
        let field = |name: &String, a: &smartmesh_formats::DataArray| FieldSummary {
            name: name.clone(),
            // A packed symmetric tensor is shown as the 9-component one it stands for,
            // implied zeros and zz = 1 included, so that every format shows one field alike.
            components: a.expanded_components(),
            shape: a.shape(),
            range: {
                let implied: &[f64] =
                    if a.layout == smartmesh_formats::Layout::Symmetric2 && !a.is_empty() {
                        &[0.0, 1.0]
                    } else {
                        &[]
                    };
                a.values.iter().chain(implied).filter(|v| !v.is_nan()).fold(
                    None,
                    |r: Option<[f64; 2]>, &v| {
                        Some(r.map_or([v, v], |[lo, hi]| [lo.min(v), hi.max(v)]))
                    },
                )
            },
            nan_items: a
                .values
                .chunks_exact(a.components.max(1))
                .filter(|item| item.iter().any(|v| v.is_nan()))
                .count(),
        };
        let planar = crate::planar::plane(mesh).is_ok();
        let solid = SolidSummary::of(mesh, topo);
        let space = topo.space.as_ref();
        let at = |i: usize| mesh.points[i];
        let topology = TopologySummary {
            points: topo
                .points
                .iter()
                .map(|p| PointSummary {
                    tag: p.tag,
                    name: p.name.clone(),
                    vertex: p.vertex,
                    origin: p.origin,
                })
                .collect(),
            curves: topo
                .curves
                .iter()
                .map(|c| CurveSummary {
                    tag: c.tag,
                    name: c.name.clone(),
                    edges: c.polylines.iter().map(|p| p.num_edges()).sum(),
                    pieces: c.polylines.len(),
                    closed_pieces: c.polylines.iter().filter(|p| p.closed).count(),
                    on_boundary: (!topo.faces.is_empty() && solid.is_none())
                        .then_some(c.on_boundary),
                    length: c
                        .polylines
                        .iter()
                        .flat_map(|p| p.edges())
                        .map(|[a, b]| crate::quality::distance(at(a), at(b)))
                        .sum(),
                    origin: space.map(|_| c.origin),
                })
                .collect(),
            faces: topo
                .faces
                .iter()
                .enumerate()
                .map(|(fi, f)| (f, space.map(|s| &s.surfaces[fi])))
                .map(|(f, shape)| FaceSummary {
                    tag: f.tag,
                    name: f.name.clone(),
                    cells: f.cells.len(),
                    area: f
                        .cells
                        .iter()
                        .map(|&ci| {
                            // In space, each triangle in its own plane (a planar mesh's
                            // cells are convex or at least not inverted: the same sum).
                            let v = topo.surface_cells[ci].vertices();
                            let area = crate::quality::area_in_space;
                            let mut a = area(at(v[0]), at(v[1]), at(v[2]));
                            if v.len() == 4 {
                                a += area(at(v[0]), at(v[2]), at(v[3]));
                            }
                            a
                        })
                        .sum(),
                    patches: shape.map(|s| s.patches),
                    boundary_loops: shape.map(|s| {
                        s.boundary
                            .iter()
                            .map(|p| LoopSummary {
                                edges: p.num_edges(),
                                closed: p.closed,
                                vertices: p.vertices.clone(),
                            })
                            .collect()
                    }),
                    boundary_curves: shape.map(|s| s.curves.clone()),
                })
                .collect(),
            ridge_angle_deg: space.map(|s| s.ridge_angle_deg),
            file_ridge_edges: space.map(|s| s.file_ridge_edges),
        };
        MeshSummary {
            points: mesh.points.len(),
            unused_points: unused_points(mesh),
            coordinate_dim: mesh.coordinate_dim,
            cells,
            bounding_box: mesh.bounding_box().map(|(lo, hi)| [lo, hi]),
            planar,
            tags: tags
                .into_iter()
                .map(|((dim, tag, elementary), n)| TagSummary {
                    dim,
                    tag,
                    elementary,
                    name: mesh.tag_name(dim, tag).map(str::to_owned),
                    cells: n,
                })
                .collect(),
            topology,
            point_data: mesh.point_data.iter().map(|(n, a)| field(n, a)).collect(),
            cell_data: mesh.cell_data.iter().map(|(n, a)| field(n, a)).collect(),
            quality: QualitySummary::of(&mesh.points, topo),
            histogram_bins: HistogramBins::standard(),
            solid,
            metric: None,
        }
    }

    /// Adds the conformity of `mesh` to `metric` (one tensor per vertex), found at `source`.
    pub fn with_metric(
        mut self,
        mesh: &TaggedMesh,
        metric: &[crate::metric::Sym2],
        source: String,
    ) -> MeshSummary {
        self.metric = Some(MetricSummary {
            source,
            conformity: crate::conformity::Conformity::of_mesh(mesh, metric),
            ugawg: None,
            expected_vertices: None,
        });
        self
    }

    /// Adds the UGAWG measures of a planar `mesh` against the 2D `metric` beside the
    /// conformity of [`MeshSummary::with_metric`] (which comes first).
    pub fn with_ugawg(mut self, mesh: &TaggedMesh, metric: &[crate::metric::Sym2]) -> MeshSummary {
        if let Some(m) = self.metric.as_mut() {
            m.ugawg = crate::conformity::Ugawg::of_mesh_2d(mesh, metric);
        }
        self
    }

    /// Adds the UGAWG measures of a mesh in space against the 3D `metric` (one tensor per
    /// vertex), found at `source`.
    pub fn with_metric_3d(
        mut self,
        mesh: &TaggedMesh,
        metric: &[crate::metric::Sym3],
        source: String,
    ) -> MeshSummary {
        self.metric = Some(MetricSummary {
            source,
            conformity: None,
            ugawg: crate::conformity::Ugawg::of_mesh_3d(mesh, metric),
            expected_vertices: None,
        });
        self
    }
}
