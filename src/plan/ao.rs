//! Where and how screen-space ambient occlusion reaches a cell's frame: the engine's rule, decided
//! here and handed to the passes as values (which bind the SSAO visibility or a neutral one per
//! object). Recorded in `cell.json` (`ambient_occlusion`).

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
}

/// The SSAO of a `pipeline` frame on `path` whose subject is of `surface`, where the scene keeps
/// HDRP's AmbientOcclusion override on (`scene_ssao`, `[hdrp] ssao`, on as HDRP's default volume
/// profile ships it). HDRP renders it on both its paths (HDRenderPipeline.AmbientOcclusion.cs;
/// HDRP has no vertex-lit path); the SRP URP renders it only through its renderer's SSAO feature,
/// which neither the default nor the High Fidelity renderer this tool emulates draws today;
/// built-in has none. Every surface reads it today, transparent ones included; HDRP's
/// GetScreenSpaceDiffuseOcclusion gives transparent surfaces none, which docs/deviations.md lists,
/// to be drawn here.
pub fn ambient_occlusion(pipeline: Pipeline, path: RenderPath, surface: SurfaceType, scene_ssao: bool) -> AoUse {
    let ssao = pipeline == Pipeline::Hdrp && scene_ssao && path != RenderPath::VertexLit;
    let _ = surface;
    AoUse { ssao, subject: ssao }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hdrp_occludes_where_the_scene_keeps_it_and_every_surface_reads_it_today() {
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            for surface in [SurfaceType::Opaque, SurfaceType::Cutout, SurfaceType::Transparent] {
                let on = ambient_occlusion(Pipeline::Hdrp, path, surface, true);
                assert_eq!(on, AoUse { ssao: true, subject: true }, "{path:?} {surface:?}");
                assert_eq!(ambient_occlusion(Pipeline::Hdrp, path, surface, false), AoUse::default());
            }
        }
        for p in [Pipeline::Builtin, Pipeline::Urp] {
            for path in p.paths() {
                assert_eq!(ambient_occlusion(p, *path, SurfaceType::Opaque, true), AoUse::default(), "{p:?} {path:?}");
            }
        }
    }
}
