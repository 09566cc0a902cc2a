//! The LAYER section of a recipe: the boundary-layer skin `adapt` inserts once the loop
//! has converged (thesis 5.5, `--Use-Layer`), as `smartmesh layer` takes it.
//!
//! TOML `[layer]` / JSON `"layer"`: `curves` (tags or names), any three of
//! `first_height`, `ratio`, `layers`, `thickness` (or `y_plus` with `reynolds` and
//! `ref_length` for the first height), optional `split`, `tag`, `fan_angle`, `gap_ratio`,
//! and `per_curve` entries `{ curve, first_height, ratio }`. libconfig: a group `LAYER = {
//! CURVES = [...]; FIRST_HEIGHT = ...; RATIO = ...; LAYERS = ...; THICKNESS; Y_PLUS;
//! REYNOLDS; REF_LENGTH; SPLIT; TAG; FAN_ANGLE; GAP_RATIO; PER_CURVE = ( { CURVE; FIRST_HEIGHT;
//! RATIO } ) }`.

use serde::{Deserialize, Serialize};

use super::model::EntityRef;
use crate::layer::{
    first_height_for_y_plus, CurveLayers, Growth, GrowthError, LayerError, LayerOptions,
};

/// Values of one curve that differ from the section's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveValues {
    /// The curve (one of the section's).
    pub curve: EntityRef,
    /// Its first height.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_height: Option<f64>,
    /// Its growth ratio.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
}

/// A boundary-layer skin as a recipe describes it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerSpec {
    /// The wall curves.
    pub curves: Vec<EntityRef>,
    /// First-cell height.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_height: Option<f64>,
    /// Growth ratio.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// Number of layers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layers: Option<usize>,
    /// Total thickness.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
    /// Target y+ of the first cell (with `reynolds` and `ref_length`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y_plus: Option<f64>,
    /// Reynolds number over the reference length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reynolds: Option<f64>,
    /// Reference length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ref_length: Option<f64>,
    /// Write each quad as two triangles.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub split: bool,
    /// Geometrical tag of the skin's cells.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tag: Option<i32>,
    /// Largest angle between two columns of a fan, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fan_angle: Option<f64>,
    /// Largest share of a gap the skin fills.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap_ratio: Option<f64>,
    /// Per-curve values.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_curve: Vec<CurveValues>,
}

/// Why a [`LayerSpec`] gives no options: what is wrong, for each front end (a recipe's
/// LAYER section, `smartmesh layer`'s flags) to say in its own words.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpecError {
    /// No wall curve.
    #[error("layer: `curves` lists no curve")]
    NoCurves,
    /// A target y+ without the Reynolds number or the reference length.
    #[error("layer: `y_plus` needs `reynolds` and `ref_length`")]
    YPlusNeeds,
    /// Both a first height and a target y+.
    #[error("layer: give `first_height` or `y_plus`, not both")]
    Both,
    /// The first height of the target y+.
    #[error(transparent)]
    YPlus(GrowthError),
    /// Per-curve values of a curve the spec does not list.
    #[error("layer: per-curve values for {0}, which `curves` does not list")]
    PerCurve(EntityRef),
    /// A curve's heights.
    #[error("layer: curve {curve}: {growth}", curve = .0.label(), growth = .1)]
    Curve(EntityRef, GrowthError),
}

impl From<SpecError> for LayerError {
    fn from(e: SpecError) -> LayerError {
        match e {
            SpecError::YPlus(g) => LayerError::Growth(g),
            e => LayerError::Bad(e.to_string()),
        }
    }
}

impl LayerSpec {
    /// The options of [`crate::layer::insert`] this section asks for.
    pub fn options(&self) -> Result<LayerOptions, LayerError> {
        Ok(self.layer_options()?)
    }

    /// [`LayerSpec::options`], its errors as values for the caller to word. A curve's
    /// values are those of its first per-curve entry, else the spec's.
    pub fn layer_options(&self) -> Result<LayerOptions, SpecError> {
        if self.curves.is_empty() {
            return Err(SpecError::NoCurves);
        }
        let first = match self.y_plus {
            Some(y) => {
                let (Some(re), Some(l)) = (self.reynolds, self.ref_length) else {
                    return Err(SpecError::YPlusNeeds);
                };
                if self.first_height.is_some() {
                    return Err(SpecError::Both);
                }
                Some(first_height_for_y_plus(y, re, l).map_err(SpecError::YPlus)?)
            }
            None => self.first_height,
        };
        for pc in &self.per_curve {
            if !self.curves.contains(&pc.curve) {
                return Err(SpecError::PerCurve(pc.curve.clone()));
            }
        }
        let mut curves = Vec::new();
        for c in &self.curves {
            let pc = self.per_curve.iter().find(|p| &p.curve == c);
            let h = pc.and_then(|p| p.first_height).or(first);
            let r = pc.and_then(|p| p.ratio).or(self.ratio);
            let growth = Growth::solve(h, r, self.layers, self.thickness)
                .map_err(|e| SpecError::Curve(c.clone(), e))?;
            curves.push(CurveLayers { curve: c.clone(), growth });
        }
        let d = LayerOptions::default();
        Ok(LayerOptions {
            curves,
            fan_angle_deg: self.fan_angle.unwrap_or(d.fan_angle_deg),
            gap_ratio: self.gap_ratio.unwrap_or(d.gap_ratio),
            split: self.split,
            tag: self.tag,
        })
    }
}
