//! A recipe resolved against one mesh: region names become topological entities of the
//! mesh's [`Topology`], function names become built functions, and every algorithm a
//! labelled [`Step`] of a [`SizingPlan`].
//!
//! Region entities are tag numbers or tag names, looked up among the topology's points,
//! curves and faces. Gmsh numbers points, curves and faces separately, so one number (or
//! name) can exist in several dimensions. The rule:
//!
//! 1. an entity absent from every dimension is an error (with what the mesh has);
//! 2. a region holds entities of one dimension (appendix A.1.1): the dimensions where
//!    *every* entity of the region exists are its candidates; none is an error;
//! 3. one candidate: that is the region's dimension. Several: the algorithms that use
//!    the region decide by the dimension they expect — each region parameter declares
//!    the dimensions it accepts, preferred first (`ParameterKind::Regions` in the
//!    algorithm's declaration): points for DISTANCE_TO_POINT, curves for the border
//!    algorithms, faces for UNIFORM and for the `REGIONS` of
//!    DISTANCE_TO_IMAGINARY_POLYLINE. If they expect different candidates, or none of
//!    the candidates, the region is ambiguous: an error that says which tags are where;
//! 4. each algorithm then checks it can use that dimension, by the same declaration:
//!    UNIFORM takes any, DISTANCE_TO_POINT points or curves (their vertices are point
//!    sources), DISTANCE_TO_BORDER and DISTANCE_BETWEEN_TWO_BORDERS curves or points,
//!    CURVATURE_OF_BORDER curves, DISTANCE_TO_IMAGINARY_POLYLINE faces.
//!
//! On a mesh in space ([`Topology::space`]) the volumes are looked up too, and each region
//! parameter accepts, before each dimension `d` ≥ 1 it declares, `d + 1`: the border of a
//! volume is a surface and the inside of a domain a volume, so DISTANCE_TO_BORDER takes
//! surfaces, curves or points, UNIFORM volumes first, CURVATURE_OF_BORDER surfaces or
//! curves, DISTANCE_TO_IMAGINARY_POLYLINE and DISTANCE_TO_IMAGINARY_SURFACE volumes or
//! surfaces. DISTANCE_TO_POINT is not lifted: its sources are vertices (points, or a
//! curve's vertices), and a surface is refused here, at the recipe's line, rather than by
//! `size`. A planar mesh has no volume, and its regions resolve as the declarations say.
//!
//! Every algorithm is then built from its table line
//! ([`crate::sizing::algorithms::TABLE`]) with its arguments in declaration order.
//!
//! A region that no algorithm uses has no effect on the plan: its entities are looked up
//! (an absent one is still an error, rule 1, so that a typo is found before the region
//! is put to use), but it is not measured, and it is reported with no counts — and with
//! no dimension when its dimension stays ambiguous, rather than refused.
//!
//! Entities are looked up by the topology's one resolver ([`Topology::resolve`]), each
//! distinct reference once, and used regions of the same entities are measured
//! (vertices, edges, cells) once: a recipe of many regions costs the mesh once plus its
//! distinct references times the topology's entities (its tags and curve junctions, not
//! its cells), not the mesh per region, and regions that nothing uses cost only their
//! lookups.

use std::collections::{BTreeMap, BTreeSet};

use serde::Serialize;

use super::error::{RecipeError, RecipeErrorKind};
use super::model::{referrer, AlgorithmSpec, EntityRef, FunctionSpec, Recipe, SpecValue};
use super::suggest::nearest;
use crate::sizing::algorithms::{Argument, Arguments, FunctionKind, ParameterKind};
use crate::sizing::plan::{EntitySet, SizingPlan, Step};
use crate::sizing::{CurvatureToSize, DistanceFunction, SizeProjectionFunction};
use crate::topology::{EntityHits, Topology};

const DIM_NAMES: [&str; 4] = ["points", "curves", "faces", "volumes"];

/// How one region of the recipe resolved on the mesh (for `smartmesh recipe check`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RegionReport {
    /// The region's name.
    pub name: String,
    /// 0 points, 1 curves, 2 faces (surfaces), 3 volumes; `None` when ambiguous and used
    /// by no algorithm.
    pub dimension: Option<usize>,
    /// Tags of the topological entities it resolved to, sorted.
    pub tags: Vec<i32>,
    /// Their names, where the mesh names them, sorted.
    pub entity_names: Vec<String>,
    /// Number of topological entities.
    pub entities: usize,
    /// Mesh vertices on them (a face's include its boundary); `None` when no algorithm
    /// uses the region (it is not measured).
    pub vertices: Option<usize>,
    /// Mesh edges on them (a face's: the edges of its cells); `None` when unused, and for
    /// volumes (not counted).
    pub edges: Option<usize>,
    /// Mesh cells (faces and volumes); `None` when unused.
    pub cells: Option<usize>,
    /// The algorithms that use it, numbered from 1.
    pub used_by: Vec<usize>,
}

/// A recipe resolved on a mesh: the plan to run and how each region resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Resolved {
    /// The plan for the sizing engine.
    pub plan: SizingPlan,
    /// One report per region, by name.
    pub regions: Vec<RegionReport>,
}

/// Which dimensions region list `field` of `a` accepts, the one it prefers first: its
/// declaration's, and on a mesh in space, when it lifts, each `d` ≥ 1 of them as `d + 1`
/// before it (see the module documentation).
fn expected(a: &AlgorithmSpec, field: &str, in_space: bool) -> Vec<usize> {
    let (declared, lift) = a
        .parameters()
        .iter()
        .find_map(|p| match p.kind {
            ParameterKind::Regions { dimensions, lift, .. } if p.field == field => {
                Some((dimensions, lift))
            }
            _ => None,
        })
        .unwrap_or((&[], false));
    if !in_space || !lift {
        return declared.to_vec();
    }
    let mut out = Vec::with_capacity(4);
    for &d in declared {
        for e in [d + 1, d] {
            if (d >= 1 || e == d) && e <= 3 && !out.contains(&e) {
                out.push(e);
            }
        }
    }
    out
}

/// The entities of each distinct reference, looked up once ([`Topology::resolve`]): a
/// recipe that names one tag in many regions pays for one lookup.
#[derive(Default)]
struct Lookups<'r> {
    found: BTreeMap<&'r EntityRef, EntityHits>,
}

impl<'r> Lookups<'r> {
    /// Indices of the entities matching `e` in each dimension.
    fn lookup(&mut self, topo: &Topology, e: &'r EntityRef) -> &EntityHits {
        self.found.entry(e).or_insert_with(|| topo.resolve(e))
    }
}

fn list_tags(tags: BTreeSet<i32>) -> String {
    let v: Vec<String> = tags.iter().take(24).map(i32::to_string).collect();
    let more =
        if tags.len() > 24 { format!(" and {} more", tags.len() - 24) } else { String::new() };
    format!("{}{more}", v.join(", "))
}

fn available_tags(topo: &Topology) -> String {
    let p: BTreeSet<i32> = topo.points.iter().filter_map(|p| p.tag).collect();
    let c: BTreeSet<i32> = topo.curves.iter().filter_map(|c| c.tag).collect();
    let f: BTreeSet<i32> = topo.faces.iter().map(|f| f.tag).collect();
    let v: BTreeSet<i32> = volumes(topo).iter().map(|v| v.tag).collect();
    let mut parts = Vec::new();
    for (what, set) in [("point", p), ("curve", c), ("face", f), ("volume", v)] {
        if !set.is_empty() {
            parts.push(format!("{what} tags {}", list_tags(set)));
        }
    }
    if parts.is_empty() {
        "; the mesh has no tagged entity".into()
    } else {
        format!("; the mesh has {}", parts.join("; "))
    }
}

fn entity_names(topo: &Topology) -> Vec<&str> {
    let mut names: Vec<&str> = topo
        .points
        .iter()
        .filter_map(|p| p.name.as_deref())
        .chain(topo.curves.iter().filter_map(|c| c.name.as_deref()))
        .chain(topo.faces.iter().filter_map(|f| f.name.as_deref()))
        .chain(volumes(topo).iter().filter_map(|v| v.name.as_deref()))
        .collect();
    names.sort_unstable();
    names.dedup();
    names
}

/// The volumes of a mesh in space; none for a planar mesh.
fn volumes(topo: &Topology) -> &[crate::topology::TopoVolume] {
    topo.space.as_ref().map_or(&[][..], |s| &s.volumes[..])
}

struct RegionState {
    /// Per dimension, the entity indices of the whole region (sorted, unique).
    by_dim: [Vec<usize>; 4],
    /// Dimensions where every entity exists.
    candidates: Vec<usize>,
    /// Per entity, the dimensions where it exists (for messages).
    entity_dims: Vec<(EntityRef, Vec<usize>)>,
    dimension: Option<usize>,
}

impl Recipe {
    /// Resolves the recipe against a mesh's topology (see the module documentation for
    /// the rule that gives each region its dimension).
    pub fn resolve(&self, topology: &Topology) -> Result<Resolved, RecipeError> {
        // The fields are public: a recipe built in code may never have been checked.
        self.validate()?;
        let names: Vec<&String> = self.regions.keys().collect();
        let in_space = topology.space.is_some();
        let mut lookups = Lookups::default();
        let mut states: Vec<RegionState> = Vec::with_capacity(names.len());
        for (name, entities) in &self.regions {
            states.push(self.region_state(topology, &mut lookups, name, entities)?);
        }

        // Ambiguous regions: the algorithms that use them vote with the dimension they
        // prefer among the region's candidates.
        let used_by = self.used_by(&names);
        for (k, st) in states.iter_mut().enumerate() {
            if st.dimension.is_some() || used_by[k].is_empty() {
                continue;
            }
            self.settle_by_vote(names[k], st, &used_by[k], in_space)?;
        }

        let mut steps = Vec::with_capacity(self.algorithms.len());
        for (i, a) in self.algorithms.iter().enumerate() {
            steps.push(self.step(i, a, &names, &states, in_space)?);
        }

        let mut measured = BTreeMap::new();
        let regions = states
            .iter()
            .enumerate()
            .map(|(k, st)| report(topology, names[k], st, used_by[k].clone(), &mut measured))
            .collect();
        let g = &self.global;
        let plan = SizingPlan {
            h_min: g.h_min,
            h_max: g.h_max,
            max_aspect_ratio: g.max_aspect_ratio,
            gradation: g.gradation,
            steps,
        };
        Ok(Resolved { plan, regions })
    }

    /// The entities of region `name` by dimension and the dimensions it may have (those
    /// every one of its entities has); an error names an entity the mesh lacks, or
    /// entities of different dimensions.
    fn region_state<'r>(
        &'r self,
        topology: &Topology,
        lookups: &mut Lookups<'r>,
        name: &str,
        entities: &'r [EntityRef],
    ) -> Result<RegionState, RecipeError> {
        let mut by_dim: [BTreeSet<usize>; 4] = Default::default();
        let mut candidates: Vec<usize> = vec![0, 1, 2, 3];
        let mut entity_dims = Vec::new();
        for (k, e) in entities.iter().enumerate() {
            let hits = lookups.lookup(topology, e);
            let dims: Vec<usize> = (0..4).filter(|&d| !hits[d].is_empty()).collect();
            if dims.is_empty() {
                let path = format!("regions.{name}[{k}]");
                let (available, suggestion) = match e {
                    EntityRef::Tag(_) => (available_tags(topology), None),
                    EntityRef::Name(n) => {
                        let all = entity_names(topology);
                        let s = nearest(n, all.iter().copied()).map(|s| format!("\"{s}\""));
                        let list = if all.is_empty() {
                            "; the mesh names no entity".to_string()
                        } else {
                            format!(
                                "; the mesh names {}",
                                all.iter()
                                    .map(|n| format!("\"{n}\""))
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            )
                        };
                        (list, s)
                    }
                };
                return Err(self
                    .error_at(
                        RecipeErrorKind::AbsentEntity {
                            region: name.to_string(),
                            entity: e.to_string(),
                            available,
                        },
                        &path,
                    )
                    .suggest(suggestion));
            }
            for d in &dims {
                by_dim[*d].extend(hits[*d].iter().copied());
            }
            candidates.retain(|d| dims.contains(d));
            entity_dims.push((e.clone(), dims));
        }
        if candidates.is_empty() {
            let detail = format!(
                "its entities are of different dimensions ({}); a region holds entities of one dimension",
                entity_dims.iter().map(|(e, d)| format!("{e}: {}", d.iter().map(|&d| DIM_NAMES[d]).collect::<Vec<_>>().join(" or "))).collect::<Vec<_>>().join(", ")
            );
            return Err(self.error_at(
                RecipeErrorKind::Dimension { region: name.to_string(), detail },
                &format!("regions.{name}"),
            ));
        }
        let dimension = (candidates.len() == 1).then(|| candidates[0]);
        Ok(RegionState {
            by_dim: by_dim.map(|s| s.into_iter().collect()),
            candidates,
            entity_dims,
            dimension,
        })
    }

    /// For each region (by its index in `names`), the algorithms that use it, numbered
    /// from 1, in order.
    fn used_by(&self, names: &[&String]) -> Vec<Vec<usize>> {
        let mut used_by: Vec<Vec<usize>> = vec![Vec::new(); names.len()];
        for (i, a) in self.algorithms.iter().enumerate() {
            for (_, list) in a.region_lists() {
                for r in list {
                    let k = names.binary_search(&r).expect("validated: the region exists");
                    if !used_by[k].contains(&(i + 1)) {
                        used_by[k].push(i + 1);
                    }
                }
            }
        }
        used_by
    }

    /// Gives ambiguous region `name` the one dimension its users (`users`, algorithms
    /// numbered from 1) prefer among its candidates, or says why it cannot.
    fn settle_by_vote(
        &self,
        name: &String,
        st: &mut RegionState,
        users: &[usize],
        in_space: bool,
    ) -> Result<(), RecipeError> {
        let mut votes: BTreeSet<usize> = BTreeSet::new();
        for &i in users {
            let a = &self.algorithms[i - 1];
            for (field, list) in a.region_lists() {
                if !list.contains(name) {
                    continue;
                }
                if let Some(&d) =
                    expected(a, field, in_space).iter().find(|d| st.candidates.contains(d))
                {
                    votes.insert(d);
                }
            }
        }
        if votes.len() == 1 {
            st.dimension = votes.into_iter().next();
        } else {
            let shared: Vec<String> = st
                .entity_dims
                .iter()
                .filter(|(_, d)| d.len() > 1)
                .map(|(e, d)| {
                    format!(
                        "{e} is in {}",
                        d.iter().map(|&d| DIM_NAMES[d]).collect::<Vec<_>>().join(" and ")
                    )
                })
                .collect();
            let users: Vec<String> = users
                .iter()
                .map(|&i| format!("{} ({})", referrer(i - 1), self.algorithms[i - 1].keyword()))
                .collect();
            let detail = format!(
                "ambiguous: {}, and {} cannot tell which is meant; use tag names, or split the region",
                shared.join(", "),
                users.join(", ")
            );
            return Err(self.error_at(
                RecipeErrorKind::Dimension { region: name.clone(), detail },
                &format!("regions.{name}"),
            ));
        }
        Ok(())
    }

    /// The step of algorithm `i`: its region lists as entity sets, each region's
    /// dimension checked against what the algorithm takes, its arguments in declaration
    /// order, then the algorithm from its table line.
    fn step(
        &self,
        i: usize,
        a: &AlgorithmSpec,
        names: &[&String],
        states: &[RegionState],
        in_space: bool,
    ) -> Result<Step, RecipeError> {
        let set_of = |k: usize| -> EntitySet {
            let st = &states[k];
            let mut s = EntitySet::default();
            match st.dimension {
                Some(0) => s.points = st.by_dim[0].clone(),
                Some(1) => s.curves = st.by_dim[1].clone(),
                Some(2) => s.faces = st.by_dim[2].clone(),
                Some(3) => s.volumes = st.by_dim[3].clone(),
                _ => {}
            }
            s
        };
        let base = format!("algorithms[{i}]");
        // Region lists to entity sets, each region's dimension checked.
        let mut sets: Vec<EntitySet> = Vec::new();
        for (field, list) in a.region_lists() {
            let mut set = EntitySet::default();
            for r in list {
                let k = names.binary_search(&r).expect("validated: the region exists");
                let d = states[k].dimension.expect("a used region has a dimension");
                let accepts = expected(a, field, in_space);
                if !accepts.contains(&d) {
                    let accepted: Vec<&str> = accepts.iter().map(|&d| DIM_NAMES[d]).collect();
                    let key = self.written_key(&format!("{base}.{field}"), field).to_string();
                    return Err(self.error_at(
                        RecipeErrorKind::Invalid(format!(
                            "{} {}: {key} \"{r}\" holds {}, but {} takes {}",
                            referrer(i),
                            a.keyword(),
                            DIM_NAMES[d],
                            a.keyword(),
                            accepted.join(" or ")
                        )),
                        &format!("{base}.{field}"),
                    ));
                }
                set = set.union(&set_of(k));
            }
            sets.push(set);
        }
        // The arguments in declaration order, then the algorithm from its table line.
        let mut sets = sets.into_iter();
        let mut arguments = Arguments::new();
        for (p, value) in a.arguments() {
            let argument = match (p.kind, value) {
                (_, SpecValue::Absent) if p.kind.is_optional() => continue,
                (
                    ParameterKind::Size | ParameterKind::OptionalSize | ParameterKind::OptionalNorm,
                    SpecValue::Size(x),
                ) => Argument::Size(*x),
                (ParameterKind::Choice(_), SpecValue::Name(word)) => Argument::Name(word.clone()),
                (ParameterKind::Function(kind), SpecValue::Name(name)) => match kind {
                    FunctionKind::Distance => Argument::Distance(self.distance(name)?),
                    FunctionKind::Projection => Argument::Projection(self.projection(name)?),
                    FunctionKind::Curvature => Argument::Curvature(self.curvature(name)?),
                },
                (ParameterKind::Regions { .. }, SpecValue::Names(_)) => {
                    Argument::Entities(sets.next().unwrap_or_default())
                }
                (ParameterKind::PointData, SpecValue::Name(name)) => Argument::Name(name.clone()),
                (ParameterKind::File, SpecValue::Name(written)) => {
                    let at = format!("{base}.{}", p.field);
                    let base_file = self.file_of(&at).map(std::path::Path::to_path_buf);
                    let key = self.written_key(&at, p.keys[0]).to_string();
                    let sheet =
                        super::sheet::read_sheet(base_file.as_deref(), written).map_err(|why| {
                            self.error_at(
                                RecipeErrorKind::Invalid(format!(
                                    "{} {}: {key} \"{written}\": {why}",
                                    referrer(i),
                                    a.keyword()
                                )),
                                &at,
                            )
                        })?;
                    Argument::Sheet(sheet)
                }
                (ParameterKind::Polyline, SpecValue::Name(name)) => Argument::Polyline(
                    self.polylines.get(name).cloned().expect("validated: the polyline exists"),
                ),
                _ => return Err(self.mismatch(i, a)),
            };
            arguments.push(p.field, argument);
        }
        let algorithm = (a.entry().build)(&mut arguments).ok_or_else(|| self.mismatch(i, a))?;
        Ok(Step { label: label(i, a), algorithm, names: step_names(a) })
    }

    /// An algorithm whose values do not match its declaration (a recipe built in code).
    fn mismatch(&self, i: usize, a: &AlgorithmSpec) -> RecipeError {
        self.error_at(
            RecipeErrorKind::Invalid(format!(
                "{} {}: its values do not match the parameters it declares",
                referrer(i),
                a.keyword()
            )),
            &format!("algorithms[{i}]"),
        )
    }

    fn function_error(&self, name: &str, e: crate::sizing::FunctionError) -> RecipeError {
        self.error_at(
            RecipeErrorKind::Function { name: name.to_string(), source: e },
            &format!("functions.{name}"),
        )
    }

    fn distance(&self, name: &str) -> Result<DistanceFunction, RecipeError> {
        match self.functions.get(name).and_then(FunctionSpec::distance) {
            Some(r) => r.map_err(|e| self.function_error(name, e)),
            None => Err(self.error_at(
                RecipeErrorKind::Invalid(format!("\"{name}\" is not a distance function")),
                &format!("functions.{name}"),
            )),
        }
    }

    fn projection(&self, name: &str) -> Result<SizeProjectionFunction, RecipeError> {
        match self.functions.get(name).and_then(FunctionSpec::projection) {
            Some(r) => r.map_err(|e| self.function_error(name, e)),
            None => Err(self.error_at(
                RecipeErrorKind::Invalid(format!("\"{name}\" is not a projection function")),
                &format!("functions.{name}"),
            )),
        }
    }

    fn curvature(&self, name: &str) -> Result<CurvatureToSize, RecipeError> {
        match self.functions.get(name).and_then(FunctionSpec::curvature) {
            Some(r) => r.map_err(|e| self.function_error(name, e)),
            None => Err(self.error_at(
                RecipeErrorKind::Invalid(format!("\"{name}\" is not a curvature-to-size function")),
                &format!("functions.{name}"),
            )),
        }
    }
}

fn quoted(names: &[String]) -> String {
    names.iter().map(|n| format!("\"{n}\"")).collect::<Vec<_>>().join(", ")
}

/// `algorithm 3 (DISTANCE_TO_BORDER on "StayVane")`: along its polyline (within its
/// regions) when it takes one, between its two region lists, or on its regions.
fn label(i: usize, a: &AlgorithmSpec) -> String {
    let lists = a.region_lists();
    let what = match (a.polyline(), lists.as_slice()) {
        (Some((_, polyline)), lists) => {
            let within: Vec<String> = lists.iter().flat_map(|(_, l)| l.iter().cloned()).collect();
            if within.is_empty() {
                format!("along \"{polyline}\"")
            } else {
                format!("along \"{polyline}\" within {}", quoted(&within))
            }
        }
        (None, [(_, first), (_, second), ..]) => {
            format!("between {} and {}", quoted(first), quoted(second))
        }
        (None, []) => a
            .arguments()
            .find_map(|(p, v)| match (p.kind, v) {
                (ParameterKind::PointData, SpecValue::Name(n)) => Some(format!("of \"{n}\"")),
                (ParameterKind::File, SpecValue::Name(n)) => Some(format!("from \"{n}\"")),
                _ => None,
            })
            .unwrap_or_else(|| "on the whole mesh".to_string()),
        (None, lists) => format!("on {}", quoted(lists.first().map_or(&[][..], |l| l.1))),
    };
    format!("{} ({} {what})", referrer(i), a.keyword())
}

/// The recipe's names of what a step works on, for captions: its polyline, else its
/// regions.
fn step_names(a: &AlgorithmSpec) -> Vec<String> {
    match a.polyline() {
        Some((_, polyline)) => vec![polyline.to_string()],
        None => a.region_lists().iter().flat_map(|(_, l)| l.iter().cloned()).collect(),
    }
}

/// A region's vertex, edge and cell counts, by dimension and entity indices.
type Measures = BTreeMap<(usize, Vec<usize>), [Option<usize>; 3]>;

/// The report of one region; a used region's counts are taken from `measured`, or
/// measured and kept there for the next region of the same entities.
fn report(
    topo: &Topology,
    name: &str,
    st: &RegionState,
    used_by: Vec<usize>,
    measured: &mut Measures,
) -> RegionReport {
    let mut tags = BTreeSet::new();
    let mut names = BTreeSet::new();
    let entities = st.dimension.map_or(0, |d| st.by_dim[d].len());
    match st.dimension {
        Some(0) => {
            for &p in &st.by_dim[0] {
                tags.extend(topo.points[p].tag);
                names.extend(topo.points[p].name.clone());
            }
        }
        Some(1) => {
            for &c in &st.by_dim[1] {
                tags.extend(topo.curves[c].tag);
                names.extend(topo.curves[c].name.clone());
            }
        }
        Some(2) => {
            for &f in &st.by_dim[2] {
                tags.insert(topo.faces[f].tag);
                names.extend(topo.faces[f].name.clone());
            }
        }
        Some(3) => {
            for &v in &st.by_dim[3] {
                tags.insert(volumes(topo)[v].tag);
                names.extend(volumes(topo)[v].name.clone());
            }
        }
        _ => {}
    }
    let [vertices, edges, cells] = match st.dimension {
        Some(d) if !used_by.is_empty() => measured
            .entry((d, st.by_dim[d].clone()))
            .or_insert_with(|| measure(topo, d, &st.by_dim[d]))
            .to_owned(),
        _ => [None; 3],
    };
    RegionReport {
        name: name.to_string(),
        dimension: st.dimension,
        tags: tags.into_iter().collect(),
        entity_names: names.into_iter().collect(),
        entities,
        vertices,
        edges,
        cells,
        used_by,
    }
}

/// Mesh vertices, edges and cells on the entities `of` of dimension `dim`. Volumes: their
/// cells, and their vertices when there is one volume (the topology counts each volume's
/// vertices, not those of a union); their edges are not counted.
fn measure(topo: &Topology, dim: usize, of: &[usize]) -> [Option<usize>; 3] {
    let mut vertices = BTreeSet::new();
    let (mut edges, mut cells) = (0, 0);
    match dim {
        3 => {
            let v = volumes(topo);
            let one = (of.len() == 1).then(|| v[of[0]].vertices);
            return [one, None, Some(of.iter().map(|&i| v[i].cells).sum())];
        }
        0 => vertices.extend(of.iter().map(|&p| topo.points[p].vertex)),
        1 => {
            for &c in of {
                for pl in &topo.curves[c].polylines {
                    vertices.extend(pl.vertices.iter().copied());
                    edges += pl.num_edges();
                }
            }
        }
        _ => {
            let mut cell_edges = BTreeSet::new();
            for &f in of {
                let f = &topo.faces[f];
                for &c in &f.cells {
                    let v = topo.surface_cells[c].vertices();
                    vertices.extend(v.iter().copied());
                    for j in 0..v.len() {
                        let (a, b) = (v[j], v[(j + 1) % v.len()]);
                        cell_edges.insert((a.min(b), a.max(b)));
                    }
                }
                cells += f.cells.len();
            }
            edges = cell_edges.len();
        }
    }
    [Some(vertices.len()), Some(edges), Some(cells)]
}
