//! HDRP's tiled light list (shaders/pass/forward.wgsl `cs_light_tiles`): between the G-buffer
//! and the lighting, a compute pass writes per screen tile a bit mask of the lights that reach
//! it, which the lighting pass reads (HDRP's LightLoop builds its light list per tile the same
//! way). Built-in and URP deferred draw light volumes instead, emulated by looping over every
//! light.

use crate::error::Error;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
use crate::shading::{wgsl, ShaderModel};

/// Screen tiles of the light loop (shaders/pass/forward.wgsl `LIGHT_TILE`).
pub const LIGHT_TILE: u32 = 16;

/// The tiled light loop's resources: per tile a bit mask of the lights that reach it, filled by a
/// compute pass (`cs_light_tiles`) and read by the lighting pass; grown to the largest frame.
pub struct LightTiles {
    /// Lighting pass, group 3: the masks, read-only.
    pub read_layout: wgpu::BindGroupLayout,
    /// Compute pass, group 3: the G-buffer depth and the masks.
    write_layout: wgpu::BindGroupLayout,
    compute_layout: wgpu::PipelineLayout,
    pipeline: Option<wgpu::ComputePipeline>,
    masks: wgpu::Buffer,
    pub read: wgpu::BindGroup,
}

/// Tiles across × down and mask words per tile for a frame.
pub fn tile_grid(width: u32, height: u32, lights: usize) -> (u32, u32, u32) {
    (width.div_ceil(LIGHT_TILE), height.div_ceil(LIGHT_TILE), (lights as u32).div_ceil(32).max(1))
}

impl LightTiles {
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> LightTiles {
        let storage = |binding: u32, read_only: bool, stage: wgpu::ShaderStages| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: stage,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let read_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("light tiles read"),
            entries: &[storage(2, true, wgpu::ShaderStages::FRAGMENT)],
        });
        let write_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("light tiles write"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                storage(1, false, wgpu::ShaderStages::COMPUTE),
            ],
        });
        let compute_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(crate::plan::Pass::LightTiles.name()),
            bind_group_layouts: &[Some(frame_layout), None, None, Some(&write_layout)],
            immediate_size: 0,
        });
        let masks = Self::buffer(device, 16);
        let read = Self::read_group(device, &read_layout, &masks);
        LightTiles { read_layout, write_layout, compute_layout, pipeline: None, masks, read }
    }

    fn buffer(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("light tile masks"),
            size: bytes.max(16).next_multiple_of(16),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    fn read_group(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, masks: &wgpu::Buffer) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("light tiles read"),
            layout,
            entries: &[wgpu::BindGroupEntry { binding: 2, resource: masks.as_entire_binding() }],
        })
    }

    /// Room for `bytes` of masks (the read bind group follows the buffer).
    fn reserve(&mut self, device: &wgpu::Device, bytes: u64) {
        if self.masks.size() < bytes {
            self.masks = Self::buffer(device, bytes);
            self.read = Self::read_group(device, &self.read_layout, &self.masks);
        }
    }

    /// Ready the pass for a `width`×`height` frame of `lights` lights on `depth`: its pipeline
    /// (compiled from `model`, HDRP's lit model, for the first frame), room for the masks, and the
    /// compute pass's group.
    pub fn prepare(
        &mut self,
        gpu: &GpuContext,
        model: &ShaderModel,
        (width, height, lights): (u32, u32, usize),
        depth: &wgpu::TextureView,
    ) -> Result<wgpu::BindGroup, Error> {
        if self.pipeline.is_none() {
            let source = wgsl::compose(wgsl::PassKind::Forward, Some(model));
            let module = gpu.shader_module(crate::plan::Pass::LightTiles.name(), &source)?;
            let pipeline = gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(crate::plan::Pass::LightTiles.name()),
                layout: Some(&self.compute_layout),
                module: &module,
                entry_point: Some("cs_light_tiles"),
                compilation_options: Default::default(),
                cache: None,
            });
            gpu.check_errors("creating the light-tile pipeline")?;
            self.pipeline = Some(pipeline);
        }
        let (tx, ty, words) = tile_grid(width, height, lights);
        self.reserve(&gpu.device, (tx * ty * words) as u64 * 4);
        Ok(self.write_group(&gpu.device, depth))
    }

    /// The pass: clear the masks, then one invocation group per tile of a `width`×`height` frame.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (frame_group, group): (&wgpu::BindGroup, &wgpu::BindGroup),
        (width, height): (u32, u32),
        timed: Option<(&PassTimer, u32)>,
    ) {
        let Some(pipeline) = &self.pipeline else { return };
        encoder.clear_buffer(&self.masks, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(crate::plan::Pass::LightTiles.name()),
            timestamp_writes: timed.map(|(t, pair)| t.compute_writes(pair)),
        });
        let (tx, ty, _) = tile_grid(width, height, 0);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(3, group, &[]);
        pass.dispatch_workgroups(tx, ty, 1);
    }

    /// The compute pass's group 3 for this frame's depth.
    fn write_group(&self, device: &wgpu::Device, depth: &wgpu::TextureView) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("light tiles write"),
            layout: &self.write_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(depth) },
                wgpu::BindGroupEntry { binding: 1, resource: self.masks.as_entire_binding() },
            ],
        })
    }
}
