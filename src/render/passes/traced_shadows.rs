//! Ray-traced visibility for the approximation study's `visibility` frames
//! (shaders/pass/traced_shadows.wgsl): a compute pass after the depth prepass casts a shadow ray
//! per pixel and light through the cell's BVH into a mask the forward pass reads in place of the
//! shadow maps, as HDRP's ray-traced shadows do. Traced in a compute pass rather than in the
//! fragment stage: on lavapipe a fragment-stage BVH walk ran about 150× slower per ray than the
//! same walk in compute (its private traversal stack is lowered lane by lane), and the pass is
//! also how the engines schedule it.

use crate::error::Error;
use crate::gpu::GpuContext;

/// The tracing pipeline and its group's layout (group 1: depth, normals, the mask).
pub struct TracedShadowsPipeline {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl TracedShadowsPipeline {
    pub fn new(
        gpu: &GpuContext,
        frame_layout: &wgpu::BindGroupLayout,
        ray_layout: &wgpu::BindGroupLayout,
        pipeline_id: u32,
    ) -> Result<TracedShadowsPipeline, Error> {
        use crate::render::resources::compute_entry::{read_write_storage, texture};
        let device = &gpu.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(crate::plan::Pass::TracedShadows.name()),
            entries: &[
                texture(0, wgpu::TextureSampleType::Depth, wgpu::TextureViewDimension::D2),
                texture(1, wgpu::TextureSampleType::Float { filterable: false }, wgpu::TextureViewDimension::D2),
                read_write_storage(2),
            ],
        });
        let module = gpu
            .shader_module(crate::plan::Pass::TracedShadows.name(), &crate::shading::wgsl::compose_traced_shadows())?;
        let constants = [("PIPELINE", pipeline_id as f64)];
        let layouts = [frame_layout, &layout, ray_layout];
        let pipeline = crate::render::truth::ray_compute_pipeline(
            device,
            crate::plan::Pass::TracedShadows.name(),
            &module,
            layouts,
            "cs_traced_shadows",
            &constants,
        );
        gpu.check_errors("creating the traced-shadow pipeline")?;
        Ok(TracedShadowsPipeline { pipeline, layout })
    }
}

/// A frame size's mask (its width, then a u32 per pixel) and the prepass normals it traces from
/// when the frame has no SSAO prepass of its own.
pub struct TracedShadowMask {
    pub mask: wgpu::Buffer,
    pub normal: wgpu::TextureView,
    size: (u32, u32),
}

impl TracedShadowMask {
    pub fn new(device: &wgpu::Device, (width, height): (u32, u32)) -> TracedShadowMask {
        let mask = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("traced shadow mask"),
            size: (4 + 4 * width as u64 * height as u64).next_multiple_of(16),
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let normal = crate::render::resources::texture_2d(
            device,
            "traced shadows normals",
            (width, height),
            crate::render::formats::NORMAL_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .create_view(&Default::default());
        TracedShadowMask { mask, normal, size: (width, height) }
    }

    /// Trace the mask from the prepass's depth and normals.
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        device: &wgpu::Device,
        pipeline: &TracedShadowsPipeline,
        encoder: &mut wgpu::CommandEncoder,
        frame_group: &wgpu::BindGroup,
        rays_group: &wgpu::BindGroup,
        (depth, normal): (&wgpu::TextureView, &wgpu::TextureView),
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(crate::plan::Pass::TracedShadows.name()),
            layout: &pipeline.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(depth) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(normal) },
                wgpu::BindGroupEntry { binding: 2, resource: self.mask.as_entire_binding() },
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(crate::plan::Pass::TracedShadows.name()),
            timestamp_writes,
        });
        pass.set_pipeline(&pipeline.pipeline);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.set_bind_group(3, rays_group, &[]);
        pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
    }
}

/// The study's traced visibility as a frame runs it: a pipeline per engine (its light
/// attenuation), made for the first cell that traces, and the mask on the frame's size.
#[derive(Default)]
pub(in crate::render) struct TracedShadowsPass {
    pipelines: std::collections::HashMap<crate::pipelines::Pipeline, TracedShadowsPipeline>,
    /// (the targets' generation, the mask of their size)
    mask: Option<(u64, TracedShadowMask)>,
}

impl TracedShadowsPass {
    /// Ready the pass for a `pipeline` frame on `targets`.
    pub(in crate::render) fn prepare(
        &mut self,
        gpu: &GpuContext,
        (frame_layout, ray_layout): (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
        pipeline: crate::pipelines::Pipeline,
        targets: &crate::render::targets::Targets,
    ) -> Result<(), Error> {
        if let std::collections::hash_map::Entry::Vacant(slot) = self.pipelines.entry(pipeline) {
            slot.insert(TracedShadowsPipeline::new(gpu, frame_layout, ray_layout, pipeline.shader_id())?);
        }
        if self.mask.as_ref().is_none_or(|(generation, _)| *generation != targets.generation) {
            let mask = TracedShadowMask::new(&gpu.device, (targets.width, targets.height));
            self.mask = Some((targets.generation, mask));
        }
        Ok(())
    }

    /// The prepared mask and the `pipeline`'s tracer.
    pub(in crate::render) fn ready(
        &self,
        pipeline: crate::pipelines::Pipeline,
    ) -> Option<(&TracedShadowMask, &TracedShadowsPipeline)> {
        Some((&self.mask.as_ref()?.1, self.pipelines.get(&pipeline)?))
    }
}
