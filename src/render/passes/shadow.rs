//! The shadow pass: every casting mesh's depth into each shadow layer the cell's plan uses
//! (`plan::shadows` decides the layers, their matrices and resolutions). The forward pass samples
//! them with a comparison sampler: one bilinear tap (hard) or 3×3 bilinear taps (soft), or HDRP's
//! n×n tent PCF texel by texel or its PCSS (shaders/pass/shadow_filters.wgsl), the receiver offset along its
//! normal and towards the light by the light's biases in shadow-map texels. APPROXIMATION,
//! stated: built-in's and URP's soft-shadow filters are stood in for by the 3×3 PCF.

use crate::geometry::Vertex;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
use crate::plan::cell::LightShadow;
use crate::render::formats::SHADOW_FORMAT;
use crate::render::prepared::PreparedScene;

/// The shader's GpuLight.shadow: (first layer or −1, layer count, strength, soft), and its
/// shadow_bias: (bias, normal bias, —, HDRP's filter: the tent's width n, or −1 for PCSS; z is the
/// probe occlusion's).
pub fn shadow_slot(shadow: &LightShadow) -> ([f32; 4], [f32; 4]) {
    match (shadow.first_layer, shadow.style) {
        (Some(first), Some(s)) => (
            [first as f32, shadow.layers as f32, s.strength as f32, if s.soft { 1.0 } else { 0.0 }],
            [s.bias as f32, s.normal_bias as f32, 0.0, if s.pcss { -1.0 } else { s.tent as f32 }],
        ),
        _ => ([-1.0, 0.0, 0.0, 0.0], [0.0; 4]),
    }
}

/// Depth of every casting object into every shadow layer (the dynamic ones alone into the
/// `dynamic_only` layers, whose light's static shadows are baked); the subject's through
/// `alpha_caster` where its alpha clips or dithers what it casts (its pipeline and material group).
pub(in crate::render) fn encode_shadow_passes(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::RenderPipeline,
    prepared: &PreparedScene,
    (layers, casting, dynamic_only): (&[(usize, u32)], &[bool], &[usize]),
    alpha_caster: Option<(&wgpu::RenderPipeline, &wgpu::BindGroup)>,
    timed: Option<(&PassTimer, u32)>,
) {
    let sh = &prepared.shadows;
    let last = layers.len().saturating_sub(1);
    for (n, &(layer, resolution)) in layers.iter().enumerate() {
        let view = &sh.layer_views[layer];
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(crate::plan::Pass::Shadow.name()),
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
        let static_baked = dynamic_only.contains(&layer);
        let casts = |i: usize| {
            let m = &prepared.layout.meshes[i];
            casting[i] && !(static_baked && m.role == crate::declarations::scene::Role::Fixed)
        };
        for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| casts(*i)) {
            let subject = prepared.layout.meshes[i].role == crate::declarations::scene::Role::Subject;
            match alpha_caster.filter(|_| subject) {
                Some((clipped, group)) => {
                    pass.set_pipeline(clipped);
                    pass.set_bind_group(2, group, &[]);
                }
                None => pass.set_pipeline(pipeline),
            }
            pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
    }
}

/// The shadow pass's pipeline for a subject whose alpha clips or dithers what it casts (shadow.wgsl
/// `fs_shadow_alpha`), its material group's layout, and the group's constant buffer (base alpha,
/// cutoff, mode, reflectivity).
pub(in crate::render) struct AlphaCasterShadow {
    pub(in crate::render) pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    material: wgpu::Buffer,
}

impl AlphaCasterShadow {
    pub(in crate::render) fn new(
        gpu: &GpuContext,
        layer_layout: &wgpu::BindGroupLayout,
        object_layout: &wgpu::BindGroupLayout,
    ) -> AlphaCasterShadow {
        let device = &gpu.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("alpha caster shadow material"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: gpu.constants.binding(),
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(16),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let material = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("alpha caster shadow material"),
            size: 16,
            usage: gpu.constants.usage() | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let pipeline = build(gpu, &[Some(layer_layout), Some(object_layout), Some(&layout)], true);
        AlphaCasterShadow { pipeline, layout, material }
    }

    /// The material group of a cell's subject: its base alpha, cutoff, mode (0 clipped, 1
    /// dithered) and reflectivity (shadow.wgsl `AlphaCaster`), its albedo map.
    pub(in crate::render) fn group(
        &self,
        gpu: &GpuContext,
        constants: [f32; 4],
        albedo: &wgpu::TextureView,
        sampler: &wgpu::Sampler,
    ) -> wgpu::BindGroup {
        gpu.queue.write_buffer(&self.material, 0, bytemuck::cast_slice(&constants));
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("alpha caster shadow material"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.material.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(albedo) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(sampler) },
            ],
        })
    }
}

/// The depth-only pipeline of the shadow pass; slope-scaled depth bias against acne on top of the
/// lights' own biases.
pub(in crate::render) fn shadow_pipeline(
    gpu: &GpuContext,
    layer_layout: &wgpu::BindGroupLayout,
    object_layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    build(gpu, &[Some(layer_layout), Some(object_layout)], false)
}

/// The shadow pipeline on `layouts`: depth only, or with the uv and the fragment that clips or
/// dithers by alpha (`alpha_caster`).
fn build(gpu: &GpuContext, layouts: &[Option<&wgpu::BindGroupLayout>], alpha_caster: bool) -> wgpu::RenderPipeline {
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(crate::plan::Pass::Shadow.name()),
        source: wgpu::ShaderSource::Wgsl(gpu.constants.wgsl(include_str!("../../../shaders/pass/shadow.wgsl"))),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(crate::plan::Pass::Shadow.name()),
        bind_group_layouts: layouts,
        immediate_size: 0,
    });
    let attributes: &[wgpu::VertexAttribute] = if alpha_caster {
        &wgpu::vertex_attr_array![0 => Float32x3, 2 => Float32x2]
    } else {
        &wgpu::vertex_attr_array![0 => Float32x3]
    };
    let mut uv_layout = attributes.to_vec();
    if alpha_caster {
        // The uv follows the position and the normal in a Vertex.
        uv_layout[1].offset = std::mem::offset_of!(Vertex, uv) as u64;
    }
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(if alpha_caster { "shadow (alpha caster)" } else { crate::plan::Pass::Shadow.name() }),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some(if alpha_caster { "vs_shadow_alpha" } else { "vs_shadow" }),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &uv_layout,
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
        fragment: alpha_caster.then_some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_shadow_alpha"),
            compilation_options: Default::default(),
            targets: &[],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The shadow pass's own state: the layer slot's layout, the depth-only pipeline, and the
/// pipeline of a subject whose alpha clips or dithers what it casts (made for the first such cell).
pub(in crate::render) struct ShadowPass {
    pub(in crate::render) layer_layout: wgpu::BindGroupLayout,
    pub(in crate::render) pipeline: wgpu::RenderPipeline,
    alpha_caster: Option<AlphaCasterShadow>,
}

impl ShadowPass {
    pub(in crate::render) fn new(gpu: &GpuContext, object_layout: &wgpu::BindGroupLayout) -> ShadowPass {
        let layer_layout = crate::render::resources::uniform_slot_layout(
            &gpu.device,
            gpu.constants,
            "shadow layer",
            wgpu::ShaderStages::VERTEX,
            64,
        );
        let pipeline = shadow_pipeline(gpu, &layer_layout, object_layout);
        ShadowPass { layer_layout, pipeline, alpha_caster: None }
    }

    /// The material group of a cell whose subject's alpha (its albedo map's, `albedo`, times its
    /// base `alpha`) clips or dithers what it casts (`plan::shadows::SubjectCaster`) into shadow
    /// maps the frame draws (`casts`); None for every other cell.
    pub(in crate::render) fn alpha_caster_group(
        &mut self,
        gpu: &GpuContext,
        object_layout: &wgpu::BindGroupLayout,
        (caster, alpha, casts): (crate::plan::shadows::SubjectCaster, f64, bool),
        (albedo, sampler): (Option<&wgpu::TextureView>, &wgpu::Sampler),
    ) -> Option<wgpu::BindGroup> {
        use crate::plan::shadows::SubjectCaster;
        let constants = match caster {
            SubjectCaster::AlphaClipped { cutoff } => [alpha as f32, cutoff as f32, 0.0, 0.0],
            SubjectCaster::Dithered { reflectivity } => [alpha as f32, 0.0, 1.0, reflectivity as f32],
            SubjectCaster::Opaque | SubjectCaster::Nothing => return None,
        };
        if !casts {
            return None;
        }
        let albedo = albedo?;
        let caster =
            self.alpha_caster.get_or_insert_with(|| AlphaCasterShadow::new(gpu, &self.layer_layout, object_layout));
        Some(caster.group(gpu, constants, albedo, sampler))
    }

    /// The alpha caster's pipeline with the cell's material `group`, where it has one.
    pub(in crate::render) fn alpha_caster<'a>(
        &'a self,
        group: Option<&'a wgpu::BindGroup>,
    ) -> Option<(&'a wgpu::RenderPipeline, &'a wgpu::BindGroup)> {
        self.alpha_caster.as_ref().map(|c| &c.pipeline).zip(group)
    }
}
