//! A light's HDRP settings (`[lights.hdrp]`): what HDAdditionalLightData adds to Unity's Light
//! (the thesis's Fig 3.13). Built-in and URP lights have none of them; their cells leave the table
//! out and say so (plan::lights::HdrpLightTerms). Defaults are HDAdditionalLightData's, so a light
//! without the table is lit as before.

use serde::{Deserialize, Serialize};

use crate::error::InputError;
use crate::input::validate::Checker;
use crate::pipelines::hdrp_light::SpotShape;

/// HDRP's Light inspector settings beyond the common light.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HdrpLightKeys {
    /// A spot's shape: `cone` (default), `pyramid` or `box` (SpotLightShape).
    #[serde(default)]
    pub spot_shape: SpotShapeName,
    /// A pyramid's width over height (aspectRatio, default 1; HDRP allows 0.05–20).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aspect_ratio: Option<f64>,
    /// A box's width and height in metres (shapeWidth, shapeHeight; default 0.5 × 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub box_size: Option<[f64; 2]>,
    /// Affect Diffuse and Affect Specular: whether the light reaches each lobe.
    #[serde(default = "yes")]
    pub affect_diffuse: bool,
    #[serde(default = "yes")]
    pub affect_specular: bool,
    /// Range Attenuation: off, the light keeps its inverse square up to the range and stops there.
    #[serde(default = "yes")]
    pub range_attenuation: bool,
    /// Intensity Multiplier (lightDimmer, 0–16).
    #[serde(default = "one")]
    pub dimmer: f64,
    /// Fade Distance: the light fades over the last tenth of it from the camera (default 10000 m).
    #[serde(default = "far")]
    pub fade_distance: f64,
    /// Shadow Dimmer (0–1): how much of the shadow is kept. Absent: the light's `shadow.strength`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shadow_dimmer: Option<f64>,
    /// Shadow Fade Distance (default 10000 m).
    #[serde(default = "far")]
    pub shadow_fade_distance: f64,
    /// Shadow Tint (sRGB, default black) and Penumbra Tint (tint the penumbra, not the umbra).
    #[serde(default)]
    pub shadow_tint: [f64; 3],
    #[serde(default)]
    pub penumbra_tint: bool,
}

/// A spot shape's name as the scene gives it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpotShapeName {
    #[default]
    Cone,
    Pyramid,
    Box,
}

/// HDAdditionalLightData's default fade distances.
pub const HDRP_DEFAULT_FADE_DISTANCE: f64 = 10_000.0;
/// HDAdditionalLightData's default box size.
pub const HDRP_DEFAULT_BOX_SIZE: [f64; 2] = [0.5, 0.5];

fn yes() -> bool {
    true
}
fn one() -> f64 {
    1.0
}
fn far() -> f64 {
    HDRP_DEFAULT_FADE_DISTANCE
}

impl Default for HdrpLightKeys {
    fn default() -> Self {
        HdrpLightKeys {
            spot_shape: SpotShapeName::Cone,
            aspect_ratio: None,
            box_size: None,
            affect_diffuse: true,
            affect_specular: true,
            range_attenuation: true,
            dimmer: 1.0,
            fade_distance: HDRP_DEFAULT_FADE_DISTANCE,
            shadow_dimmer: None,
            shadow_fade_distance: HDRP_DEFAULT_FADE_DISTANCE,
            shadow_tint: [0.0; 3],
            penumbra_tint: false,
        }
    }
}

impl HdrpLightKeys {
    pub fn is_default(&self) -> bool {
        *self == HdrpLightKeys::default()
    }

    /// The spot's shape with its sizes (HDRP's defaults where the scene is silent).
    pub fn spot_shape(&self) -> SpotShape {
        match self.spot_shape {
            SpotShapeName::Cone => SpotShape::Cone,
            SpotShapeName::Pyramid => SpotShape::Pyramid { aspect_ratio: self.aspect_ratio.unwrap_or(1.0) },
            SpotShapeName::Box => {
                let [width, height] = self.box_size.unwrap_or(HDRP_DEFAULT_BOX_SIZE);
                SpotShape::Box { width, height }
            }
        }
    }

    /// The keys' names that are set away from HDRP's defaults, for messages and records.
    pub fn changed(&self) -> Vec<&'static str> {
        let d = HdrpLightKeys::default();
        let mut out = Vec::new();
        let mut note = |changed: bool, name: &'static str| {
            if changed {
                out.push(name);
            }
        };
        note(self.spot_shape != d.spot_shape, "spot_shape");
        note(!self.affect_diffuse, "affect_diffuse");
        note(!self.affect_specular, "affect_specular");
        note(!self.range_attenuation, "range_attenuation");
        note(self.dimmer != d.dimmer, "dimmer");
        note(self.fade_distance != d.fade_distance, "fade_distance");
        note(self.shadow_dimmer.is_some(), "shadow_dimmer");
        note(self.shadow_fade_distance != d.shadow_fade_distance, "shadow_fade_distance");
        note(self.shadow_tint != d.shadow_tint, "shadow_tint");
        note(self.penumbra_tint, "penumbra_tint");
        out
    }
}

/// What the checks of a light's HDRP keys need to know of the light.
pub(super) struct LightOf<'a> {
    /// Its kind as the scene names it (`point`, `spot`, ...).
    pub kind: &'a str,
    pub baked: bool,
}

/// The checks of lights[i].hdrp.
pub(super) fn validate(c: &Checker, i: usize, light: LightOf, h: &HdrpLightKeys) -> Result<(), InputError> {
    let k = |f: &str| format!("lights[{i}].hdrp.{f}");
    let (kind, baked) = (light.kind, light.baked);
    if h.spot_shape != SpotShapeName::Cone && kind != "spot" {
        return Err(c.err(&k("spot_shape"), format!("only spot lights have a shape; this one is {kind}")));
    }
    if h.aspect_ratio.is_some() && h.spot_shape != SpotShapeName::Pyramid {
        return Err(c.err(&k("aspect_ratio"), "only a spot_shape = \"pyramid\" light has an aspect ratio"));
    }
    if h.box_size.is_some() && h.spot_shape != SpotShapeName::Box {
        return Err(c.err(&k("box_size"), "only a spot_shape = \"box\" light has a box size"));
    }
    let punctual = matches!(kind, "point" | "spot");
    if !h.range_attenuation && !punctual {
        return Err(
            c.err(&k("range_attenuation"), format!("only point and spot lights have it here; this one is {kind}"))
        );
    }
    if kind == "directional" && (h.fade_distance != far() || h.shadow_fade_distance != far()) {
        let key = if h.fade_distance != far() { "fade_distance" } else { "shadow_fade_distance" };
        return Err(c.err(&k(key), "a directional light has no fade distance in HDRP (it reaches everywhere)"));
    }
    if let Some(a) = h.aspect_ratio {
        c.range(&k("aspect_ratio"), a, 0.05, 20.0)?;
    }
    if let Some([w, h]) = h.box_size {
        c.range(&k("box_size[0]"), w, 1e-3, 100.0)?;
        c.range(&k("box_size[1]"), h, 1e-3, 100.0)?;
    }
    c.range(&k("dimmer"), h.dimmer, 0.0, 16.0)?;
    c.range(&k("fade_distance"), h.fade_distance, 1e-3, 1e6)?;
    c.range(&k("shadow_fade_distance"), h.shadow_fade_distance, 1e-3, 1e6)?;
    if let Some(d) = h.shadow_dimmer {
        c.unit(&k("shadow_dimmer"), d)?;
    }
    c.color(&k("shadow_tint"), h.shadow_tint)?;
    if baked && !h.is_default() {
        return Err(c.err(
            &k(h.changed()[0]),
            "HDRP's light settings here apply to real-time lights; this light is baked or mixed (mode), \
             and the lightmapper's emulation does not read them",
        ));
    }
    Ok(())
}
