//! HDRP's depth prepass: every drawn object's depth and shading normal, what SSAO reads; and the
//! screen group the scene passes read the occlusion through.

use super::FrameDraw;
use crate::gpu::timing::PassTimer;
use crate::render::prepared::PreparedScene;

/// HDRP's depth prepass: every drawn object's depth and shading normal, what SSAO reads.
pub(in crate::render) fn encode_depth_prepass(
    encoder: &mut wgpu::CommandEncoder,
    prepared: &PreparedScene,
    draw: &FrameDraw,
    pipelines: crate::render::pipeline_cache::ByFace,
    (normal, depth): (&wgpu::TextureView, &wgpu::TextureView),
    timed: Option<(&PassTimer, u32)>,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(crate::plan::Pass::DepthPrepass.name()),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: normal,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: timed.map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, draw.group, &[]);
    pass.set_bind_group(2, draw.screen, &[]);
    for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| draw.drawn[*i]) {
        let face = prepared.layout.meshes[i].render_face as usize;
        pass.set_pipeline(pipelines[face].expect("a prepass pipeline for every face drawn"));
        pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
        pass.set_vertex_buffer(0, o.vertices.slice(..));
        pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..o.index_count, 0, 0..1);
    }
}
