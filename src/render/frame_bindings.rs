//! Group 0 of the scene passes, the frame's: its uniforms, the environment and its samplers, the
//! lights and shadow maps, and the subject's material maps, which are uploaded on first use and
//! kept per preset.

use std::collections::HashMap;

use super::material_maps::MaterialTextures;
use super::prepared::{own_textures, PreparedScene};
use crate::error::Error;
use crate::gpu::GpuContext;
use crate::materials::MaterialMaps;
use crate::render::uniforms::FrameUniforms;

/// The frame group's layout, the samplers and tables it binds, and the material maps uploaded.
pub(in crate::render) struct FrameBindings {
    pub(in crate::render) layout: wgpu::BindGroupLayout,
    pub(in crate::render) sampler: wgpu::Sampler,
    /// The split-sum DFG table (shading::fgd).
    pub(in crate::render) fgd: wgpu::TextureView,
    pub(in crate::render) shadow_sampler: wgpu::Sampler,
    pub(in crate::render) material_sampler: wgpu::Sampler,
    /// Per preset ("" the neutral set), uploaded on first use and kept.
    pub(in crate::render) material_textures: HashMap<&'static str, MaterialTextures>,
    /// Standard's secondary maps, the same for every subject (`material_maps::detail_texture`).
    pub(in crate::render) detail: wgpu::TextureView,
}

impl FrameBindings {
    /// The frame group's layout, its samplers and tables, with no material maps uploaded yet.
    pub(in crate::render) fn new(gpu: &GpuContext) -> FrameBindings {
        let device = &gpu.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    // Compute too: the tiled light loop reads the frame and the lights.
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
                    ty: wgpu::BindingType::Buffer {
                        ty: gpu.constants.binding(),
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<FrameUniforms>() as u64),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                super::luts::fgd_layout_entry(
                    3,
                    wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
                ),
                storage_entry(4),
                storage_entry(5),
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 7,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                storage_entry(8),
                material_map_entry(9),
                material_map_entry(10),
                material_map_entry(11),
                material_map_entry(13),
                material_map_entry(15),
                wgpu::BindGroupLayoutEntry {
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    ..material_map_entry(16)
                },
                wgpu::BindGroupLayoutEntry {
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    ..material_map_entry(14)
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 12,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        FrameBindings {
            layout,
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("environment"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
            fgd: super::luts::fgd_texture(gpu),
            shadow_sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow comparison"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
            material_sampler: crate::render::material_maps::sampler(device),
            material_textures: HashMap::new(),
            detail: crate::render::material_maps::detail_texture(device, &gpu.queue),
        }
    }

    /// The albedo map the subject wears with `maps`, once `frame_group` has uploaded it.
    pub(in crate::render) fn albedo_view<'a>(
        &'a self,
        prepared: &'a PreparedScene,
        maps: Option<&'static str>,
    ) -> Option<&'a wgpu::TextureView> {
        let key = maps.unwrap_or("");
        if key == crate::declarations::presets::OWN.name {
            return prepared.own_textures.get().map(|t| &t.albedo);
        }
        self.material_textures.get(key).map(|t| &t.albedo)
    }

    /// The frame bind group of a composition with the subject wearing `maps` (None: flat), made and
    /// the maps uploaded on first use.
    pub(in crate::render) fn frame_group(
        &mut self,
        gpu: &GpuContext,
        prepared: &PreparedScene,
        maps: Option<&'static str>,
    ) -> Result<std::sync::Arc<wgpu::BindGroup>, Error> {
        let key = maps.unwrap_or("");
        if let Some(g) = prepared.frame_groups.lock().unwrap_or_else(|e| e.into_inner()).get(key) {
            return Ok(g.clone());
        }
        let (device, queue) = (&gpu.device, &gpu.queue);
        let textures = if key == crate::declarations::presets::OWN.name {
            if prepared.own_textures.get().is_none() {
                let textures = own_textures(device, queue, &prepared.scene)?;
                let _ = prepared.own_textures.set(textures);
            }
            prepared.own_textures.get().expect("just set")
        } else {
            self.material_textures.entry(key).or_insert_with(|| match maps {
                Some(preset) => {
                    crate::render::material_maps::MaterialTextures::new(device, queue, &MaterialMaps::of(preset))
                }
                None => crate::render::material_maps::MaterialTextures::neutral(device, queue),
            });
            &self.material_textures[key]
        };
        let group = std::sync::Arc::new(self.frame_bind_group(device, prepared, &prepared.frame_buffer, textures));
        prepared.frame_groups.lock().unwrap_or_else(|e| e.into_inner()).insert(key, group.clone());
        Ok(group)
    }

    /// A frame bind group over `frame_buffer` (the cell's, or a probe face's) with the subject's maps.
    pub(in crate::render) fn frame_bind_group(
        &self,
        device: &wgpu::Device,
        prepared: &PreparedScene,
        frame_buffer: &wgpu::Buffer,
        textures: &crate::render::material_maps::MaterialTextures,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: frame_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&prepared.env_view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&self.sampler) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&self.fgd) },
                wgpu::BindGroupEntry { binding: 4, resource: prepared.lights_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 5, resource: prepared.modes_buffer.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(&prepared.shadows.array_view),
                },
                wgpu::BindGroupEntry { binding: 7, resource: wgpu::BindingResource::Sampler(&self.shadow_sampler) },
                wgpu::BindGroupEntry { binding: 8, resource: prepared.shadows.layers_storage.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 9, resource: wgpu::BindingResource::TextureView(&textures.albedo) },
                wgpu::BindGroupEntry { binding: 10, resource: wgpu::BindingResource::TextureView(&textures.normal) },
                wgpu::BindGroupEntry { binding: 11, resource: wgpu::BindingResource::TextureView(&textures.mask) },
                wgpu::BindGroupEntry { binding: 12, resource: wgpu::BindingResource::Sampler(&self.material_sampler) },
                wgpu::BindGroupEntry { binding: 13, resource: wgpu::BindingResource::TextureView(&textures.emission) },
                wgpu::BindGroupEntry { binding: 15, resource: wgpu::BindingResource::TextureView(&self.detail) },
                wgpu::BindGroupEntry {
                    binding: 16,
                    resource: wgpu::BindingResource::TextureView(&prepared.lightmap_texture.view),
                },
                wgpu::BindGroupEntry {
                    binding: 14,
                    resource: wgpu::BindingResource::TextureView(&prepared.fixed_maps.view),
                },
            ],
        })
    }
}

/// A material map of the frame group, sampled by both stages (the vertex-lit path reads them) and
/// by the truth's tracer.
fn material_map_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// A read-only storage buffer of the frame group, seen by both stages (vertex lights read it).
fn storage_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}
