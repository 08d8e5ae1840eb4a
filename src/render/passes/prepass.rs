//! HDRP's depth prepass: every drawn object's depth and shading normal, what SSAO reads; and the
//! screen group the scene passes read the occlusion through.

use super::FrameDraw;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
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

/// The screen group over an SSAO visibility texture.
pub(in crate::render) fn screen_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    visibility: &wgpu::Texture,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("screen"),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 6,
            resource: wgpu::BindingResource::TextureView(&visibility.create_view(&Default::default())),
        }],
    })
}

/// The screen group of a frame without SSAO: a 1×1 visibility of 1.
pub(in crate::render) fn neutral_screen_group(gpu: &GpuContext, layout: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
    let texture = crate::render::texture_2d(
        &gpu.device,
        "no ssao",
        (1, 1),
        wgpu::TextureFormat::Rg32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    gpu.queue.write_texture(
        texture.as_image_copy(),
        bytemuck::cast_slice(&[1.0f32, 0.0]),
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(8), rows_per_image: None },
        wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
    );
    screen_group(&gpu.device, layout, &texture)
}
