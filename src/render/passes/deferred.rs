//! The deferred path: a G-buffer pass (base colour and occlusion 8-bit sRGB, metallic and
//! smoothness 8-bit, the normal in the pipeline's format, the ambient/environment term in half
//! float as Unity's RT3, the role, depth), then a screen-space lighting pass that evaluates every
//! light per pixel from it, one draw per role so the subject's model and the fixed objects' model
//! each shade their own pixels. Models the G-buffer cannot carry (per-vertex, ForwardBase-only) draw
//! forward afterwards, as Unity draws forward-only shaders in its deferred path.
//! The G-buffer and the light tiles are the renderer's (render::gbuffer).

use super::FrameDraw;
use crate::gpu::timing::PassTimer;
use crate::plan::cell::CellParams;
use crate::render::gbuffer::{tile_grid, LightTiles};
use crate::render::pipeline_cache::{ForwardKey, PipelineCache};
use crate::render::prepared::PreparedScene;
use crate::render::targets::Targets;
use crate::render::uniforms::{ROLE_FIXED, ROLE_SUBJECT};
use crate::shading::ShaderModel;
use crate::spec::scene::Role;

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
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &[
                color(&gb.albedo, clear),
                color(&gb.material, clear),
                color(gb.normal(p), clear),
                color(&gb.lighting, clear),
                color(&t.role_view, clear),
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
        for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| drawn[*i] && model_of(*i).deferrable()) {
            let textured = subject(i) && cell.settings.material_maps.is_some();
            pass.set_pipeline(&pipelines.gbuffer[&(p, model_of(i).name.to_string(), textured)]);
            pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
    }
    if let (Some(group), Some(pipeline)) = (tile_group, &tiles.pipeline) {
        encoder.clear_buffer(&tiles.masks, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("light tiles"),
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
            label: Some("deferred lighting"),
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
        for (model, role) in [(cell.model, ROLE_SUBJECT), (fixed_model, ROLE_FIXED)] {
            if let Some(pipeline) = pipelines.lighting.get(&(p, model.name.to_string(), role as u32)) {
                pass.set_pipeline(pipeline);
                pass.draw(0..3, 0..1);
            }
        }
    }
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("forward-only and background"),
        color_attachments: &[color(&t.color_view, wgpu::LoadOp::Load), color(&t.role_view, wgpu::LoadOp::Load)],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &t.depth_view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Discard }),
            stencil_ops: None,
        }),
        timestamp_writes: timed[last_at].map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, frame_group, &[]);
    pass.set_bind_group(1, &prepared.object_bind_group, &[0]);
    pass.set_bind_group(2, screen, &[]);
    for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| drawn[*i] && !model_of(*i).deferrable()) {
        let textured = subject(i) && cell.settings.material_maps.is_some();
        pass.set_pipeline(&pipelines.forward[&(p, model_of(i).name.to_string(), ForwardKey::plain(textured))]);
        pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
        pass.set_vertex_buffer(0, o.vertices.slice(..));
        pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..o.index_count, 0, 0..1);
    }
    if let (true, Some(bg)) = (prepared.plan.background, pipelines.background.get(&1)) {
        pass.set_pipeline(bg);
        pass.draw(0..3, 0..1);
    }
}
