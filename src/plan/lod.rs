//! LOD groups (Unity's LODGroup): which levels of an object a camera draws and with what
//! cross-fade. A level is used while the group's relative screen height — its size over the
//! height the frustum spans at its distance, times the LOD bias — is at or above the level's
//! transition height; below the last transition the group is culled. With a fade width w the last
//! w of each level's range (from its transition up w·(previous transition − its own)) is a
//! cross-fade band: the level is drawn with fade t ∈ (0, 1) and the next with −t, and each keeps
//! the fragments its dither says (`lod_clip` in forward.wgsl, each engine's as `CrossFade` says),
//! so the two cover the pixels between them. Sources: Unity
//! LODGroup (screenRelativeTransitionHeight, fadeTransitionWidth, size), QualitySettings.lodBias;
//! unity_LODFade.x as the tutorial reads it (1 → 0 for the level fading out, −1 → 0 for the one
//! fading in).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::declarations::scene::{Camera, Scene};

/// One level drawn in a frame: its index (0 the object's own mesh) and its fade (1: whole; in
/// (0, 1): fading out; in (−1, 0): fading in).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LodDraw {
    pub level: usize,
    pub fade: f64,
}

/// The relative screen height of a group of world size `size` at `distance` from a perspective
/// camera of vertical field of view `fov_y` (radians), scaled by `bias`
/// (LODUtility: distance = size·0.5 / (height·tan(fov/2))).
pub fn relative_height(size: f64, distance: f64, fov_y: f64, bias: f64) -> f64 {
    size / (2.0 * distance.max(1e-9) * (fov_y * 0.5).tan()) * bias
}

/// The levels drawn at relative screen height `h`, given each level's transition height
/// (`transitions[i]`, strictly decreasing) and the fade width (0: no cross-fade).
pub fn select(h: f64, transitions: &[f64], fade_width: f64) -> Vec<LodDraw> {
    let Some(level) = transitions.iter().position(|&t| h >= t) else {
        return Vec::new();
    };
    let upper = if level == 0 { 1.0f64.max(transitions[0]) } else { transitions[level - 1] };
    let band = fade_width * (upper - transitions[level]);
    if band > 0.0 && h < transitions[level] + band {
        let t = (h - transitions[level]) / band;
        let mut draws = vec![LodDraw { level, fade: t }];
        if level + 1 < transitions.len() {
            draws.push(LodDraw { level: level + 1, fade: -t });
        }
        return draws;
    }
    vec![LodDraw { level, fade: 1.0 }]
}

/// A LOD group as a camera sees it: its relative screen height and the levels drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupSeen {
    /// Index into the scene's objects.
    pub object: usize,
    pub relative_height: f64,
    pub drawn: Vec<LodDraw>,
}

/// Every LOD group of `scene` as `camera` sees it, given each object's world bounds (level 0's):
/// the group's size is the bounds' largest extent, its distance that of the bounds' centre.
/// `quality_bias`: QualitySettings.lodBias where the group sets none (`Pipeline::quality_lod_bias`).
pub fn groups_seen(
    scene: &Scene,
    world_bounds: &[(DVec3, DVec3)],
    camera: &Camera,
    quality_bias: f64,
) -> Vec<GroupSeen> {
    scene
        .objects
        .iter()
        .zip(world_bounds)
        .enumerate()
        .filter_map(|(object, (o, (lo, hi)))| {
            let group = o.lod.as_ref()?;
            let distance = (DVec3::from(camera.position) - (*lo + *hi) * 0.5).length();
            let bias = group.bias.unwrap_or(quality_bias);
            let h = relative_height((*hi - *lo).max_element(), distance, camera.fov_y_deg.to_radians(), bias);
            Some(GroupSeen { object, relative_height: h, drawn: select(h, &group.transitions, group.fade_width) })
        })
        .collect()
}

/// How a model's shader dithers the two levels of a cross-fade band (shaders/pass/forward.wgsl
/// `lod_clip`, `LOD_DITHER`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CrossFade {
    /// No LOD_FADE_CROSSFADE variant: built-in's Standard (Standard.shader compiles none) and the
    /// built-in classic shaders ignore unity_LODFade, so both levels of a band draw whole.
    None,
    /// The SRP tutorial's ClipLOD on interleaved gradient noise (its `srp_lit`).
    InterleavedGradientNoise,
    /// Core Common.hlsl LODDitheringTransition on GenerateHashedRandomFloat(ComputeFadeMaskSeed(V,
    /// positionSS)) (ShaderVariablesFunctions.hlsl): HDRP's Lit, and URP's Lit up to URP 13. URP 14
    /// samples its 64² blue-noise texture instead, a Unity asset not shipped here: the hashed
    /// white noise stands in for it (docs/deviations.md).
    HashedViewDirection,
}

impl CrossFade {
    /// The dither of `model` in `pipeline`.
    pub fn of(pipeline: crate::pipelines::Pipeline, model: &crate::shading::ShaderModel) -> CrossFade {
        use crate::pipelines::Pipeline;
        match pipeline {
            Pipeline::Builtin => CrossFade::None,
            // The tutorial's pipeline is the only one with its own dither.
            _ if model.name == "srp_lit" => CrossFade::InterleavedGradientNoise,
            Pipeline::Urp | Pipeline::Hdrp => CrossFade::HashedViewDirection,
        }
    }

    /// `LOD_DITHER` in shaders/pass/forward.wgsl.
    pub fn shader_value(self) -> u32 {
        self as u32
    }
}

/// A LOD group in a cell: its relative screen height and the levels drawn (`plan::lod`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LodUse {
    pub object: String,
    pub relative_height: f64,
    pub drawn: Vec<LodDraw>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_follow_the_transitions_and_fade_across_bands() {
        let t = [0.6, 0.3, 0.1];
        assert_eq!(select(0.8, &t, 0.0), vec![LodDraw { level: 0, fade: 1.0 }]);
        assert_eq!(select(0.45, &t, 0.0), vec![LodDraw { level: 1, fade: 1.0 }]);
        assert_eq!(select(0.2, &t, 0.0), vec![LodDraw { level: 2, fade: 1.0 }]);
        assert!(select(0.05, &t, 0.0).is_empty(), "culled below the last transition");
        // Level 1's band with w = 0.5: from 0.3 up to 0.3 + 0.5·(0.6 − 0.3) = 0.45.
        let d = select(0.3375, &t, 0.5);
        assert_eq!(d.len(), 2);
        assert_eq!((d[0].level, d[1].level), (1, 2));
        assert!((d[0].fade - 0.25).abs() < 1e-12 && (d[1].fade + 0.25).abs() < 1e-12, "{d:?}");
        assert_eq!(select(0.46, &t, 0.5), vec![LodDraw { level: 1, fade: 1.0 }]);
        // The last level fades out to nothing.
        let last = select(0.11, &t, 0.5);
        assert_eq!(last.len(), 1);
        assert!(last[0].fade > 0.0 && last[0].fade < 1.0);
    }

    #[test]
    fn each_engine_dithers_its_own_way() {
        use crate::pipelines::Pipeline;
        let r = crate::shading::Registry::builtin();
        let of = |p: Pipeline, name: &str| CrossFade::of(p, r.find(p, name).unwrap());
        assert_eq!(of(Pipeline::Builtin, "standard"), CrossFade::None);
        assert_eq!(of(Pipeline::Urp, "srp_lit"), CrossFade::InterleavedGradientNoise);
        assert_eq!(of(Pipeline::Urp, "lit"), CrossFade::HashedViewDirection);
        assert_eq!(of(Pipeline::Hdrp, "lit"), CrossFade::HashedViewDirection);
    }

    #[test]
    fn relative_height_is_size_over_the_frustum_height() {
        // A 2 m group 5 m away under a 90° field of view: the frustum is 10 m tall there.
        let h = relative_height(2.0, 5.0, std::f64::consts::FRAC_PI_2, 1.0);
        assert!((h - 0.2).abs() < 1e-12);
        assert!((relative_height(2.0, 5.0, std::f64::consts::FRAC_PI_2, 2.0) - 0.4).abs() < 1e-12, "bias");
    }
}
