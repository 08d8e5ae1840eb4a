//! A scene's lights (`[[lights]]`): their keys as the scene file gives them, and what each is
//! as the pipelines see it (`Light::emitter`, `Light::radiance`). HDRP's own light settings are
//! the `[lights.hdrp]` table (`hdrp_light`).

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LightKind {
    Directional,
    Point,
    Spot,
    /// An area light: a rectangle `size` wide and high, shining along `direction` (declarations::area_light).
    Rect,
    /// An area light: a disc of radius `shape_radius`, shining along `direction`.
    Disc,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Light {
    /// The glTF file and light name of a light `[gltf_scene]` brought in (None: the scene file's
    /// `[[lights]]`): what a message about it names.
    #[serde(skip)]
    pub from_gltf: Option<String>,
    pub kind: LightKind,
    /// Point and spot lights.
    #[serde(default)]
    pub position: [f64; 3],
    /// Direction the light travels (directional, spot).
    #[serde(default = "default_direction")]
    pub direction: [f64; 3],
    /// sRGB colour.
    #[serde(default = "white")]
    pub color: [f64; 3],
    /// Unitless (built-in/URP convention); the HDRP emulation scales it (see `pipelines`).
    #[serde(default = "one")]
    pub intensity: f64,
    #[serde(default = "default_range")]
    pub range: f64,
    /// Spot: full cone angle, and the inner angle where the falloff starts.
    #[serde(default = "default_spot_angle")]
    pub spot_angle_deg: f64,
    #[serde(default)]
    pub inner_spot_angle_deg: Option<f64>,
    #[serde(default)]
    pub shadows: bool,
    /// Shadow settings with the built-in light's defaults (strength 1, bias 0.05, normal bias 0.4,
    /// soft): biases in shadow-map texels, as Unity's are.
    #[serde(default)]
    pub shadow: ShadowSettings,
    /// Point and spot: the light's shape radius in metres (HDRP's default 0.025); sets HDRP's
    /// per-light minimum roughness. Disc: its radius (default 0.5).
    #[serde(default)]
    pub shape_radius: Option<f64>,
    /// Rect: width and height in metres (HDRP's default 0.5 × 0.5). Left out of the serialised
    /// scene when absent, so the keys of scenes without area lights are as they were.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<[f64; 2]>,
    /// Directional: the sun's angular diameter in degrees (HDRP's default 0.5).
    #[serde(default)]
    pub angular_diameter_deg: Option<f64>,
    /// Spot: HDRP's "Reflector" (lumen focused into the cone); on by default as in HDRP.
    #[serde(default)]
    pub reflector: Option<bool>,
    /// Unity's Light.renderMode: `auto` (default), `important` (always per-pixel) or
    /// `not_important` (per-vertex or SH in built-in forward).
    #[serde(default)]
    pub render_mode: RenderMode,
    /// The key light receives the matrix's light intensity and range axes; at most one, and when
    /// no light says so, the first point light is the key.
    #[serde(default)]
    pub key: bool,
    /// `intensity` is photometric — candela for point and spot lights, lux for directional ones
    /// (glTF's `KHR_lights_punctual` units) — and each pipeline converts it (`Light::radiance`):
    /// HDRP takes it as is; built-in and URP, whose intensity I delivers irradiance π·I, take C/π.
    #[serde(default)]
    pub photometric: bool,
    /// Unity's Light Mode (`realtime`, `mixed`, `baked`; declarations::gi); baking needs the scene's `[gi]`.
    #[serde(default, skip_serializing_if = "super::gi::is_realtime")]
    pub mode: super::gi::LightBakeMode,
    /// Indirect Multiplier: the scale of this light's bounced light in the bake.
    #[serde(default = "one", skip_serializing_if = "super::gi::is_one")]
    pub indirect_multiplier: f64,
    /// Baked Shadow Radius (point, spot: metres) and Angle (directional: degrees): soft baked shadows.
    #[serde(default, skip_serializing_if = "super::gi::is_zero")]
    pub baked_shadow_radius: f64,
    #[serde(default, skip_serializing_if = "super::gi::is_zero")]
    pub baked_shadow_angle_deg: f64,
    /// HDRP's own settings of the light (`[lights.hdrp]`, declarations::hdrp_light); left out of
    /// the serialised scene at their defaults, so the keys of scenes without them are as they were.
    #[serde(default, skip_serializing_if = "super::hdrp_light::HdrpLightKeys::is_default")]
    pub hdrp: super::hdrp_light::HdrpLightKeys,
}

/// A light's shadow settings (Unity's Light inspector: Strength, Bias, Normal Bias, Soft/Hard).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShadowSettings {
    #[serde(default = "one")]
    pub strength: f64,
    /// Along the light direction, in shadow-map texels.
    #[serde(default = "default_shadow_bias")]
    pub bias: f64,
    /// Along the surface normal, in shadow-map texels.
    #[serde(default = "default_normal_bias")]
    pub normal_bias: f64,
    /// Percentage-closer filtering (3×3 bilinear taps) instead of one bilinear tap.
    #[serde(default = "yes")]
    pub soft: bool,
    /// Shadow-map resolution in texels (each cube face for point lights); absent: the pipeline's
    /// default (`Pipeline::default_shadow_resolution`).
    #[serde(default)]
    pub resolution: Option<u32>,
}

fn default_shadow_bias() -> f64 {
    0.05
}
fn default_normal_bias() -> f64 {
    0.4
}

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            strength: 1.0,
            bias: default_shadow_bias(),
            normal_bias: default_normal_bias(),
            soft: true,
            resolution: None,
        }
    }
}

/// Unity's LightRenderMode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RenderMode {
    #[default]
    Auto,
    Important,
    NotImportant,
}

fn default_direction() -> [f64; 3] {
    [0.0, -1.0, 0.0]
}
fn white() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}
fn one() -> f64 {
    1.0
}
fn default_range() -> f64 {
    10.0
}
fn default_spot_angle() -> f64 {
    30.0
}

impl LightKind {
    /// The kind as scene files name it.
    pub fn name(self) -> &'static str {
        match self {
            LightKind::Directional => "directional",
            LightKind::Point => "point",
            LightKind::Spot => "spot",
            LightKind::Rect => "rect",
            LightKind::Disc => "disc",
        }
    }
}

impl Light {
    /// Units and shape as the pipelines see them, with HDRP's defaults where the scene is silent.
    /// Linear colour × intensity as `p`'s shaders receive it (per unit attenuation), the
    /// intensity being `intensity` (the key light's axis value, or the light's own):
    /// `Pipeline::light_radiance_with` in the pipeline's own units, or for a photometric light
    /// HDRP's candela or lux as they are, and built-in's and URP's I = C/π through their own
    /// colour handling (built-in multiplies it into the gamma-space colour).
    pub fn radiance(
        &self,
        p: crate::pipelines::Pipeline,
        intensity: f64,
        engine: &crate::pipelines::settings::PipelineSettings,
    ) -> [f64; 3] {
        use crate::pipelines::Pipeline;
        if !self.photometric {
            return p.light_radiance_with(self.color, intensity, self.emitter(), engine);
        }
        match p {
            Pipeline::Hdrp => self.color.map(|c| crate::color::srgb_to_linear(c) * intensity),
            Pipeline::Builtin | Pipeline::Urp => {
                p.light_radiance(self.color, intensity / std::f64::consts::PI, self.emitter())
            }
        }
    }

    pub fn is_area(&self) -> bool {
        matches!(self.kind, LightKind::Rect | LightKind::Disc)
    }

    /// An area light's (forward, right): `area_light::area_frame`.
    pub fn area_frame(&self) -> (glam::DVec3, glam::DVec3) {
        super::area_light::area_frame(self.direction)
    }

    pub fn emitter(&self) -> crate::pipelines::Emitter {
        use crate::pipelines::{Emitter, HDRP_DEFAULT_ANGULAR_DIAMETER_DEG, HDRP_DEFAULT_SHAPE_RADIUS};
        let radius = self.shape_radius.unwrap_or(HDRP_DEFAULT_SHAPE_RADIUS);
        match self.kind {
            LightKind::Directional => Emitter::Directional {
                angular_diameter_deg: self.angular_diameter_deg.unwrap_or(HDRP_DEFAULT_ANGULAR_DIAMETER_DEG),
            },
            LightKind::Point => Emitter::Point { radius },
            LightKind::Spot => {
                let reflector = self.reflector.unwrap_or(true);
                Emitter::Spot { radius, angle_deg: self.spot_angle_deg, reflector, shape: self.hdrp.spot_shape() }
            }
            LightKind::Rect => {
                let [width, height] = self.size.unwrap_or(super::area_light::HDRP_DEFAULT_RECT_SIZE);
                Emitter::Rect { width, height }
            }
            LightKind::Disc => {
                Emitter::Disc { radius: self.shape_radius.unwrap_or(super::area_light::DEFAULT_DISC_RADIUS) }
            }
        }
    }
}

fn yes() -> bool {
    true
}
