//! The subject's material maps on the GPU (`materials::MaterialMaps`): albedo modulation, normal
//! mask and emission as mip-mapped Rgba16Float textures, uploaded once per preset and kept; a 1×1 neutral
//! set (albedo 1, normal +Z, mask with no offset) for flat cells. Sampled the way Unity imports a
//! texture by default: bilinear within a mip, the nearest mip (FilterMode.Bilinear), repeating.

use half::f16;

use crate::materials::MaterialMaps;

pub struct MaterialTextures {
    pub albedo: wgpu::TextureView,
    pub normal: wgpu::TextureView,
    pub mask: wgpu::TextureView,
    /// Emission multiplier (white 1×1 where the material has no emission map).
    pub emission: wgpu::TextureView,
}

/// Standard's secondary maps (`materials::detail`: detail normal xyz, linear detail albedo w), one
/// grain for every subject: uploaded once per renderer and bound beside whatever maps it wears.
pub fn detail_texture(device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::TextureView {
    let levels: Vec<(usize, &[[f32; 4]])> =
        crate::materials::detail::detail_levels().iter().map(|l| (l.size, l.texels.as_slice())).collect();
    upload(device, queue, "material detail", &levels)
}

fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    levels: &[(usize, &[[f32; 4]])],
) -> wgpu::TextureView {
    let size = levels[0].0 as u32;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (mip, (s, texels)) in levels.iter().enumerate() {
        write_level(queue, &texture, (mip, 0), *s, texels);
    }
    texture.create_view(&Default::default())
}

/// One `size`² level of linear RGBA texels into mip `mip`, layer `layer` of an Rgba16Float texture.
pub(in crate::render) fn write_level(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    (mip, layer): (usize, usize),
    size: usize,
    texels: &[[f32; 4]],
) {
    let bytes: Vec<f16> = texels.iter().flat_map(|t| t.map(f16::from_f32)).collect();
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: mip as u32,
            origin: wgpu::Origin3d { x: 0, y: 0, z: layer as u32 },
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(&bytes),
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(size as u32 * 8), rows_per_image: None },
        wgpu::Extent3d { width: size as u32, height: size as u32, depth_or_array_layers: 1 },
    );
}

impl MaterialTextures {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, maps: &MaterialMaps) -> MaterialTextures {
        let pick = |f: fn(&crate::materials::MapLevel) -> &Vec<[f32; 4]>| -> Vec<(usize, &[[f32; 4]])> {
            maps.levels.iter().map(|l| (l.size, f(l).as_slice())).collect()
        };
        MaterialTextures {
            albedo: upload(device, queue, "material albedo", &pick(|l| &l.albedo)),
            normal: upload(device, queue, "material normal", &pick(|l| &l.normal)),
            mask: upload(device, queue, "material mask", &pick(|l| &l.mask)),
            emission: match maps.levels[0].emission.is_empty() {
                true => upload(device, queue, "no emission map", &[(1, &[[1.0; 4]][..])]),
                false => upload(device, queue, "material emission", &pick(|l| &l.emission)),
            },
        }
    }

    /// A flat cell's maps: no modulation.
    pub fn neutral(device: &wgpu::Device, queue: &wgpu::Queue) -> MaterialTextures {
        let one = |v: [f32; 4], label: &str| upload(device, queue, label, &[(1, &[v][..])]);
        MaterialTextures {
            albedo: one([1.0; 4], "neutral albedo"),
            normal: one([0.0, 0.0, 1.0, crate::materials::NO_HEIGHT], "neutral normal"),
            mask: one([1.0, 1.0, 1.0, 0.5], "neutral mask"),
            emission: one([1.0; 4], "neutral emission"),
        }
    }
}

/// Unity's default import filtering: FilterMode.Bilinear (linear within a mip, nearest between
/// mips), TextureWrapMode.Repeat.
pub fn sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("material maps"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Nearest,
        ..Default::default()
    })
}
