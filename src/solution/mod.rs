//! Metrics from a computed field (a solution): the scalar point field's gradient and
//! Hessian recovered on the mesh ([`recovery`]), the Lp-optimal metric of the continuous
//! mesh framework normalised to a vertex count or an error ([`lp`]), and the field read
//! from a mesh or a solver's file on the same vertices ([`input`]). The sizing algorithm
//! SOLUTION_HESSIAN ([`crate::sizing::SolutionHessian`]) puts them in a recipe. On
//! tetrahedra: [`recovery3`] and [`lp3`], what both dimensions share in `patch`.

pub mod combined;
mod edge_fit;
pub mod input;
pub mod lp;
pub mod lp3;
mod lp_space;
mod patch;
pub mod recovery;
pub mod recovery3;

pub use combined::lp_metric_of_fields;
pub use lp::{
    intersect_all, lp_metric, vertices_of, LpError, LpMetric, LpMetricOf, LpOptions, Target,
};
pub use lp3::{lp_metric3, vertices_of3, LpMetric3};
pub use recovery::{recover, Derivatives, Method, P1Mesh, RecoveryError};
pub use recovery3::{recover3, Derivatives3, P1Mesh3};

#[cfg(test)]
pub(crate) mod test_meshes;
#[cfg(test)]
pub(crate) mod test_meshes3;
