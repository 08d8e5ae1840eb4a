//! What a cell's baked lighting holds: each light's effective mode in this pipeline, what of it
//! goes into the bake (lightmaps of the static objects, light probes of the dynamic ones), and
//! which objects the frame draws it on in real time.
//!
//! - Light Mode per light (Unity's Light.lightmapBakeType): realtime lights are drawn, never
//!   baked; baked lights are baked (direct and indirect) and never drawn; mixed lights follow the
//!   scene's Lighting Mode. Area lights are baked-only in built-in and URP, and discs in HDRP
//!   (Unity manual, "Area Lights"; HDAdditionalLightData), whatever the scene says.
//! - Lighting Mode (Unity manual, "Lighting Mode"): Baked Indirect bakes a mixed light's indirect
//!   light only; Shadowmask and Distance Shadowmask also bake its occlusion by static objects into
//!   one of four shadow-mask channels (a fifth overlapping mixed light is baked fully instead);
//!   Subtractive bakes its direct light into the static objects' lightmaps and into the probes,
//!   keeping the main directional light real-time on dynamic objects. HDRP has no Subtractive
//!   mode (HDRP manual, "Lighting Mode"): it bakes as Baked Indirect, and the plan says so.
//! - Indirect Multiplier scales a light's bounced light in the bake; Max Bounces ends the paths.
//!
//! Static objects are the fixed ones (lightmapped); the subjects are dynamic (lit by probes).

use serde::{Deserialize, Serialize};

use crate::declarations::gi::{GiSettings, LightBakeMode, LightmapQuality, MixedLighting, SHADOW_MASK_CHANNELS};
use crate::declarations::scene::{Light, LightKind};
use crate::pipelines::Pipeline;

/// What the bake holds of one light, and where the frame draws it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BakedLight {
    /// The light's mode in this pipeline (an area light may be baked whatever the scene says).
    pub mode: LightBakeMode,
    /// Its direct light is in the static objects' lightmaps.
    pub direct_in_lightmaps: bool,
    /// Its direct light is in the light probes.
    pub direct_in_probes: bool,
    /// The scale of its bounced light in the bake (0: none).
    pub indirect: f64,
    /// Its shadow-mask channel (Shadowmask modes).
    pub shadow_mask: Option<u8>,
    /// The probes' occlusion channel of a light the frame draws on dynamic objects without a
    /// shadow mask: Subtractive's main light, which the probes shadow (below).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub probe_occlusion: Option<u8>,
    /// The frame draws it on static (fixed) objects, and on dynamic ones (the subjects).
    pub drawn_on_static: bool,
    pub drawn_on_dynamic: bool,
    /// Why it is as it is, in one line.
    pub note: String,
}

/// A cell's baked lighting.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GiPlan {
    /// The Lighting Mode the pipeline bakes with.
    pub mixed_lighting: MixedLighting,
    /// Why it differs from the scene's, if it does.
    pub mixed_lighting_note: Option<String>,
    pub lights: Vec<BakedLight>,
    /// The dynamic objects take light probes (a grid in `[gi]`), else the sky's ambient probe.
    pub probes: bool,
    pub bounces: u32,
    /// The Lightmap Encoding the pipeline stores its lightmaps with, and why it differs from the
    /// scene's, if it does.
    #[serde(default = "normal_quality")]
    pub encoding: LightmapQuality,
    #[serde(default)]
    pub encoding_note: Option<String>,
}

/// How a light's real-time light reaches the frame under the bake: the value the passes read in
/// the light's `color.w` (forward.wgsl, the deferred lighting).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RealtimeOnBake {
    /// Drawn on every object, shadowed by its real-time map alone.
    Full,
    /// Drawn on no object: its light is all in the bake.
    BakedAlone,
    /// Drawn on the dynamic objects alone: Subtractive's main light (forward paths leave it out of
    /// the static objects' light lists; the deferred lighting reads the G-buffer's lightmapped
    /// flag).
    DynamicOnly,
    /// A Shadowmask light of mask channel c: its real-time shadow takes the minimum with the baked
    /// one (URP MixRealtimeAndBakedShadows under LIGHTMAP_SHADOW_MIXING; built-in
    /// UnityDeferredComputeShadow).
    ShadowmaskChannel(u8),
}

/// How a probe-lit (dynamic) object's baked occlusion of a light meets the light's real-time
/// shadow: a Shadowmask light's probe channel, and Subtractive's main light's (channel 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProbeOcclusion {
    /// The darker of the two: URP's MixRealtimeAndBakedShadows (LIGHTMAP_SHADOW_MIXING) of
    /// unity_ProbesOcclusion; built-in's deferred lighting, whose shadow-mask G-buffer holds it
    /// (UnityStandardCore.cginc UnityGetRawBakedOcclusions, Internal-DeferredShading's
    /// UnityDeferredComputeShadow); HDRP's shadow mask.
    #[default]
    Min,
    /// Their product: built-in's forward and vertex-lit passes set each object's lights on the
    /// CPU, which scales a light's colour by the object's probe occlusion (UnityShadowLibrary.cginc
    /// UnitySampleBakedOcclusion: "light probe occlusion is done on the CPU by attenuating the
    /// light color"; the shader's baked occlusion is 1 there).
    LightColour,
}

impl ProbeOcclusion {
    /// The value the forward passes read in a light's `shadow_bias.z`.
    pub fn shader_value(self) -> f64 {
        match self {
            ProbeOcclusion::Min => 0.0,
            ProbeOcclusion::LightColour => 1.0,
        }
    }
}

/// How `pipeline`'s forward-drawn objects (every object of a forward or vertex-lit path, and the
/// forward-only ones of a deferred path) mix a dynamic object's probe occlusion with a real-time
/// shadow. The deferred lighting reads the occlusion from the shadow-mask G-buffer and takes the
/// darker in every engine (`ProbeOcclusion::Min`).
pub fn probe_occlusion(pipeline: Pipeline) -> ProbeOcclusion {
    match pipeline {
        Pipeline::Builtin => ProbeOcclusion::LightColour,
        Pipeline::Urp | Pipeline::Hdrp => ProbeOcclusion::Min,
    }
}

impl RealtimeOnBake {
    /// The value the shaders read: 0 full, 1 baked alone, 2 + c a Shadowmask channel, 6 dynamic
    /// objects alone.
    pub fn shader_value(self) -> f64 {
        match self {
            RealtimeOnBake::Full => 0.0,
            RealtimeOnBake::BakedAlone => 1.0,
            RealtimeOnBake::ShadowmaskChannel(c) => 2.0 + c as f64,
            RealtimeOnBake::DynamicOnly => 6.0,
        }
    }
}

impl GiPlan {
    /// How light `slot` reaches the frame: which objects it lights in real time and how its
    /// shadow mixes with the baked one. Distance Shadowmask reads the real-time map alone inside
    /// the shadow distance, where every composition lies (its fade to the baked mask beyond is
    /// not drawn), so only Shadowmask mixes.
    pub fn realtime_on_bake(&self, slot: usize) -> RealtimeOnBake {
        let b = &self.lights[slot];
        let mixing = self.mixed_lighting == MixedLighting::Shadowmask;
        match b.shadow_mask {
            _ if !b.drawn_on_static && !b.drawn_on_dynamic => RealtimeOnBake::BakedAlone,
            _ if !b.drawn_on_static => RealtimeOnBake::DynamicOnly,
            Some(c) if mixing => RealtimeOnBake::ShadowmaskChannel(c),
            _ => RealtimeOnBake::Full,
        }
    }
}

fn normal_quality() -> LightmapQuality {
    LightmapQuality::Normal
}

/// The Lightmap Encoding `pipeline` stores with when the scene asks for `asked`: built-in's and
/// URP's desktop default is Normal Quality (RGBM); HDRP supports High Quality alone (the HDRP
/// Wizard's lightmap-encoding check sets it), so it stores that whatever is asked.
pub fn lightmap_quality(pipeline: Pipeline, asked: Option<LightmapQuality>) -> (LightmapQuality, Option<String>) {
    match (pipeline, asked) {
        (Pipeline::Hdrp, Some(q)) if q != LightmapQuality::High => {
            (LightmapQuality::High, Some(format!("HDRP stores High Quality lightmaps only, not {} quality", q.name())))
        }
        (Pipeline::Hdrp, _) => (LightmapQuality::High, None),
        (_, Some(q)) => (q, None),
        (_, None) => (LightmapQuality::Normal, None),
    }
}

impl GiPlan {
    /// The plan of a scene that bakes (`gi`), in `pipeline`, for `lights` as the cell sees them;
    /// `main`: the pipeline's main directional light.
    pub fn new(gi: &GiSettings, pipeline: Pipeline, lights: &[Light], main: Option<usize>) -> GiPlan {
        let (mixed_lighting, mixed_lighting_note) = match (gi.mixed_lighting, pipeline) {
            (MixedLighting::Subtractive, Pipeline::Hdrp) => (
                MixedLighting::BakedIndirect,
                Some("HDRP has no Subtractive mode; its mixed lights bake as Baked Indirect".to_string()),
            ),
            (m, _) => (m, None),
        };
        let mut channels = 0usize;
        let lights = lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let (mode, why) = effective_mode(pipeline, l);
                let indirect = l.indirect_multiplier;
                match mode {
                    LightBakeMode::Realtime => BakedLight {
                        mode,
                        direct_in_lightmaps: false,
                        direct_in_probes: false,
                        indirect: 0.0,
                        shadow_mask: None,
                        probe_occlusion: None,
                        drawn_on_static: true,
                        drawn_on_dynamic: true,
                        note: "realtime: drawn every frame, not baked".into(),
                    },
                    LightBakeMode::Baked => baked_fully(
                        indirect,
                        why.unwrap_or_else(|| "baked: direct and indirect light in lightmaps and probes".into()),
                    ),
                    LightBakeMode::Mixed => mixed(mixed_lighting, Some(i) == main, indirect, &mut channels),
                }
            })
            .collect();
        let (encoding, encoding_note) = lightmap_quality(pipeline, gi.encoding);
        GiPlan {
            mixed_lighting,
            mixed_lighting_note,
            lights,
            probes: gi.probes.is_some(),
            bounces: gi.bounces,
            encoding,
            encoding_note,
        }
    }

    /// Whether the bake holds anything that can reach the frame: a light with baked direct or
    /// indirect light, a light whose occlusion is baked (a Shadowmask channel, Subtractive's probe
    /// occlusion: the static objects' shadows of a mixed light live there alone), or the
    /// environment (always baked: Unity's lightmaps and probes hold the sky's light).
    pub fn needs_bake(&self, environment: bool) -> bool {
        environment
            || self.lights.iter().any(|l| {
                l.direct_in_lightmaps
                    || l.direct_in_probes
                    || l.indirect > 0.0
                    || l.shadow_mask.is_some()
                    || l.probe_occlusion.is_some()
            })
    }

    /// Per light, why the bake alone brings it to dynamic objects (the subjects) or static ones
    /// (None where the frame draws it on them): what the light budgets leave out (plan::lights).
    pub fn baked_alone(&self, dynamic: bool) -> Vec<Option<String>> {
        self.lights
            .iter()
            .map(|b| (!if dynamic { b.drawn_on_dynamic } else { b.drawn_on_static }).then(|| b.note.clone()))
            .collect()
    }

    /// One line for `list`: the Lighting Mode and what each light bakes.
    pub fn summary(&self) -> String {
        let mut s = self.mixed_lighting.name().to_string();
        if let Some(note) = &self.mixed_lighting_note {
            s += &format!(" ({note})");
        }
        s += &format!(", {} quality lightmaps", self.encoding.name());
        if let Some(note) = &self.encoding_note {
            s += &format!(" ({note})");
        }
        s += &format!(", {} bounces, {}", self.bounces, if self.probes { "a probe grid" } else { "no probe grid" });
        for (i, l) in self.lights.iter().enumerate() {
            s += &format!("; lights[{i}] {}", l.note);
        }
        s
    }

    /// Whether light `i`'s real-time shadow map holds the dynamic objects alone: a mixed light under
    /// Shadowmask (the static objects' shadows are in the shadow mask) or Subtractive (in the
    /// lightmaps). Distance Shadowmask draws every caster within the shadow distance.
    pub fn static_shadows_baked(&self, i: usize) -> bool {
        self.lights[i].mode == LightBakeMode::Mixed
            && matches!(self.mixed_lighting, MixedLighting::Shadowmask | MixedLighting::Subtractive)
    }

    /// The number of shadow-mask channels in use.
    pub fn shadow_mask_channels(&self) -> usize {
        self.lights.iter().filter(|l| l.shadow_mask.is_some()).count()
    }
}

/// A light whose direct and bounced light are baked and which the frame never draws.
fn baked_fully(indirect: f64, note: String) -> BakedLight {
    BakedLight {
        mode: LightBakeMode::Baked,
        direct_in_lightmaps: true,
        direct_in_probes: true,
        indirect,
        shadow_mask: None,
        probe_occlusion: None,
        drawn_on_static: false,
        drawn_on_dynamic: false,
        note,
    }
}

/// A mixed light under `mode`.
fn mixed(mode: MixedLighting, main: bool, indirect: f64, channels: &mut usize) -> BakedLight {
    let realtime = |note: String, shadow_mask| BakedLight {
        mode: LightBakeMode::Mixed,
        direct_in_lightmaps: false,
        direct_in_probes: false,
        indirect,
        shadow_mask,
        probe_occlusion: None,
        drawn_on_static: true,
        drawn_on_dynamic: true,
        note,
    };
    match mode {
        MixedLighting::BakedIndirect => {
            realtime("mixed (baked indirect): direct in real time, indirect baked".into(), None)
        }
        MixedLighting::Shadowmask | MixedLighting::DistanceShadowmask if *channels < SHADOW_MASK_CHANNELS => {
            *channels += 1;
            realtime(
                format!(
                    "mixed ({}): direct in real time, indirect and static occlusion baked (shadow-mask channel {})",
                    mode.name(),
                    *channels - 1
                ),
                Some((*channels - 1) as u8),
            )
        }
        MixedLighting::Shadowmask | MixedLighting::DistanceShadowmask => baked_fully(
            indirect,
            format!("mixed, but the {SHADOW_MASK_CHANNELS} shadow-mask channels are taken: baked fully, as Unity does"),
        ),
        MixedLighting::Subtractive => BakedLight {
            mode: LightBakeMode::Mixed,
            direct_in_lightmaps: true,
            direct_in_probes: !main,
            indirect,
            shadow_mask: None,
            // Dynamic objects take static shadows through the probes alone (Unity manual,
            // Subtractive mode): their occlusion of the main light, in the probes' first channel
            probe_occlusion: main.then_some(0),
            drawn_on_static: false,
            drawn_on_dynamic: main,
            note: if main {
                "mixed (subtractive), the main directional light: baked into the lightmaps, real-time on dynamic objects, shadowed there by the probes' occlusion".into()
            } else {
                "mixed (subtractive): direct and indirect baked into lightmaps and probes".into()
            },
        },
    }
}

/// The mode a light has in `pipeline`, and why it differs from the scene's, if it does.
pub fn effective_mode(pipeline: Pipeline, light: &Light) -> (LightBakeMode, Option<String>) {
    match (light.kind, pipeline) {
        (LightKind::Rect | LightKind::Disc, Pipeline::Builtin | Pipeline::Urp)
            if light.mode != LightBakeMode::Baked =>
        {
            (LightBakeMode::Baked, Some(format!("{} bakes area lights only", pipeline.name())))
        }
        (LightKind::Disc, Pipeline::Hdrp) if light.mode != LightBakeMode::Baked => {
            (LightBakeMode::Baked, Some("HDRP bakes disc lights only".into()))
        }
        _ => (light.mode, None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(kind: LightKind, mode: LightBakeMode) -> Light {
        let mut scene = crate::declarations::scene::Scene::load("default", None, "t", "k").unwrap();
        let mut l = scene.lights.remove(0);
        l.kind = kind;
        l.mode = mode;
        l
    }

    fn gi(mode: MixedLighting) -> GiSettings {
        toml::from_str::<GiSettings>(&format!("mixed_lighting = \"{}\"", mode.name())).unwrap()
    }

    #[test]
    fn hdrp_stores_high_quality_lightmaps_whatever_is_asked() {
        use crate::declarations::gi::LightmapQuality::*;
        assert_eq!(lightmap_quality(Pipeline::Builtin, None), (Normal, None));
        assert_eq!(lightmap_quality(Pipeline::Urp, Some(Low)), (Low, None));
        assert_eq!(lightmap_quality(Pipeline::Hdrp, None), (High, None));
        let (q, note) = lightmap_quality(Pipeline::Hdrp, Some(Normal));
        assert_eq!(q, High);
        assert!(note.unwrap().contains("High Quality"));
    }

    #[test]
    fn modes_decide_what_is_baked_and_what_is_drawn() {
        let lights = [
            light(LightKind::Point, LightBakeMode::Realtime),
            light(LightKind::Point, LightBakeMode::Baked),
            light(LightKind::Directional, LightBakeMode::Mixed),
        ];
        let plan = GiPlan::new(&gi(MixedLighting::BakedIndirect), Pipeline::Urp, &lights, Some(2));
        let [r, b, m] = [0, 1, 2].map(|i| plan.lights[i].clone());
        assert!(r.drawn_on_static && r.indirect == 0.0 && !r.direct_in_lightmaps);
        assert!(!b.drawn_on_static && !b.drawn_on_dynamic && b.direct_in_lightmaps && b.direct_in_probes);
        assert!(m.drawn_on_static && m.drawn_on_dynamic && !m.direct_in_lightmaps && m.indirect == 1.0);
        // Subtractive: the main directional light stays real-time on dynamic objects only.
        let sub = GiPlan::new(&gi(MixedLighting::Subtractive), Pipeline::Builtin, &lights, Some(2));
        let m = &sub.lights[2];
        assert!(!m.drawn_on_static && m.drawn_on_dynamic && m.direct_in_lightmaps && !m.direct_in_probes);
        // HDRP has no Subtractive mode.
        let hdrp = GiPlan::new(&gi(MixedLighting::Subtractive), Pipeline::Hdrp, &lights, Some(2));
        assert_eq!(hdrp.mixed_lighting, MixedLighting::BakedIndirect);
        assert!(hdrp.mixed_lighting_note.is_some() && hdrp.lights[2].drawn_on_static);
    }

    #[test]
    fn which_lights_reach_a_lightmapped_frame_and_how() {
        use RealtimeOnBake::*;
        let lights = [
            light(LightKind::Point, LightBakeMode::Realtime),
            light(LightKind::Point, LightBakeMode::Baked),
            light(LightKind::Directional, LightBakeMode::Mixed),
        ];
        let on = |mode, p| {
            let plan = GiPlan::new(&gi(mode), p, &lights, Some(2));
            [0, 1, 2].map(|i| plan.realtime_on_bake(i))
        };
        assert_eq!(on(MixedLighting::BakedIndirect, Pipeline::Urp), [Full, BakedAlone, Full]);
        assert_eq!(on(MixedLighting::Subtractive, Pipeline::Builtin), [Full, BakedAlone, DynamicOnly]);
        assert_eq!(on(MixedLighting::Shadowmask, Pipeline::Urp), [Full, BakedAlone, ShadowmaskChannel(0)]);
        assert_eq!(ShadowmaskChannel(3).shader_value(), 5.0);
        assert_eq!(DynamicOnly.shader_value(), 6.0);
    }

    #[test]
    fn builtins_forward_scales_the_light_by_the_probes_occlusion_and_the_rest_take_the_darker() {
        assert_eq!(probe_occlusion(Pipeline::Builtin), ProbeOcclusion::LightColour);
        assert_eq!(probe_occlusion(Pipeline::Urp), ProbeOcclusion::Min);
        assert_eq!(probe_occlusion(Pipeline::Hdrp), ProbeOcclusion::Min);
    }

    #[test]
    fn a_fifth_mixed_light_is_baked_fully_under_shadowmask() {
        let lights: Vec<Light> = (0..5).map(|_| light(LightKind::Point, LightBakeMode::Mixed)).collect();
        let plan = GiPlan::new(&gi(MixedLighting::Shadowmask), Pipeline::Builtin, &lights, None);
        let channels: Vec<Option<u8>> = plan.lights.iter().map(|l| l.shadow_mask).collect();
        assert_eq!(channels, [Some(0), Some(1), Some(2), Some(3), None]);
        assert_eq!(plan.lights[4].mode, LightBakeMode::Baked);
        assert!(!plan.lights[4].drawn_on_static && plan.lights[4].direct_in_lightmaps);
    }

    #[test]
    fn area_lights_are_baked_where_the_pipeline_bakes_them() {
        let rect = light(LightKind::Rect, LightBakeMode::Realtime);
        assert_eq!(effective_mode(Pipeline::Builtin, &rect).0, LightBakeMode::Baked);
        assert_eq!(effective_mode(Pipeline::Hdrp, &rect).0, LightBakeMode::Realtime);
        let disc = light(LightKind::Disc, LightBakeMode::Realtime);
        assert_eq!(effective_mode(Pipeline::Hdrp, &disc).0, LightBakeMode::Baked);
    }
}
