//! HDRP's screen-space ambient occlusion (shaders/pass/ssao.wgsl; f64 twin: `images::ssao`).
//! HDRP's default volume profile enables its AmbientOcclusion override with intensity 0.5 and
//! radius 1.5 at the Medium quality level: 6 steps, 2 directions, a 40-pixel radius cap (scaled
//! with resolution), half resolution with a bilateral upsample (HDRenderPipeline.AmbientOcclusion.cs
//! PrepareRenderAOParameters; GlobalLightingQualitySettings). The lighting reads the result as the
//! indirect light's occlusion (shaders/pass/forward.wgsl `indirect_light`); the direct light is not
//! occluded (direct lighting strength 0).
//!
//! HDRP's default (temporalAccumulation on) traces one direction per frame, rotated and offset
//! frame by frame, and accumulates them in a history; this renders each cell's frames without AO
//! history, so it runs HDRP's non-temporal path, both directions every frame. What the temporal
//! path converges to (`images::ssao::temporal_visibility`, 24 frames averaged) is darker: on the
//! test's crease frame by 0.020 in mean visibility (mean |Δ| 0.026, worst 0.32;
//! tests/e2e/ssao.rs).
//!
//! The depth-normal prepass that feeds it draws into `normal` and the frame's depth; the compute
//! steps copy that depth into a float texture (so the steps can also be fed directly in tests),
//! build two closest-depth levels, search horizons at half resolution and upsample.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3};
use wgpu::util::DeviceExt;

use crate::declarations::scene::Camera;
use crate::error::Error;
use crate::gpu::GpuContext;
use crate::render::resources::ComputeStep;

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

const CLOSEST: u32 = 1;
const HORIZONS: u32 = 2;
const UPSAMPLE: u32 = 3;
const HORIZONS_FULL: u32 = 4;
const SPATIAL_DENOISE: u32 = 5;

/// The AmbientOcclusion override as HDRP's default profile sets it, at a quality level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SsaoSettings {
    pub intensity: f64,
    /// World-space radius of the horizon search, metres.
    pub radius: f64,
    pub step_count: u32,
    pub direction_count: u32,
    /// At 960×540 running resolution; scaled by √(pixels / 960·540), at least 16.
    pub maximum_radius_in_pixels: f64,
    /// Whether the horizon search runs at the frame's resolution (then GTAOSpatialDenoise
    /// filters it, without an upsample) or at half of it (then BilateralUpsample brings it up).
    pub full_resolution: bool,
    /// The spatial denoise's depth rejection (ScreenSpaceAmbientOcclusion's default 0.15; the
    /// shader reads it × 15).
    pub spatial_bilateral_aggressiveness: f64,
}

impl Default for SsaoSettings {
    fn default() -> Self {
        SsaoSettings {
            intensity: 0.5,
            radius: 1.5,
            step_count: 6,
            direction_count: 2,
            maximum_radius_in_pixels: 40.0,
            full_resolution: false,
            spatial_bilateral_aggressiveness: 0.15,
        }
    }
}

impl SsaoSettings {
    /// The default profile's override at a quality level (GlobalLightingQualitySettings: AOStepCount
    /// 4 / 6 / 16, AODirectionCount 1 / 2 / 4, AOMaximumRadiusPixels 32 / 40 / 80, AOFullRes off /
    /// off / on). Low and Medium run the same half-resolution steps (AOBilateralUpsample picks an
    /// upsample for the temporal path alone); High searches at full resolution and filters with
    /// GTAOSpatialDenoise (HDRenderPipeline.AmbientOcclusion.cs RenderAmbientOcclusion).
    pub fn at(quality: crate::pipelines::settings::HdrpQuality) -> SsaoSettings {
        use crate::pipelines::settings::HdrpQuality;
        match quality {
            HdrpQuality::Low => {
                SsaoSettings { step_count: 4, direction_count: 1, maximum_radius_in_pixels: 32.0, ..Default::default() }
            }
            HdrpQuality::Medium => SsaoSettings::default(),
            HdrpQuality::High => SsaoSettings {
                step_count: 16,
                direction_count: 4,
                maximum_radius_in_pixels: 80.0,
                full_resolution: true,
                ..Default::default()
            },
        }
    }
}

/// What the steps read of the camera (shaders/pass/ssao.wgsl `SsaoFrame`; the twin reads it too).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct SsaoFrame {
    pub buffer_size: [f32; 4],
    pub params0: [f32; 4],
    pub params1: [f32; 4],
    pub depth_to_view: [f32; 4],
    pub z_buffer: [f32; 4],
    pub view_x: [f32; 4],
    pub view_y: [f32; 4],
    pub view_z: [f32; 4],
}

/// The world-to-view rotation rows of `camera` (right-handed, looking down −z: Unity's view space).
pub fn view_rows(camera: &Camera) -> [DVec3; 3] {
    let view: DMat4 = crate::plan::camera::view_matrix(camera);
    let r = view.transpose();
    [r.x_axis.truncate(), r.y_axis.truncate(), r.z_axis.truncate()]
}

impl SsaoFrame {
    /// PrepareRenderAOParameters for a `width`×`height` frame seen by `camera`, at the running
    /// resolution `s` asks for: the frame's, or half of it.
    pub fn new(camera: &Camera, width: u32, height: u32, s: &SsaoSettings) -> SsaoFrame {
        let (rw, rh) =
            if s.full_resolution { (width as f64, height as f64) } else { (width as f64 * 0.5, height as f64 * 0.5) };
        let inv_half_tan_fov = 1.0 / (camera.fov_y_deg.to_radians() * 0.5).tan();
        let aspect = rh / rw;
        let scale = rw * rh / (540.0 * 960.0);
        let radius_in_pixels = (s.maximum_radius_in_pixels * scale.sqrt()).max(16.0);
        let f = |v: [f64; 4]| v.map(|x| x as f32);
        let [x, y, z] = view_rows(camera);
        SsaoFrame {
            buffer_size: f([rw, rh, width as f64, height as f64]),
            params0: f([
                rh * inv_half_tan_fov * 0.25,
                s.radius,
                s.step_count as f64,
                1.0 / (s.step_count as f64 + 1.0),
            ]),
            params1: f([s.intensity, 1.0 / (s.radius * s.radius), s.direction_count as f64, radius_in_pixels.floor()]),
            depth_to_view: f([
                2.0 / (inv_half_tan_fov * aspect * rw),
                2.0 / (inv_half_tan_fov * rh),
                1.0 / (inv_half_tan_fov * aspect),
                1.0 / inv_half_tan_fov,
            ]),
            z_buffer: f([camera.near, camera.far, s.spatial_bilateral_aggressiveness * 15.0, 0.0]),
            view_x: f([x.x, x.y, x.z, 0.0]),
            view_y: f([y.x, y.y, y.z, 0.0]),
            view_z: f([z.x, z.y, z.z, 0.0]),
        }
    }
}

/// The sizes of the steps' textures for a frame: full, level 1 (half; also the horizon search's
/// running resolution) and level 2.
pub fn level_sizes(width: u32, height: u32) -> [(u32, u32); 3] {
    let half = |(w, h): (u32, u32)| (w.div_ceil(2).max(1), h.div_ceil(2).max(1));
    let l1 = half((width, height));
    [(width, height), l1, half(l1)]
}

/// The compute pipelines, made once per renderer.
pub struct SsaoPipeline {
    steps: wgpu::ComputePipeline,
    steps_layout: wgpu::BindGroupLayout,
    copy: wgpu::ComputePipeline,
    copy_layout: wgpu::BindGroupLayout,
    space: crate::gpu::ConstantSpace,
}

impl SsaoPipeline {
    pub fn new(gpu: &GpuContext) -> Result<SsaoPipeline, Error> {
        let device = &gpu.device;
        let source = crate::shading::wgsl::with_math(include_str!("../../../shaders/pass/ssao.wgsl"));
        let module = gpu.shader_module(crate::plan::Pass::Ssao.name(), &source)?;
        use crate::render::resources::compute_entry::{constants, float_2d, storage_2d, texture};
        let steps_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ssao steps"),
            entries: &[
                constants(gpu.constants, 0),
                float_2d(1),
                float_2d(2),
                float_2d(3),
                storage_2d(4, FORMAT),
                constants(gpu.constants, 5),
            ],
        });
        let depth = texture(6, wgpu::TextureSampleType::Depth, wgpu::TextureViewDimension::D2);
        let copy_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ssao depth copy"),
            entries: &[depth, storage_2d(7, FORMAT)],
        });
        let steps = crate::render::resources::compute_pipeline(
            device,
            crate::plan::Pass::Ssao.name(),
            &steps_layout,
            &module,
            "cs_ssao",
        );
        let copy = crate::render::resources::compute_pipeline(
            device,
            "ssao depth copy",
            &copy_layout,
            &module,
            "cs_depth_copy",
        );
        gpu.check_errors("creating the SSAO pipelines")?;
        Ok(SsaoPipeline { steps, steps_layout, copy, copy_layout, space: gpu.constants })
    }
}

/// The textures and dispatches of one frame size and running resolution: the depth copy, the
/// closest-depth levels, the packed AO and the full-resolution visibility the lighting reads.
pub struct SsaoChain {
    /// The prepass's normal target.
    pub normal: wgpu::TextureView,
    /// The visibility (r) the lighting loads per pixel.
    pub visibility: wgpu::Texture,
    frame: wgpu::Buffer,
    copy: Option<ComputeStep>,
    steps: Vec<ComputeStep>,
}

impl SsaoChain {
    /// The chain for `width`×`height` frames searched at full or half resolution. `depth`: the
    /// prepass depth it copies (None: the caller fills the returned full-resolution depth texture
    /// itself, as the tests do).
    pub fn new(
        device: &wgpu::Device,
        pipeline: &SsaoPipeline,
        (width, height): (u32, u32),
        full_resolution: bool,
        depth: Option<&wgpu::TextureView>,
        normal: Option<wgpu::TextureView>,
    ) -> (SsaoChain, wgpu::Texture) {
        let storage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING;
        let make = |label: &str, size: (u32, u32), extra: wgpu::TextureUsages| {
            crate::render::resources::texture_2d(device, label, size, FORMAT, storage | extra)
        };
        let [full, l1, l2] = level_sizes(width, height);
        let depth0 = make("ssao depth", full, wgpu::TextureUsages::COPY_DST);
        let level1 = make("ssao depth level 1", l1, wgpu::TextureUsages::empty());
        let running = if full_resolution { full } else { l1 };
        let packed = make("ssao packed", running, wgpu::TextureUsages::empty());
        let visibility = make("ssao visibility", full, wgpu::TextureUsages::COPY_SRC);
        let normal = normal.unwrap_or_else(|| {
            crate::render::resources::texture_2d(
                device,
                "ssao normals",
                full,
                crate::render::formats::NORMAL_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
            .create_view(&Default::default())
        });
        let frame = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ssao frame"),
            size: std::mem::size_of::<SsaoFrame>() as u64,
            usage: pipeline.space.usage() | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let copy = depth.map(|d| ComputeStep {
            group: device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ssao depth copy"),
                layout: &pipeline.copy_layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::TextureView(d) },
                    wgpu::BindGroupEntry { binding: 7, resource: wgpu::BindingResource::TextureView(&view(&depth0)) },
                ],
            }),
            size: full,
        });
        let step = |mode: u32,
                    source: &wgpu::Texture,
                    coarse: &wgpu::Texture,
                    dst: &wgpu::Texture,
                    size: (u32, u32)| {
            let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ssao step"),
                contents: bytemuck::cast_slice(&[size.0, size.1, mode, 0]),
                usage: pipeline.space.usage(),
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ssao step"),
                layout: &pipeline.steps_layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view(source)) },
                    wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&view(coarse)) },
                    wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&normal) },
                    wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&view(dst)) },
                    wgpu::BindGroupEntry { binding: 5, resource: frame.as_entire_binding() },
                ],
            });
            ComputeStep { group, size }
        };
        // Full resolution reads levels 0 and 1 alone (GTAOCommon.hlsl FULL_RES has no
        // LOWER_RES_SAMPLE), so level 2 is left out.
        let steps = if full_resolution {
            vec![
                step(CLOSEST, &depth0, &depth0, &level1, l1),
                step(HORIZONS_FULL, &depth0, &level1, &packed, full),
                step(SPATIAL_DENOISE, &packed, &packed, &visibility, full),
            ]
        } else {
            let level2 = make("ssao depth level 2", l2, wgpu::TextureUsages::empty());
            vec![
                step(CLOSEST, &depth0, &depth0, &level1, l1),
                step(CLOSEST, &level1, &level1, &level2, l2),
                step(HORIZONS, &level1, &level2, &packed, l1),
                step(UPSAMPLE, &packed, &depth0, &visibility, full),
            ]
        };
        (SsaoChain { normal, visibility, frame, copy, steps }, depth0)
    }

    /// The camera values of the next frame.
    pub fn write_frame(&self, queue: &wgpu::Queue, frame: &SsaoFrame) {
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(frame));
    }

    /// The depth copy and the steps, one compute pass (timed as one span).
    pub fn encode(
        &self,
        pipeline: &SsaoPipeline,
        encoder: &mut wgpu::CommandEncoder,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(crate::plan::Pass::Ssao.name()),
            timestamp_writes: timestamps,
        });
        let mut run = |p: &wgpu::ComputePipeline, s: &ComputeStep| {
            pass.set_pipeline(p);
            pass.set_bind_group(0, &s.group, &[]);
            pass.dispatch_workgroups(s.size.0.div_ceil(8), s.size.1.div_ceil(8), 1);
        };
        if let Some(copy) = &self.copy {
            run(&pipeline.copy, copy);
        }
        for s in &self.steps {
            run(&pipeline.steps, s);
        }
    }
}

/// The visibility the GPU steps compute from a raw depth buffer (wgpu's 0..1, row-major, top row
/// first) and world normals encoded as the prepass writes them (n·0.5 + 0.5 per channel): what
/// the tests hold against the twin.
pub fn visibility_of(
    gpu: &GpuContext,
    (width, height): (u32, u32),
    depth: &[f32],
    encoded_normals: &[[f32; 3]],
    frame: &SsaoFrame,
    full_resolution: bool,
) -> Result<Vec<f32>, Error> {
    let device = &gpu.device;
    let pipeline = SsaoPipeline::new(gpu)?;
    let normal_texture = test_normals(gpu, (width, height), encoded_normals);
    let normal_view = Some(normal_texture.create_view(&Default::default()));
    let (chain, depth0) = SsaoChain::new(device, &pipeline, (width, height), full_resolution, None, normal_view);
    let depth_texels: Vec<[f32; 2]> = depth.iter().map(|&d| [d, 0.0]).collect();
    write_whole(gpu, &depth0, bytemuck::cast_slice(&depth_texels), 8);
    chain.write_frame(&gpu.queue, frame);
    let readback = crate::gpu::readback::TextureReadback::new(device, "ssao visibility", width, height, 8);
    let mut encoder = device.create_command_encoder(&Default::default());
    chain.encode(&pipeline, &mut encoder, None);
    readback.encode_copy(&mut encoder, &chain.visibility);
    gpu.queue.submit([encoder.finish()]);
    gpu.wait_idle()?;
    let bytes = readback.read(device)?;
    let texels: &[[f32; 2]] = bytemuck::cast_slice(&bytes);
    gpu.check_errors("running SSAO on test input")?;
    Ok(texels.iter().map(|t| t[0]).collect())
}

/// The prepass normals a test feeds an SSAO chain: `encoded` (n·0.5 + 0.5) in a float texture.
pub(crate) fn test_normals(gpu: &GpuContext, size: (u32, u32), encoded: &[[f32; 3]]) -> wgpu::Texture {
    let texture = crate::render::resources::texture_2d(
        &gpu.device,
        "ssao test normals",
        size,
        wgpu::TextureFormat::Rgba32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    let texels: Vec<[f32; 4]> = encoded.iter().map(|n| [n[0], n[1], n[2], 1.0]).collect();
    write_whole(gpu, &texture, bytemuck::cast_slice(&texels), 16);
    texture
}

/// `bytes`, rows of `texel`-byte texels, into the whole of `texture`.
pub(crate) fn write_whole(gpu: &GpuContext, texture: &wgpu::Texture, bytes: &[u8], texel: u32) {
    let size = texture.size();
    gpu.queue.write_texture(
        texture.as_image_copy(),
        bytes,
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(size.width * texel), rows_per_image: None },
        size,
    );
}

/// A screen-space occlusion pass across a run's cells: its pipelines (made for the first cell that
/// occludes), its chain on the frame's targets with the screen group the lighting reads the
/// visibility through, and the key of the prepass and SSAO whose visibility the chain holds.
/// HDRP's (`SsaoPass`) and URP's (`urp_ssao::UrpSsaoPass`) differ in their pipeline and chain.
pub(in crate::render) struct OcclusionPass<P, C> {
    pipeline: Option<P>,
    /// ((the targets' generation, the chain's variant), the chain on their depth, the group
    /// reading its visibility)
    chain: Option<((u64, u64), C, wgpu::BindGroup)>,
    holds: Option<u64>,
}

impl<P, C> Default for OcclusionPass<P, C> {
    fn default() -> Self {
        OcclusionPass { pipeline: None, chain: None, holds: None }
    }
}

impl<P, C> OcclusionPass<P, C> {
    /// The pipeline (`make` for the first frame) and the chain on `targets` (`chain` where the
    /// targets are new or the frame needs another `variant` of it: a new chain holds nothing yet).
    pub(in crate::render) fn ensure(
        &mut self,
        targets: &crate::render::targets::Targets,
        variant: u64,
        make: impl FnOnce() -> Result<P, Error>,
        chain: impl FnOnce(&P) -> (C, wgpu::BindGroup),
    ) -> Result<&C, Error> {
        if self.pipeline.is_none() {
            self.pipeline = Some(make()?);
        }
        let pipeline = self.pipeline.as_ref().expect("just made");
        let key = (targets.generation, variant);
        if self.chain.as_ref().is_none_or(|(held, _, _)| *held != key) {
            let (c, group) = chain(pipeline);
            self.chain = Some((key, c, group));
            self.holds = None;
        }
        Ok(&self.chain.as_ref().expect("just made").1)
    }

    /// Whether the prepass and SSAO must run for a frame whose inputs hash to `key`: not where
    /// `reuse` lets the frame keep what the chain holds from the cell before.
    pub(in crate::render) fn needed(&mut self, key: u64, reuse: bool) -> bool {
        let kept = reuse && self.holds == Some(key);
        self.holds = Some(key);
        !kept
    }

    /// The prepared chain, its pipelines and the screen group reading its visibility.
    pub(in crate::render) fn ready(&self) -> Option<(&C, &P, &wgpu::BindGroup)> {
        let (_, chain, group) = self.chain.as_ref()?;
        Some((chain, self.pipeline.as_ref()?, group))
    }
}

/// HDRP's SSAO as a frame runs it.
pub(in crate::render) type SsaoPass = OcclusionPass<SsaoPipeline, SsaoChain>;

impl SsaoPass {
    /// Ready the pass for a frame on `targets` seen by `camera`.
    pub(in crate::render) fn prepare(
        &mut self,
        gpu: &GpuContext,
        screen_layout: &wgpu::BindGroupLayout,
        targets: &crate::render::targets::Targets,
        camera: &Camera,
        settings: &SsaoSettings,
    ) -> Result<(), Error> {
        let full = settings.full_resolution;
        let chain = self.ensure(
            targets,
            full as u64,
            || SsaoPipeline::new(gpu),
            |pipeline| {
                let size = (targets.width, targets.height);
                let (chain, _) = SsaoChain::new(&gpu.device, pipeline, size, full, Some(&targets.depth_view), None);
                let group = screen_group(&gpu.device, screen_layout, &chain.visibility);
                (chain, group)
            },
        )?;
        let frame = SsaoFrame::new(camera, targets.width, targets.height, settings);
        chain.write_frame(&gpu.queue, &frame);
        Ok(())
    }
}

/// The screen group over an SSAO visibility texture.
pub(in crate::render) fn screen_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    visibility: &wgpu::Texture,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("screen"),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 6,
            resource: wgpu::BindingResource::TextureView(&visibility.create_view(&Default::default())),
        }],
    })
}

/// The screen group of a frame without SSAO: a 1×1 visibility of 1.
pub(in crate::render) fn neutral_screen_group(gpu: &GpuContext, layout: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
    let texture = crate::render::resources::texture_2d(
        &gpu.device,
        "no ssao",
        (1, 1),
        wgpu::TextureFormat::Rg32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    gpu.queue.write_texture(
        texture.as_image_copy(),
        bytemuck::cast_slice(&[1.0f32, 0.0]),
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(8), rows_per_image: None },
        wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
    );
    screen_group(&gpu.device, layout, &texture)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_follow_prepare_render_ao_parameters() {
        let camera = Camera { position: [0.0, 0.0, 5.0], target: [0.0; 3], fov_y_deg: 60.0, near: 0.1, far: 100.0 };
        let f = SsaoFrame::new(&camera, 384, 256, &SsaoSettings::default());
        assert_eq!(f.buffer_size[..2], [192.0, 128.0]);
        // runningRes.y·cot(fov/2)·0.25
        let cot = 1.0 / 30f64.to_radians().tan();
        assert!((f.params0[0] as f64 - 128.0 * cot * 0.25).abs() < 1e-4);
        // √(192·128/(960·540)) · 40 < 16: the floor holds
        assert_eq!(f.params1[3], 16.0);
        assert!((f.params1[1] - 1.0 / 2.25).abs() < 1e-7);
        // The pixel at the running resolution's centre maps to the view axis.
        let c = [96.0 * f.depth_to_view[0] - f.depth_to_view[2], 64.0 * f.depth_to_view[1] - f.depth_to_view[3]];
        assert!(c[0].abs() < 1e-6 && c[1].abs() < 1e-6, "{c:?}");
        assert_eq!(level_sizes(384, 256), [(384, 256), (192, 128), (96, 64)]);
        assert_eq!(level_sizes(5, 3), [(5, 3), (3, 2), (2, 1)]);
    }
}
