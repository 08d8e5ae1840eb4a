//! Which draws a frame makes, decided from the path, the models' engine passes and the light
//! assignment, as each engine structures its frame:
//!
//! - Built-in forward (Unity manual "Forward rendering path details"; Standard.shader's
//!   FORWARD and FORWARD_DELTA passes): each object is drawn once in ForwardBase (the main
//!   directional light, SH and vertex lights, ambient, emission), then once more in ForwardAdd for
//!   every other per-pixel light that reaches it, blended `One One` with depth test LEqual and no
//!   depth writes. A ForwardBase-only shader (no ForwardAdd pass) and Gouraud models, whose lights
//!   are summed at the vertices, are drawn once.
//! - URP forward and HDRP forward: one draw per object, every light in its loop.
//! - Deferred: the G-buffer draw of each object whose shader has a G-buffer pass, one lighting
//!   pass (a full-screen draw per material type: URP's StencilDeferred.shader has its Lit and
//!   SimpleLit passes, chosen by stencil), then every other object drawn forward as above.
//! - Built-in vertex-lit: one draw per object.

use std::collections::BTreeMap;

use super::lights::{lit_path, LightMode, ObjectLights};
use crate::pipelines::settings::PipelineSettings;
use crate::pipelines::{Pipeline, RenderPath};
use crate::shading::ShaderModel;

/// What a draw of a frame is, as `DrawPlan::counts` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DrawKind {
    /// Built-in's ForwardBase and ForwardAdd draws.
    ForwardBase,
    ForwardAdd,
    /// One draw with every light (URP, HDRP, a model without additive passes).
    Forward,
    /// An object into the G-buffer.
    GBuffer,
    /// A full-screen lighting draw per material type.
    DeferredLighting,
    /// An object the G-buffer cannot carry, drawn forward on a deferred path.
    ForwardOnly,
    /// An object of the vertex-lit path.
    Vertex,
    /// The Transparent queue's draws on a deferred path (counted in `ForwardOnly`'s too).
    Transparent,
}

impl DrawKind {
    /// Its name in `DrawPlan::counts` and `cell.json`'s `draws`: the pass's own where the draws
    /// are one pass's (`plan::Pass`).
    pub fn name(self) -> &'static str {
        match self {
            DrawKind::ForwardBase => "forward_base",
            DrawKind::ForwardAdd => "forward_add",
            DrawKind::Forward => super::Pass::Forward.name(),
            DrawKind::GBuffer => super::Pass::GBuffer.name(),
            DrawKind::DeferredLighting => "deferred_lighting",
            DrawKind::ForwardOnly => "forward_only",
            DrawKind::Vertex => "vertex",
            DrawKind::Transparent => super::Pass::Transparent.name(),
        }
    }
}

/// The frame's draws: per mesh the lights of its additive passes, and the count of draws per pass.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DrawPlan {
    /// Per mesh (layout order): the scene lights drawn in its own ForwardAdd draws, in scene order.
    pub forward_add: Vec<Vec<usize>>,
    /// Draws per pass, by name: `forward_base`, `forward_add`, `forward`, `gbuffer`,
    /// `deferred_lighting`, `forward_only`, `vertex`.
    pub counts: BTreeMap<String, u32>,
}

/// Whether `model` has a G-buffer pass in `pipeline`, so that a deferred path draws it into the
/// G-buffer: where the engine's shader has one (built-in Standard's DEFERRED pass,
/// Standard.shader; URP Lit's and Simple Lit's GBuffer pass, UniversalGBuffer in Lit.shader and
/// SimpleLit.shader; HDRP Lit's GBuffer pass, ShaderPassGBuffer), declared per model
/// (`EnginePasses::gbuffer`). A model lit per vertex or by the main light alone has none: the
/// engines draw such shaders forward after the deferred lighting.
pub fn gbuffer_pass(pipeline: Pipeline, model: &ShaderModel) -> bool {
    model.deferrable() || legacy_deferred(pipeline, model).is_some()
}

/// Whether `model` in `pipeline` has built-in's legacy Deferred pass: a surface shader lit by
/// Lighting.cginc's Lambert or BlinnPhong, whose LightingLambert_Deferred and
/// LightingBlinnPhong_Deferred write UnityStandardData (diffuseColor = Albedo; specularColor 0
/// and smoothness 0, or _SpecColor·Gloss/π and Specular; occlusion 1; the emission and
/// Albedo·indirect diffuse into RT3), which Internal-DeferredShading lights with BRDF1 and
/// Internal-DeferredReflections reflects (`EnginePasses::legacy_deferred`). A per-vertex or
/// ForwardBase-only variant has none.
pub fn legacy_deferred(pipeline: Pipeline, model: &ShaderModel) -> Option<crate::shading::registry::LegacyLighting> {
    let has = pipeline == Pipeline::Builtin && !model.per_vertex && !model.main_light_only;
    model.passes.legacy_deferred.filter(|_| has)
}

/// Whether the subject's alpha test resolves by alpha-to-coverage: URP Lit's passes declare
/// `AlphaToMask[_AlphaToMask]`, which BaseShaderGUI turns on with Alpha Clipping, and AlphaClip
/// (ShaderVariablesFunctions.hlsl) then exports SharpenAlpha(alpha, cutoff) = sat((alpha −
/// cutoff)/max(fwidth(alpha), 10⁻⁴) + ½) instead of clipping wherever the renderer multisamples
/// (IsAlphaToMaskAvailable). Built-in Standard has no AlphaToMask; HDRP Lit's Alpha To Mask is off
/// by default. `samples`: the forward frame's samples per pixel.
pub fn alpha_to_coverage(pipeline: Pipeline, surface: crate::pipelines::surface::SurfaceType, samples: u32) -> bool {
    pipeline == Pipeline::Urp && surface.clips() && samples > 1
}

/// The Transparent queue of a frame: of the meshes in it (`transparent`: a fixed object whose
/// material is transparent, the subject where its cell's surface is), the drawn ones in the order
/// they are drawn — back to front by `distance`, from the camera to the object's bounds centre, as
/// Unity sorts the queue for a perspective camera (TransparencySortMode.Default), the scene's
/// order breaking ties.
pub fn transparent_queue(transparent: &[bool], drawn: &[bool], distance: impl Fn(usize) -> f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..transparent.len()).filter(|&i| transparent[i] && drawn[i]).collect();
    order.sort_by(|&a, &b| distance(b).total_cmp(&distance(a)));
    order
}

/// Which of a cell's models its deferred path draws into the G-buffer: the subject's (where its
/// model has a G-buffer pass and its surface is opaque: the engines draw the Transparent queue
/// forward) and the fixed objects'.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GBufferModels {
    pub subject: bool,
    pub fixed: bool,
    /// The subject's G-buffer holds built-in's legacy UnityStandardData of this lighting function,
    /// lit with BRDF1 (the fixed objects' Standard) rather than its own model (`legacy_deferred`).
    pub subject_legacy: Option<crate::shading::registry::LegacyLighting>,
}

/// Whether `model` is drawn with ForwardBase + ForwardAdd passes when lit on `path` in `pipeline`.
/// `deferrable`: the object is drawn into a G-buffer on a deferred path (its model has a G-buffer
/// pass and its surface is opaque).
pub fn additive_passes(
    pipeline: Pipeline,
    path: RenderPath,
    model: &ShaderModel,
    deferrable: bool,
    engine: &PipelineSettings,
) -> bool {
    pipeline == Pipeline::Builtin
        && lit_path(path, !deferrable) == RenderPath::Forward
        && engine.builtin.forward_add
        && !model.per_vertex
        && !model.main_light_only
}

/// Whether lights other than the main directional one shadow `model` in `pipeline`: in built-in
/// only shaders compiled with `fullforwardshadows` (Standard) are shadowed by ForwardAdd lights;
/// the SRP pipelines decide per light (`shadows::shadow_style`), not per shader.
pub fn shadowed_by_additional_lights(pipeline: Pipeline, model: &ShaderModel) -> bool {
    pipeline != Pipeline::Builtin || model.passes.full_forward_shadows
}

/// The draws of a frame. `meshes`: per mesh, its scene object, whether it is drawn, its model,
/// whether a deferred path draws it into the G-buffer, and whether it is in the Transparent queue
/// (drawn forward on a deferred path, counted under `transparent` as well);
/// `main_light`: the pipeline's main light (ForwardBase's).
pub fn plan_draws(
    pipeline: Pipeline,
    path: RenderPath,
    engine: &PipelineSettings,
    meshes: &[(usize, bool, &ShaderModel, bool, bool)],
    assignment: &[ObjectLights],
    main_light: Option<usize>,
) -> DrawPlan {
    let mut counts: BTreeMap<String, u32> = BTreeMap::new();
    let mut add = |kind: DrawKind, n: u32| *counts.entry(kind.name().to_string()).or_default() += n;
    let mut forward_add = vec![Vec::new(); meshes.len()];
    let mut lighting_models: Vec<&str> = Vec::new();
    for (m, &(object, drawn, model, deferrable, transparent)) in meshes.iter().enumerate() {
        if !drawn {
            continue;
        }
        if path == RenderPath::Deferred && transparent {
            add(DrawKind::Transparent, 1);
        }
        if path == RenderPath::VertexLit {
            add(DrawKind::Vertex, 1);
            continue;
        }
        if path == RenderPath::Deferred && deferrable {
            add(DrawKind::GBuffer, 1);
            if !lighting_models.contains(&model.name.as_ref()) {
                lighting_models.push(model.name.as_ref());
            }
            continue;
        }
        if additive_passes(pipeline, path, model, deferrable, engine) {
            let lights: Vec<usize> = assignment[object]
                .lights
                .iter()
                .filter(|u| u.mode == LightMode::PerPixel && Some(u.light) != main_light)
                .map(|u| u.light)
                .collect();
            add(DrawKind::ForwardBase, 1);
            add(DrawKind::ForwardAdd, lights.len() as u32);
            forward_add[m] = lights;
        } else if path == RenderPath::Deferred {
            add(DrawKind::ForwardOnly, 1);
        } else {
            add(DrawKind::Forward, 1);
        }
    }
    if path == RenderPath::Deferred {
        add(DrawKind::DeferredLighting, lighting_models.len().max(1) as u32);
    }
    DrawPlan { forward_add, counts }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urps_alpha_clipping_turns_to_coverage_under_msaa_alone() {
        use crate::pipelines::surface::SurfaceType;
        assert!(alpha_to_coverage(Pipeline::Urp, SurfaceType::Cutout, 4));
        assert!(!alpha_to_coverage(Pipeline::Urp, SurfaceType::Cutout, 1), "no MSAA: the alpha test");
        assert!(!alpha_to_coverage(Pipeline::Urp, SurfaceType::Opaque, 4));
        assert!(!alpha_to_coverage(Pipeline::Urp, SurfaceType::Transparent, 4));
        for p in [Pipeline::Builtin, Pipeline::Hdrp] {
            assert!(!alpha_to_coverage(p, SurfaceType::Cutout, 8), "{p:?}");
        }
    }

    #[test]
    fn the_engines_lit_shaders_have_a_gbuffer_pass_and_per_vertex_or_main_light_models_do_not() {
        let models = crate::shading::Registry::builtin();
        let has = |p: Pipeline, name: &str| gbuffer_pass(p, models.find(p, name).expect(name));
        for (p, name) in [
            (Pipeline::Builtin, "standard"),
            (Pipeline::Urp, "lit"),
            (Pipeline::Urp, "simple_lit"),
            (Pipeline::Hdrp, "lit"),
        ] {
            assert!(has(p, name), "{p:?} {name}");
        }
        for p in Pipeline::ALL {
            assert!(!has(p, "phong_vertex") && !has(p, "lambert_vertex"), "{p:?}: lit per vertex");
        }
        assert!(!has(Pipeline::Builtin, "torrance_sparrow"), "ForwardBase only");
    }

    #[test]
    fn builtins_lambert_and_blinn_phong_have_the_legacy_deferred_pass_and_custom_lighting_none() {
        let models = crate::shading::Registry::builtin();
        let model = |p: Pipeline, name: &str| models.find(p, name).expect(name).clone();
        for name in ["lambert", "blinn_phong"] {
            assert!(gbuffer_pass(Pipeline::Builtin, &model(Pipeline::Builtin, name)), "{name}");
            assert!(legacy_deferred(Pipeline::Builtin, &model(Pipeline::Builtin, name)).is_some(), "{name}");
            for p in [Pipeline::Urp, Pipeline::Hdrp] {
                assert!(!gbuffer_pass(p, &model(p, name)), "{p:?} {name}: a custom shader there");
            }
            assert!(model(Pipeline::Builtin, name).passes.vertex_lit_fallback, "{name}: VertexLit fallback");
        }
        for name in ["phong", "oren_nayar", "half_lambert", "cook_torrance", "lambert_vertex", "blinn_phong_vertex"] {
            assert!(!gbuffer_pass(Pipeline::Builtin, &model(Pipeline::Builtin, name)), "{name}: forward only");
        }
        assert_eq!(legacy_deferred(Pipeline::Builtin, &model(Pipeline::Builtin, "standard")), None, "Standard's own");
    }
}
