//! Periodic sides as OpenFOAM `cyclic` patch pairs ([`couple`]): the patches of a
//! pair's master tags become one `cyclic` patch, those of its slave tags another, each
//! naming the other as `neighbourPatch`, with the transform OpenFOAM's cyclicPolyPatch
//! reads (`transform translational; separationVector (dx dy dz);` or `transform
//! rotational; rotationAxis (..); rotationCentre (..);`, the keywords of Debian's
//! OpenFOAM `etc/caseDicts/annotated/createPatchDict`).
//!
//! OpenFOAM glues face i of one half to face i of the other, so the slave faces are
//! put in the order of the master faces they are images of: each master face's centre
//! is mapped by the transform and its slave found by a sweep over the slave centres
//! sorted along a generic direction (no side lies across it, so the window holds a
//! few faces, not the whole side). Every face must find its partner within
//! [`MATCH_TOLERANCE`] of the mesh's bounding-box diagonal, both sides having as many
//! faces; otherwise the write is refused naming the pair. Each slave face is turned so
//! that its first point is the image of the master face's first point (its winding,
//! out of the domain, is kept), as OpenFOAM's own cyclic ordering leaves them.

use std::collections::BTreeMap;

use super::extrude::{Patch, PolyMesh};

/// Largest distance, relative to the bounding-box diagonal, between a master face
/// centre's image and its slave face's centre.
pub const MATCH_TOLERANCE: f64 = 1e-6;

/// The map from a cyclic pair's master side to its slave side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CyclicTransform {
    /// p ↦ p + vector.
    Translation([f64; 3]),
    /// p ↦ centre + R(axis, angle)(p − centre), the angle in degrees, counter-clockwise
    /// seen from the tip of `axis`.
    Rotation {
        /// The axis direction (any length but zero).
        axis: [f64; 3],
        /// A point of the axis.
        centre: [f64; 3],
        /// The angle, degrees.
        angle_degrees: f64,
    },
}

impl CyclicTransform {
    /// The image of `p`.
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        match *self {
            CyclicTransform::Translation(t) => [p[0] + t[0], p[1] + t[1], p[2] + t[2]],
            CyclicTransform::Rotation { axis, centre, angle_degrees } => {
                // Rodrigues: v cos + (k × v) sin + k (k·v)(1 − cos), k the unit axis.
                let n = dot(axis, axis).sqrt();
                let k = [axis[0] / n, axis[1] / n, axis[2] / n];
                let v = [p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]];
                let (s, c) = angle_degrees.to_radians().sin_cos();
                let kv = cross(k, v);
                let d = dot(k, v) * (1.0 - c);
                std::array::from_fn(|i| centre[i] + v[i] * c + kv[i] * s + k[i] * d)
            }
        }
    }

    /// Whether the numbers are finite and a rotation's axis is not zero.
    pub(crate) fn is_valid(&self) -> bool {
        match *self {
            CyclicTransform::Translation(t) => t.iter().all(|x| x.is_finite()),
            CyclicTransform::Rotation { axis, centre, angle_degrees } => {
                axis.iter().chain(&centre).all(|x| x.is_finite())
                    && angle_degrees.is_finite()
                    && dot(axis, axis) > 0.0
            }
        }
    }
}

/// One periodic pair to write as two `cyclic` patches: the boundary tags (line tags
/// of a 2D mesh, surface tags of a 3D one) of each side, and the map.
#[derive(Debug, Clone, PartialEq)]
pub struct CyclicPair {
    /// The master side's tags.
    pub master: Vec<i32>,
    /// The slave side's tags.
    pub slave: Vec<i32>,
    /// Master to slave.
    pub transform: CyclicTransform,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// Boundary faces with their owners.
type Faces = Vec<(Vec<u32>, u32)>;

/// The patches with their faces, in patch order.
type Sides = Vec<(Patch, Faces)>;

/// Makes each pair of `pairs` two `cyclic` patches of `poly`; `patch_of` gives the
/// patch name a tag was written as. The new patches take the place of the master's
/// first patch; the others keep their order.
pub fn couple(
    poly: &mut PolyMesh,
    pairs: &[CyclicPair],
    patch_of: &BTreeMap<i32, String>,
) -> Result<(), String> {
    if pairs.is_empty() {
        return Ok(());
    }
    let n_internal = poly.neighbour.len();
    let mut sides: Sides = Vec::new();
    let mut start = n_internal;
    for p in &poly.patches {
        let faces = (start..start + p.n_faces)
            .map(|f| (std::mem::take(&mut poly.faces[f]), poly.owner[f]))
            .collect();
        sides.push((p.clone(), faces));
        start += p.n_faces;
    }
    let diag = diagonal(&poly.points);
    let mut used = vec![false; sides.len()];
    // The new patches, keyed by the index of the patch they replace.
    let mut new: BTreeMap<usize, Sides> = BTreeMap::new();
    for (k, pair) in pairs.iter().enumerate() {
        let label =
            format!("cyclic pair {} (master {:?}, slave {:?})", k + 1, pair.master, pair.slave);
        if !pair.transform.is_valid() {
            return Err(format!(
                "{label}: the transform has a number that is not finite or a zero axis"
            ));
        }
        let take =
            |tags: &[i32], used: &mut Vec<bool>| -> Result<(usize, Vec<String>, Faces), String> {
                let mut faces = Vec::new();
                let mut names = Vec::new();
                let mut first = usize::MAX;
                for t in tags {
                    let name = patch_of.get(t).ok_or_else(|| {
                        format!("{label}: tag {t} is no boundary patch of the mesh")
                    })?;
                    let i = sides
                        .iter()
                        .position(|(p, _)| &p.name == name)
                        .ok_or_else(|| format!("{label}: tag {t} has no boundary face"))?;
                    if used[i] {
                        return Err(format!("{label}: tag {t} is in two sides of cyclic pairs"));
                    }
                    used[i] = true;
                    first = first.min(i);
                    names.push(name.clone());
                    faces.extend(sides[i].1.iter().cloned());
                }
                Ok((first, names, faces))
            };
        let (at, master_names, master) = take(&pair.master, &mut used)?;
        let (_, slave_names, slave) = take(&pair.slave, &mut used)?;
        if master.len() != slave.len() {
            return Err(format!(
                "{label}: {} faces on the master side, {} on the slave side",
                master.len(),
                slave.len()
            ));
        }
        let slave = order_slave(&poly.points, &master, slave, &pair.transform, diag)
            .map_err(|e| format!("{label}: {e}"))?;
        let (mname, sname) = (master_names.join("_"), slave_names.join("_"));
        let entries = |nbr: &str, master_side: bool| {
            let mut e = vec![("neighbourPatch".to_string(), nbr.to_string())];
            match pair.transform {
                CyclicTransform::Translation(t) => {
                    let s = if master_side { 1.0 } else { -1.0 };
                    e.push(("transform".into(), "translational".into()));
                    e.push((
                        "separationVector".into(),
                        vector(std::array::from_fn(|i| s * t[i] + 0.0)),
                    ));
                }
                CyclicTransform::Rotation { axis, centre, .. } => {
                    e.push(("transform".into(), "rotational".into()));
                    e.push(("rotationAxis".into(), vector(axis)));
                    e.push(("rotationCentre".into(), vector(centre)));
                }
            }
            e
        };
        let patch = |name: &str, nbr: &str, n: usize, m: bool| Patch {
            name: name.to_string(),
            kind: "cyclic".into(),
            n_faces: n,
            entries: entries(nbr, m),
        };
        let n = master.len();
        new.insert(
            at,
            vec![
                (patch(&mname, &sname, n, true), master),
                (patch(&sname, &mname, n, false), slave),
            ],
        );
    }
    poly.faces.truncate(n_internal);
    poly.owner.truncate(n_internal);
    poly.patches.clear();
    for (i, side) in sides.into_iter().enumerate() {
        let list = match new.remove(&i) {
            Some(list) => list,
            None if used[i] => continue,
            None => vec![side],
        };
        for (p, faces) in list {
            for (f, o) in faces {
                poly.faces.push(f);
                poly.owner.push(o);
            }
            poly.patches.push(p);
        }
    }
    Ok(())
}

/// `(x y z)` as a dictionary entry writes a vector (`+ 0.0` above turns -0 into 0).
fn vector(v: [f64; 3]) -> String {
    format!("({} {} {})", v[0], v[1], v[2])
}

/// The diagonal of the points' bounding box (1 when they have no extent).
pub(crate) fn diagonal(points: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let d = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    if d.is_finite() && d > 0.0 {
        d
    } else {
        1.0
    }
}

fn centre(points: &[[f64; 3]], f: &[u32]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &v in f {
        let p = points[v as usize];
        for k in 0..3 {
            c[k] += p[k] / f.len() as f64;
        }
    }
    c
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// The slave faces in the order of the master faces they are images of, each turned
/// so its first point is the image of its master's first point (the Fluent writer
/// pairs its periodic faces by it too, the second member of each face then its index).
pub(crate) fn order_slave(
    points: &[[f64; 3]],
    master: &[(Vec<u32>, u32)],
    slave: Faces,
    t: &CyclicTransform,
    diag: f64,
) -> Result<Faces, String> {
    let tol = MATCH_TOLERANCE * diag;
    // A direction no usual side lies across (irrational components).
    let dir = [0.577_215_664_9, 0.618_033_988_7, 0.414_213_562_4];
    let mut sorted: Vec<(f64, usize, [f64; 3])> = slave
        .iter()
        .enumerate()
        .map(|(i, (f, _))| {
            let c = centre(points, f);
            (dot(c, dir), i, c)
        })
        .collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let reach = tol * dot(dir, dir).sqrt();
    let mut taken = vec![false; slave.len()];
    let mut out = Vec::with_capacity(slave.len());
    for (mi, (mf, _)) in master.iter().enumerate() {
        let image = t.apply(centre(points, mf));
        let key = dot(image, dir);
        let from = sorted.partition_point(|s| s.0 < key - reach);
        let mut best: Option<(f64, usize)> = None;
        for s in sorted[from..].iter().take_while(|s| s.0 <= key + reach) {
            let d = distance(s.2, image);
            if d <= tol
                && !taken[s.1]
                && match best {
                    Some(b) => d < b.0,
                    None => true,
                }
            {
                best = Some((d, s.1));
            }
        }
        let Some((_, si)) = best else {
            return Err(format!(
                "master face {mi} (centre mapped to {image:?}) has no slave face within {tol:e}: the sides are not images of each other by the transform"
            ));
        };
        taken[si] = true;
        let (mut f, o) = slave[si].clone();
        let first = t.apply(points[mf[0] as usize]);
        let turn = (0..f.len())
            .min_by(|&a, &b| {
                distance(points[f[a] as usize], first)
                    .total_cmp(&distance(points[f[b] as usize], first))
            })
            .unwrap_or(0);
        f.rotate_left(turn);
        out.push((f, o));
    }
    Ok(out)
}
