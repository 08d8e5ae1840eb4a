//! The deferred path: a G-buffer pass (base colour and occlusion 8-bit sRGB, metallic and
//! smoothness 8-bit, the normal in the pipeline's format, the ambient/environment term in half
//! float as Unity's RT3, the role, the baked shadow mask as RT4, depth) of the objects whose shader has a G-buffer pass, then
//! one screen-space lighting pass that evaluates every light per pixel from it: one full-screen
//! draw over every G-buffer pixel, or one per material type where the subject's deferred model
//! differs from the fixed objects' (URP's StencilDeferred Lit and SimpleLit passes). Every other
//! object is drawn forward afterwards (built-in: ForwardBase + ForwardAdd), as the engines draw
//! shaders without a deferred pass.
//! One function per pass; the G-buffer's textures are render::gbuffer's, HDRP's light list
//! passes::light_tiles'.

use super::forward::{draw_meshes, draw_objects, ForwardPipelines};
use super::FrameDraw;
use crate::declarations::scene::Role;
use crate::gpu::timing::PassTimer;
use crate::plan::cell::CellParams;
use crate::plan::Pass;
use crate::render::pipeline_cache::PipelineCache;
use crate::render::prepared::PreparedScene;
use crate::render::targets::Targets;
use crate::render::uniforms::{ROLE_FIXED, ROLE_SUBJECT};
use crate::shading::registry::LegacyLighting;
use crate::shading::ShaderModel;

/// What a deferred frame's passes draw: the frame's meshes and groups, the cell and its fixed
/// objects' model, the targets and pipelines, and the forward draws of what the G-buffer cannot
/// carry (`forward_add`: each mesh's ForwardAdd lights).
pub(in crate::render) struct DeferredFrame<'a> {
    pub(in crate::render) prepared: &'a PreparedScene,
    pub(in crate::render) draw: FrameDraw<'a>,
    pub(in crate::render) cell: &'a CellParams<'a>,
    pub(in crate::render) fixed_model: &'a ShaderModel,
    pub(in crate::render) targets: &'a Targets,
    pub(in crate::render) pipelines: &'a PipelineCache,
    pub(in crate::render) forward: &'a ForwardPipelines<'a>,
    pub(in crate::render) forward_add: &'a [Vec<usize>],
    /// Which models go into the G-buffer (the plan's).
    pub(in crate::render) gbuffer: crate::plan::draws::GBufferModels,
    /// The lighting pipelines' optional light-loop paths (`CellPlan::light_paths`).
    pub(in crate::render) lights: crate::plan::lights::LightPaths,
}

impl DeferredFrame<'_> {
    fn subject(&self, i: usize) -> bool {
        self.prepared.layout.meshes[i].role == Role::Subject
    }

    /// Whether mesh `i` goes into the G-buffer: what its model's G-buffer pass can draw, less the
    /// Transparent queue.
    fn deferred(&self, i: usize) -> bool {
        let model = if self.subject(i) { self.gbuffer.subject } else { self.gbuffer.fixed };
        model && !self.transparent(i)
    }

    fn transparent(&self, i: usize) -> bool {
        self.draw.transparent[i]
    }
}

fn attachment(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations { load, store: wgpu::StoreOp::Store },
    })
}

/// The G-buffer pass: every drawn object whose model has a G-buffer pass.
pub(in crate::render) fn encode_gbuffer(
    f: &DeferredFrame,
    encoder: &mut wgpu::CommandEncoder,
    timed: Option<(&PassTimer, u32)>,
) {
    let (p, t) = (f.cell.pipeline, f.targets);
    let gb = &t.gbuffer;
    let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(Pass::GBuffer.name()),
        color_attachments: &[
            attachment(&gb.albedo, clear),
            attachment(&gb.material, clear),
            attachment(gb.normal(p), clear),
            attachment(&gb.lighting, clear),
            attachment(&t.role_view, clear),
            // Unlit by any shadow-mask light until an object's bake says otherwise
            attachment(&gb.shadow_mask, wgpu::LoadOp::Clear(wgpu::Color::WHITE)),
        ],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &t.depth_view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: timed.map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, f.draw.group, &[]);
    pass.set_bind_group(2, f.draw.screen, &[]);
    let prepared = f.prepared;
    for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| f.draw.drawn[*i] && f.deferred(*i)) {
        let subject = f.subject(i);
        let model = if subject { f.cell.model } else { f.fixed_model };
        let textured = if subject { f.cell.settings.material_maps.is_some() } else { prepared.fixed_maps.any() };
        let face = prepared.layout.meshes[i].render_face;
        let key = (p, model.name.to_string(), textured, face, f.pipelines.terms);
        pass.set_bind_group(2, f.draw.screen_of(prepared, i), &[]);
        pass.set_pipeline(&f.pipelines.gbuffer[&key]);
        pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
        pass.set_vertex_buffer(0, o.vertices.slice(..));
        pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..o.index_count, 0, 0..1);
    }
}

/// The lighting pass: a full-screen draw per material type over the G-buffer (`tiles`: the light
/// list's masks, read where HDRP's tiled loop filled them).
pub(in crate::render) fn encode_lighting(
    f: &DeferredFrame,
    tiles: &wgpu::BindGroup,
    encoder: &mut wgpu::CommandEncoder,
    timed: Option<(&PassTimer, u32)>,
) {
    let (p, t) = (f.cell.pipeline, f.targets);
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(Pass::DeferredLighting.name()),
        color_attachments: &[attachment(&t.color_view, wgpu::LoadOp::Clear(wgpu::Color::BLACK))],
        depth_stencil_attachment: None,
        timestamp_writes: timed.map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, f.draw.group, &[]);
    pass.set_bind_group(1, &f.prepared.object_bind_group, &[0]);
    pass.set_bind_group(2, t.gbuffer.read(p), &[]);
    pass.set_bind_group(3, tiles, &[]);
    for (model, role, legacy) in lighting_draws((f.cell.model, f.fixed_model), f.gbuffer) {
        let legacy = legacy.map_or(0, LegacyLighting::shader_value);
        let key = (p, model.name.to_string(), role as u32, f.pipelines.terms, legacy, f.lights);
        if let Some(pipeline) = f.pipelines.lighting.get(&key) {
            pass.set_pipeline(pipeline);
            pass.draw(0..3, 0..1);
        }
    }
}

/// A forward pass over the lit frame, on its depth (kept where `keep_depth`: a later pass reads it).
fn forward_over<'e>(
    f: &DeferredFrame,
    encoder: &'e mut wgpu::CommandEncoder,
    (label, keep_depth): (Pass, bool),
    timed: Option<(&PassTimer, u32)>,
) -> wgpu::RenderPass<'e> {
    let t = f.targets;
    let store = if keep_depth { wgpu::StoreOp::Store } else { wgpu::StoreOp::Discard };
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label.name()),
        color_attachments: &[
            attachment(&t.color_view, wgpu::LoadOp::Load),
            attachment(&t.role_view, wgpu::LoadOp::Load),
        ],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &t.depth_view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store }),
            stencil_ops: None,
        }),
        timestamp_writes: timed.map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, f.draw.group, &[]);
    pass.set_bind_group(1, &f.prepared.object_bind_group, &[0]);
    pass.set_bind_group(2, f.draw.screen, &[]);
    pass
}

/// The forward-only pass: the opaque objects the G-buffer cannot carry, then the sky.
/// `keep_depth`: a Transparent queue follows.
pub(in crate::render) fn encode_forward_only(
    f: &DeferredFrame,
    keep_depth: bool,
    encoder: &mut wgpu::CommandEncoder,
    timed: Option<(&PassTimer, u32)>,
) {
    let mut pass = forward_over(f, encoder, (Pass::ForwardOnly, keep_depth), timed);
    let (prepared, drawn) = (f.prepared, f.draw.drawn);
    draw_objects(&mut pass, (prepared, &f.draw), f.forward, f.forward_add, |i| {
        drawn[i] && !f.deferred(i) && !f.transparent(i)
    });
    if let (true, Some(bg)) = (prepared.plan.background, f.pipelines.background.get(&(1, f.pipelines.terms))) {
        pass.set_pipeline(bg);
        pass.draw(0..3, 0..1);
    }
}

/// The Transparent queue, after everything else, back to front (the plan's order).
pub(in crate::render) fn encode_transparent(
    f: &DeferredFrame,
    encoder: &mut wgpu::CommandEncoder,
    timed: Option<(&PassTimer, u32)>,
) {
    let mut pass = forward_over(f, encoder, (Pass::Transparent, false), timed);
    let queue = f.draw.transparent_order.iter().copied();
    draw_meshes(&mut pass, (f.prepared, &f.draw), f.forward, f.forward_add, queue);
}

/// The lighting pass's full-screen draws: (model, role shaded (0 every G-buffer pixel), the
/// subject's legacy data lit by it). One draw when one deferred model covers the frame's G-buffer
/// (the subject's is the fixed objects', or the subject is drawn forward); one per model where
/// they differ. A built-in legacy subject (`GBufferModels::subject_legacy`) is lit by the fixed
/// objects' Standard, as Internal-DeferredShading lights every G-buffer pixel with BRDF1.
pub(in crate::render) fn lighting_draws<'m>(
    (subject, fixed): (&'m ShaderModel, &'m ShaderModel),
    gbuffer: crate::plan::draws::GBufferModels,
) -> Vec<(&'m ShaderModel, u8, Option<LegacyLighting>)> {
    match (gbuffer.subject, gbuffer.fixed, gbuffer.subject_legacy) {
        (true, true, Some(legacy)) => vec![(fixed, ROLE_SUBJECT, Some(legacy)), (fixed, ROLE_FIXED, None)],
        (true, true, None) if subject.name == fixed.name => vec![(fixed, ROLE_ANY, None)],
        (true, true, None) => vec![(subject, ROLE_SUBJECT, None), (fixed, ROLE_FIXED, None)],
        (true, false, _) => vec![(subject, ROLE_SUBJECT, None)],
        (false, true, _) => vec![(fixed, ROLE_FIXED, None)],
        (false, false, _) => Vec::new(),
    }
}

/// `DEFERRED_ROLE` for a lighting draw over every G-buffer pixel.
pub(in crate::render) const ROLE_ANY: u8 = 0;
