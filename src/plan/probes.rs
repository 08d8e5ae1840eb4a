//! How a cell's frame reads each reflection probe: the engine's rule, decided here and handed to
//! the shaders as values (`render::uniforms::GpuReflectionProbe`), which apply it and decide
//! nothing. Recorded in `cell.json` (`reflection_probes`), so the record says what the frame drew.

use serde::{Deserialize, Serialize};

use crate::declarations::scene::ReflectionProbe;
use crate::pipelines::settings::PipelineSettings;
use crate::pipelines::Pipeline;

/// How a probe's weight falls off with the shaded point's position.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ProbeWeight {
    /// 1 deep inside the box, falling linearly to 0 at its faces over `distance` metres inside:
    /// URP's CalculateProbeWeight (GlobalIllumination.hlsl), sat(min over axes of the distance
    /// into the box / blend distance).
    FadeInside { distance: f64 },
}

/// How a cell's frame reads one reflection probe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProbeUse {
    /// The lookup direction is the reflected ray's hit on the probe's box seen from the probe
    /// (BoxProjectedCubemapDirection), rather than the ray's own direction.
    pub box_projection: bool,
    pub weight: ProbeWeight,
}

/// How `pipeline` (with its `engine` settings) reads `probe`.
/// - Box projection: where the probe asks for it (Reflection Probe ▸ Box Projection), and in URP
///   only where the asset turns the feature on: UniversalRenderPipeline.cs enables
///   `_REFLECTION_PROBE_BOX_PROJECTION` from `asset.reflectionProbeBoxProjection`, and
///   GlobalIllumination.hlsl box-projects (BoxProjectedCubemapDirection) only under it; the
///   default asset has it off, High Fidelity on. Built-in box-projects a box-projected probe
///   (UnityStandardUtils.cginc BoxProjectedCubemapDirection under UNITY_SPECCUBE_BOX_PROJECTION,
///   on in every desktop tier), HDRP likewise (its proxy volume is the influence box by default).
/// - Weight: faded inside the box over the probe's blend distance, URP's CalculateProbeWeight
///   (GlobalIllumination.hlsl), for every pipeline today; what the engines decide beyond that
///   (URP's `reflectionProbeBlending`, built-in deferred's fade outside the box, HDRP's influence
///   volume) is docs/deviations.md's, to be drawn here.
pub fn probe_use(pipeline: Pipeline, engine: &PipelineSettings, probe: &ReflectionProbe) -> ProbeUse {
    let feature = match pipeline {
        Pipeline::Urp => engine.urp.reflection_probe_box_projection,
        Pipeline::Builtin | Pipeline::Hdrp => true,
    };
    ProbeUse {
        box_projection: probe.box_projection && feature,
        weight: ProbeWeight::FadeInside { distance: probe.blend_distance },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(box_projection: bool, blend_distance: f64) -> ReflectionProbe {
        ReflectionProbe {
            position: [0.0, 1.0, 0.0],
            box_min: [-2.0, 0.0, -2.0],
            box_max: [2.0, 3.0, 2.0],
            blend_distance,
            box_projection,
            resolution: 128,
            near: 0.3,
        }
    }

    #[test]
    fn box_projection_follows_the_probe_and_in_urp_the_asset() {
        let default = PipelineSettings::default();
        let mut high = PipelineSettings::default();
        high.urp = crate::pipelines::settings::UrpAssetPreset::HighFidelity.asset();
        for (p, engine, expected) in [
            (Pipeline::Builtin, &default, true),
            (Pipeline::Hdrp, &default, true),
            // URP's default asset has reflectionProbeBoxProjection off: sampled along the ray.
            (Pipeline::Urp, &default, false),
            (Pipeline::Urp, &high, true),
        ] {
            assert_eq!(probe_use(p, engine, &probe(true, 1.0)).box_projection, expected, "{p:?}");
            assert!(!probe_use(p, engine, &probe(false, 1.0)).box_projection, "{p:?}: the probe's own toggle");
        }
    }

    #[test]
    fn every_pipeline_fades_the_weight_inside_the_box_today() {
        for p in Pipeline::ALL {
            for blend in [1.0, 0.5] {
                let u = probe_use(p, &PipelineSettings::default(), &probe(true, blend));
                assert_eq!(u.weight, ProbeWeight::FadeInside { distance: blend }, "{p:?}");
            }
        }
    }
}
