//! What a recipe or a command names, and the one lookup that finds it: an [`EntityRef`]
//! (a tag number or a tag name) resolved to the topological entities that bear it, in
//! every dimension ([`Topology::resolve`]).
//!
//! Gmsh numbers points, curves and faces separately, so one number (or name) can exist
//! in several dimensions: the lookup answers for each, and the caller decides (a recipe's
//! region by the rule of `recipe::resolve`, a boundary-layer wall or a periodic side by
//! taking the curves, [`Topology::resolve_curves`]). A tag matches an entity whose tag is
//! that number (derived curves and recovered points have none); a name matches an entity
//! whose tag the file names exactly so.
//!
//! In a mesh in space the faces are its surfaces, and the volumes are looked up too (the
//! fourth dimension of [`EntityHits`]; a planar mesh has none).
//!
//! Cost: one pass over the entities per lookup, O(points + curves + faces + volumes),
//! which are the tags of a file and the junctions of its curves, not its cells.

use super::Topology;

/// A topological entity as a recipe or a command names it: a tag number or a tag name.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(untagged)]
pub enum EntityRef {
    /// A tag number (Gmsh physical or elementary tag, Triangle marker…).
    Tag(i32),
    /// A tag name (Gmsh physical name, OBJ group…).
    Name(String),
}

/// Read by hand rather than derived (`#[serde(untagged)]`), whose only error is "data did
/// not match any variant of untagged enum EntityRef": this one says what was found and
/// what is expected.
impl<'de> serde::Deserialize<'de> for EntityRef {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<EntityRef, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = EntityRef;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an entity: a tag number (an integer) or a tag name (a string)")
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<EntityRef, E> {
                i32::try_from(v).map(EntityRef::Tag).map_err(|_| {
                    E::custom(format!(
                        "tag {v} is out of range (a tag is a 32-bit integer, at most {})",
                        i32::MAX
                    ))
                })
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<EntityRef, E> {
                self.visit_i64(i64::try_from(v).unwrap_or(i64::MAX))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<EntityRef, E> {
                Ok(EntityRef::Name(v.to_string()))
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// As messages about a recipe name it: `tag 302`, `"wall"`.
impl std::fmt::Display for EntityRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EntityRef::Tag(t) => write!(f, "tag {t}"),
            EntityRef::Name(n) => write!(f, "\"{n}\""),
        }
    }
}

/// As a command line spells an entity: an integer is a tag, anything else a name; the
/// blanks around either are not part of it.
impl From<&str> for EntityRef {
    fn from(s: &str) -> EntityRef {
        let s = s.trim();
        match s.parse::<i32>() {
            Ok(t) => EntityRef::Tag(t),
            Err(_) => EntityRef::Name(s.to_string()),
        }
    }
}

impl EntityRef {
    /// As a command line spells it (the inverse of `From<&str>`): `302`, `wall`.
    pub fn label(&self) -> String {
        match self {
            EntityRef::Tag(t) => t.to_string(),
            EntityRef::Name(n) => n.clone(),
        }
    }

    fn matches(&self, tag: Option<i32>, name: Option<&str>) -> bool {
        match self {
            EntityRef::Tag(t) => tag == Some(*t),
            EntityRef::Name(n) => name == Some(n.as_str()),
        }
    }
}

/// The entities one reference names, per dimension: indices into [`Topology::points`],
/// [`Topology::curves`], [`Topology::faces`] and the volumes of [`Topology::space`],
/// ascending. Indexed by dimension (`hits[1]`: the curves).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EntityHits(pub [Vec<usize>; 4]);

impl std::ops::Index<usize> for EntityHits {
    type Output = Vec<usize>;
    fn index(&self, dim: usize) -> &Vec<usize> {
        &self.0[dim]
    }
}

/// Equal to the hits of points, curves and faces alone when it names no volume (what a
/// planar mesh answers).
impl PartialEq<[Vec<usize>; 3]> for EntityHits {
    fn eq(&self, other: &[Vec<usize>; 3]) -> bool {
        self.0[3].is_empty() && self.0[..3] == other[..]
    }
}

/// No curve bears the tag or name asked for; the message lists the tagged curves.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("no curve `{asked}` (the mesh has: {known})")]
pub struct AbsentCurve {
    /// The entity asked for, as a command line spells it.
    pub asked: String,
    /// The tagged curves, `302 "wall"` or `302` each, or "no tagged curve".
    pub known: String,
}

impl Topology {
    /// The entities `e` names, per dimension (0 points, 1 curves, 2 faces or surfaces,
    /// 3 volumes): indices into [`Topology::points`], [`Topology::curves`],
    /// [`Topology::faces`] and the volumes of [`Topology::space`], ascending.
    pub fn resolve(&self, e: &EntityRef) -> EntityHits {
        let find = |it: &mut dyn Iterator<Item = (Option<i32>, Option<&str>)>| -> Vec<usize> {
            it.enumerate().filter(|(_, (t, n))| e.matches(*t, *n)).map(|(i, _)| i).collect()
        };
        let volumes = self.space.as_ref().map_or(&[][..], |s| &s.volumes[..]);
        EntityHits([
            find(&mut self.points.iter().map(|p| (p.tag, p.name.as_deref()))),
            find(&mut self.curves.iter().map(|c| (c.tag, c.name.as_deref()))),
            find(&mut self.faces.iter().map(|f| (Some(f.tag), f.name.as_deref()))),
            find(&mut volumes.iter().map(|v| (Some(v.tag), v.name.as_deref()))),
        ])
    }

    /// The curves `e` names ([`Topology::resolve`]'s curves), or an error listing the
    /// tagged curves when there is none.
    pub fn resolve_curves(&self, e: &EntityRef) -> Result<Vec<usize>, AbsentCurve> {
        let EntityHits([_, found, _, _]) = self.resolve(e);
        if !found.is_empty() {
            return Ok(found);
        }
        let known: Vec<String> = self
            .curves
            .iter()
            .filter_map(|c| {
                c.tag.map(|t| match &c.name {
                    Some(n) => format!("{t} \"{n}\""),
                    None => t.to_string(),
                })
            })
            .collect();
        Err(AbsentCurve {
            asked: e.label(),
            known: if known.is_empty() { "no tagged curve".to_string() } else { known.join(", ") },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::{CellKind, TaggedMesh};

    /// A unit square of two triangles (face 7, named "fluid"), its sides tagged 1 to 4
    /// ("wall" the first), a corner vertex tagged 1 ("corner") and one untagged side
    /// (a derived curve): tag 1 exists as a point and a curve, and the names of all three
    /// dimensions differ.
    fn square() -> Topology {
        let mut m = TaggedMesh::new();
        m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let t = m.block_mut(CellKind::Triangle);
        for tri in [[0u32, 1, 2], [0, 2, 3]] {
            t.push(&tri, 7, 7);
        }
        let l = m.block_mut(CellKind::Line);
        for (k, e) in [[0u32, 1], [1, 2], [2, 3]].iter().enumerate() {
            l.push(e, k as i32 + 1, k as i32 + 1);
        }
        m.block_mut(CellKind::Vertex).push(&[0], 1, 1);
        for (dim, tag, name) in [(2, 7, "fluid"), (1, 1, "wall"), (0, 1, "corner")] {
            m.tag_names.insert((dim, tag), name.to_string());
        }
        Topology::from_mesh(&m)
    }

    /// The brute-force twin: every entity's tag and name compared by hand.
    fn twin(topo: &Topology, e: &EntityRef) -> [Vec<usize>; 3] {
        let hit = |tag: Option<i32>, name: Option<&String>| match e {
            EntityRef::Tag(t) => tag == Some(*t),
            EntityRef::Name(n) => name == Some(n),
        };
        let mut out: [Vec<usize>; 3] = Default::default();
        for (i, p) in topo.points.iter().enumerate() {
            if hit(p.tag, p.name.as_ref()) {
                out[0].push(i);
            }
        }
        for (i, c) in topo.curves.iter().enumerate() {
            if hit(c.tag, c.name.as_ref()) {
                out[1].push(i);
            }
        }
        for (i, f) in topo.faces.iter().enumerate() {
            if hit(Some(f.tag), f.name.as_ref()) {
                out[2].push(i);
            }
        }
        out
    }

    #[test]
    fn a_tag_or_a_name_resolves_in_every_dimension_it_exists_in() {
        let topo = square();
        let one = topo.resolve(&EntityRef::Tag(1));
        assert!(!one[0].is_empty() && !one[1].is_empty() && one[2].is_empty(), "{one:?}");
        let wall = topo.resolve(&EntityRef::Name("wall".into()));
        assert_eq!((wall[0].len(), wall[1].len(), wall[2].len()), (0, 1, 0));
        assert_eq!(topo.curves[wall[1][0]].tag, Some(1));
        assert_eq!(topo.resolve(&EntityRef::Name("fluid".into()))[2].len(), 1);
        assert_eq!(topo.resolve(&EntityRef::Name("corner".into()))[0].len(), 1);
        for e in [
            EntityRef::Tag(1),
            EntityRef::Tag(2),
            EntityRef::Tag(7),
            EntityRef::Tag(9),
            EntityRef::Name("wall".into()),
            EntityRef::Name("1".into()),
            EntityRef::Name("nothing".into()),
        ] {
            assert_eq!(topo.resolve(&e), twin(&topo, &e), "{e:?}");
        }
    }

    #[test]
    fn an_absent_curve_lists_the_tagged_ones() {
        let topo = square();
        assert_eq!(topo.resolve_curves(&"wall".into()), topo.resolve_curves(&EntityRef::Tag(1)));
        let e = topo.resolve_curves(&" 9 ".into()).unwrap_err();
        assert_eq!(e.to_string(), "no curve `9` (the mesh has: 1 \"wall\", 2, 3)");
        // A name that spells a number is a name: no curve is named "2".
        assert!(topo.resolve_curves(&EntityRef::Name("2".into())).is_err());
    }

    #[test]
    fn a_command_line_spelling_reads_back_as_it_was_written() {
        assert_eq!(EntityRef::from(" 302 "), EntityRef::Tag(302));
        assert_eq!(EntityRef::from("wall"), EntityRef::Name("wall".into()));
        assert_eq!(EntityRef::from("-4"), EntityRef::Tag(-4));
        for s in ["302", "wall", "-4"] {
            assert_eq!(EntityRef::from(s).label(), s);
        }
    }
}
