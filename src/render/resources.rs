//! How the passes make their GPU resources the same way: 2D and multisampled textures, uniform
//! slots with dynamic offsets, compute pipelines and their steps, half-float texels.

use crate::gpu::ConstantSpace;

/// A single-sample 2-D texture of one layer, as every render target here is but the MSAA ones.
pub fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    multisampled_2d(device, label, size, format, usage, 1)
}

/// A 2-D render target of one layer with `samples` samples per pixel.
pub(crate) fn multisampled_2d(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
    samples: u32,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// The layout `uniform_slots` binds: one constant buffer of `size` bytes at a dynamic offset.
pub(crate) fn uniform_slot_layout(
    device: &wgpu::Device,
    space: ConstantSpace,
    label: &str,
    visibility: wgpu::ShaderStages,
    size: u64,
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: space.binding(),
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(size),
            },
            count: None,
        }],
    })
}

/// A constant buffer of `count` slots of `size` bytes at the device's offset alignment, and a bind
/// group (`layout`: one constant binding with a dynamic offset) that sees one slot at a time.
pub(crate) fn uniform_slots(
    device: &wgpu::Device,
    space: ConstantSpace,
    layout: &wgpu::BindGroupLayout,
    label: &str,
    size: u64,
    count: usize,
) -> (wgpu::Buffer, u64, wgpu::BindGroup) {
    let align = space.offset_alignment(&device.limits());
    let stride = size.div_ceil(align) * align;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: stride * count.max(1) as u64,
        usage: space.usage() | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &buffer,
                offset: 0,
                size: wgpu::BufferSize::new(size),
            }),
        }],
    });
    (buffer, stride, group)
}

/// A compute pipeline with one bind group, running `entry` of `module`.
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// Layout entries of the compute passes (bloom, probe prefilter, SSAO): what each binding is.
pub(crate) mod compute_entry {
    const STAGE: wgpu::ShaderStages = wgpu::ShaderStages::COMPUTE;

    /// A constant buffer (gpu::constants: uniform, or read-only storage on lavapipe).
    pub fn constants(space: crate::gpu::ConstantSpace, binding: u32) -> wgpu::BindGroupLayoutEntry {
        buffer(binding, space.binding())
    }

    pub fn read_only_storage(binding: u32) -> wgpu::BindGroupLayoutEntry {
        buffer(binding, wgpu::BufferBindingType::Storage { read_only: true })
    }

    pub fn read_write_storage(binding: u32) -> wgpu::BindGroupLayoutEntry {
        buffer(binding, wgpu::BufferBindingType::Storage { read_only: false })
    }

    fn buffer(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: STAGE,
            ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
            count: None,
        }
    }

    /// A texture read with loads (32-bit floats need not be filterable).
    pub fn texture(
        binding: u32,
        sample_type: wgpu::TextureSampleType,
        view_dimension: wgpu::TextureViewDimension,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: STAGE,
            ty: wgpu::BindingType::Texture { sample_type, view_dimension, multisampled: false },
            count: None,
        }
    }

    /// An unfilterable float 2-D texture.
    pub fn float_2d(binding: u32) -> wgpu::BindGroupLayoutEntry {
        texture(binding, wgpu::TextureSampleType::Float { filterable: false }, wgpu::TextureViewDimension::D2)
    }

    /// A write-only 2-D storage texture.
    pub fn storage_2d(binding: u32, format: wgpu::TextureFormat) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: STAGE,
            ty: wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
            count: None,
        }
    }
}

/// One dispatch of an 8×8-workgroup compute shader: its bind group and the grid it covers.
pub(crate) struct ComputeStep {
    pub group: wgpu::BindGroup,
    pub size: (u32, u32),
}

/// One compute pass running `steps` in order (timed as one span when `timestamps` is given).
pub(crate) fn encode_steps<'a>(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    steps: impl IntoIterator<Item = &'a ComputeStep>,
    timestamps: Option<wgpu::ComputePassTimestampWrites>,
) {
    let mut pass =
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: timestamps });
    pass.set_pipeline(pipeline);
    for s in steps {
        pass.set_bind_group(0, &s.group, &[]);
        pass.dispatch_workgroups(s.size.0.div_ceil(8), s.size.1.div_ceil(8), 1);
    }
}

/// A linear radiance as an Rgba16Float texel (alpha 1), capped below half-float's maximum so a
/// bright sun stays finite.
pub(crate) fn half_texel(c: glam::DVec3) -> [half::f16; 4] {
    [c.x, c.y, c.z, 1.0].map(|v| half::f16::from_f64(v.min(65000.0)))
}
