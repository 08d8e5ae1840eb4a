//! Pipeline warm-up: before a cell's frames are encoded, every pipeline its plan's passes draw
//! with is compiled (once per device: `PipelineCache` keeps them), so that encoding only looks
//! them up and a first frame's time holds no compilation.

use super::passes::deferred::lighting_draws;
use super::pipeline_cache::{faces_of, ForwardKey, ForwardPass, PipelineCache};
use super::prepared::PreparedScene;
use crate::declarations::scene::Role;
use crate::error::Error;
use crate::gpu::GpuContext;
use crate::pipelines::surface::{RenderFace, SurfaceType};
use crate::pipelines::RenderPath;
use crate::plan::cell::{CellParams, CellPlan};
use crate::plan::draws::{additive_passes, shadowed_by_additional_lights};
use crate::plan::Pass;
use crate::shading::ShaderModel;

/// A model's forward pipelines: its one draw (or ForwardBase), and its ForwardAdd where the plan
/// draws one.
pub(in crate::render) type ModelKeys = (ForwardKey, Option<ForwardKey>);

/// What the frame's passes look their pipelines up by.
pub(in crate::render) struct FrameKeys {
    pub(in crate::render) subject: ModelKeys,
    pub(in crate::render) fixed: ModelKeys,
    /// The transparent fixed objects' (None: the frame draws none).
    pub(in crate::render) fixed_transparent: Option<ModelKeys>,
    /// The render faces each role's meshes have, and every mesh's (the prepass draws them all).
    pub(in crate::render) subject_faces: Vec<RenderFace>,
    pub(in crate::render) fixed_faces: Vec<RenderFace>,
    pub(in crate::render) fixed_transparent_faces: Vec<RenderFace>,
    pub(in crate::render) prepass_faces: Vec<RenderFace>,
    /// The depth-normal prepass samples normal maps (the subject's or the fixed objects').
    pub(in crate::render) prepass_textured: bool,
    /// The subject's split diffuse lighting (passes::subsurface), where the frame splits it.
    pub(in crate::render) subsurface: Option<ForwardKey>,
}

/// The forward keys of a role's model: each model's one draw or ForwardBase, and its ForwardAdd
/// where it has additive passes and the plan gives some mesh of the role an extra pixel light.
fn model_keys(
    cell: &CellParams,
    plan: &CellPlan,
    prepared: &PreparedScene,
    (model, textured, subject, surface): (&ShaderModel, bool, bool, SurfaceType),
) -> ModelKeys {
    // The Transparent queue is drawn forward on a deferred path.
    let deferrable = !surface.is_transparent() && if subject { plan.gbuffer.subject } else { plan.gbuffer.fixed };
    let additive = additive_passes(cell.pipeline, cell.settings.path, model, deferrable, &cell.settings.engine);
    let adds = plan
        .draws
        .forward_add
        .iter()
        .zip(&prepared.layout.meshes)
        .any(|(lights, m)| !lights.is_empty() && (m.role == Role::Subject) == subject);
    let draw = ForwardKey {
        vertex_lit: cell.settings.path == RenderPath::VertexLit,
        samples: plan.multisampling.samples,
        textured,
        exact: cell.settings.exact,
        pass: if additive { ForwardPass::Base } else { ForwardPass::All },
        additional_shadows: shadowed_by_additional_lights(cell.pipeline, model),
        surface,
        face: RenderFace::Front,
        terms: 0,
        alpha_to_coverage: subject && plan.alpha_to_coverage,
        occlusion: match subject {
            true => plan.ao.subject_read,
            false => plan.ao.fixed_read(),
        },
        lights: plan.light_paths(),
        subsurface: false,
    };
    (draw, (additive && adds).then_some(ForwardKey { pass: ForwardPass::Add, ..draw }))
}

/// Compile every pipeline the cell's passes draw with (`terms`: the term layers drawn; `split`:
/// the frame splits the subject's lighting for its subsurface scattering) and return the keys
/// they are found by.
pub(in crate::render) fn warm_up(
    pipelines: &mut PipelineCache,
    gpu: &GpuContext,
    (prepared, cell, plan): (&PreparedScene, &CellParams, &CellPlan),
    fixed_model: &ShaderModel,
    (terms, split): (u32, bool),
) -> Result<FrameKeys, Error> {
    use crate::pipelines::terms::{DIRECT_SPECULAR, INDIRECT_SPECULAR};
    let textured = cell.settings.material_maps.is_some();
    // Fixed objects with maps of their own (materials::fixed) draw with pipelines that sample
    // them; the depth-normal prepass draws every object with one pipeline.
    let fixed_textured = prepared.fixed_maps.any();
    let with_terms =
        |(draw, add): ModelKeys, terms| (ForwardKey { terms, ..draw }, add.map(|add| ForwardKey { terms, ..add }));
    // A split subject's forward draw keeps its specular (HDRP's outColor); the SSS lighting draw
    // takes the rest.
    let subject_terms = if split { terms & (DIRECT_SPECULAR | INDIRECT_SPECULAR) } else { terms };
    let subject = model_keys(cell, plan, prepared, (cell.model, textured, true, cell.settings.surface.kind));
    let fixed_transparent = plan.transparent_order.iter().any(|&i| prepared.layout.meshes[i].role == Role::Fixed);
    let keys = FrameKeys {
        subject: with_terms(subject, subject_terms),
        fixed: with_terms(
            model_keys(cell, plan, prepared, (fixed_model, fixed_textured, false, SurfaceType::Opaque)),
            terms,
        ),
        fixed_transparent: fixed_transparent.then(|| {
            let surface = SurfaceType::Transparent;
            with_terms(model_keys(cell, plan, prepared, (fixed_model, fixed_textured, false, surface)), terms)
        }),
        subject_faces: faces_of(&prepared.layout, |m| m.role == Role::Subject),
        fixed_faces: faces_of(&prepared.layout, |m| m.role == Role::Fixed && !m.transparent),
        fixed_transparent_faces: faces_of(&prepared.layout, |m| m.role == Role::Fixed && m.transparent),
        prepass_faces: faces_of(&prepared.layout, |_| true),
        prepass_textured: textured || fixed_textured,
        subsurface: split.then_some(ForwardKey {
            terms: terms & !(DIRECT_SPECULAR | INDIRECT_SPECULAR),
            subsurface: true,
            ..subject.0
        }),
    };
    let subsurface = keys.subsurface.map(|key| (cell.model, (key, None), &keys.subject_faces));
    let glass = keys.fixed_transparent.map(|keys_| (fixed_model, keys_, &keys.fixed_transparent_faces));
    for (model, (draw, add), faces) in
        [(cell.model, keys.subject, &keys.subject_faces), (fixed_model, keys.fixed, &keys.fixed_faces)]
            .into_iter()
            .chain(subsurface)
            .chain(glass)
    {
        for key in std::iter::once(draw).chain(add) {
            for &face in faces {
                pipelines.forward_pipeline(gpu, cell.pipeline, model, ForwardKey { face, ..key })?;
            }
        }
    }
    if plan.has(Pass::GBuffer) {
        let gbuffer = [
            (cell.model, plan.gbuffer.subject, textured, &keys.subject_faces),
            (fixed_model, plan.gbuffer.fixed, fixed_textured, &keys.fixed_faces),
        ];
        for (model, into_gbuffer, maps, faces) in gbuffer {
            for &face in faces.iter().filter(|_| into_gbuffer) {
                pipelines.gbuffer_pipeline(gpu, cell.pipeline, model, maps, face)?;
            }
        }
        for (model, role, legacy) in lighting_draws((cell.model, fixed_model), plan.gbuffer) {
            pipelines.lighting_pipeline(gpu, cell.pipeline, model, (role, legacy, plan.light_paths()))?;
        }
    }
    if prepared.plan.background {
        pipelines.background_pipeline(gpu, plan.multisampling.samples)?;
    }
    if plan.has(Pass::DepthPrepass) {
        for &face in &keys.prepass_faces {
            pipelines.depth_normal_pipeline(gpu, cell.pipeline, fixed_model, keys.prepass_textured, face)?;
        }
    }
    Ok(keys)
}
