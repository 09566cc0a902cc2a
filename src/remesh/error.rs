//! Why a mesh cannot be remeshed.

/// Why a mesh cannot be remeshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RemeshError {
    /// The metric does not have one tensor per point.
    #[error("the metric has {items} tensors for {vertices} vertices")]
    MetricCount {
        /// Tensors given.
        items: usize,
        /// Points of the mesh.
        vertices: usize,
    },
    /// A vertex used by a triangle has a metric that is not finite and SPD.
    #[error("the metric at vertex {vertex} (0-based), [[{a}, {b}], [{b}, {c}]], is not finite and positive definite")]
    NotSpd {
        /// The vertex.
        vertex: usize,
        /// m11.
        a: f64,
        /// m12.
        b: f64,
        /// m22.
        c: f64,
    },
    /// A point with a non-finite coordinate.
    #[error("vertex {vertex} (0-based) has a coordinate that is not finite")]
    BadPoint {
        /// The vertex.
        vertex: usize,
    },
    /// A cell kind the remesher does not handle.
    #[error("the remesher handles first-order triangles and quads, lines and vertex cells; the mesh has {kind} cells")]
    UnsupportedCell {
        /// The kind's name.
        kind: &'static str,
    },
    /// No triangle at all.
    #[error("the mesh has no triangles")]
    NoTriangles,
    /// Every surface cell is kept: nothing to remesh.
    #[error(
        "every surface cell of the mesh is a quad, or a triangle of a skin of quads, which the native remesher keeps frozen; no triangle is left to remesh: --split-quads splits each quad in two triangles and remeshes them all"
    )]
    AllKept,
    /// The input's quads and triangles do not form a valid mixed mesh.
    #[error("the mesh's quads and triangles do not form a valid mesh ({0}): the native remesher keeps quads frozen as a skin; --split-quads splits each quad in two triangles and remeshes them with the rest")]
    InvalidMixed(String),
    /// The result with its kept cells failed the mixed-mesh check (a bug).
    #[error("the remeshed mesh with its kept cells is not valid: {0}")]
    Invalid(String),
    /// A triangle with zero area or a repeated vertex.
    #[error("triangle {triangle} (0-based, vertices {vertices:?}) has zero area")]
    DegenerateTriangle {
        /// The triangle.
        triangle: usize,
        /// Its vertices.
        vertices: [usize; 3],
    },
    /// An edge shared by more than two triangles.
    #[error(
        "edge {edge:?} is shared by {triangles} triangles; the remesher needs a manifold mesh"
    )]
    NonManifold {
        /// The edge.
        edge: [usize; 2],
        /// How many triangles hold it.
        triangles: usize,
    },
    /// More vertices than the remesher's 32-bit indices allow.
    #[error("{vertices} vertices is more than the remesher handles")]
    TooLarge {
        /// Points of the mesh.
        vertices: usize,
    },
    /// The metric asks for more vertices than the limit allows: refused before any work.
    #[error("the metric asks for about {} vertices (its complexity), more than the limit of {limit}; raise it with --max-vertices, or bound the sizes (hmin)", crate::metric::complexity::format_count(*estimate))]
    TooManyVertices {
        /// Expected output vertices.
        estimate: f64,
        /// The limit.
        limit: usize,
    },
    /// The metric asks for more memory than the process may use (`ulimit -v`, a cgroup's
    /// `memory.max`): refused before any work, as an allocation failure would abort.
    #[error("the metric asks for about {} vertices, about {} of memory, more than {which} of {}; lower --max-vertices or the sizes' bounds (hmin), or raise the limit", crate::metric::complexity::format_count(*estimate), super::memory::format_bytes(*bytes), super::memory::format_bytes(*limit as f64))]
    MemoryLimit {
        /// Expected output vertices.
        estimate: f64,
        /// Their memory, bytes.
        bytes: f64,
        /// The limit, bytes.
        limit: u64,
        /// Which limit.
        which: &'static str,
    },
    /// The splits made more vertices than twice the limit (the estimate was wrong): the
    /// run stopped rather than grow without bound.
    #[error("remeshing passed {vertices} vertices, more than twice the limit of {limit} (the metric's complexity promised about {}); raise it with --max-vertices", crate::metric::complexity::format_count(*estimate))]
    Grew {
        /// Vertices when it stopped.
        vertices: usize,
        /// The limit.
        limit: usize,
        /// What the estimate said.
        estimate: f64,
    },
}

impl RemeshError {
    /// Whether the limit on the output's size refused the run (the input is valid, but
    /// asks for more than the user allowed).
    pub fn is_limit(&self) -> bool {
        matches!(
            self,
            RemeshError::TooManyVertices { .. }
                | RemeshError::MemoryLimit { .. }
                | RemeshError::Grew { .. }
        )
    }
}
