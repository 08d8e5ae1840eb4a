//! How a cell's frame reads each reflection probe: the engine's rule, decided here and handed to
//! the shaders as values (`render::uniforms::GpuReflectionProbe`, and each object's own probe in
//! its uniforms), which apply it and decide nothing. Recorded in `cell.json` (`rules`), so the
//! record says what the frame drew.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::declarations::scene::ReflectionProbe;
use crate::pipelines::settings::PipelineSettings;
use crate::pipelines::{Pipeline, RenderPath};

/// How a probe's weight at a shaded point is found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ProbeWeight {
    /// 1 deep inside the box, falling linearly to 0 at its faces over `distance` metres inside:
    /// sat(min over axes of the distance into the box / blend distance) (URP's
    /// CalculateProbeWeight, GlobalIllumination.hlsl; HDRP's influence volume fade).
    FadeInside { distance: f64 },
    /// 1 everywhere inside the box, falling to 0 at `distance` metres outside it, box-projected on
    /// the box grown by `distance` (built-in's Internal-DeferredReflections.shader:
    /// saturate(1 − length(distanceFromAABB(p, boxMin, boxMax)) / blendDistance)).
    FadeOutside { distance: f64 },
    /// The whole renderer takes its one probe at full weight (URP with probe blending off: each
    /// renderer's unity_SpecCube0, chosen on the CPU; `renderer_probe`).
    Renderer,
}

impl ProbeWeight {
    /// The value the shaders read (scene.wgsl `probe_weight`).
    pub fn shader_mode(self) -> u32 {
        match self {
            ProbeWeight::FadeInside { .. } => 0,
            ProbeWeight::FadeOutside { .. } => 1,
            ProbeWeight::Renderer => 2,
        }
    }

    /// The blend distance it fades over (0 where it does not fade).
    pub fn distance(self) -> f64 {
        match self {
            ProbeWeight::FadeInside { distance } | ProbeWeight::FadeOutside { distance } => distance,
            ProbeWeight::Renderer => 0.0,
        }
    }
}

/// How a cell's frame reads one reflection probe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProbeUse {
    /// The lookup direction is the reflected ray's hit on the probe's box seen from the probe
    /// (BoxProjectedCubemapDirection), rather than the ray's own direction.
    pub box_projection: bool,
    pub weight: ProbeWeight,
}

/// The blend distance of `probe` in `pipeline` where the scene gives none: the Reflection Probe
/// component's default blendDistance 1 m in built-in and URP; HDRP's InfluenceVolume blend
/// distances default to 0 (m_BoxBlendDistancePositive/Negative = Vector3.zero, InfluenceVolume.cs).
pub fn blend_distance(pipeline: Pipeline, probe: &ReflectionProbe) -> f64 {
    probe.blend_distance.unwrap_or(match pipeline {
        Pipeline::Builtin | Pipeline::Urp => 1.0,
        Pipeline::Hdrp => 0.0,
    })
}

/// How `pipeline` (with its `engine` settings) on `path` reads `probe`.
/// - Box projection: where the probe asks for it (Reflection Probe ▸ Box Projection), and in URP
///   only where the asset turns the feature on: UniversalRenderPipeline.cs enables
///   `_REFLECTION_PROBE_BOX_PROJECTION` from `asset.reflectionProbeBoxProjection`, and
///   GlobalIllumination.hlsl box-projects (BoxProjectedCubemapDirection) only under it; the
///   default asset has it off, High Fidelity on. Built-in box-projects a box-projected probe
///   (UnityStandardUtils.cginc BoxProjectedCubemapDirection under UNITY_SPECCUBE_BOX_PROJECTION,
///   on in every desktop tier), HDRP likewise (its proxy volume is the influence box by default).
/// - Weight: URP blends probes per pixel only with the asset's `reflectionProbeBlending`
///   (`_REFLECTION_PROBE_BLENDING`, CalculateIrradianceFromReflectionProbes); without it each
///   renderer samples its unity_SpecCube0 at full weight (GlossyEnvironmentReflection). HDRP fades
///   inside the influence volume over its blend distance. Built-in deferred lights reflections per
///   probe volume in screen space (Internal-DeferredReflections.shader): full weight inside the
///   box, fading outside it. Built-in forward blends two probes per renderer by a weight the CPU
///   computes from the renderer's bounds; APPROXIMATED by the per-pixel fade inside the box
///   (docs/deviations.md).
pub fn probe_use(pipeline: Pipeline, path: RenderPath, engine: &PipelineSettings, probe: &ReflectionProbe) -> ProbeUse {
    let feature = match pipeline {
        Pipeline::Urp => engine.urp.reflection_probe_box_projection,
        Pipeline::Builtin | Pipeline::Hdrp => true,
    };
    let distance = blend_distance(pipeline, probe);
    let weight = match (pipeline, path) {
        (Pipeline::Urp, _) if !engine.urp.reflection_probe_blending => ProbeWeight::Renderer,
        (Pipeline::Builtin, RenderPath::Deferred) => ProbeWeight::FadeOutside { distance },
        _ => ProbeWeight::FadeInside { distance },
    };
    ProbeUse { box_projection: probe.box_projection && feature, weight }
}

/// The probe a renderer whose bounds are centred at `centre` takes where probes are chosen per
/// renderer (`ProbeWeight::Renderer`): of the probes whose box holds the centre, the smallest
/// (Unity orders a renderer's probes by importance, equal by default, then by size: the smaller
/// box is the more specific); None: no probe holds it, and it reflects the sky.
pub fn renderer_probe(probes: &[ReflectionProbe], centre: DVec3) -> Option<usize> {
    let volume = |p: &ReflectionProbe| (DVec3::from(p.box_max) - DVec3::from(p.box_min)).element_product();
    let holds =
        |p: &ReflectionProbe| centre.cmpge(DVec3::from(p.box_min)).all() && centre.cmple(DVec3::from(p.box_max)).all();
    probes
        .iter()
        .enumerate()
        .filter(|(_, p)| holds(p))
        .min_by(|(_, a), (_, b)| volume(a).total_cmp(&volume(b)))
        .map(|(k, _)| k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipelines::settings::UrpAssetPreset;

    fn probe(box_projection: bool, blend_distance: Option<f64>) -> ReflectionProbe {
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

    fn high_fidelity() -> PipelineSettings {
        PipelineSettings { urp: UrpAssetPreset::HighFidelity.asset(), ..Default::default() }
    }

    #[test]
    fn box_projection_follows_the_probe_and_in_urp_the_asset() {
        let (default, high) = (PipelineSettings::default(), high_fidelity());
        for (p, engine, expected) in [
            (Pipeline::Builtin, &default, true),
            (Pipeline::Hdrp, &default, true),
            // URP's default asset has reflectionProbeBoxProjection off: sampled along the ray.
            (Pipeline::Urp, &default, false),
            (Pipeline::Urp, &high, true),
        ] {
            let at = |probe| probe_use(p, RenderPath::Forward, engine, &probe).box_projection;
            assert_eq!(at(probe(true, None)), expected, "{p:?}");
            assert!(!at(probe(false, None)), "{p:?}: the probe's own toggle");
        }
    }

    #[test]
    fn each_engine_weighs_its_probes_by_its_own_rule() {
        let (default, high) = (PipelineSettings::default(), high_fidelity());
        let weight = |p, path, engine: &PipelineSettings, blend| probe_use(p, path, engine, &probe(true, blend)).weight;
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            // URP without probe blending: the renderer's probe at full weight; with it, the fade.
            assert_eq!(weight(Pipeline::Urp, path, &default, None), ProbeWeight::Renderer);
            assert_eq!(weight(Pipeline::Urp, path, &high, None), ProbeWeight::FadeInside { distance: 1.0 });
            // HDRP: the influence volume's fade, 0 m unless the scene sets one.
            assert_eq!(weight(Pipeline::Hdrp, path, &default, None), ProbeWeight::FadeInside { distance: 0.0 });
            assert_eq!(weight(Pipeline::Hdrp, path, &default, Some(0.5)), ProbeWeight::FadeInside { distance: 0.5 });
        }
        // Built-in deferred: full weight inside, fading outside; forward: the labelled fade inside.
        assert_eq!(
            weight(Pipeline::Builtin, RenderPath::Deferred, &default, None),
            ProbeWeight::FadeOutside { distance: 1.0 }
        );
        assert_eq!(
            weight(Pipeline::Builtin, RenderPath::Forward, &default, None),
            ProbeWeight::FadeInside { distance: 1.0 }
        );
    }

    #[test]
    fn a_renderer_takes_the_smallest_probe_that_holds_its_centre() {
        let room = probe(true, None);
        let mut alcove = probe(true, None);
        (alcove.box_min, alcove.box_max) = ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
        let probes = [room, alcove];
        assert_eq!(renderer_probe(&probes, DVec3::new(0.5, 0.5, 0.5)), Some(1));
        assert_eq!(renderer_probe(&probes, DVec3::new(-1.0, 0.5, 0.5)), Some(0));
        assert_eq!(renderer_probe(&probes, DVec3::new(5.0, 0.5, 0.5)), None, "outside every box: the sky");
    }
}
