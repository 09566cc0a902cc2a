//! The sizing algorithms of thesis 4.3.6–4.3.7, declared in one table.
//!
//! Each algorithm is one file, `algorithms/<name>.rs`, holding one type (its resolved
//! parameters: built functions, entity sets of one mesh) that implements
//! `SizingAlgorithm`: its recipe [`Declaration`] (keyword, documentation, the
//! functions, regions, sizes and polylines it takes), how it is built from resolved
//! [`Arguments`], the entities and sources a report shows, and its `Work`: the
//! vertices it gives a tensor to (a list, or those within a reach of one or two
//! [`Source`]s) and the `Tensor` of each from its closest points. How that work is
//! evaluated — propagation, vertex order, tensors collected or merged into a field — is
//! the driver's choice ([`crate::sizing::field`]); an algorithm never sees it.
//!
//! The table below (`algorithms!`) is the only list of algorithms. It makes the
//! [`Algorithm`] enum of a plan and the [`TABLE`] of declarations that the recipe model,
//! its libconfig/TOML/JSON readers and writers, resolution, `recipe check` and the
//! report read. Adding an algorithm is one new file and one line here:
//!
//! ```text
//! // src/sizing/algorithms/solution_hessian.rs
//! pub struct SolutionHessian { pub field: ..., pub within: EntitySet }
//! impl SizingAlgorithm for SolutionHessian {
//!     const DECLARATION: Declaration = Declaration { keyword: "SOLUTION_HESSIAN", .. };
//!     fn from_arguments(..) .. fn entity_sets(..) .. fn zoom(..) .. fn work(..) ..
//! }
//! // the table
//! algorithms! { ..., solution_hessian::SolutionHessian, }
//! ```
//!
//! In space. An algorithm that sizes a mesh in space (tetrahedra, or triangles off one
//! plane) also implements `SizingAlgorithm::work_in_space`, in the same file as its 2D
//! `work` and sharing its functions, and says so with `IN_SPACE = true`; by default it
//! refuses with `Failure::NotInSpace` naming its keyword. Its `SpaceWork` is a list of
//! vertices with [`SizeTensor3`]s, or a `SpaceTensor` of each vertex from its exact
//! closest point(s) on one or two `SpaceSource`s within a reach; the 3D driver
//! ([`crate::sizing::field3`]) evaluates it.
//!
//! Maximum distance. An algorithm propagates up to the largest maximum distance of the
//! functions it evaluates at a distance (perpendicular, parallel, projection; the
//! polyline's abscissa function and the curvature-to-size function take no distance).
//! Past its own maximum distance a function holds its end value (thesis 4.3.5.1 extended
//! by continuity), so every function is honoured over its whole range and none is cut
//! short by another. The perpendicular function usually has the largest reach; when it
//! does, it alone decides where the algorithm applies.

mod declaration;
mod frame;
mod frame3;
mod sources;

pub use declaration::{
    infinite_norm, Argument, Arguments, Declaration, EntitySet, FunctionKind, Given, Marks,
    Parameter, ParameterKind, PolylinePoints, Refusal, Sheet, INFINITE_NORM,
};
pub use frame::ON_SOURCE;
pub(crate) use frame::{direction, normal_at, on_source, tangent_at, tensor, unit, Junctions};
pub(crate) use frame3::{across, on_source3, wall_tensor, Across};
pub(crate) use sources::{border_source, check_entities, reach_of, space_border_source};

use crate::geometry::Point2;
use crate::mesh_graph::MeshGraph;
use crate::metric::{SizeTensor, SizeTensor3};
use crate::sizing::propagation::{ClosestPoint, Source, SourceError};
use crate::sizing::space::{SpaceClosest, SpaceMesh, SpaceSource};
use crate::topology::Topology;

/// The table of algorithms: one line each, `module::Type`, in the order recipes list
/// them (`recipe check`, error messages).
macro_rules! algorithms {
    ($($module:ident :: $name:ident,)*) => {
        $(
            pub mod $module;
            pub use $module::$name;
            impl From<$name> for Algorithm {
                fn from(a: $name) -> Algorithm {
                    Algorithm::$name(a)
                }
            }
        )*

        /// One algorithm of a plan (thesis 4.3.6–4.3.7), its functions built and its
        /// regions resolved: one variant per line of the table.
        #[derive(Debug, Clone, PartialEq)]
        pub enum Algorithm {
            $(
                #[doc = concat!("[`", stringify!($name), "`].")]
                $name($name),
            )*
        }

        impl Algorithm {
            /// Its recipe declaration.
            pub fn declaration(&self) -> &'static Declaration {
                match self {
                    $(Algorithm::$name(_) => &<$name as SizingAlgorithm>::DECLARATION,)*
                }
            }

            /// Its appendix keyword (`DISTANCE_TO_BORDER`).
            pub fn keyword(&self) -> &'static str {
                self.declaration().keyword
            }

            /// Every entity set it takes, in declaration order.
            pub fn entity_sets(&self) -> Vec<&EntitySet> {
                match self {
                    $(Algorithm::$name(a) => a.entity_sets(),)*
                }
            }

            /// Where its sources lie and the distance over which it acts, for a zoom
            /// window; `None` without a localised source.
            pub fn zoom(&self) -> Option<(Around<'_>, f64)> {
                match self {
                    $(Algorithm::$name(a) => a.zoom(),)*
                }
            }

            /// What a report marks over the mesh for it.
            pub fn marks(&self) -> Marks<'_> {
                match self {
                    $(Algorithm::$name(a) => a.marks(),)*
                }
            }

            /// Whether it sizes a mesh in space (`SizingAlgorithm::IN_SPACE`).
            pub fn in_space(&self) -> bool {
                match self {
                    $(Algorithm::$name(a) => a.sized_in_space(),)*
                }
            }

            /// Whether it sizes a mesh in space that has no volume cell (a surface mesh
            /// off one plane).
            pub fn on_surface_in_space(&self) -> bool {
                match self {
                    $(Algorithm::$name(a) => a.sized_on_surface_in_space(),)*
                }
            }

            /// What it asks of the 3D driver on `mesh` (see [`SpaceWork`]).
            pub(crate) fn work_in_space<'a>(
                &'a self,
                mesh: &'a SpaceMesh<'a>,
                topology: &'a Topology,
            ) -> Result<SpaceWork<'a>, Failure> {
                match self {
                    $(Algorithm::$name(a) => a.work_in_space(mesh, topology),)*
                }
            }

            /// Calls `visitor` with the algorithm as its own type.
            pub(crate) fn visit<V: Visit>(&self, visitor: V) -> V::Output {
                match self {
                    $(Algorithm::$name(a) => visitor.visit(a),)*
                }
            }
        }

        /// The declarations of the algorithms, in table order, each with how to build it.
        pub static TABLE: &[Entry] = &[
            $(Entry {
                declaration: &<$name as SizingAlgorithm>::DECLARATION,
                build: build::<$name>,
                check: <$name as SizingAlgorithm>::check,
            },)*
        ];
    };
}

algorithms! {
    uniform::Uniform,
    distance_to_point::DistanceToPoint,
    distance_to_border::DistanceToBorder,
    curvature_of_border::CurvatureOfBorder,
    distance_between_two_borders::DistanceBetweenTwoBorders,
    distance_to_imaginary_polyline::DistanceToImaginaryPolyline,
    solution_hessian::SolutionHessian,
    distance_to_imaginary_surface::DistanceToImaginarySurface,
}

/// One line of [`TABLE`].
pub struct Entry {
    /// What recipes know of the algorithm.
    pub declaration: &'static Declaration,
    /// Builds it from its resolved arguments (`None` when an argument is missing or of
    /// another kind than declared).
    pub build: fn(&mut Arguments) -> Option<Algorithm>,
    /// Checks how the numbers a recipe gives it go together (ranges beyond a size's, one
    /// parameter excluding another), before anything is resolved.
    pub check: fn(Given<'_>) -> Result<(), Refusal>,
}

impl std::fmt::Debug for Entry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Entry").field("keyword", &self.declaration.keyword).finish()
    }
}

impl Entry {
    /// The line of the table with appendix keyword `keyword` (upper case) or TOML/JSON
    /// type `name`.
    pub fn find(keyword_or_name: &str) -> Option<&'static Entry> {
        TABLE.iter().find(|e| {
            e.declaration.keyword == keyword_or_name || e.declaration.name == keyword_or_name
        })
    }
}

fn build<A: SizingAlgorithm + Into<Algorithm>>(arguments: &mut Arguments) -> Option<Algorithm> {
    A::from_arguments(arguments).map(Into::into)
}

/// Where a step's sources lie, for a zoom window.
#[derive(Debug, Clone, PartialEq)]
pub enum Around<'a> {
    /// Topological entities.
    Entities(EntitySet),
    /// Points given by coordinates (an imaginary polyline).
    Points(&'a [Point2]),
}

/// A sizing algorithm: see the module header.
pub(crate) trait SizingAlgorithm: Sized {
    /// What recipes know of it.
    const DECLARATION: Declaration;

    /// The tensor of a vertex from its closest points.
    type Tensor<'a>: Tensor
    where
        Self: 'a;

    /// Built from the arguments of its declared parameters (`None` when one is missing
    /// or of another kind).
    fn from_arguments(arguments: &mut Arguments) -> Option<Self>;

    /// Refuses numbers that do not go together (every size is already within [1e-30,
    /// 1e30]); none by default.
    fn check(_: Given<'_>) -> Result<(), Refusal> {
        Ok(())
    }

    /// Every entity set it takes, in declaration order.
    fn entity_sets(&self) -> Vec<&EntitySet>;

    /// Where its sources lie and the distance over which it acts; `None` when it has no
    /// localised source.
    fn zoom(&self) -> Option<(Around<'_>, f64)>;

    /// What a report marks over the mesh for it: none by default.
    fn marks(&self) -> Marks<'_> {
        Marks::default()
    }

    /// What it asks of the driver on the mesh of `graph` and `topology`.
    fn work<'a>(
        &'a self,
        graph: &'a MeshGraph,
        topology: &'a Topology,
    ) -> Result<Work<Self::Tensor<'a>>, Failure>;

    /// Whether it implements [`work_in_space`](Self::work_in_space) (`recipe check` on a
    /// mesh in space says which steps are sized there).
    const IN_SPACE: bool = false;

    /// Whether this instance sizes a mesh in space: [`IN_SPACE`](Self::IN_SPACE) unless
    /// its arguments say otherwise (a polyline of (x, y) points).
    fn sized_in_space(&self) -> bool {
        Self::IN_SPACE
    }

    /// Whether this instance sizes a surface mesh in space (no volume cell): as in space,
    /// unless the work needs volume cells.
    fn sized_on_surface_in_space(&self) -> bool {
        self.sized_in_space()
    }

    /// What it asks of the 3D driver on a mesh in space: by default a refusal naming the
    /// keyword ([`Failure::NotInSpace`], exit code 2 from the command line).
    fn work_in_space<'a>(
        &'a self,
        _mesh: &'a SpaceMesh<'a>,
        _topology: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        Err(Failure::NotInSpace { keyword: Self::DECLARATION.keyword })
    }
}

/// What an algorithm asks the 3D driver to evaluate on a mesh in space (the 3D
/// counterpart of [`Work`]; the tensor of a vertex is a trait object, called once per
/// vertex within reach, next to a closest-point query that costs far more). Made once
/// per step and moved once: the size of its variants does not matter.
#[allow(clippy::large_enum_variant)]
pub(crate) enum SpaceWork<'a> {
    /// Tensors of listed vertices (each once, ascending), with no source (UNIFORM,
    /// SOLUTION_HESSIAN).
    Listed {
        /// The vertices.
        vertices: Vec<u32>,
        /// The tensor of each.
        tensors: Vec<SizeTensor3>,
    },
    /// A tensor for every vertex whose exact distance to `source` is within `reach`
    /// (squared distance <= reach², see [`crate::sizing::field3`]), from its closest point.
    FromSource {
        /// The source.
        source: SpaceSource,
        /// The largest distance that matters.
        reach: f64,
        /// The tensor of a vertex.
        tensor: Box<dyn SpaceTensor + 'a>,
    },
    /// A tensor for every vertex within `reach` of both sources, from its closest point
    /// on each.
    #[allow(dead_code)]
    FromTwoSources {
        /// The sources.
        sources: [SpaceSource; 2],
        /// The largest distance that matters.
        reach: f64,
        /// The tensor of a vertex.
        tensor: Box<dyn SpaceTensor + 'a>,
    },
}

/// The tensor of vertex `v` (at `at`) from its closest point on each source of its
/// [`SpaceWork`] (`sources` and `closest` have one entry per source): `Ok(None)` leaves
/// the vertex out. Called from any thread, in any order: a function of its arguments.
pub(crate) trait SpaceTensor: Sync {
    /// The tensor of `v`.
    fn tensor(
        &self,
        sources: &[SpaceSource],
        v: usize,
        at: [f64; 3],
        closest: &[SpaceClosest],
    ) -> Result<Option<SizeTensor3>, Failure>;
}

/// What an algorithm asks the driver to evaluate. One per step, made once and moved
/// once: the size of its variants does not matter.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Work<T> {
    /// Tensors of listed vertices, with no source (UNIFORM).
    Listed(Contribution),
    /// A tensor for every vertex within `reach` of `source`, from its closest point.
    FromSource {
        /// The source.
        source: Source,
        /// The largest distance that matters.
        reach: f64,
        /// The tensor of a vertex.
        tensor: T,
    },
    /// A tensor for every vertex within `reach` of both sources, from its closest
    /// point on each.
    FromTwoSources {
        /// The sources.
        sources: [Source; 2],
        /// The largest distance that matters.
        reach: f64,
        /// The tensor of a vertex.
        tensor: T,
    },
}

/// The tensor of vertex `v` from its closest point on each source of its [`Work`]
/// (`sources` and `closest` have one entry per source): `Ok(None)` leaves the vertex
/// out. Called from any thread, in any order: a function of its arguments only.
pub(crate) trait Tensor: Sync {
    /// The tensor of `v`.
    fn tensor(
        &self,
        sources: &[Source],
        v: usize,
        closest: &[ClosestPoint],
    ) -> Result<Option<SizeTensor>, Failure>;
}

/// The tensor of an algorithm whose work is a list.
impl Tensor for std::convert::Infallible {
    fn tensor(
        &self,
        _: &[Source],
        _: usize,
        _: &[ClosestPoint],
    ) -> Result<Option<SizeTensor>, Failure> {
        match *self {}
    }
}

/// Something done with an algorithm as its own type ([`Algorithm::visit`]).
pub(crate) trait Visit {
    /// What it gives.
    type Output;

    /// Does it with `algorithm`.
    fn visit<A: SizingAlgorithm>(self, algorithm: &A) -> Self::Output;
}

/// What one algorithm asks for: the vertices it reaches and one tensor each.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Contribution {
    /// Reached vertices, each once, in the algorithm's order (seeds first, then by
    /// propagation level).
    pub vertices: Vec<u32>,
    /// The tensor of each vertex of `vertices`.
    pub tensors: Vec<SizeTensor>,
    /// Vertices the propagation started from (0 for UNIFORM).
    pub seeds: usize,
}

impl Contribution {
    /// Number of vertices reached.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Whether no vertex was reached.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }
}

/// Why an algorithm could not run; the driver adds the step.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Failure {
    /// A topological entity index the topology does not have.
    EntityOutOfRange { what: &'static str, index: usize, len: usize },
    /// An entity of a kind the algorithm cannot use as a source.
    UnsupportedEntity { what: &'static str, index: usize },
    /// The sources make no segment and no point.
    NoSource,
    /// An imaginary polyline with no point.
    EmptyPolyline,
    /// A polyline point with a NaN or infinite coordinate.
    NonFinitePoint { point: usize },
    /// A size outside [MIN_SIZE, MAX_SIZE].
    InvalidSize { size: f64 },
    /// A vertex whose tensor could not be formed (non-finite coordinates).
    Degenerate { vertex: usize },
    /// The field an algorithm sizes from is missing or unusable: why, in words.
    Field { why: String },
    /// The algorithm does not size a mesh in space yet.
    NotInSpace { keyword: &'static str },
    /// An algorithm that sizes meshes in space only, on a planar mesh.
    OnlyInSpace { keyword: &'static str },
    /// A polyline of 2 coordinates on a mesh in space, or of 3 on a planar mesh.
    PolylineComponents { components: usize, in_space: bool },
}

impl From<SourceError> for Failure {
    fn from(e: SourceError) -> Failure {
        match e {
            SourceError::VertexOutOfRange { vertex, len, .. } => {
                Failure::EntityOutOfRange { what: "mesh vertex", index: vertex, len }
            }
            SourceError::EntityOutOfRange { what, index, len, .. } => {
                Failure::EntityOutOfRange { what, index, len }
            }
            SourceError::EmptyPiece { .. } => Failure::EmptyPolyline,
            SourceError::NonFinite { point, .. } => Failure::NonFinitePoint { point },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::TABLE;

    /// The table's declarations are what the recipe readers rely on: unique keywords,
    /// the TOML/JSON type the keyword in lower case, and within each algorithm unique
    /// fields and libconfig keys, every parameter with a key to write.
    #[test]
    fn declarations_are_consistent() {
        let mut keywords: Vec<&str> = TABLE.iter().map(|e| e.declaration.keyword).collect();
        keywords.sort_unstable();
        keywords.dedup();
        assert_eq!(keywords.len(), TABLE.len());
        for e in TABLE {
            let d = e.declaration;
            assert_eq!(d.name, d.keyword.to_ascii_lowercase(), "{}", d.keyword);
            assert!(!d.doc.is_empty(), "{}", d.keyword);
            let mut fields: Vec<&str> = d
                .parameters
                .iter()
                .flat_map(|p| p.aliases.iter().copied().chain([p.field]))
                .collect();
            let mut keys: Vec<&str> =
                d.parameters.iter().flat_map(|p| p.keys.iter().copied()).collect();
            let (nf, nk) = (fields.len(), keys.len());
            fields.sort_unstable();
            fields.dedup();
            keys.sort_unstable();
            keys.dedup();
            assert_eq!((fields.len(), keys.len()), (nf, nk), "{}", d.keyword);
            assert!(d.parameters.iter().all(|p| !p.keys.is_empty()), "{}", d.keyword);
            assert!(!fields.contains(&"type") && !keys.contains(&"TYPE"), "{}", d.keyword);
        }
    }
}
