//! Baked global illumination (plan::gi): what the bake of a cell's scene holds — light probes
//! for the dynamic objects and, for the static ones, lightmaps — gathered by the path tracer
//! (render::truth::bake) as Unity's Progressive Lightmapper gathers them, and how each object
//! reads it in place of the sky's ambient SH.

pub mod cache;
pub mod lightmaps;
pub mod probes;

use glam::DVec3;

use probes::Probe;

/// A scene's bake for one set of inputs (`key`), shared by every cell whose bake reads the same.
#[derive(Debug, Clone)]
pub struct BakedLighting {
    /// What the bake read, hashed: cells with the same key share it.
    pub key: u64,
    /// The grid's probes (None: the scene has no probe grid).
    pub probes: Option<Vec<Probe>>,
    /// The static objects' lightmap (None: the scene has no static object).
    pub lightmap: Option<lightmaps::Lightmap>,
    /// Directional Mode: the lightmap's direction layer is read.
    pub directional: bool,
    /// Samples per probe, the samples the texels took to reach `noise_target` (or the most
    /// they may take), the target (0: none) and the bounces of their paths.
    pub samples: u32,
    pub texel_samples: u32,
    pub noise_target: f64,
    pub bounces: u32,
    /// Wall time of the bake, s (a one-off cost, not per frame).
    pub seconds: f64,
    /// Read from the bake cache (an earlier run made it).
    pub cached: bool,
}

/// What a cell's frame measured of the bake it read (the plan's decisions are `CellPlan::gi`).
#[derive(Debug, Clone, PartialEq)]
pub struct BakeUse {
    /// Made for this cell (false: an earlier cell's, whose inputs were the same).
    pub made: bool,
    /// Read from the bake cache (an earlier run made it; `seconds` is that run's).
    pub cached: bool,
    pub seconds: f64,
    pub samples: u32,
    pub texel_samples: u32,
    pub noise_target: f64,
    pub bounces: u32,
    /// The lightmap's size in texels and covered texels, and its stated noise.
    pub lightmap: Option<([u32; 2], usize, Option<f64>)>,
    pub probes: usize,
    /// How the lightmap is stored (`rgbm`, `hdr`).
    pub encoding: &'static str,
}

impl BakeUse {
    /// What a frame planned with `plan` read of `baked` (None: nothing baked reached it); `made`:
    /// baked for this cell; `covered`: the composition's lightmap texels.
    pub fn of(plan: &crate::plan::gi::GiPlan, baked: Option<&BakedLighting>, made: bool, covered: usize) -> BakeUse {
        let encoding = lightmaps::LightmapEncoding::of_quality(plan.encoding).name();
        match baked {
            Some(b) => BakeUse {
                made,
                cached: b.cached,
                seconds: b.seconds,
                samples: b.samples,
                texel_samples: b.texel_samples,
                noise_target: b.noise_target,
                bounces: b.bounces,
                lightmap: b.lightmap.as_ref().map(|m| ([m.width, m.height], covered, m.noise)),
                probes: b.probes.as_ref().map_or(0, Vec::len),
                encoding,
            },
            None => BakeUse {
                made: false,
                cached: false,
                seconds: 0.0,
                samples: 0,
                texel_samples: 0,
                noise_target: 0.0,
                bounces: plan.bounces,
                lightmap: None,
                probes: 0,
                encoding,
            },
        }
    }
}

/// Where an object's ambient (diffuse indirect) light comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum AmbientSource {
    /// The sky's SH (nothing baked reaches the object).
    Sky,
    /// Its interpolated light probe.
    Probe(Box<Probe>),
    /// Its lightmap (`directional`: with the dominant direction).
    Lightmap { directional: bool },
}

impl AmbientSource {
    /// The value the shaders read in `Object.bake.x` (forward.wgsl `object_ambient`).
    pub fn shader_value(&self) -> f32 {
        match self {
            AmbientSource::Sky => 0.0,
            AmbientSource::Probe(_) => 1.0,
            AmbientSource::Lightmap { .. } => 2.0,
        }
    }

    /// `Object.bake.y`: 1 where the lightmap's direction is read, + 2 where Subtractive's
    /// main-light shadow darkens it.
    pub fn flags(&self, subtractive: bool) -> f32 {
        match self {
            AmbientSource::Lightmap { directional } => (*directional as u32 + 2 * subtractive as u32) as f32,
            _ => 0.0,
        }
    }
}

/// The lightmap texture of a composition: LIGHTMAP_LAYERS layers of Rgba16Float at the atlas's
/// size, holding the bake whose key `holds` says (a cell reading another bake uploads its own).
pub struct LightmapTexture {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    pub holds: std::sync::Mutex<Option<u64>>,
}

impl LightmapTexture {
    pub fn new(gpu: &crate::gpu::GpuContext, atlas: Option<&crate::geometry::lightmap_uv::LightmapAtlas>) -> Self {
        let (width, height) = atlas.map_or((1, 1), |a| (a.width, a.height));
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("lightmap"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: lightmaps::LIGHTMAP_LAYERS },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        LightmapTexture { texture, view, holds: std::sync::Mutex::new(None) }
    }

    /// Make the texture hold `baked`'s lightmap, unless it does already.
    pub fn hold(&self, queue: &wgpu::Queue, baked: &BakedLighting) {
        let Some(map) = &baked.lightmap else { return };
        let mut holds = self.holds.lock().unwrap_or_else(|e| e.into_inner());
        if *holds == Some(baked.key) {
            return;
        }
        let halves: Vec<half::f16> = map.texels.iter().flatten().map(|&v| half::f16::from_f32(v)).collect();
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(&halves),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(map.width * 8),
                rows_per_image: Some(map.height),
            },
            wgpu::Extent3d { width: map.width, height: map.height, depth_or_array_layers: lightmaps::LIGHTMAP_LAYERS },
        );
        *holds = Some(baked.key);
    }
}

impl BakedLighting {
    /// The ambient source of a dynamic object whose bounds centre is `centre`.
    pub fn dynamic_ambient(&self, grid: Option<&crate::declarations::gi::ProbeGrid>, centre: DVec3) -> AmbientSource {
        match (&self.probes, grid) {
            (Some(probes), Some(grid)) => AmbientSource::Probe(Box::new(probes::interpolate(grid, probes, centre))),
            _ => AmbientSource::Sky,
        }
    }
}
