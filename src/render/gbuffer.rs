//! The deferred path's screen-space resources: the G-buffer (base colour and occlusion 8-bit
//! sRGB, metallic and smoothness 8-bit, the normal in the pipeline's format, the
//! ambient/environment term in half float as Unity's RT3, the baked shadow mask 8-bit as
//! built-in's RT4, URP's and HDRP's shadow-mask G-buffer) and HDRP's light tiles. The G-buffer
//! stores base colour and metallic where built-in's stores diffuse and specular colours: the same
//! information at the same 8-bit precision, laid out for any model. passes::deferred draws them.

use crate::pipelines::Pipeline;

pub const GB_ALBEDO: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub const GB_MATERIAL: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub const GB_LIGHTING: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const GB_SHADOW_MASK: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The lighting pass's binding of the shadow mask (0–5: the other targets and depth; 6 is the
/// G-buffer pass's screen occlusion).
const SHADOW_MASK_BINDING: u32 = 7;

/// Each pipeline's normal buffer: built-in's RT2 is ARGB2101010; URP's default ("Accurate G-buffer
/// normals" off) is 8-bit; HDRP packs octahedral normals into 8-bit channels, APPROXIMATED here by
/// 10:10:10:2.
pub fn normal_format(p: Pipeline) -> wgpu::TextureFormat {
    match p {
        Pipeline::Builtin | Pipeline::Hdrp => wgpu::TextureFormat::Rgb10a2Unorm,
        Pipeline::Urp => wgpu::TextureFormat::Rgba8Unorm,
    }
}

/// The G-buffer textures of one size (both normal formats, chosen per pipeline).
pub struct GBuffer {
    pub albedo: wgpu::TextureView,
    pub material: wgpu::TextureView,
    pub normal_10: wgpu::TextureView,
    pub normal_8: wgpu::TextureView,
    pub lighting: wgpu::TextureView,
    pub shadow_mask: wgpu::TextureView,
    /// Lighting-pass bind groups reading the G-buffer with the 10-bit and the 8-bit normals.
    pub read_10: wgpu::BindGroup,
    pub read_8: wgpu::BindGroup,
}

impl GBuffer {
    pub fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        width: u32,
        height: u32,
        role: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> GBuffer {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let make = |label: &str, format: wgpu::TextureFormat| {
            crate::render::texture_2d(device, label, (width, height), format, usage).create_view(&Default::default())
        };
        let albedo = make("gbuffer albedo", GB_ALBEDO);
        let material = make("gbuffer material", GB_MATERIAL);
        let normal_10 = make("gbuffer normal 10:10:10:2", wgpu::TextureFormat::Rgb10a2Unorm);
        let normal_8 = make("gbuffer normal 8", wgpu::TextureFormat::Rgba8Unorm);
        let lighting = make("gbuffer lighting", GB_LIGHTING);
        let shadow_mask = make("gbuffer shadow mask", GB_SHADOW_MASK);
        let read = |normal: &wgpu::TextureView| {
            let views = [&albedo, &material, normal, &lighting, role, depth];
            let entries: Vec<wgpu::BindGroupEntry> = views
                .iter()
                .enumerate()
                .map(|(i, v)| (i as u32, *v))
                .chain([(SHADOW_MASK_BINDING, &shadow_mask)])
                .map(|(binding, v)| wgpu::BindGroupEntry { binding, resource: wgpu::BindingResource::TextureView(v) })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("gbuffer read"),
                layout,
                entries: &entries,
            })
        };
        let read_10 = read(&normal_10);
        let read_8 = read(&normal_8);
        GBuffer { albedo, material, normal_10, normal_8, lighting, shadow_mask, read_10, read_8 }
    }

    pub fn normal(&self, p: Pipeline) -> &wgpu::TextureView {
        match normal_format(p) {
            wgpu::TextureFormat::Rgba8Unorm => &self.normal_8,
            _ => &self.normal_10,
        }
    }

    pub fn read(&self, p: Pipeline) -> &wgpu::BindGroup {
        match normal_format(p) {
            wgpu::TextureFormat::Rgba8Unorm => &self.read_8,
            _ => &self.read_10,
        }
    }
}

/// The lighting pass's group 2: the G-buffer read with textureLoad.
pub fn read_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let texture = |binding: u32, sample_type: wgpu::TextureSampleType| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    let float = wgpu::TextureSampleType::Float { filterable: false };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("gbuffer read"),
        entries: &[
            texture(0, float),
            texture(1, float),
            texture(2, float),
            texture(3, float),
            texture(4, wgpu::TextureSampleType::Uint),
            texture(5, wgpu::TextureSampleType::Depth),
            texture(SHADOW_MASK_BINDING, float),
        ],
    })
}

/// Screen tiles of the light loop (shaders/pass/forward.wgsl `LIGHT_TILE`).
pub const LIGHT_TILE: u32 = 16;

/// The tiled light loop's resources: per tile a bit mask of the lights that reach it, filled by a
/// compute pass (`cs_light_tiles`) and read by the lighting pass; grown to the largest frame.
pub struct LightTiles {
    /// Lighting pass, group 3: the masks, read-only.
    pub read_layout: wgpu::BindGroupLayout,
    /// Compute pass, group 3: the G-buffer depth and the masks.
    pub write_layout: wgpu::BindGroupLayout,
    pub compute_layout: wgpu::PipelineLayout,
    pub pipeline: Option<wgpu::ComputePipeline>,
    pub masks: wgpu::Buffer,
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
    pub fn reserve(&mut self, device: &wgpu::Device, bytes: u64) {
        if self.masks.size() < bytes {
            self.masks = Self::buffer(device, bytes);
            self.read = Self::read_group(device, &self.read_layout, &self.masks);
        }
    }

    /// The compute pass's group 3 for this frame's depth.
    pub fn write_group(&self, device: &wgpu::Device, depth: &wgpu::TextureView) -> wgpu::BindGroup {
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
