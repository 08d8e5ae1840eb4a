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

/// How `pipeline` (with its `engine` settings) reads `probe`. Today every pipeline follows the
/// scene's probe: box projection where the probe asks for it, the weight faded inside the box
/// over the probe's blend distance, URP's CalculateProbeWeight (GlobalIllumination.hlsl) and
/// BoxProjectedCubemapDirection (UnityStandardUtils.cginc; URP's of the same name). What the
/// engines decide beyond that (the URP asset's `reflectionProbeBoxProjection` and
/// `reflectionProbeBlending`, built-in deferred's fade outside the box, HDRP's influence volume)
/// is docs/deviations.md's, to be drawn here.
pub fn probe_use(pipeline: Pipeline, engine: &PipelineSettings, probe: &ReflectionProbe) -> ProbeUse {
    let _ = (pipeline, engine);
    ProbeUse {
        box_projection: probe.box_projection,
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
    fn every_pipeline_follows_the_scenes_probe_today() {
        for p in Pipeline::ALL {
            for (box_projection, blend) in [(true, 1.0), (false, 0.5)] {
                let u = probe_use(p, &PipelineSettings::default(), &probe(box_projection, blend));
                assert_eq!(u.box_projection, box_projection, "{p:?}");
                assert_eq!(u.weight, ProbeWeight::FadeInside { distance: blend }, "{p:?}");
            }
        }
    }

    #[test]
    fn the_urp_default_asset_box_projects_what_the_probe_asks_today() {
        // URP's default asset records reflectionProbeBoxProjection off, and the frame still box
        // projects: the difference docs/deviations.md lists, fixed as its own change.
        let engine = PipelineSettings::default();
        assert!(!engine.urp.reflection_probe_box_projection);
        assert!(probe_use(Pipeline::Urp, &engine, &probe(true, 1.0)).box_projection);
    }
}
