//! The deferred path's screen-space resources: the G-buffer (base colour and occlusion 8-bit
//! sRGB, metallic and smoothness 8-bit, the normal in the pipeline's format, the
//! ambient/environment term in half float as Unity's RT3, the baked shadow mask 8-bit as
//! built-in's RT4, URP's and HDRP's shadow-mask G-buffer) (HDRP's light tiles are
//! passes::light_tiles'). The G-buffer
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
            crate::render::resources::texture_2d(device, label, (width, height), format, usage)
                .create_view(&Default::default())
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
