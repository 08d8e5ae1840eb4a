//! Where and how screen-space ambient occlusion reaches a cell's frame: the engine's rule, decided
//! here and handed to the passes as values (which bind the SSAO visibility or a neutral one per
//! object, and tell the G-buffer pass how HDRP's deferred Lit folds occlusion into its baked
//! light). Recorded in `cell.json` (`rules.ambient_occlusion`).

use serde::{Deserialize, Serialize};

use crate::pipelines::surface::SurfaceType;
use crate::pipelines::{Pipeline, RenderPath};

/// A cell's screen-space occlusion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct AoUse {
    /// The frame renders SSAO (with the depth-normal prepass it reads).
    pub ssao: bool,
    /// The subject's shading reads it (the fixed objects, opaque, read it wherever it is drawn).
    pub subject: bool,
    /// HDRP's deferred Lit: the G-buffer pass multiplies the baked diffuse light by the material's
    /// occlusion and adds the emission (Lit.hlsl EncodeIntoGBuffer), and the lighting pass
    /// multiplies that sum by SSAO's multi-bounce visibility alone (DecodeFromGBuffer sets the
    /// material's occlusion to 1; MaterialEvaluation.hlsl ApplyAmbientOcclusionFactor: "SSAO is
    /// multiplied by emissive which is wrong"). Elsewhere the indirect diffuse takes
    /// GTAOMultiBounce(min(material, SSAO)) and the emission none.
    #[serde(default)]
    pub in_bake: bool,
}

/// The SSAO of a `pipeline` frame on `path` whose subject is of `surface`, where the scene keeps
/// HDRP's AmbientOcclusion override on (`scene_ssao`, `[hdrp] ssao`, on as HDRP's default volume
/// profile ships it).
/// - HDRP renders it on both its paths (HDRenderPipeline.AmbientOcclusion.cs; HDRP has no
///   vertex-lit path); a transparent surface reads none (Lit.hlsl GetScreenSpaceDiffuseOcclusion
///   returns 1 under _SURFACE_TYPE_TRANSPARENT: the occlusion texture holds the opaque depth).
/// - URP renders it only through its renderer's SSAO feature, which neither the default nor the
///   High Fidelity renderer this tool emulates draws today; built-in has none.
pub fn ambient_occlusion(pipeline: Pipeline, path: RenderPath, surface: SurfaceType, scene_ssao: bool) -> AoUse {
    let hdrp = pipeline == Pipeline::Hdrp;
    let ssao = hdrp && scene_ssao && path != RenderPath::VertexLit;
    AoUse { ssao, subject: ssao && !surface.is_transparent(), in_bake: hdrp && path == RenderPath::Deferred }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hdrp_occludes_where_the_scene_keeps_it_but_not_its_transparent_surfaces() {
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let in_bake = path == RenderPath::Deferred;
            for surface in [SurfaceType::Opaque, SurfaceType::Cutout] {
                let on = ambient_occlusion(Pipeline::Hdrp, path, surface, true);
                assert_eq!(on, AoUse { ssao: true, subject: true, in_bake }, "{path:?} {surface:?}");
                let off = ambient_occlusion(Pipeline::Hdrp, path, surface, false);
                assert_eq!(off, AoUse { in_bake, ..AoUse::default() });
            }
            for surface in [SurfaceType::Transparent, SurfaceType::Premultiply, SurfaceType::Additive] {
                let on = ambient_occlusion(Pipeline::Hdrp, path, surface, true);
                assert_eq!(on, AoUse { ssao: true, subject: false, in_bake }, "{path:?} {surface:?}");
            }
        }
        for p in [Pipeline::Builtin, Pipeline::Urp] {
            for path in p.paths() {
                assert_eq!(ambient_occlusion(p, *path, SurfaceType::Opaque, true), AoUse::default(), "{p:?} {path:?}");
            }
        }
    }
}
