//! What an algorithm declares to the recipe: its keyword, its documentation and its
//! parameters (the functions, regions, sizes and polylines it takes), and the resolved
//! arguments it is built from.
//!
//! The recipe model, its libconfig, TOML and JSON readers and writers, resolution
//! against a mesh and `recipe check` read these declarations only: no part of the recipe
//! names an algorithm. A parameter's `field` is its name in the model and in TOML/JSON;
//! `keys` are its libconfig spellings (thesis appendix A), the first one written.

use crate::geometry::Point2;
use crate::sizing::functions::{CurvatureToSize, DistanceFunction, SizeProjectionFunction};

/// The points of a recipe polyline: every point (x, y) for a planar mesh, or every
/// point (x, y, z) for a mesh in space; never a mix (the readers refuse one, naming the
/// point). TOML and JSON write it as an array of 2- or 3-number arrays, libconfig as
/// `X_COORDS`, `Y_COORDS` and, in space, `Z_COORDS`.
#[derive(Debug, Clone, PartialEq)]
pub enum PolylinePoints {
    /// Points (x, y).
    Plane(Vec<Point2>),
    /// Points (x, y, z).
    Space(Vec<[f64; 3]>),
}

impl PolylinePoints {
    /// Number of points.
    pub fn len(&self) -> usize {
        match self {
            PolylinePoints::Plane(p) => p.len(),
            PolylinePoints::Space(p) => p.len(),
        }
    }

    /// Whether it has no point.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// 2 or 3.
    pub fn components(&self) -> usize {
        match self {
            PolylinePoints::Plane(_) => 2,
            PolylinePoints::Space(_) => 3,
        }
    }

    /// The coordinates of point `i` (2 or 3 numbers).
    pub fn point(&self, i: usize) -> &[f64] {
        match self {
            PolylinePoints::Plane(p) => &p[i],
            PolylinePoints::Space(p) => &p[i],
        }
    }

    /// The points in the plane, `None` in space.
    pub fn plane(&self) -> Option<&[Point2]> {
        match self {
            PolylinePoints::Plane(p) => Some(p),
            PolylinePoints::Space(_) => None,
        }
    }

    /// The points in space, `None` in the plane.
    pub fn space(&self) -> Option<&[[f64; 3]]> {
        match self {
            PolylinePoints::Plane(_) => None,
            PolylinePoints::Space(p) => Some(p),
        }
    }

    /// The points from lists of coordinates, each of 2 or 3 numbers, all of one length;
    /// otherwise why not (naming the 1-based point).
    pub fn from_coordinates(points: Vec<Vec<f64>>) -> Result<PolylinePoints, String> {
        let n = points.first().map_or(2, Vec::len);
        if n != 2 && n != 3 {
            return Err(format!("point 1 has {n} coordinates: expected 2 (x, y) or 3 (x, y, z)"));
        }
        if let Some(i) = points.iter().position(|p| p.len() != n) {
            return Err(format!(
                "point {} has {} coordinates but point 1 has {n}: every point of a polyline \
                 has 2 (x, y) or every point 3 (x, y, z)",
                i + 1,
                points[i].len()
            ));
        }
        Ok(if n == 2 {
            PolylinePoints::Plane(points.iter().map(|p| [p[0], p[1]]).collect())
        } else {
            PolylinePoints::Space(points.iter().map(|p| [p[0], p[1], p[2]]).collect())
        })
    }
}

/// A triangulated sheet in space (a wake, a shock surface) read from a file, for
/// DISTANCE_TO_IMAGINARY_SURFACE: its points and triangles (quads split), as read.
#[derive(Debug, Clone, PartialEq)]
pub struct Sheet {
    /// The file it was read from, as resolved (for messages).
    pub path: std::path::PathBuf,
    /// Its points.
    pub points: Vec<[f64; 3]>,
    /// Its triangles, indices into `points`, at least one.
    pub triangles: Vec<[u32; 3]>,
}

impl serde::Serialize for PolylinePoints {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            PolylinePoints::Plane(p) => p.serialize(s),
            PolylinePoints::Space(p) => p.serialize(s),
        }
    }
}

impl<'de> serde::Deserialize<'de> for PolylinePoints {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<PolylinePoints, D::Error> {
        let points: Vec<Vec<f64>> = serde::Deserialize::deserialize(d)?;
        PolylinePoints::from_coordinates(points).map_err(serde::de::Error::custom)
    }
}

/// Topological entities of one mesh, by index into [`crate::Topology`] (a region's, once resolved).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EntitySet {
    /// Indices into `Topology::points`.
    pub points: Vec<usize>,
    /// Indices into `Topology::curves`.
    pub curves: Vec<usize>,
    /// Indices into `Topology::faces`.
    pub faces: Vec<usize>,
    /// Indices into the volumes of `Topology::space` (a mesh in space).
    pub volumes: Vec<usize>,
}

impl EntitySet {
    /// Whether the set names no entity.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
            && self.curves.is_empty()
            && self.faces.is_empty()
            && self.volumes.is_empty()
    }

    /// The union of two sets, each list sorted and without repeats.
    pub fn union(&self, other: &EntitySet) -> EntitySet {
        let merge = |a: &[usize], b: &[usize]| {
            let mut v: Vec<usize> = a.iter().chain(b).copied().collect();
            v.sort_unstable();
            v.dedup();
            v
        };
        EntitySet {
            points: merge(&self.points, &other.points),
            curves: merge(&self.curves, &other.curves),
            faces: merge(&self.faces, &other.faces),
            volumes: merge(&self.volumes, &other.volumes),
        }
    }
}

/// An algorithm as recipes know it.
#[derive(Debug, PartialEq)]
pub struct Declaration {
    /// The appendix keyword (`DISTANCE_TO_BORDER`); its lower case is the TOML/JSON
    /// `type`.
    pub keyword: &'static str,
    /// The TOML/JSON `type` (the keyword in lower case).
    pub name: &'static str,
    /// One paragraph for `recipe` documentation.
    pub doc: &'static str,
    /// Its parameters, in the order recipes write them.
    pub parameters: &'static [Parameter],
}

/// One parameter of an algorithm in a recipe.
#[derive(Debug, PartialEq)]
pub struct Parameter {
    /// The model field and TOML/JSON key (`perpendicular`).
    pub field: &'static str,
    /// Other TOML/JSON keys accepted for it (`regions2`).
    pub aliases: &'static [&'static str],
    /// The libconfig keys accepted (`PERPENDICULAR_FUNCTION`), the first one written.
    pub keys: &'static [&'static str],
    /// What it takes.
    pub kind: ParameterKind,
    /// Whether the libconfig writer starts a new line after it.
    pub line_break_after: bool,
    /// What it is for.
    pub doc: &'static str,
}

/// What a parameter takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParameterKind {
    /// A size (a number in [1e-30, 1e30]).
    Size,
    /// A size that may be left out (the algorithm then chooses; its documentation says
    /// how).
    OptionalSize,
    /// The exponent of a norm: a number >= 1 or infinity, which may be left out. Written
    /// `inf` (or `infinity`) as a string in every recipe format, and as TOML's own `inf`.
    OptionalNorm,
    /// One of the words listed, the first when left out.
    Choice(&'static [&'static str]),
    /// The name of a function of this kind.
    Function(FunctionKind),
    /// Region names. `dimensions`: the entity dimensions accepted (0 points, 1 curves,
    /// 2 faces), the one preferred first when a region's dimension is ambiguous. On a
    /// mesh in space, when `lift`, each dimension from 1 up is also accepted one higher,
    /// before it (the border of a volume is a surface): see `recipe::resolve`.
    /// `optional`: may be left out or empty (then the set is empty).
    Regions {
        /// Accepted dimensions, preferred first.
        dimensions: &'static [usize],
        /// Whether it may be empty.
        optional: bool,
        /// Whether a mesh in space also takes each dimension d ≥ 1 as d + 1 (false for
        /// DISTANCE_TO_POINT, whose sources are vertices: points, or a curve's vertices).
        lift: bool,
    },
    /// The name of a polyline of the recipe.
    Polyline,
    /// The path of a file (a triangulated surface), relative to the recipe file that
    /// names it; read when the recipe is resolved.
    File,
    /// The name of a scalar point-data array of the mesh being sized (a solution field),
    /// looked up when the step runs.
    PointData,
}

/// The word a recipe writes for an infinite norm exponent.
pub const INFINITE_NORM: &str = "inf";

/// The value of a norm exponent written as a word: `inf` or `infinity` (any case, an
/// optional `+`) is infinity; any other word is none.
pub fn infinite_norm(word: &str) -> Option<f64> {
    let w = word.trim().strip_prefix('+').unwrap_or(word.trim());
    (w.eq_ignore_ascii_case("inf") || w.eq_ignore_ascii_case("infinity")).then_some(f64::INFINITY)
}

impl ParameterKind {
    /// Whether the parameter is a list of names (regions) rather than one value.
    pub fn is_list(self) -> bool {
        matches!(self, ParameterKind::Regions { .. })
    }

    /// Whether it may be left out.
    pub fn is_optional(self) -> bool {
        matches!(
            self,
            ParameterKind::Regions { optional: true, .. }
                | ParameterKind::OptionalSize
                | ParameterKind::OptionalNorm
                | ParameterKind::Choice(_)
        )
    }
}

/// The numbers a recipe gives an algorithm (its sizes, the optional ones left out
/// absent), for the algorithm's own check of how they go together.
#[derive(Debug, Clone, Copy)]
pub struct Given<'a> {
    /// (parameter field, value), in declaration order.
    pub sizes: &'a [(&'static str, f64)],
}

impl Given<'_> {
    /// The value of `field`, if given.
    pub fn get(&self, field: &str) -> Option<f64> {
        self.sizes.iter().find(|(f, _)| *f == field).map(|(_, x)| *x)
    }
}

/// Why an algorithm refuses the numbers it was given: the parameter to blame and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    /// The parameter field the recipe should change.
    pub field: &'static str,
    /// Why, in words (the recipe error names the key and the place).
    pub why: String,
}

/// The kind of function a parameter needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FunctionKind {
    /// A distance function.
    Distance,
    /// A projection function.
    Projection,
    /// A curvature-to-size function.
    Curvature,
}

impl FunctionKind {
    /// `distance`, `projection` or `curvature-to-size`.
    pub fn name(self) -> &'static str {
        match self {
            FunctionKind::Distance => "distance",
            FunctionKind::Projection => "projection",
            FunctionKind::Curvature => "curvature-to-size",
        }
    }
}

/// One resolved argument: a parameter's value with its functions built and its regions
/// turned into topological entities of one mesh.
#[derive(Debug, Clone, PartialEq)]
pub enum Argument {
    /// A size.
    Size(f64),
    /// A distance function.
    Distance(DistanceFunction),
    /// A projection function.
    Projection(SizeProjectionFunction),
    /// A curvature-to-size function.
    Curvature(CurvatureToSize),
    /// The entities of a region list.
    Entities(EntitySet),
    /// A polyline's points.
    Polyline(PolylinePoints),
    /// A triangulated sheet read from a file.
    Sheet(Sheet),
    /// A name passed as it is (a point-data array).
    Name(String),
}

/// The resolved arguments of one algorithm, by parameter field, in declaration order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Arguments {
    values: Vec<(&'static str, Argument)>,
}

impl Arguments {
    /// No argument yet.
    pub fn new() -> Arguments {
        Arguments::default()
    }

    /// Adds the argument of parameter `field`.
    pub fn push(&mut self, field: &'static str, value: Argument) {
        self.values.push((field, value));
    }

    fn take(&mut self, field: &str) -> Option<Argument> {
        let i = self.values.iter().position(|(f, _)| *f == field)?;
        Some(self.values.remove(i).1)
    }

    /// The size of `field`.
    pub fn size(&mut self, field: &str) -> Option<f64> {
        match self.take(field)? {
            Argument::Size(s) => Some(s),
            _ => None,
        }
    }

    /// The distance function of `field`.
    pub fn distance(&mut self, field: &str) -> Option<DistanceFunction> {
        match self.take(field)? {
            Argument::Distance(f) => Some(f),
            _ => None,
        }
    }

    /// The projection function of `field`.
    pub fn projection(&mut self, field: &str) -> Option<SizeProjectionFunction> {
        match self.take(field)? {
            Argument::Projection(f) => Some(f),
            _ => None,
        }
    }

    /// The curvature-to-size function of `field`.
    pub fn curvature(&mut self, field: &str) -> Option<CurvatureToSize> {
        match self.take(field)? {
            Argument::Curvature(f) => Some(f),
            _ => None,
        }
    }

    /// The entities of `field`.
    pub fn entities(&mut self, field: &str) -> Option<EntitySet> {
        match self.take(field)? {
            Argument::Entities(e) => Some(e),
            _ => None,
        }
    }

    /// The polyline of `field`.
    pub fn polyline(&mut self, field: &str) -> Option<PolylinePoints> {
        match self.take(field)? {
            Argument::Polyline(p) => Some(p),
            _ => None,
        }
    }

    /// The sheet of `field`.
    pub fn sheet(&mut self, field: &str) -> Option<Sheet> {
        match self.take(field)? {
            Argument::Sheet(s) => Some(s),
            _ => None,
        }
    }

    /// The name of `field`.
    pub fn name(&mut self, field: &str) -> Option<String> {
        match self.take(field)? {
            Argument::Name(n) => Some(n),
            _ => None,
        }
    }
}

/// What a report marks over the mesh for a step: an imaginary polyline, point sources
/// (indices into `Topology::points`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Marks<'a> {
    /// A polyline drawn dashed.
    pub polyline: Option<&'a [Point2]>,
    /// Topological points drawn as rings.
    pub points: &'a [usize],
}
