//! The options of a metric from a solution field, shared by `size --field` and
//! `adapt --solver`: the field, the normalisation (a vertex count or an error), the
//! norm, the recovery method and the anisotropy bound; and the sizing step they make.

use clap::Args;
use smartmesh::formats::TaggedMesh;
use smartmesh::recipe::Recipe;
use smartmesh::sizing::plan::Step;
use smartmesh::sizing::solution::{Method, Target};
use smartmesh::SizeBounds;

use super::output::positive_size;
use super::CliError;

/// How a solution field becomes a metric.
#[derive(Debug, Clone, Args)]
pub(super) struct SolutionArgs {
    /// The scalar point-data array of the solution (size: of the mesh, or of
    /// --solution-file; adapt: of the solver's output, whose only scalar array is taken
    /// when none is named). Repeat it or separate names by commas for several fields:
    /// each one's metric is normalised to the target alone, they are intersected in the
    /// order given, and the intersection is scaled to the target as a whole.
    #[arg(long, value_name = "NAME", value_delimiter = ',', help_heading = "Solution")]
    pub field: Vec<String>,
    /// The vertex count the solution's metric asks for (its complexity); adapt: the
    /// vertex budget of the mesh (the last value of the schedule), for the recipe's field,
    /// the solution's, or both intersected: the final field is scaled to it, the recipe's
    /// hmin and hmax with it, --hmin, --hmax, the aspect ratio and the gradation inside
    /// the scaling (with a solver the recipe takes at most --recipe-share of it).
    #[arg(long, value_name = "N", value_parser = positive_size, conflicts_with = "error", help_heading = "Solution")]
    pub complexity: Option<f64>,
    /// Normalise the metric to this Lp norm of the interpolation error instead.
    #[arg(long, value_name = "E", value_parser = positive_size, help_heading = "Solution")]
    pub error: Option<f64>,
    /// The Lp norm the metric minimises the interpolation error in (>= 1; `inf`, the
    /// density |H| that the H1 seminorm of the error asks for).
    #[arg(long, default_value_t = 2.0, value_parser = norm, help_heading = "Solution")]
    pub p: f64,
    /// How the Hessian is recovered, both exact on quadratics at every vertex of any mesh:
    /// quadratic-fit (a quadratic fitted to each vertex's patch) or l2-projection (a
    /// gradient fitted to the P1 gradient's edge components, then its gradient's lumped
    /// L2 projection).
    #[arg(long, default_value = "quadratic-fit", value_parser = method, help_heading = "Solution")]
    pub recovery: Method,
    /// Largest aspect ratio of the solution's metric (default: the recipe's, else 1e4).
    #[arg(long, value_name = "R", value_parser = aspect, help_heading = "Solution")]
    pub max_aspect: Option<f64>,
}

fn norm(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(p) if p >= 1.0 => Ok(p),
        Ok(p) => Err(format!("{p} is not a norm (expected a number >= 1, or inf)")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

fn aspect(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(r) if r.is_finite() && r >= 1.0 => Ok(r),
        Ok(r) => Err(format!("{r} is not an aspect ratio (expected a finite number >= 1)")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

fn method(s: &str) -> Result<Method, String> {
    Method::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        format!("unknown recovery `{s}`; known: {}", names.join(", "))
    })
}

impl SolutionArgs {
    /// The target given: the vertex count or the error; `None` without either.
    pub(super) fn target(&self) -> Option<Target> {
        match (self.complexity, self.error) {
            (Some(n), _) => Some(Target::Vertices(n)),
            (None, Some(e)) => Some(Target::Error(e)),
            (None, None) => None,
        }
    }

    /// The fields named by --field, in order: each once, none empty.
    pub(super) fn fields(&self) -> Result<Vec<String>, CliError> {
        for (i, name) in self.field.iter().enumerate() {
            if name.trim().is_empty() {
                return Err(CliError::usage(format!(
                    "--field: an empty name in `{}`",
                    self.field.join(",")
                )));
            }
            if self.field[..i].contains(name) {
                return Err(CliError::usage(format!("--field: `{name}` is named twice")));
            }
        }
        Ok(self.field.clone())
    }

    /// The bounds of the solution's metric on `mesh`: --max-aspect, else the recipe's
    /// global values (the command line's sizes already over them), else defaults from
    /// the mesh's extent ([`Recipe::solution_bounds`]).
    pub(super) fn bounds(
        &self,
        mesh: &TaggedMesh,
        recipe: &Recipe,
    ) -> Result<SizeBounds, CliError> {
        recipe.solution_bounds(mesh, self.max_aspect).map_err(|e| CliError::usage(e.to_string()))
    }

    /// The sizing step of fields `names` (one or more) on `mesh` normalised together to
    /// `target`, within [`SolutionArgs::bounds`].
    pub(super) fn step(
        &self,
        names: &[String],
        target: Target,
        mesh: &TaggedMesh,
        recipe: &Recipe,
    ) -> Result<Step, CliError> {
        let bounds = self.bounds(mesh, recipe)?;
        Ok(Step::solution_hessian(names, target, self.p, self.recovery, &bounds))
    }
}
