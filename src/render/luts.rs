//! Lookup tables the shaders read, uploaded once per device.

use wgpu::util::DeviceExt;

use crate::gpu::GpuContext;
use crate::shading::fgd::{FgdTable, FGD_SIZE};

/// HDRP's FGD table as an Rgba32Float texture (read with textureLoad, interpolated by hand), with
/// the rect lights' LTC tables below it: rows 64–127 GGX, 128–191 Disney diffuse
/// (shaders/common/area.wgsl `LTC_GGX_ROW`, `LTC_DISNEY_ROW`).
pub fn fgd_texture(gpu: &GpuContext) -> wgpu::TextureView {
    let fgd = FgdTable::get();
    let ltc = crate::shading::ltc::LtcTables::get();
    let texels: Vec<[f32; 4]> = fgd.texels.iter().chain(&ltc.ggx).chain(&ltc.disney).copied().collect();
    let texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("hdrp fgd"),
            size: wgpu::Extent3d { width: FGD_SIZE as u32, height: 3 * FGD_SIZE as u32, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&texels),
    );
    texture.create_view(&Default::default())
}

/// The bind-group-layout entry for it.
pub fn fgd_layout_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}
