//! The shadow pass: every casting mesh's depth into each shadow layer the cell's plan uses
//! (`plan::shadows` decides the layers, their matrices and resolutions). The forward pass samples
//! them with a comparison sampler: one bilinear tap (hard) or 3×3 bilinear taps (soft), the
//! receiver offset along its normal and towards the light by the light's biases in shadow-map
//! texels. APPROXIMATION, stated: Unity's soft-shadow tent filters are stood in for by the 3×3 PCF.

use crate::geometry::Vertex;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
use crate::plan::cell::LightShadow;
use crate::render::formats::SHADOW_FORMAT;
use crate::render::prepared::PreparedScene;

/// The shader's GpuLight.shadow: (first layer or −1, layer count, strength, soft).
pub fn shadow_slot(shadow: &LightShadow) -> ([f32; 4], [f32; 4]) {
    match (shadow.first_layer, shadow.style) {
        (Some(first), Some(s)) => (
            [first as f32, shadow.layers as f32, s.strength as f32, if s.soft { 1.0 } else { 0.0 }],
            [s.bias as f32, s.normal_bias as f32, 0.0, 0.0],
        ),
        _ => ([-1.0, 0.0, 0.0, 0.0], [0.0; 4]),
    }
}

/// Depth of every casting object into every shadow layer.
pub(in crate::render) fn encode_shadow_passes(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::RenderPipeline,
    prepared: &PreparedScene,
    layers: &[(usize, u32)],
    casting: &[bool],
    timed: Option<(&PassTimer, u32)>,
) {
    let sh = &prepared.shadows;
    let last = layers.len().saturating_sub(1);
    for (n, &(layer, resolution)) in layers.iter().enumerate() {
        let view = &sh.layer_views[layer];
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            // One timed span over every layer: begin on the first, end on the last.
            timestamp_writes: timed.filter(|_| n == 0 || n == last).map(|(t, pair)| t.writes(pair, n == 0, n == last)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        // The light's map is the top-left resolution² of the layer (plan::shadows).
        pass.set_viewport(0.0, 0.0, resolution as f32, resolution as f32, 0.0, 1.0);
        pass.set_bind_group(0, &sh.layer_bind_group, &[(layer as u64 * sh.layer_stride) as u32]);
        let casts = |i: usize| casting[i] && prepared.layout.meshes[i].cast_shadows;
        for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| casts(*i)) {
            pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
    }
}

/// The depth-only pipeline of the shadow pass; slope-scaled depth bias against acne on top of the
/// lights' own biases.
pub(in crate::render) fn shadow_pipeline(
    gpu: &GpuContext,
    layer_layout: &wgpu::BindGroupLayout,
    object_layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("shadow"),
        source: wgpu::ShaderSource::Wgsl(gpu.constants.wgsl(include_str!("../../../shaders/pass/shadow.wgsl"))),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("shadow"),
        bind_group_layouts: &[Some(layer_layout), Some(object_layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("shadow"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_shadow"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            })],
        },
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: wgpu::DepthBiasState { constant: 2, slope_scale: 1.5, clamp: 0.0 },
        }),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}
