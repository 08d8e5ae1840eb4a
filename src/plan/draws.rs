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

/// The frame's draws: per mesh the lights of its additive passes, and the count of draws per pass.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DrawPlan {
    /// Per mesh (layout order): the scene lights drawn in its own ForwardAdd draws, in scene order.
    pub forward_add: Vec<Vec<usize>>,
    /// Draws per pass, by name: `forward_base`, `forward_add`, `forward`, `gbuffer`,
    /// `deferred_lighting`, `forward_only`, `vertex`.
    pub counts: BTreeMap<String, u32>,
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

/// The draws of a frame. `meshes`: per mesh, its scene object, whether it is drawn, its model and
/// whether a deferred path draws it into the G-buffer (a transparent surface is drawn forward,
/// counted under `transparent` as well);
/// `main_light`: the pipeline's main light (ForwardBase's).
pub fn plan_draws(
    pipeline: Pipeline,
    path: RenderPath,
    engine: &PipelineSettings,
    meshes: &[(usize, bool, &ShaderModel, bool)],
    assignment: &[ObjectLights],
    main_light: Option<usize>,
) -> DrawPlan {
    let mut counts: BTreeMap<String, u32> = BTreeMap::new();
    let mut add = |name: &str, n: u32| *counts.entry(name.to_string()).or_default() += n;
    let mut forward_add = vec![Vec::new(); meshes.len()];
    let mut lighting_models: Vec<&str> = Vec::new();
    for (m, &(object, drawn, model, deferrable)) in meshes.iter().enumerate() {
        if !drawn {
            continue;
        }
        if path == RenderPath::Deferred && model.deferrable() && !deferrable {
            add("transparent", 1);
        }
        if path == RenderPath::VertexLit {
            add("vertex", 1);
            continue;
        }
        if path == RenderPath::Deferred && deferrable {
            add("gbuffer", 1);
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
            add("forward_base", 1);
            add("forward_add", lights.len() as u32);
            forward_add[m] = lights;
        } else if path == RenderPath::Deferred {
            add("forward_only", 1);
        } else {
            add("forward", 1);
        }
    }
    if path == RenderPath::Deferred {
        add("deferred_lighting", lighting_models.len().max(1) as u32);
    }
    DrawPlan { forward_add, counts }
}
