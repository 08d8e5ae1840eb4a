//! Where and how screen-space ambient occlusion reaches a cell's frame: the engine's rule, decided
//! here and handed to the passes as values (which SSAO runs, which objects bind its visibility or
//! a neutral one, how the shaders apply it, and how the deferred paths fold it into their baked
//! light). Recorded in `cell.json` (`rules.ambient_occlusion`).

use serde::{Deserialize, Serialize};

use crate::pipelines::settings::{PipelineSettings, UrpSsaoFeature};
use crate::pipelines::surface::SurfaceType;
use crate::pipelines::{Pipeline, RenderPath};

/// Which engine's SSAO a frame renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SsaoMethod {
    /// HDRP's GTAO (render::passes::ssao).
    #[default]
    HdrpGtao,
    /// URP's renderer feature: the Alchemy obscurance estimator with interleaved gradient noise
    /// and the bilateral blur (SSAO.hlsl; render::passes::urp_ssao).
    UrpAlchemy,
}

/// How a shader reads the occlusion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OcclusionRead {
    /// It does not (a neutral visibility of 1 is bound).
    #[default]
    None,
    /// The engine's lit shaders: HDRP's Lit rule, or URP's AmbientOcclusionFactor (indirect
    /// min(material, SSAO), direct lerp(1, SSAO, strength)).
    Lit,
    /// URP's Unlit (UnlitForwardPass.hlsl): the colour × the direct factor.
    Unlit,
}

/// A cell's screen-space occlusion.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct AoUse {
    /// The frame renders SSAO (with the depth-normal prepass it reads).
    pub ssao: bool,
    /// The subject's shading reads it (the fixed objects, opaque and drawn with the pipeline's
    /// lit shader, read it wherever it is drawn).
    pub subject: bool,
    /// HDRP's deferred Lit: the G-buffer pass multiplies the baked diffuse light by the material's
    /// occlusion and adds the emission (Lit.hlsl EncodeIntoGBuffer), and the lighting pass
    /// multiplies that sum by SSAO's multi-bounce visibility alone (DecodeFromGBuffer sets the
    /// material's occlusion to 1; MaterialEvaluation.hlsl ApplyAmbientOcclusionFactor: "SSAO is
    /// multiplied by emissive which is wrong"). Elsewhere the indirect diffuse takes
    /// GTAOMultiBounce(min(material, SSAO)) and the emission none.
    #[serde(default)]
    pub in_bake: bool,
    /// Which SSAO runs.
    #[serde(default)]
    pub method: SsaoMethod,
    /// How the subject's shader reads it.
    #[serde(default)]
    pub subject_read: OcclusionRead,
    /// URP's feature, where it runs: its direct lighting strength reaches the shaders.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urp: Option<UrpSsaoFeature>,
}

impl OcclusionRead {
    /// The value forward.wgsl's `SCREEN_OCCLUSION` takes.
    pub fn shader_id(self) -> u32 {
        match self {
            OcclusionRead::None => 0,
            OcclusionRead::Lit => 1,
            OcclusionRead::Unlit => 2,
        }
    }
}

impl AoUse {
    /// How the fixed objects read the occlusion: they are opaque and drawn with the pipeline's lit
    /// shader, so wherever the frame renders SSAO.
    pub fn fixed_read(&self) -> OcclusionRead {
        if self.ssao {
            OcclusionRead::Lit
        } else {
            OcclusionRead::None
        }
    }

    /// The share of the occlusion the direct light takes: URP's DirectLightingStrength
    /// (_AmbientOcclusionParam.w); HDRP's lit shaders leave the direct light alone.
    pub fn direct_lighting_strength(&self) -> f64 {
        self.urp.filter(|_| self.ssao).map_or(0.0, |f| f.direct_lighting_strength)
    }
}

/// How a `pipeline` shader named `model` reads SSAO.
/// - HDRP: every model through its Lit rule (HDRP has no shader without the light loop's
///   ambient occlusion here).
/// - URP: its own shaders compile `_SCREEN_SPACE_OCCLUSION` — Lit and Simple Lit through
///   AmbientOcclusion.hlsl CreateAmbientOcclusionFactor, Unlit through UnlitForwardPass.hlsl —
///   while custom shaders (the classic models, the SRP tutorial's Lit) declare no such keyword
///   and read none.
/// - Built-in: no SSAO.
pub fn occlusion_read(pipeline: Pipeline, model: &str) -> OcclusionRead {
    match (pipeline, model) {
        (Pipeline::Hdrp, _) => OcclusionRead::Lit,
        (Pipeline::Urp, "lit" | "simple_lit") => OcclusionRead::Lit,
        (Pipeline::Urp, "unlit") => OcclusionRead::Unlit,
        _ => OcclusionRead::None,
    }
}

/// The SSAO of a `pipeline` frame on `path` whose subject, drawn with `model`, is of `surface`.
/// - HDRP renders it where the scene keeps its AmbientOcclusion override on (`scene_ssao`,
///   `[hdrp] ssao`, on as HDRP's default volume profile ships it), on both its paths
///   (HDRenderPipeline.AmbientOcclusion.cs; HDRP has no vertex-lit path).
/// - URP renders it where the asset's renderer has the SSAO feature (`engine.urp.ssao`: the
///   High Fidelity renderer's, not the default asset's), on both its paths
///   (ScreenSpaceAmbientOcclusionPass.Setup: after the prepass on forward, after the G-buffer on
///   deferred).
/// - Built-in has none.
///
/// A transparent surface reads none: HDRP's Lit.hlsl GetScreenSpaceDiffuseOcclusion returns 1
/// under _SURFACE_TYPE_TRANSPARENT, URP's reads are compiled under
/// !defined(_SURFACE_TYPE_TRANSPARENT) (the occlusion holds the opaque depth).
pub fn ambient_occlusion(
    pipeline: Pipeline,
    path: RenderPath,
    engine: &PipelineSettings,
    (model, surface): (&str, SurfaceType),
    scene_ssao: bool,
) -> AoUse {
    let (ssao, method, urp) = match pipeline {
        Pipeline::Hdrp => (scene_ssao && path != RenderPath::VertexLit, SsaoMethod::HdrpGtao, None),
        Pipeline::Urp => (engine.urp.ssao.is_some(), SsaoMethod::UrpAlchemy, engine.urp.ssao),
        Pipeline::Builtin => (false, SsaoMethod::default(), None),
    };
    let read = occlusion_read(pipeline, model);
    let subject = ssao && !surface.is_transparent() && read != OcclusionRead::None;
    AoUse {
        ssao,
        subject,
        in_bake: pipeline == Pipeline::Hdrp && path == RenderPath::Deferred,
        method,
        subject_read: if subject { read } else { OcclusionRead::None },
        urp: urp.filter(|_| ssao),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipelines::settings::UrpAssetPreset;

    fn engine(urp: UrpAssetPreset) -> PipelineSettings {
        PipelineSettings { urp: urp.asset(), ..Default::default() }
    }

    #[test]
    fn hdrp_occludes_where_the_scene_keeps_it_but_not_its_transparent_surfaces() {
        let e = PipelineSettings::default();
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let in_bake = path == RenderPath::Deferred;
            for surface in [SurfaceType::Opaque, SurfaceType::Cutout] {
                let on = ambient_occlusion(Pipeline::Hdrp, path, &e, ("lit", surface), true);
                let lit = OcclusionRead::Lit;
                assert_eq!(on, AoUse { ssao: true, subject: true, in_bake, subject_read: lit, ..Default::default() });
                let off = ambient_occlusion(Pipeline::Hdrp, path, &e, ("lit", surface), false);
                assert_eq!(off, AoUse { in_bake, ..AoUse::default() });
            }
            for surface in [SurfaceType::Transparent, SurfaceType::Premultiply, SurfaceType::Additive] {
                let on = ambient_occlusion(Pipeline::Hdrp, path, &e, ("lit", surface), true);
                assert_eq!(on, AoUse { ssao: true, subject: false, in_bake, ..Default::default() }, "{path:?}");
            }
        }
        for path in Pipeline::Builtin.paths() {
            let high = engine(UrpAssetPreset::HighFidelity);
            let got = ambient_occlusion(Pipeline::Builtin, *path, &high, ("standard", SurfaceType::Opaque), true);
            assert_eq!(got, AoUse::default(), "{path:?}");
        }
    }

    #[test]
    fn urp_occludes_with_the_high_fidelity_renderers_feature_alone() {
        let opaque = SurfaceType::Opaque;
        for path in Pipeline::Urp.paths() {
            let default =
                ambient_occlusion(Pipeline::Urp, *path, &engine(UrpAssetPreset::Default), ("lit", opaque), true);
            assert_eq!(default, AoUse { method: SsaoMethod::UrpAlchemy, ..AoUse::default() }, "{path:?}");
            assert_eq!(default.direct_lighting_strength(), 0.0);
            let high = engine(UrpAssetPreset::HighFidelity);
            let lit = ambient_occlusion(Pipeline::Urp, *path, &high, ("lit", opaque), false);
            assert!(lit.ssao && lit.subject && !lit.in_bake, "HDRP's volume switch does not reach URP: {lit:?}");
            assert_eq!((lit.method, lit.subject_read), (SsaoMethod::UrpAlchemy, OcclusionRead::Lit));
            assert_eq!(lit.direct_lighting_strength(), 0.25);
            let simple = ambient_occlusion(Pipeline::Urp, *path, &high, ("simple_lit", opaque), true);
            assert_eq!(simple.subject_read, OcclusionRead::Lit);
            let unlit = ambient_occlusion(Pipeline::Urp, *path, &high, ("unlit", opaque), true);
            assert_eq!(unlit.subject_read, OcclusionRead::Unlit);
            // Custom shaders compile no _SCREEN_SPACE_OCCLUSION: the frame still renders it for the
            // fixed objects, the subject reads none.
            for custom in ["lambert", "phong", "srp_lit"] {
                let c = ambient_occlusion(Pipeline::Urp, *path, &high, (custom, opaque), true);
                assert!(c.ssao && !c.subject && c.subject_read == OcclusionRead::None, "{custom}: {c:?}");
            }
            let glass = ambient_occlusion(Pipeline::Urp, *path, &high, ("lit", SurfaceType::Transparent), true);
            assert!(glass.ssao && !glass.subject, "{glass:?}");
        }
    }
}
