//! The PERIODIC section of a recipe: pairs of boundary sides a solver glues, each a
//! master and a slave list of curves and the map from master to slave, a translation or
//! a rotation ([`crate::periodic`]).
//!
//! TOML `[[periodic]]` / JSON `"periodic": [...]`: `master` and `slave` (curve tags or
//! names), then `translation = [dx, dy]`, or `centre = [x, y]` with `angle` (degrees,
//! counter-clockwise). libconfig: a list `PERIODIC = ( { MASTER = [...]; SLAVE = [...];
//! TRANSLATION = [dx, dy]; } , { MASTER; SLAVE; CENTRE = [x, y]; ANGLE = a; } );`.

use serde::{Deserialize, Serialize};

use crate::periodic::{PeriodicPair, Transform};
use crate::topology::EntityRef;

/// One periodic pair as a recipe describes it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeriodicSpec {
    /// The master side's curves.
    pub master: Vec<EntityRef>,
    /// The slave side's curves.
    pub slave: Vec<EntityRef>,
    /// A translation from master to slave.
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "xy")]
    pub translation: Option<[f64; 2]>,
    /// The centre of a rotation from master to slave.
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "xy")]
    pub centre: Option<[f64; 2]>,
    /// The rotation's angle, degrees, counter-clockwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle: Option<f64>,
}

/// A point or vector of the plane: exactly two numbers. A plain `[f64; 2]` lets TOML
/// drop a third number silently (and JSON call it "trailing characters"): a 3D
/// translation `[dx, dy, dz]` is refused, naming what was found.
fn xy<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
    use serde::de::Error;
    let v: Option<Vec<f64>> = Option::deserialize(d)?;
    match v.as_deref() {
        None => Ok(None),
        Some(&[x, y]) => Ok(Some([x, y])),
        Some(other) => Err(D::Error::custom(format!(
            "expected two numbers [x, y] (the plane's), found {} numbers",
            other.len()
        ))),
    }
}

impl PeriodicSpec {
    /// The pair this entry describes, or why not.
    pub fn pair(&self) -> Result<PeriodicPair, String> {
        if self.master.is_empty() || self.slave.is_empty() {
            return Err("periodic: `master` and `slave` each list at least one curve".into());
        }
        if let Some(c) = self.master.iter().find(|c| self.slave.contains(c)) {
            return Err(format!("periodic: curve {} is on both sides", c.label()));
        }
        let transform =
            match (self.translation, self.centre, self.angle) {
                (Some(t), None, None) => Transform::Translation(t),
                (None, Some(centre), Some(angle_degrees)) => {
                    Transform::Rotation { centre, angle_degrees }
                }
                _ => return Err(
                    "periodic: give `translation`, or `centre` and `angle` (a rotation), not both"
                        .into(),
                ),
            };
        if !transform.is_finite() {
            return Err("periodic: the transform has a number that is not finite".into());
        }
        Ok(PeriodicPair { master: self.master.clone(), slave: self.slave.clone(), transform })
    }
}
