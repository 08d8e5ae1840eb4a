//! The deferred path: a G-buffer pass (base colour and occlusion 8-bit sRGB, metallic and
//! smoothness 8-bit, the normal in the pipeline's format, the ambient/environment term in half
//! float as Unity's RT3, the role, the baked shadow mask as RT4, depth) of the objects whose shader has a G-buffer pass, then
//! one screen-space lighting pass that evaluates every light per pixel from it: one full-screen
//! draw over every G-buffer pixel, or one per material type where the subject's deferred model
//! differs from the fixed objects' (URP's StencilDeferred Lit and SimpleLit passes). Every other
//! object is drawn forward afterwards (built-in: ForwardBase + ForwardAdd), as the engines draw
//! shaders without a deferred pass.
//! The G-buffer and the light tiles are the renderer's (render::gbuffer).

use super::forward::{draw_objects, ForwardPipelines};
use super::FrameDraw;
use crate::declarations::scene::Role;
use crate::gpu::timing::PassTimer;
use crate::plan::cell::CellParams;
use crate::plan::Pass;
use crate::render::gbuffer::{tile_grid, LightTiles};
use crate::render::pipeline_cache::PipelineCache;
use crate::render::prepared::PreparedScene;
use crate::render::targets::Targets;
use crate::render::uniforms::{ROLE_FIXED, ROLE_SUBJECT};
use crate::shading::ShaderModel;

/// One deferred frame: G-buffer, lighting per role, then what the G-buffer cannot carry drawn
/// forward, and the background. The frame's timestamps bracket all three passes.
#[allow(clippy::too_many_arguments)]
pub(in crate::render) fn encode_deferred(
    encoder: &mut wgpu::CommandEncoder,
    prepared: &PreparedScene,
    draw: FrameDraw,
    cell: &CellParams,
    fixed_model: &ShaderModel,
    tile_group: Option<&wgpu::BindGroup>,
    timed: &[Option<(&PassTimer, u32)>],
    (t, pipelines, tiles): (&Targets, &PipelineCache, &LightTiles),
    (forward_only, forward_add): (&ForwardPipelines, &[Vec<usize>]),
) {
    let p = cell.pipeline;
    let FrameDraw { group: frame_group, drawn, screen } = draw;
    // With the tiled loop, its compute pass sits between the G-buffer and the lighting.
    let (light_at, last_at) = if tile_group.is_some() { (2, 3) } else { (1, 2) };
    let gb = &t.gbuffer;
    let color = |view, clear| {
        Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: clear, store: wgpu::StoreOp::Store },
        })
    };
    let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
    let subject = |i: usize| prepared.layout.meshes[i].role == Role::Subject;
    let model_of = |i: usize| if subject(i) { cell.model } else { fixed_model };
    // Into the G-buffer: what the model's G-buffer pass can draw, less a transparent subject.
    let deferred = |i: usize| if subject(i) { cell.subject_deferrable() } else { fixed_model.deferrable() };
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(Pass::GBuffer.name()),
            color_attachments: &[
                color(&gb.albedo, clear),
                color(&gb.material, clear),
                color(gb.normal(p), clear),
                color(&gb.lighting, clear),
                color(&t.role_view, clear),
                // Unlit by any shadow-mask light until an object's bake says otherwise
                color(&gb.shadow_mask, wgpu::LoadOp::Clear(wgpu::Color::WHITE)),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: timed[0].map(|(t, pair)| t.writes(pair, true, true)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(2, screen, &[]);
        for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| drawn[*i] && deferred(*i)) {
            let textured = if subject(i) { cell.settings.material_maps.is_some() } else { prepared.fixed_maps.any() };
            let face = prepared.layout.meshes[i].render_face;
            pass.set_pipeline(&pipelines.gbuffer[&(p, model_of(i).name.to_string(), textured, face, pipelines.terms)]);
            pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
    }
    if let (Some(group), Some(pipeline)) = (tile_group, &tiles.pipeline) {
        encoder.clear_buffer(&tiles.masks, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(Pass::LightTiles.name()),
            timestamp_writes: timed[1].map(|(t, pair)| t.compute_writes(pair)),
        });
        let (tx, ty, _) = tile_grid(t.width, t.height, 0);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(3, group, &[]);
        pass.dispatch_workgroups(tx, ty, 1);
    }
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(Pass::DeferredLighting.name()),
            color_attachments: &[color(&t.color_view, wgpu::LoadOp::Clear(wgpu::Color::BLACK))],
            depth_stencil_attachment: None,
            timestamp_writes: timed[light_at].map(|(t, pair)| t.writes(pair, true, true)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(1, &prepared.object_bind_group, &[0]);
        pass.set_bind_group(2, gb.read(p), &[]);
        pass.set_bind_group(3, &tiles.read, &[]);
        for (model, role) in lighting_draws(cell.model, cell.subject_deferrable(), fixed_model) {
            if let Some(pipeline) = pipelines.lighting.get(&(p, model.name.to_string(), role as u32, pipelines.terms)) {
                pass.set_pipeline(pipeline);
                pass.draw(0..3, 0..1);
            }
        }
    }
    // The depth stays for a Transparent queue after this pass.
    let depth_store =
        if cell.settings.surface.kind.is_transparent() { wgpu::StoreOp::Store } else { wgpu::StoreOp::Discard };
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(Pass::ForwardOnly.name()),
        color_attachments: &[color(&t.color_view, wgpu::LoadOp::Load), color(&t.role_view, wgpu::LoadOp::Load)],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &t.depth_view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: depth_store }),
            stencil_ops: None,
        }),
        timestamp_writes: timed[last_at].map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, frame_group, &[]);
    pass.set_bind_group(1, &prepared.object_bind_group, &[0]);
    pass.set_bind_group(2, screen, &[]);
    // The opaque forward-only objects and the sky; then the Transparent queue (the subject alone)
    // in its own pass, timed apart.
    let transparent = |i: usize| subject(i) && cell.settings.surface.kind.is_transparent();
    draw_objects(&mut pass, prepared, forward_only, forward_add, |i| drawn[i] && !deferred(i) && !transparent(i));
    if let (true, Some(bg)) = (prepared.plan.background, pipelines.background.get(&(1, pipelines.terms))) {
        pass.set_pipeline(bg);
        pass.draw(0..3, 0..1);
    }
    drop(pass);
    if !cell.settings.surface.kind.is_transparent() {
        return;
    }
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(Pass::Transparent.name()),
        color_attachments: &[color(&t.color_view, wgpu::LoadOp::Load), color(&t.role_view, wgpu::LoadOp::Load)],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &t.depth_view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Discard }),
            stencil_ops: None,
        }),
        timestamp_writes: timed.get(last_at + 1).copied().flatten().map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, frame_group, &[]);
    pass.set_bind_group(1, &prepared.object_bind_group, &[0]);
    pass.set_bind_group(2, screen, &[]);
    draw_objects(&mut pass, prepared, forward_only, forward_add, |i| drawn[i] && transparent(i));
}

/// The lighting pass's full-screen draws: (model, role shaded; 0 every G-buffer pixel). One draw
/// when one deferred model covers the frame's G-buffer (the subject's is the fixed objects', or
/// the subject is drawn forward); one per model where they differ.
pub(in crate::render) fn lighting_draws<'m>(
    subject: &'m ShaderModel,
    subject_deferrable: bool,
    fixed: &'m ShaderModel,
) -> Vec<(&'m ShaderModel, u8)> {
    match (subject_deferrable, fixed.deferrable()) {
        (true, true) if subject.name == fixed.name => vec![(fixed, ROLE_ANY)],
        (true, true) => vec![(subject, ROLE_SUBJECT), (fixed, ROLE_FIXED)],
        (true, false) => vec![(subject, ROLE_SUBJECT)],
        (false, true) => vec![(fixed, ROLE_FIXED)],
        (false, false) => Vec::new(),
    }
}

/// `DEFERRED_ROLE` for a lighting draw over every G-buffer pixel.
pub(in crate::render) const ROLE_ANY: u8 = 0;
