//! Baked global illumination in a scene: each light's mode (Unity's Light.lightmapBakeType) and
//! the scene's lighting settings (Unity's Lighting Settings asset: Baked Global Illumination,
//! Lighting Mode, Max Bounces, Lightmap Resolution, Directional Mode) with its light-probe grid.
//!
//! A scene without `[gi]` bakes nothing and every light is drawn in real time, as it was before
//! baked GI existed here (Unity's new scenes bake by default; these compositions were compared in
//! real time, so baking is something a scene asks for).

use serde::{Deserialize, Serialize};

use crate::error::InputError;
use crate::input::validate::Checker;

/// Unity's Light Mode: how a light reaches the frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LightBakeMode {
    /// Drawn every frame; no part of it is baked.
    #[default]
    Realtime,
    /// Direct light in real time (or baked, as the Lighting Mode says), indirect light baked.
    Mixed,
    /// Direct and indirect light baked into lightmaps and light probes; not drawn in real time.
    Baked,
}

impl LightBakeMode {
    pub fn name(self) -> &'static str {
        match self {
            LightBakeMode::Realtime => "realtime",
            LightBakeMode::Mixed => "mixed",
            LightBakeMode::Baked => "baked",
        }
    }

    pub fn is_realtime(&self) -> bool {
        *self == LightBakeMode::Realtime
    }
}

/// Unity's Lighting Mode: what Mixed lights bake and how their shadows are made.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MixedLighting {
    /// Indirect light baked; direct light and every shadow in real time.
    BakedIndirect,
    /// Indirect light and static objects' shadows baked (a shadow mask per texel and probe);
    /// real-time shadow maps hold the dynamic objects alone. The Lighting Settings asset's default.
    #[default]
    Shadowmask,
    /// As `shadowmask`, but real-time shadows from every object within the shadow distance.
    DistanceShadowmask,
    /// Direct and indirect light of Mixed lights baked for static objects; the main directional
    /// light's real-time shadow of dynamic objects darkens their lightmap (Realtime Shadow Color).
    Subtractive,
}

impl MixedLighting {
    pub fn name(self) -> &'static str {
        match self {
            MixedLighting::BakedIndirect => "baked_indirect",
            MixedLighting::Shadowmask => "shadowmask",
            MixedLighting::DistanceShadowmask => "distance_shadowmask",
            MixedLighting::Subtractive => "subtractive",
        }
    }

    pub fn bakes_shadow_mask(self) -> bool {
        matches!(self, MixedLighting::Shadowmask | MixedLighting::DistanceShadowmask)
    }
}

/// Player Settings' Lightmap Encoding: Low Quality stores double LDR (dLDR), Normal Quality RGBM,
/// High Quality HDR (BC6H-compressed in the engine, half floats here).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LightmapQuality {
    Low,
    Normal,
    High,
}

impl LightmapQuality {
    pub fn name(self) -> &'static str {
        match self {
            LightmapQuality::Low => "low",
            LightmapQuality::Normal => "normal",
            LightmapQuality::High => "high",
        }
    }
}

/// Unity's Lighting Settings defaults (Lightmapping settings of a new asset).
pub const DEFAULT_BOUNCES: u32 = 2;
pub const DEFAULT_TEXELS_PER_UNIT: f64 = 40.0;
pub const DEFAULT_PADDING: u32 = 2;
/// Indirect samples per texel and per probe (Unity's default Indirect Samples, 512).
pub const DEFAULT_SAMPLES: u32 = 512;
/// The lightmap noise a bake converges to (`noise`): 2 % of the mean texel's light.
pub const DEFAULT_NOISE: f64 = 0.02;
/// The subtractive mode's Realtime Shadow Color (Lighting Settings default: 0.42, 0.478, 0.627 sRGB).
pub const DEFAULT_REALTIME_SHADOW_COLOR: [f64; 3] = [0.42, 0.478, 0.627];
/// Shadow-mask channels: a texel holds the occlusion of at most four overlapping Mixed lights;
/// Unity bakes the rest fully ("Lighting Mode: Shadowmask").
pub const SHADOW_MASK_CHANNELS: usize = 4;

/// The scene's baked lighting (`[gi]`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GiSettings {
    #[serde(default)]
    pub mixed_lighting: MixedLighting,
    /// Max Bounces of indirect light.
    #[serde(default = "default_bounces")]
    pub bounces: u32,
    /// Lightmap Resolution: texels per world unit of the static objects' lightmaps.
    #[serde(default = "default_texels_per_unit")]
    pub texels_per_unit: f64,
    /// Lightmap Padding: texels between charts.
    #[serde(default = "default_padding")]
    pub padding: u32,
    /// Samples per probe, and the most per texel; the bake records the noise they leave.
    #[serde(default = "default_samples")]
    pub samples: u32,
    /// The lightmap's noise to converge to: texels take rounds of samples until the mean over
    /// them of their light's standard error, over their mean light, falls to it (`samples` at
    /// most; 0: every texel takes `samples`).
    #[serde(default = "default_noise")]
    pub noise: f64,
    /// Directional Mode: `true` (Directional, the default) also bakes the dominant direction.
    #[serde(default = "yes")]
    pub directional: bool,
    /// Player Settings' Lightmap Encoding (absent: each pipeline's default, plan::gi).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub encoding: Option<LightmapQuality>,
    /// Subtractive's Realtime Shadow Color (sRGB).
    #[serde(default = "default_shadow_color")]
    pub realtime_shadow_color: [f64; 3],
    /// A light-probe grid for the dynamic objects (the subjects); without one they take the
    /// ambient probe (the sky's SH), as Unity's objects outside every probe group do.
    #[serde(default)]
    pub probes: Option<ProbeGrid>,
}

/// A regular grid of light probes between `min` and `max` (corners included), `counts` per axis;
/// each cube is cut into six tetrahedra about its main diagonal, and an object takes the
/// barycentric blend of its tetrahedron's four probes at its bounds centre (Unity's
/// LightProbes.GetInterpolatedProbe over its tetrahedralised probe group).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeGrid {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub counts: [u32; 3],
}

impl ProbeGrid {
    /// Probe positions, x fastest, then y, then z.
    pub fn positions(&self) -> Vec<[f64; 3]> {
        let [nx, ny, nz] = self.counts;
        let mut out = Vec::with_capacity((nx * ny * nz) as usize);
        let at = |a: usize, i: u32, n: u32| {
            self.min[a] + (self.max[a] - self.min[a]) * if n > 1 { i as f64 / (n - 1) as f64 } else { 0.5 }
        };
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    out.push([at(0, x, nx), at(1, y, ny), at(2, z, nz)]);
                }
            }
        }
        out
    }
}

fn default_bounces() -> u32 {
    DEFAULT_BOUNCES
}
fn default_texels_per_unit() -> f64 {
    DEFAULT_TEXELS_PER_UNIT
}
fn default_padding() -> u32 {
    DEFAULT_PADDING
}
fn default_samples() -> u32 {
    DEFAULT_SAMPLES
}
fn default_noise() -> f64 {
    DEFAULT_NOISE
}
fn default_shadow_color() -> [f64; 3] {
    DEFAULT_REALTIME_SHADOW_COLOR
}
fn yes() -> bool {
    true
}

/// The most probes a grid may hold (each is baked on its own).
pub const MAX_GRID_PROBES: u32 = 4096;

/// The checks of `[gi]`.
pub fn validate(c: &Checker, gi: &GiSettings) -> Result<(), InputError> {
    c.range("gi.bounces", gi.bounces as f64, 0.0, 16.0)?;
    c.range("gi.texels_per_unit", gi.texels_per_unit, 0.1, 200.0)?;
    c.range("gi.padding", gi.padding as f64, 1.0, 16.0)?;
    c.range("gi.samples", gi.samples as f64, 1.0, 65536.0)?;
    c.range("gi.noise", gi.noise, 0.0, 1.0)?;
    c.color("gi.realtime_shadow_color", gi.realtime_shadow_color)?;
    if let Some(g) = &gi.probes {
        c.finite_vector("gi.probes.min", g.min)?;
        c.finite_vector("gi.probes.max", g.max)?;
        for axis in 0..3 {
            if g.counts[axis] == 0 {
                return Err(c.err("gi.probes.counts", format!("{:?}: every count must be at least 1", g.counts)));
            }
            if g.counts[axis] > 1 && g.max[axis] <= g.min[axis] {
                return Err(c.err(
                    "gi.probes.max",
                    format!("{:?} must exceed min {:?} on every axis with more than one probe", g.max, g.min),
                ));
            }
        }
        let total = g.counts.iter().map(|&n| n as u64).product::<u64>();
        if total > MAX_GRID_PROBES as u64 {
            return Err(c.err(
                "gi.probes.counts",
                format!("{:?} makes {total} probes; at most {MAX_GRID_PROBES} are allowed", g.counts),
            ));
        }
    }
    Ok(())
}

/// A light's baking keys as the scene gives them.
pub struct LightGiKeys {
    pub mode: LightBakeMode,
    pub indirect_multiplier: f64,
    pub baked_shadow_radius: f64,
    pub baked_shadow_angle_deg: f64,
    pub directional: bool,
    pub area: bool,
}

/// The checks of lights[i]'s baking keys; `gi`: whether the scene bakes.
pub fn validate_light(c: &Checker, i: usize, keys: LightGiKeys, gi: bool) -> Result<(), InputError> {
    let k = |f: &str| format!("lights[{i}].{f}");
    c.range(&k("indirect_multiplier"), keys.indirect_multiplier, 0.0, 100.0)?;
    c.range(&k("baked_shadow_radius"), keys.baked_shadow_radius, 0.0, 100.0)?;
    c.range(&k("baked_shadow_angle_deg"), keys.baked_shadow_angle_deg, 0.0, 90.0)?;
    if keys.directional && keys.baked_shadow_radius > 0.0 {
        return Err(c.err(&k("baked_shadow_radius"), "a directional light's baked shadows use baked_shadow_angle_deg"));
    }
    if !keys.directional && keys.baked_shadow_angle_deg > 0.0 {
        return Err(c.err(&k("baked_shadow_angle_deg"), "only directional lights have it; use baked_shadow_radius"));
    }
    if !keys.mode.is_realtime() && !gi {
        return Err(c.err(
            &k("mode"),
            format!(
                "\"{}\" needs the scene's baked lighting: add a [gi] table (or use mode = \"realtime\")",
                keys.mode.name()
            ),
        ));
    }
    if keys.area && keys.mode == LightBakeMode::Mixed {
        return Err(
            c.err(&k("mode"), "area lights are realtime (HDRP rectangles) or baked; Unity has no mixed area light")
        );
    }
    Ok(())
}

pub fn is_realtime(m: &LightBakeMode) -> bool {
    m.is_realtime()
}

pub fn is_one(v: &f64) -> bool {
    *v == 1.0
}

pub fn is_zero(v: &f64) -> bool {
    *v == 0.0
}
