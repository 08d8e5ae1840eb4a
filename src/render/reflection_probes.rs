//! Reflection probes that see the scene: each probe renders the scene's fixed objects and sky from
//! its position into six 90° faces, and a compute pass resamples them into the equirectangular
//! layout of the sky's probe and prefilters Unity's seven levels (mip = pr'·6 with
//! pr' = pr(1.7 − 0.7pr), models.md#builtin; HDRP and URP convolve and fetch with the same
//! mapping and UNITY_SPECCUBE_LOD_STEPS = 6) exactly as `environment::prefilter` does on the CPU,
//! its twin. The levels sit in one array texture after the sky's seven: probe k's level l is layer
//! 7(k + 1) + l. The shaders blend probes per pixel as URP's CalculateIrradianceFromReflectionProbes
//! does (GlobalIllumination.hlsl: each probe's weight is sat(min distance into its box / blend
//! distance), capped at what the earlier ones left, the sky taking the rest) and box-project as
//! BoxProjectedCubemapDirection (UnityStandardUtils.cginc; URP BoxProjectedCubemapDirection).
//!
//! Written here rather than taken from a crate: the capture draws with the tool's own pipelines
//! and the prefilter must be the twin of the CPU one to be tested against it.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3};
use wgpu::util::DeviceExt;

use crate::environment::filtered::{self, LobeWeight};
use crate::environment::prefilter::{self, EquirectImage, LEVELS, MIRROR_ALPHA, PROBE_WIDTH, SOURCE_WIDTH};
use crate::error::Error;
use crate::gpu::GpuContext;

use crate::declarations::scene::ReflectionProbe;
use crate::render::resources::ComputeStep;
pub use crate::render::uniforms::{first_layer, GpuReflectionProbe};

pub use crate::declarations::scene::MAX_PROBES;
/// The capture's colour format: the forward pipelines' target format.
pub const CAPTURE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const LEVEL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
const PROBE_HEIGHT: usize = PROBE_WIDTH / 2;
/// Sub-samples per side when the faces are resampled to the equirectangular source.
const FACE_SUBSAMPLES: u32 = 2;

/// Captures kept per composition: one per pipeline and then some, so a run that alternates
/// pipelines (references first) does not capture again each time.
pub const CAPTURE_SLOTS: usize = 4;

/// The view-projections of the six faces from `position`, in the order +X, −X, +Y, −Y, +Z, −Z
/// (the prefilter picks the face of a direction's major axis in this order).
pub fn face_view_proj(position: DVec3, near: f64) -> [DMat4; 6] {
    let dirs = [
        (DVec3::X, DVec3::Y),
        (DVec3::NEG_X, DVec3::Y),
        (DVec3::Y, DVec3::NEG_Z),
        (DVec3::NEG_Y, DVec3::Z),
        (DVec3::Z, DVec3::Y),
        (DVec3::NEG_Z, DVec3::Y),
    ];
    let proj = DMat4::perspective_rh(std::f64::consts::FRAC_PI_2, 1.0, near, 1000.0);
    dirs.map(|(d, up)| proj * DMat4::look_at_rh(position, position + d, up))
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct PrefilterParams {
    dims: [u32; 4],
    level: [f32; 4],
    faces: [[[f32; 4]; 4]; 6],
    probe_position: [f32; 4],
}

const MODE_FACES: u32 = 0;
const MODE_HALVE: u32 = 1;
const MODE_FILTERED: u32 = 2;
const MODE_COPY: u32 = 3;

/// The source's mips: 256 wide down to `filtered::MIP_CHAIN_MIN_WIDTH`.
fn chain_mips() -> usize {
    (SOURCE_WIDTH / filtered::MIP_CHAIN_MIN_WIDTH).trailing_zeros() as usize + 1
}

/// The prefilter's pipeline and its scratch: the equirectangular source (256×128) and its mip
/// chain down to `filtered::MIP_CHAIN_MIN_WIDTH`, which the levels sample. Built once per renderer.
pub struct Prefilter {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// Trilinear, wrapping in u and clamped in v: the chain's reads.
    chain_sampler: wgpu::Sampler,
    chain: wgpu::Texture,
    /// Bound where a step reads no faces, and where it reads no source.
    no_faces: wgpu::TextureView,
    no_source: wgpu::TextureView,
    space: crate::gpu::ConstantSpace,
}

impl Prefilter {
    pub fn new(gpu: &GpuContext) -> Result<Prefilter, Error> {
        let device = &gpu.device;
        let module = gpu.shader_module(
            crate::plan::Pass::ProbePrefilter.name(),
            &crate::shading::wgsl::with_math(include_str!("../../shaders/pass/probe_prefilter.wgsl")),
        )?;
        use crate::render::resources::compute_entry::{constants, storage_2d, texture};
        let float = wgpu::TextureSampleType::Float { filterable: false };
        let filterable = wgpu::TextureSampleType::Float { filterable: true };
        let sampler_entry = |binding, kind| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Sampler(kind),
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(crate::plan::Pass::ProbePrefilter.name()),
            entries: &[
                constants(gpu.constants, 0),
                texture(1, float, wgpu::TextureViewDimension::D2Array),
                texture(2, filterable, wgpu::TextureViewDimension::D2),
                sampler_entry(3, wgpu::SamplerBindingType::NonFiltering),
                storage_2d(4, LEVEL_FORMAT),
                sampler_entry(5, wgpu::SamplerBindingType::Filtering),
            ],
        });
        let pipeline = crate::render::resources::compute_pipeline(
            device,
            crate::plan::Pass::ProbePrefilter.name(),
            &layout,
            &module,
            "cs_prefilter",
        );
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("probe faces"),
            mag_filter: wgpu::FilterMode::Nearest,
            min_filter: wgpu::FilterMode::Nearest,
            ..Default::default()
        });
        let chain_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("probe source chain"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let chain = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("probe source chain"),
            size: wgpu::Extent3d {
                width: SOURCE_WIDTH as u32,
                height: SOURCE_WIDTH as u32 / 2,
                depth_or_array_layers: 1,
            },
            mip_level_count: chain_mips() as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: LEVEL_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let no_source = crate::render::resources::texture_2d(
            device,
            "no probe source",
            (1, 1),
            LEVEL_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .create_view(&Default::default());
        let no_faces = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("no probe faces"),
                size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: CAPTURE_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            });
        Ok(Prefilter { pipeline, layout, sampler, chain_sampler, chain, no_faces, no_source, space: gpu.constants })
    }

    /// A view of the chain's mips `first..first + count`.
    fn chain_view(&self, first: usize, count: usize) -> wgpu::TextureView {
        self.chain.create_view(&wgpu::TextureViewDescriptor {
            base_mip_level: first as u32,
            mip_level_count: Some(count as u32),
            ..Default::default()
        })
    }

    /// The dispatches that fill `levels` (the seven layers from `first`) from `faces` (None: the
    /// 256-wide source was uploaded already) captured at `position` with `view_proj`, the lobe
    /// weighed by `weight`.
    fn steps(
        &self,
        device: &wgpu::Device,
        faces: Option<(&wgpu::TextureView, [DMat4; 6], DVec3)>,
        (levels, first): (&wgpu::Texture, usize),
        weight: LobeWeight,
    ) -> Vec<ComputeStep> {
        let mut steps = Vec::new();
        let layer = |t: &wgpu::Texture, layer: usize| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer as u32,
                array_layer_count: Some(1),
                ..Default::default()
            })
        };
        let mut step = |mode: u32,
                        out: wgpu::TextureView,
                        size: (usize, usize),
                        level: [f32; 4],
                        source: &wgpu::TextureView| {
            let mut params = PrefilterParams::zeroed();
            params.dims = [size.0 as u32, size.1 as u32, 0, mode];
            params.level = level;
            if let Some((_, vp, p)) = &faces {
                params.faces = vp.map(|m| m.as_mat4().to_cols_array_2d());
                params.probe_position = [p.x as f32, p.y as f32, p.z as f32, 1.0];
            }
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("probe prefilter step"),
                contents: bytemuck::bytes_of(&params),
                usage: self.space.usage(),
            });
            let faces_view = faces.as_ref().map(|f| f.0).unwrap_or(&self.no_faces);
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("probe prefilter step"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(faces_view) },
                    wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(source) },
                    wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::Sampler(&self.sampler) },
                    wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&out) },
                    wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::Sampler(&self.chain_sampler) },
                ],
            });
            steps.push(ComputeStep { group, size: (size.0 as u32, size.1 as u32) });
        };
        if faces.is_some() {
            let sub = 1.0 / FACE_SUBSAMPLES as f32;
            step(
                MODE_FACES,
                self.chain_view(0, 1),
                (SOURCE_WIDTH, SOURCE_WIDTH / 2),
                [0.0, sub, 0.0, 0.0],
                &self.no_source,
            );
        }
        for m in 1..chain_mips() {
            let size = (SOURCE_WIDTH >> m, SOURCE_WIDTH >> (m + 1));
            step(MODE_HALVE, self.chain_view(m, 1), size, [0.0; 4], &self.chain_view(m - 1, 1));
        }
        // The mirror level: the source halved to the levels' width.
        let mirror = (SOURCE_WIDTH / PROBE_WIDTH).trailing_zeros() as usize;
        let whole = self.chain_view(0, chain_mips());
        for level in 0..LEVELS {
            let alpha = prefilter::level_alpha(level);
            let out = layer(levels, first + level);
            let size = (PROBE_WIDTH, PROBE_HEIGHT);
            // A lobe narrower than a texel copies the mirror image (as on the CPU).
            if level == 0 || alpha < MIRROR_ALPHA {
                step(MODE_COPY, out, size, [0.0; 4], &self.chain_view(mirror, 1));
            } else {
                let n = filtered::sample_count(level) as f32;
                step(MODE_FILTERED, out, size, [alpha as f32, n, 0.0, weight.code() as f32], &whole);
            }
        }
        steps
    }

    /// Prefilter an equirectangular source (256×128) on the GPU and read the seven levels back:
    /// the GPU twin of `Probe::from_source`, for tests and the convergence study.
    pub fn prefilter_source(
        &self,
        gpu: &GpuContext,
        source: &EquirectImage,
        weight: LobeWeight,
    ) -> Result<Vec<Vec<[f32; 4]>>, Error> {
        let device = &gpu.device;
        if (source.width, source.height) != (SOURCE_WIDTH, SOURCE_WIDTH / 2) {
            return Err(Error::Other(format!(
                "the GPU prefilter takes a {SOURCE_WIDTH}×{} source, not {}×{}",
                SOURCE_WIDTH / 2,
                source.width,
                source.height
            )));
        }
        let texels: Vec<half::f16> =
            source.texels.iter().flat_map(|t| crate::render::resources::half_texel(*t)).collect();
        gpu.queue.write_texture(
            self.chain.as_image_copy(),
            bytemuck::cast_slice(&texels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(SOURCE_WIDTH as u32 * 8),
                rows_per_image: None,
            },
            wgpu::Extent3d { width: SOURCE_WIDTH as u32, height: SOURCE_WIDTH as u32 / 2, depth_or_array_layers: 1 },
        );
        let levels = level_texture(device, LEVELS, wgpu::TextureUsages::COPY_SRC);
        let steps = self.steps(device, None, (&levels, 0), weight);
        let mut encoder = device.create_command_encoder(&Default::default());
        crate::render::resources::encode_steps(
            &mut encoder,
            crate::plan::Pass::ProbePrefilter.name(),
            &self.pipeline,
            &steps,
            None,
        );
        let row = PROBE_WIDTH as u32 * 8;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe levels readback"),
            size: (row as usize * PROBE_HEIGHT * LEVELS) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            levels.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(PROBE_HEIGHT as u32),
                },
            },
            wgpu::Extent3d {
                width: PROBE_WIDTH as u32,
                height: PROBE_HEIGHT as u32,
                depth_or_array_layers: LEVELS as u32,
            },
        );
        gpu.queue.submit([encoder.finish()]);
        let bytes = crate::gpu::readback::map_read(device, &readback)?;
        gpu.check_errors("prefiltering a probe source")?;
        let halves: &[half::f16] = bytemuck::cast_slice(&bytes);
        let per_level = PROBE_WIDTH * PROBE_HEIGHT;
        Ok((0..LEVELS)
            .map(|l| {
                (0..per_level)
                    .map(|i| {
                        let t = &halves[(l * per_level + i) * 4..][..4];
                        [t[0].to_f32(), t[1].to_f32(), t[2].to_f32(), t[3].to_f32()]
                    })
                    .collect()
            })
            .collect())
    }
}

/// An array of `layers` probe levels (128×64, half float) the prefilter writes and shaders sample.
pub fn level_texture(device: &wgpu::Device, layers: usize, extra: wgpu::TextureUsages) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("reflection probe levels"),
        size: wgpu::Extent3d {
            width: PROBE_WIDTH as u32,
            height: PROBE_HEIGHT as u32,
            depth_or_array_layers: layers as u32,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: LEVEL_FORMAT,
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::COPY_DST
            | extra,
        view_formats: &[],
    })
}

/// The sky's levels resampled to the probes' 128×64 (a constant sky's single texel repeated), for
/// the layers before the probes'.
pub fn sky_levels(probe: &prefilter::Probe) -> Vec<half::f16> {
    let mut out = Vec::with_capacity(LEVELS * PROBE_WIDTH * PROBE_HEIGHT * 4);
    for l in 0..LEVELS {
        let level = &probe.levels[l.min(probe.levels.len() - 1)];
        for y in 0..PROBE_HEIGHT {
            for x in 0..PROBE_WIDTH {
                let t = if (level.width, level.height) == (PROBE_WIDTH, PROBE_HEIGHT) {
                    level.get(x, y)
                } else {
                    let (d, _) = EquirectImage { width: PROBE_WIDTH, height: PROBE_HEIGHT, texels: Vec::new() }
                        .texel_direction(x, y);
                    level.lookup(d)
                };
                out.extend(crate::render::resources::half_texel(t));
            }
        }
    }
    out
}

/// One probe's capture targets and prefilter dispatches.
pub struct ProbeTargets {
    pub probe: ReflectionProbe,
    pub face_views: Vec<wgpu::TextureView>,
    pub role_views: Vec<wgpu::TextureView>,
    pub depth_view: wgpu::TextureView,
    /// A frame uniform buffer per face (the cell's frame seen from the probe).
    pub frame_buffers: Vec<wgpu::Buffer>,
    pub view_proj: [DMat4; 6],
    /// The prefilter's dispatches into each capture slot, by lobe weight (`LobeWeight::code`).
    steps: Vec<[Vec<ComputeStep>; 2]>,
}

/// A composition's probes: the level array (the sky's seven layers, then seven per probe in each
/// capture slot), each probe's capture targets, and which cell inputs each slot was captured with.
pub struct SceneProbes {
    pub levels: wgpu::Texture,
    pub probes: Vec<ProbeTargets>,
    /// Per slot: the hash of everything its capture saw (lights, shadows, fixed objects,
    /// environment, pipeline) and when it was last used; a cell with the same inputs reuses it.
    slots: std::sync::Mutex<Vec<Option<(u64, u64)>>>,
    /// Per slot: the GPU time of its capture and prefilter, ms (a cell that reads the slot
    /// reports the cost of what it reads).
    times: std::sync::Mutex<Vec<Option<(f64, f64)>>>,
    uses: std::sync::atomic::AtomicU64,
}

/// Where a cell's probe levels are: a slot already captured with its inputs, or one to capture into.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Slot {
    Captured(usize),
    ToCapture(usize),
}

impl Slot {
    pub fn index(self) -> usize {
        match self {
            Slot::Captured(i) | Slot::ToCapture(i) => i,
        }
    }
}

impl SceneProbes {
    pub fn new(
        gpu: &GpuContext,
        prefilter: &Prefilter,
        probes: &[ReflectionProbe],
        sky: &prefilter::Probe,
    ) -> SceneProbes {
        let device = &gpu.device;
        let count = probes.len();
        let levels = level_texture(device, LEVELS * (1 + count * CAPTURE_SLOTS), wgpu::TextureUsages::empty());
        let sky_texels = sky_levels(sky);
        gpu.queue.write_texture(
            levels.as_image_copy(),
            bytemuck::cast_slice(&sky_texels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(PROBE_WIDTH as u32 * 8),
                rows_per_image: Some(PROBE_HEIGHT as u32),
            },
            wgpu::Extent3d {
                width: PROBE_WIDTH as u32,
                height: PROBE_HEIGHT as u32,
                depth_or_array_layers: LEVELS as u32,
            },
        );
        let probes = probes
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let r = p.resolution;
                let layered = |label: &str, format, layers: u32| {
                    device.create_texture(&wgpu::TextureDescriptor {
                        label: Some(label),
                        size: wgpu::Extent3d { width: r, height: r, depth_or_array_layers: layers },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format,
                        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                        view_formats: &[],
                    })
                };
                let faces = layered("probe faces", CAPTURE_FORMAT, 6);
                let roles = layered("probe roles", crate::render::formats::ROLE_FORMAT, 6);
                let depth = layered("probe depth", crate::render::formats::DEPTH_FORMAT, 1);
                let layer_views = |t: &wgpu::Texture| -> Vec<wgpu::TextureView> {
                    (0..6)
                        .map(|i| {
                            t.create_view(&wgpu::TextureViewDescriptor {
                                dimension: Some(wgpu::TextureViewDimension::D2),
                                base_array_layer: i,
                                array_layer_count: Some(1),
                                ..Default::default()
                            })
                        })
                        .collect()
                };
                let all_faces = faces.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                });
                let position = DVec3::from(p.position);
                let view_proj = face_view_proj(position, p.near);
                let steps = (0..CAPTURE_SLOTS)
                    .map(|slot| {
                        let first = first_layer(slot, k, count);
                        let faces = Some((&all_faces, view_proj, position));
                        [LobeWeight::CosineWeighted, LobeWeight::SmithMasked]
                            .map(|w| prefilter.steps(device, faces, (&levels, first), w))
                    })
                    .collect();
                ProbeTargets {
                    probe: p.clone(),
                    face_views: layer_views(&faces),
                    role_views: layer_views(&roles),
                    depth_view: depth.create_view(&Default::default()),
                    frame_buffers: (0..6)
                        .map(|_| {
                            device.create_buffer(&wgpu::BufferDescriptor {
                                label: Some("probe face frame"),
                                size: std::mem::size_of::<crate::render::uniforms::FrameUniforms>() as u64,
                                usage: gpu.constants.usage() | wgpu::BufferUsages::COPY_DST,
                                mapped_at_creation: false,
                            })
                        })
                        .collect(),
                    view_proj,
                    steps,
                }
            })
            .collect();
        SceneProbes {
            levels,
            probes,
            slots: std::sync::Mutex::new(vec![None; CAPTURE_SLOTS]),
            times: std::sync::Mutex::new(vec![None; CAPTURE_SLOTS]),
            uses: Default::default(),
        }
    }

    /// The slot holding a capture with inputs `key` (unless `reuse` is off), or the least recently
    /// used one to capture into.
    pub fn slot_for(&self, key: u64, reuse: bool) -> Slot {
        let now = self.uses.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        let mut slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = slots.iter().position(|s| reuse && s.is_some_and(|(k, _)| k == key)) {
            slots[i] = Some((key, now));
            return Slot::Captured(i);
        }
        let i = (0..slots.len()).min_by_key(|&i| slots[i].map_or(0, |(_, used)| used)).expect("slots");
        Slot::ToCapture(i)
    }

    /// Record that `slot` now holds the capture of inputs `key`, made in `times` (capture,
    /// prefilter; ms; None without timestamp queries).
    pub fn captured(&self, slot: usize, key: u64, times: Option<(f64, f64)>) {
        let now = self.uses.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        self.slots.lock().unwrap_or_else(|e| e.into_inner())[slot] = Some((key, now));
        self.times.lock().unwrap_or_else(|e| e.into_inner())[slot] = times;
    }

    /// The GPU time of the capture `slot` holds, ms.
    pub fn capture_times(&self, slot: usize) -> Option<(f64, f64)> {
        self.times.lock().unwrap_or_else(|e| e.into_inner())[slot]
    }

    pub fn view(&self) -> wgpu::TextureView {
        self.levels.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
    }

    /// Encode every probe's prefilter into capture slot `slot` (after its faces were drawn), the
    /// lobe weighed by `weight` (the pipeline's).
    pub fn encode_prefilter(
        &self,
        prefilter: &Prefilter,
        encoder: &mut wgpu::CommandEncoder,
        (slot, weight): (usize, LobeWeight),
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let steps = self.probes.iter().flat_map(|p| &p.steps[slot][weight.code() as usize]);
        crate::render::resources::encode_steps(
            encoder,
            crate::plan::Pass::ProbePrefilter.name(),
            &prefilter.pipeline,
            steps,
            timestamps,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefilter_params_mirror_the_wgsl_struct() {
        let source = crate::shading::wgsl::with_math(include_str!("../../shaders/pass/probe_prefilter.wgsl"));
        let (size, fields) = crate::mirror_layout!(PrefilterParams, [dims, level, faces, probe_position]);
        crate::gpu::layout::check_mirror(&source, "PrefilterParams", size, &fields).unwrap();
    }

    #[test]
    fn faces_cover_their_axes() {
        let vp = face_view_proj(DVec3::new(1.0, 2.0, 3.0), 0.3);
        let axes = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];
        for (m, a) in vp.iter().zip(axes) {
            let c = *m * (DVec3::new(1.0, 2.0, 3.0) + a * 5.0).extend(1.0);
            assert!(c.w > 0.0 && (c.x / c.w).abs() < 1e-9 && (c.y / c.w).abs() < 1e-9, "{a}: {c}");
        }
    }
}
