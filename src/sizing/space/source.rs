//! A source in space: what the distance-based algorithms measure the distance to on a
//! mesh in space — surface triangles (a surface's cells, quads split along their 0–2
//! diagonal; or a triangulated sheet given by file), segments (a curve's edges, a
//! polyline's pieces) and points — all held in one [`SurfaceIndex`], so that every
//! distance goes through the one triangle kernel of `geometry::space` and is bit for bit
//! what a scan of every piece gives ([`SpaceSource::closest_brute`], the twin).
//!
//! A segment ab is the degenerate triangle (a, b, b) and a point p the triangle
//! (p, p, p): the kernel treats a degenerate triangle as its three edges, so the
//! distance is the exact distance to the segment (the point), with no second kernel.
//!
//! Each piece keeps its kind and its corners (indices into the source's own points), so
//! that the tensor of a vertex can ask for the surface normal at a foot on an edge or a
//! vertex of the surface ([`SpaceSource::surface_normal`]).

use crate::geometry::space::triangle::box_distance_squared;
use crate::geometry::space::{
    Feature, Point3, SurfaceError, SurfaceIndex, SurfacePoint, TriangleGeom,
};
use crate::sizing::propagation::SourceError;
use crate::topology::Topology;

/// What a piece of a source is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PieceKind3 {
    /// A triangle of a surface.
    Surface,
    /// A segment (corners a, b, b).
    Segment,
    /// A point (corners p, p, p).
    Point,
}

/// One piece: its kind and its corners (indices into the source's points).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Piece {
    /// Its kind.
    pub(crate) kind: PieceKind3,
    /// Its corners, as given to the index.
    pub(crate) corners: [u32; 3],
}

/// The closest point of a source to a vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SpaceClosest {
    /// The squared distance, as the kernel computes it.
    pub(crate) distance_squared: f64,
    /// Its square root.
    pub(crate) distance: f64,
    /// The closest point.
    pub(crate) foot: Point3,
    /// The piece (lowest index among equally near ones).
    pub(crate) piece: u32,
    /// The part of the piece the foot lies on.
    pub(crate) feature: Feature,
}

impl SpaceClosest {
    fn from(p: SurfacePoint) -> SpaceClosest {
        SpaceClosest {
            distance_squared: p.projection.distance_squared,
            distance: p.projection.distance_squared.sqrt(),
            foot: p.projection.foot,
            piece: p.triangle,
            feature: p.projection.feature,
        }
    }
}

/// A source in space (see the module header).
#[derive(Debug, Clone)]
pub(crate) struct SpaceSource {
    index: SurfaceIndex,
    points: Vec<Point3>,
    pieces: Vec<Piece>,
    /// (corner, surface piece) for every corner of every surface piece, sorted.
    around: Vec<(u32, u32)>,
    /// The box of every piece.
    lo: Point3,
    hi: Point3,
    /// Whether every point is a free point (no mesh vertex): an imaginary polyline or
    /// sheet, whose coarse-mesh rule the driver applies.
    free: bool,
}

/// Builds a [`SpaceSource`] from mesh entities and free coordinates.
pub(crate) struct SpaceSourceBuilder<'m> {
    mesh_points: &'m [Point3],
    /// Local index of each mesh vertex taken, `u32::MAX` when not.
    local: Vec<u32>,
    points: Vec<Point3>,
    pieces: Vec<Piece>,
}

impl<'m> SpaceSourceBuilder<'m> {
    /// A builder over the vertices `mesh_points` of a mesh in space.
    pub(crate) fn new(mesh_points: &'m [Point3]) -> SpaceSourceBuilder<'m> {
        SpaceSourceBuilder {
            mesh_points,
            local: Vec::new(),
            points: Vec::new(),
            pieces: Vec::new(),
        }
    }

    /// The local index of mesh vertex `v`.
    fn vertex_index(&mut self, v: usize) -> Result<u32, SourceError> {
        let n = self.mesh_points.len();
        if v >= n {
            return Err(SourceError::VertexOutOfRange {
                piece: self.pieces.len(),
                vertex: v,
                len: n,
            });
        }
        if self.local.is_empty() {
            self.local = vec![u32::MAX; n];
        }
        if self.local[v] == u32::MAX {
            self.local[v] = self.points.len() as u32;
            self.points.push(self.mesh_points[v]);
        }
        Ok(self.local[v])
    }

    /// A free point (not a mesh vertex), checked finite (`point` numbers it in errors).
    pub(crate) fn free_point(&mut self, p: Point3, point: usize) -> Result<u32, SourceError> {
        if !p.iter().all(|c| c.is_finite()) {
            return Err(SourceError::NonFinite { piece: self.pieces.len(), point });
        }
        self.points.push(p);
        Ok(self.points.len() as u32 - 1)
    }

    /// The triangle of local points `a`, `b`, `c`.
    pub(crate) fn triangle(&mut self, corners: [u32; 3]) {
        self.pieces.push(Piece { kind: PieceKind3::Surface, corners });
    }

    /// The segment of local points `a`, `b` (a point when they are equal).
    pub(crate) fn segment(&mut self, a: u32, b: u32) {
        if self.points[a as usize] == self.points[b as usize] {
            self.point(a);
        } else {
            self.pieces.push(Piece { kind: PieceKind3::Segment, corners: [a, b, b] });
        }
    }

    /// The point of local index `a`.
    pub(crate) fn point(&mut self, a: u32) {
        self.pieces.push(Piece { kind: PieceKind3::Point, corners: [a, a, a] });
    }

    /// Mesh vertex `v` as a point.
    pub(crate) fn vertex(&mut self, v: usize) -> Result<(), SourceError> {
        let a = self.vertex_index(v)?;
        self.point(a);
        Ok(())
    }

    /// Every cell of topological face (surface) `f`, quads split along the 0–2 diagonal.
    pub(crate) fn surface(&mut self, topology: &Topology, f: usize) -> Result<(), SourceError> {
        let face = topology.faces.get(f).ok_or(SourceError::EntityOutOfRange {
            piece: self.pieces.len(),
            what: "face",
            index: f,
            len: topology.faces.len(),
        })?;
        for &c in &face.cells {
            let cell = topology.surface_cells.get(c).ok_or(SourceError::EntityOutOfRange {
                piece: self.pieces.len(),
                what: "surface cell",
                index: c,
                len: topology.surface_cells.len(),
            })?;
            let mut v = [0u32; 4];
            let corners = cell.vertices();
            for (k, &x) in corners.iter().enumerate() {
                v[k] = self.vertex_index(x)?;
            }
            self.triangle([v[0], v[1], v[2]]);
            if corners.len() == 4 {
                self.triangle([v[0], v[2], v[3]]);
            }
        }
        Ok(())
    }

    /// Every edge of the polylines of topological curve `c`.
    pub(crate) fn curve(&mut self, topology: &Topology, c: usize) -> Result<(), SourceError> {
        let curve = topology.curves.get(c).ok_or(SourceError::EntityOutOfRange {
            piece: self.pieces.len(),
            what: "curve",
            index: c,
            len: topology.curves.len(),
        })?;
        for pl in &curve.polylines {
            for [a, b] in pl.edges() {
                let (a, b) = (self.vertex_index(a)?, self.vertex_index(b)?);
                self.segment(a, b);
            }
            if pl.num_edges() == 0 {
                if let Some(&v) = pl.vertices.first() {
                    self.vertex(v)?;
                }
            }
        }
        Ok(())
    }

    /// Topological point `p`, as a point.
    pub(crate) fn topology_point(
        &mut self,
        topology: &Topology,
        p: usize,
    ) -> Result<(), SourceError> {
        let point = topology.points.get(p).ok_or(SourceError::EntityOutOfRange {
            piece: self.pieces.len(),
            what: "point",
            index: p,
            len: topology.points.len(),
        })?;
        self.vertex(point.vertex)
    }

    /// Whether no piece was added.
    pub(crate) fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }

    /// The source (with no piece when none was added: check [`is_empty`](Self::is_empty)).
    pub(crate) fn build(self) -> Result<SpaceSource, SourceError> {
        let corners: Vec<[u32; 3]> = self.pieces.iter().map(|p| p.corners).collect();
        let index = SurfaceIndex::new(&self.points, &corners).map_err(|e| match e {
            SurfaceError::VertexOutOfRange { triangle, vertex, count } => {
                SourceError::VertexOutOfRange {
                    piece: triangle,
                    vertex: vertex as usize,
                    len: count,
                }
            }
            SurfaceError::NonFinite { triangle, vertex } => {
                SourceError::NonFinite { piece: triangle, point: vertex as usize }
            }
            SurfaceError::TooMany(n) => SourceError::EntityOutOfRange {
                piece: n,
                what: "source piece",
                index: n,
                len: u32::MAX as usize - 1,
            },
        })?;
        let mut around: Vec<(u32, u32)> = Vec::new();
        for (i, p) in self.pieces.iter().enumerate() {
            if p.kind == PieceKind3::Surface {
                around.extend(p.corners.iter().map(|&c| (c, i as u32)));
            }
        }
        around.sort_unstable();
        around.dedup();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in &self.pieces {
            for &c in &p.corners {
                let x = self.points[c as usize];
                for k in 0..3 {
                    lo[k] = lo[k].min(x[k]);
                    hi[k] = hi[k].max(x[k]);
                }
            }
        }
        let free = self.local.is_empty() && !self.points.is_empty();
        Ok(SpaceSource { index, points: self.points, pieces: self.pieces, around, lo, hi, free })
    }
}

impl SpaceSource {
    /// Number of pieces.
    pub(crate) fn len(&self) -> usize {
        self.pieces.len()
    }

    /// Whether the source is made of free points only (see [`SpaceSourceBuilder::free_point`]).
    pub(crate) fn is_free(&self) -> bool {
        self.free
    }

    /// The corners of piece `i` (a segment `(a, b, b)`, a point `(p, p, p)`).
    pub(crate) fn piece_corners(&self, i: usize) -> [Point3; 3] {
        self.pieces[i].corners.map(|k| self.points[k as usize])
    }

    /// The box of every piece: (lowest, highest) corner.
    pub(crate) fn bounds(&self) -> (Point3, Point3) {
        (self.lo, self.hi)
    }

    /// The pieces, by index.
    pub(crate) fn pieces(&self) -> &[Piece] {
        &self.pieces
    }

    /// The source's points (corners of its pieces).
    pub(crate) fn points(&self) -> &[Point3] {
        &self.points
    }

    /// Squared distance from `p` to the box of every piece: never above the squared
    /// distance the kernel gives to any piece (the box test of the index), so a vertex
    /// whose box distance exceeds reach² is out of reach.
    pub(crate) fn box_distance_squared(&self, p: Point3) -> f64 {
        box_distance_squared(self.lo, self.hi, p)
    }

    /// The closest point of the source to `p`, with piece `seed` tried first (any seed
    /// gives the same answer); `None` when `p` is not finite.
    pub(crate) fn closest_from(&self, p: Point3, seed: u32) -> Option<SpaceClosest> {
        self.index.closest_from(p, seed).map(SpaceClosest::from)
    }

    /// The twin: the closest point by projecting `p` on every piece in index order,
    /// ties to the lower index.
    pub(crate) fn closest_brute(&self, p: Point3) -> Option<SpaceClosest> {
        let geoms: Vec<TriangleGeom> =
            (0..self.pieces.len() as u32).map(|i| *self.index.triangle(i)).collect();
        crate::geometry::space::closest_brute(&geoms, p).map(SpaceClosest::from)
    }

    /// The longest edge of piece `i` (0 for a point).
    pub(crate) fn piece_size(&self, i: u32) -> f64 {
        let c = self.pieces[i as usize].corners.map(|k| self.points[k as usize]);
        (0..3).map(|k| dist(c[k], c[(k + 1) % 3])).fold(0.0, f64::max)
    }

    /// The unit direction of segment piece `i` (from its first corner), `None` for
    /// another kind.
    pub(crate) fn segment_direction(&self, i: u32) -> Option<Point3> {
        let p = self.pieces[i as usize];
        if p.kind != PieceKind3::Segment {
            return None;
        }
        let (a, b) = (self.points[p.corners[0] as usize], self.points[p.corners[1] as usize]);
        unit3(sub(b, a))
    }

    /// The surface normal at the foot of `c` on a surface piece (`None` for another kind,
    /// or where the normals cancel), for a vertex on the source: in the face, the
    /// triangle's unit normal; on an edge or at a corner, the area-weighted mean of the
    /// normals of the source's triangles that share that edge or corner — the sum of
    /// their cross products (b − a) × (c − a), each twice the triangle's area times its
    /// unit normal, each turned to agree with the foot's own triangle (so an
    /// inconsistently oriented neighbour adds, not cancels) — normalised.
    ///
    /// Where the foot lies is told by its coordinates, not by the kernel's feature (a
    /// point at a corner projects into the face with two edge functions zero): at a
    /// corner when within `tolerance` of it, else on an edge when within `tolerance` of
    /// its line, else in the face.
    pub(crate) fn surface_normal(&self, c: &SpaceClosest, tolerance: f64) -> Option<Point3> {
        let own = self.pieces[c.piece as usize];
        if own.kind != PieceKind3::Surface {
            return None;
        }
        let corner = own.corners.map(|k| self.points[k as usize]);
        let n0 = self.raw_normal(c.piece);
        let shared: Vec<u32> =
            if let Some(k) = (0..3).find(|&k| dist(corner[k], c.foot) <= tolerance) {
                self.around_corner(own.corners[k]).collect()
            } else if let Some(k) = (0..3).find(|&k| {
                let (a, b) = (corner[k], corner[(k + 1) % 3]);
                let e = sub(b, a);
                let len = dot(e, e).sqrt();
                len > 0.0 && {
                    let x = cross(e, sub(c.foot, a));
                    dot(x, x).sqrt() / len <= tolerance
                }
            }) {
                let (a, b) = (own.corners[k], own.corners[(k + 1) % 3]);
                self.around_corner(a)
                    .filter(|&t| self.pieces[t as usize].corners.contains(&b))
                    .collect()
            } else {
                return unit3(n0);
            };
        let mut sum = [0.0; 3];
        for t in shared {
            let n = self.raw_normal(t);
            let s = if dot(n, n0) < 0.0 { -1.0 } else { 1.0 };
            for k in 0..3 {
                sum[k] += s * n[k];
            }
        }
        unit3(sum)
    }

    /// The surface pieces with corner `corner`, ascending.
    fn around_corner(&self, corner: u32) -> impl Iterator<Item = u32> + '_ {
        let start = self.around.partition_point(|&(c, _)| c < corner);
        self.around[start..].iter().take_while(move |&&(c, _)| c == corner).map(|&(_, t)| t)
    }

    /// (b − a) × (c − a) of piece `i`.
    fn raw_normal(&self, i: u32) -> Point3 {
        let c = self.pieces[i as usize].corners.map(|k| self.points[k as usize]);
        cross(sub(c[1], c[0]), sub(c[2], c[0]))
    }
}

pub(crate) fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dist(a: Point3, b: Point3) -> f64 {
    dot(sub(a, b), sub(a, b)).sqrt()
}

/// The unit vector along `v`, if it has a finite non-zero length.
pub(crate) fn unit3(v: Point3) -> Option<Point3> {
    let n = dot(v, v).sqrt();
    (n > 0.0 && n.is_finite()).then(|| [v[0] / n, v[1] / n, v[2] / n])
}
