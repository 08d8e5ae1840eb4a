//! How each light reaches a cell's frame beyond its colour and position: which lobes it lights,
//! its shape's window, its range attenuation, its dimmers and its shadow's tint. HDRP decides these
//! from the light's `[lights.hdrp]` settings once per light on the CPU, as its GetLightData does
//! (LightLoop.cs; HDGpuLightsBuilder.Jobs.cs ConvertLightToGPUFormat); built-in's and URP's lights
//! have no such settings, so their cells light every lobe, attenuate as their engine does, and
//! say which settings they left out.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::declarations::scene::{Light, LightKind};
use crate::pipelines::hdrp_light::{linear_distance_fade, shadow_tint, SpotShape};
use crate::pipelines::Pipeline;

/// One light's terms in a cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LightTerms {
    /// The light's index in the scene.
    pub light: usize,
    pub shape: SpotShape,
    pub affect_diffuse: bool,
    pub affect_specular: bool,
    pub range_attenuation: bool,
    /// lightDimmer: the Intensity Multiplier times the fade at the light's distance from the
    /// camera, which scales its colour.
    pub dimmer: f64,
    /// The shadow's dimmer (HDRP's Shadow Dimmer times its fade; elsewhere the light's Strength).
    pub shadow_dimmer: f64,
    /// The shadow tint as the shaders receive it (linear), and whether it tints the penumbra.
    pub shadow_tint: [f64; 3],
    pub penumbra_tint: bool,
}

impl LightTerms {
    /// What a light without HDRP's settings gets: every lobe, the engine's attenuation, its Strength.
    pub fn common(light: usize, l: &Light) -> LightTerms {
        LightTerms {
            light,
            shape: SpotShape::Cone,
            affect_diffuse: true,
            affect_specular: true,
            range_attenuation: true,
            dimmer: 1.0,
            shadow_dimmer: l.shadow.strength,
            shadow_tint: [0.0; 3],
            penumbra_tint: false,
        }
    }

    /// Whether the shadow's colour is other than its value (a tint to compute).
    pub fn tints_shadow(&self) -> bool {
        self.shadow_tint != [0.0; 3] || self.penumbra_tint
    }

    /// Whether the shaders' light loop must read these terms (`plan::lights::LightPaths`): the
    /// common light's lobes, cone and attenuation with an untinted shadow need nothing beyond
    /// its colour and shadow strength, where the dimmers are folded in.
    pub fn needs_shader_path(&self) -> bool {
        self.shape != SpotShape::Cone
            || !self.affect_diffuse
            || !self.affect_specular
            || !self.range_attenuation
            || self.tints_shadow()
    }

    /// What these terms change that no light transport does: the truth cannot follow them.
    pub fn unphysical(&self, casts_shadow: bool) -> Option<String> {
        let what = match (self.affect_diffuse, self.affect_specular) {
            (false, true) => Some("lights the specular lobe alone (Affect Diffuse off)"),
            (true, false) => Some("lights the diffuse lobe alone (Affect Specular off)"),
            (false, false) => Some("lights neither lobe (Affect Diffuse and Affect Specular off)"),
            (true, true) => None,
        };
        if let Some(w) = what {
            return Some(format!("light {} {w}", self.light));
        }
        if casts_shadow && self.shadow_dimmer < 1.0 {
            return Some(format!(
                "light {}'s shadow lets {:.3} of the light through its occluders",
                self.light,
                1.0 - self.shadow_dimmer
            ));
        }
        if casts_shadow && self.tints_shadow() {
            return Some(format!("light {}'s shadow is tinted", self.light));
        }
        None
    }
}

/// Each light's terms in a cell of `pipeline` seen from `camera_position`, and the settings the
/// cell leaves out (a light's HDRP settings in built-in or URP).
pub fn light_terms(
    pipeline: Pipeline,
    lights: &[Light],
    camera_position: DVec3,
) -> (Vec<LightTerms>, Vec<(String, String)>) {
    let mut left_out = Vec::new();
    let terms = lights
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let h = &l.hdrp;
            if pipeline != Pipeline::Hdrp {
                if !h.is_default() {
                    left_out.push((
                        format!("HDRP settings of light {i} ({})", h.changed().join(", ")),
                        format!("{}'s lights have no such settings (HDAdditionalLightData is HDRP's)", pipeline.name()),
                    ));
                }
                return LightTerms::common(i, l);
            }
            // Directional lights have no distance fade (GetDirectionalLightData).
            let distance = DVec3::from(l.position).distance(camera_position);
            let fades = l.kind != LightKind::Directional;
            let fade = if fades { linear_distance_fade(distance, h.fade_distance) } else { 1.0 };
            // The shadow fades by the nearer of its fade distance and the shadows' Max Distance.
            let shadow_fade_at = h.shadow_fade_distance.min(pipeline.shadow_cascades().max_distance);
            let shadow_fade = if fades { linear_distance_fade(distance, shadow_fade_at) } else { 1.0 };
            let (tint, penumbra) = shadow_tint(h.shadow_tint, h.penumbra_tint);
            LightTerms {
                light: i,
                shape: if l.kind == LightKind::Spot { h.spot_shape() } else { SpotShape::Cone },
                affect_diffuse: h.affect_diffuse,
                affect_specular: h.affect_specular,
                // HDRP forces it off for a box (LightLoop.cs GetLightData: applyRangeAttenuation).
                range_attenuation: h.range_attenuation && !matches!(h.spot_shape(), SpotShape::Box { .. }),
                dimmer: h.dimmer * fade,
                shadow_dimmer: h.shadow_dimmer.unwrap_or(l.shadow.strength) * shadow_fade,
                shadow_tint: tint.to_array(),
                penumbra_tint: penumbra,
            }
        })
        .collect();
    (terms, left_out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::declarations::hdrp_light::{HdrpLightKeys, SpotShapeName};

    fn spot(hdrp: HdrpLightKeys) -> Light {
        let text = "kind = \"spot\"\nposition = [0.0, 5.0, 0.0]\nshadows = true\n";
        let mut l: Light = toml::from_str(text).unwrap();
        l.hdrp = hdrp;
        l
    }

    #[test]
    fn hdrp_decides_the_terms_and_the_others_leave_them_out() {
        let keys = HdrpLightKeys {
            spot_shape: SpotShapeName::Box,
            affect_specular: false,
            dimmer: 2.0,
            fade_distance: 10.0,
            shadow_dimmer: Some(0.5),
            ..HdrpLightKeys::default()
        };
        let lights = [spot(keys)];
        // The light 5 m from the camera at the origin, its fade distance 10: unfaded.
        let (t, left) = light_terms(Pipeline::Hdrp, &lights, DVec3::ZERO);
        assert!(left.is_empty());
        assert_eq!(t[0].shape, SpotShape::Box { width: 0.5, height: 0.5 });
        assert!(!t[0].range_attenuation, "a box has no range attenuation");
        assert_eq!((t[0].dimmer, t[0].shadow_dimmer), (2.0, 0.5));
        assert!(t[0].unphysical(true).unwrap().contains("Affect Specular off"));
        // 9.5 m away: half faded.
        let (t, _) = light_terms(Pipeline::Hdrp, &lights, DVec3::new(0.0, -4.5, 0.0));
        assert!((t[0].dimmer - 1.0).abs() < 1e-12);
        for p in [Pipeline::Builtin, Pipeline::Urp] {
            let (t, left) = light_terms(p, &lights, DVec3::ZERO);
            assert_eq!(t[0], LightTerms::common(0, &lights[0]));
            assert!(
                left[0].0.contains("spot_shape, affect_specular, dimmer, fade_distance, shadow_dimmer"),
                "{left:?}"
            );
        }
    }
}
