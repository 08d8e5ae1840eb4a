//! URP's SSAO renderer feature (shaders/pass/urp_ssao.wgsl; f64 twin: `images::urp_ssao`), as the
//! High Fidelity renderer ships it (`pipelines::settings::UrpSsaoFeature`): the Alchemy
//! obscurance estimator over 12 interleaved-gradient samples at full resolution from the
//! DepthNormals prepass, then the bilateral blur (horizontal, vertical, final 5-tap), each step
//! into an 8-bit target as URP's ARGB32 and R8 ones (ScreenSpaceAmbientOcclusionPass.cs,
//! SSAO.hlsl). The lit shaders read the final visibility per pixel (shaders/pass/forward.wgsl:
//! indirect min(material, SSAO), direct lerp(1, SSAO, DirectLightingStrength)).
//!
//! URP's deferred renderer runs it after the G-buffer from the G-buffer's depth and normals; here
//! it runs after the DepthNormals prepass on both paths (the G-buffer pass reads it to fold the
//! occlusion into the light it stores, which Unity's first directional light pass multiplies
//! afterwards): the same depth, and normals quantised to 8 bits either way.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::declarations::scene::Camera;
use crate::error::Error;
use crate::gpu::GpuContext;
use crate::pipelines::settings::UrpSsaoFeature;
use crate::render::resources::ComputeStep;

/// URP's ARGB32 occlusion targets and R8 result, as 8-bit RGBA storage.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The steps in the order they run (urp_ssao.wgsl `step.mode`).
pub const OCCLUSION: u32 = 0;
pub const BLUR_HORIZONTAL: u32 = 1;
pub const BLUR_VERTICAL: u32 = 2;
pub const BLUR_FINAL: u32 = 3;

/// What the steps read of the camera and the feature (urp_ssao.wgsl `UrpSsaoFrame`; the twin
/// reads it too).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct UrpSsaoFrame {
    pub source_size: [f32; 4],
    pub params: [f32; 4],
    pub top_left: [f32; 4],
    pub x_extent: [f32; 4],
    pub y_extent: [f32; 4],
    pub camera: [f32; 4],
    pub view_proj0: [f32; 4],
    pub view_proj1: [f32; 4],
    pub view_z: [f32; 4],
}

impl UrpSsaoFrame {
    /// ScreenSpaceAmbientOcclusionPass SetupKeywordsAndParameters for a `width`×`height` frame
    /// seen by `camera`: the near plane's corners of proj·view without its translation, the
    /// view-projection's first two rows, _SSAOParams (intensity, radius as the Interleaved
    /// Gradient method passes it, 1/downsample = 1, falloff).
    pub fn new(camera: &Camera, width: u32, height: u32, feature: &UrpSsaoFeature) -> UrpSsaoFrame {
        let [right, up, back] = crate::render::passes::ssao::view_rows(camera);
        let tan = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let aspect = width as f64 / height as f64;
        let (half_h, half_w) = (camera.near * tan, camera.near * tan * aspect);
        let top_left = -back * camera.near - right * half_w + up * half_h;
        let (p00, p11) = (1.0 / (aspect * tan), 1.0 / tan);
        let f = |v: [f64; 4]| v.map(|x| x as f32);
        let v3 = |v: glam::DVec3, w: f64| f([v.x, v.y, v.z, w]);
        UrpSsaoFrame {
            source_size: f([width as f64, height as f64, 1.0 / width as f64, 1.0 / height as f64]),
            params: f([feature.intensity, feature.radius, 1.0, feature.falloff]),
            top_left: v3(top_left, 0.0),
            x_extent: v3(right * (2.0 * half_w), 0.0),
            y_extent: v3(-up * (2.0 * half_h), 0.0),
            camera: f([1.0 / camera.near, camera.near, camera.far, feature.samples as f64]),
            view_proj0: v3(right * p00, 0.0),
            view_proj1: v3(up * p11, 0.0),
            view_z: v3(back, 0.0),
        }
    }
}

/// The compute pipeline and its layout, made once per renderer.
pub struct UrpSsaoPipeline {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    space: crate::gpu::ConstantSpace,
}

impl UrpSsaoPipeline {
    pub fn new(gpu: &GpuContext) -> Result<UrpSsaoPipeline, Error> {
        let device = &gpu.device;
        let source = crate::shading::wgsl::with_math(include_str!("../../../shaders/pass/urp_ssao.wgsl"));
        let module = gpu.shader_module(crate::plan::Pass::UrpSsao.name(), &source)?;
        use crate::render::resources::compute_entry::{constants, float_2d, storage_2d, texture};
        let filterable = wgpu::TextureSampleType::Float { filterable: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("urp ssao steps"),
            entries: &[
                constants(gpu.constants, 0),
                texture(1, filterable, wgpu::TextureViewDimension::D2),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                storage_2d(3, FORMAT),
                constants(gpu.constants, 4),
                float_2d(5),
                float_2d(6),
            ],
        });
        let pipeline = crate::render::resources::compute_pipeline(
            device,
            crate::plan::Pass::UrpSsao.name(),
            &layout,
            &module,
            "cs_urp_ssao",
        );
        // sampler_BlitTexture: the targets' FilterMode.Bilinear, clamped
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("urp ssao bilinear"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        gpu.check_errors("creating the URP SSAO pipeline")?;
        Ok(UrpSsaoPipeline { pipeline, layout, sampler, space: gpu.constants })
    }
}

/// The targets and dispatches of one frame size.
pub struct UrpSsaoChain {
    /// The prepass's normal target.
    pub normal: wgpu::TextureView,
    /// The visibility (r) the lighting loads per pixel.
    pub visibility: wgpu::Texture,
    frame: wgpu::Buffer,
    steps: Vec<ComputeStep>,
}

impl UrpSsaoChain {
    /// The chain for `width`×`height` frames reading the prepass `depth` and `normal` targets
    /// (None: made here, for the caller to fill, as the tests do).
    pub fn new(
        device: &wgpu::Device,
        pipeline: &UrpSsaoPipeline,
        size: (u32, u32),
        depth: &wgpu::TextureView,
        normal: Option<wgpu::TextureView>,
    ) -> UrpSsaoChain {
        let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING;
        let make = |label: &str, extra: wgpu::TextureUsages| {
            crate::render::resources::texture_2d(device, label, size, FORMAT, usage | extra)
        };
        let occlusion = make("urp ssao occlusion", wgpu::TextureUsages::empty());
        let blurred = make("urp ssao blur", wgpu::TextureUsages::empty());
        let visibility = make("urp ssao visibility", wgpu::TextureUsages::COPY_SRC);
        let normal = normal.unwrap_or_else(|| {
            crate::render::resources::texture_2d(
                device,
                "urp ssao normals",
                size,
                crate::render::formats::NORMAL_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_DST,
            )
            .create_view(&Default::default())
        });
        let frame = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("urp ssao frame"),
            size: std::mem::size_of::<UrpSsaoFrame>() as u64,
            usage: pipeline.space.usage() | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        // The occlusion step reads no source; it binds the blur target, which it does not write.
        let steps = [
            (OCCLUSION, &blurred, &occlusion),
            (BLUR_HORIZONTAL, &occlusion, &blurred),
            (BLUR_VERTICAL, &blurred, &occlusion),
            (BLUR_FINAL, &occlusion, &visibility),
        ]
        .into_iter()
        .map(|(mode, source, destination)| {
            let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("urp ssao step"),
                contents: bytemuck::cast_slice(&[mode, 0, 0, 0]),
                usage: pipeline.space.usage(),
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("urp ssao step"),
                layout: &pipeline.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view(source)) },
                    wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&pipeline.sampler) },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&view(destination)),
                    },
                    wgpu::BindGroupEntry { binding: 4, resource: frame.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::TextureView(depth) },
                    wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::TextureView(&normal) },
                ],
            });
            ComputeStep { group, size }
        })
        .collect();
        UrpSsaoChain { normal, visibility, frame, steps }
    }

    /// The camera values of the next frame.
    pub fn write_frame(&self, queue: &wgpu::Queue, frame: &UrpSsaoFrame) {
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(frame));
    }

    /// The four steps, one compute pass (timed as one span).
    pub fn encode(
        &self,
        pipeline: &UrpSsaoPipeline,
        encoder: &mut wgpu::CommandEncoder,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let label = crate::plan::Pass::UrpSsao.name();
        crate::render::resources::encode_steps(encoder, label, &pipeline.pipeline, &self.steps, timestamps);
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
    frame: &UrpSsaoFrame,
) -> Result<Vec<f32>, Error> {
    let device = &gpu.device;
    let pipeline = UrpSsaoPipeline::new(gpu)?;
    let depth_texture = crate::render::resources::texture_2d(
        device,
        "urp ssao test depth",
        (width, height),
        wgpu::TextureFormat::R32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    let normal_texture = super::ssao::test_normals(gpu, (width, height), encoded_normals);
    let depth_view = depth_texture.create_view(&Default::default());
    let normal_view = normal_texture.create_view(&Default::default());
    let chain = UrpSsaoChain::new(device, &pipeline, (width, height), &depth_view, Some(normal_view));
    super::ssao::write_whole(gpu, &depth_texture, bytemuck::cast_slice(depth), 4);
    chain.write_frame(&gpu.queue, frame);
    let readback = crate::gpu::readback::TextureReadback::new(device, "urp ssao visibility", width, height, 4);
    let mut encoder = device.create_command_encoder(&Default::default());
    chain.encode(&pipeline, &mut encoder, None);
    readback.encode_copy(&mut encoder, &chain.visibility);
    gpu.queue.submit([encoder.finish()]);
    gpu.wait_idle()?;
    let bytes = readback.read(device)?;
    gpu.check_errors("running URP's SSAO on test input")?;
    Ok(bytes.chunks(4).map(|t| t[0] as f32 / 255.0).collect())
}

/// URP's SSAO as a frame runs it.
pub(in crate::render) type UrpSsaoPass = super::ssao::OcclusionPass<UrpSsaoPipeline, UrpSsaoChain>;

impl UrpSsaoPass {
    /// Ready the pass for a frame on `targets` seen by `camera`, with the renderer's `feature`.
    pub(in crate::render) fn prepare(
        &mut self,
        gpu: &GpuContext,
        screen_layout: &wgpu::BindGroupLayout,
        targets: &crate::render::targets::Targets,
        camera: &Camera,
        feature: &UrpSsaoFeature,
    ) -> Result<(), Error> {
        let chain = self.ensure(
            targets,
            0,
            || UrpSsaoPipeline::new(gpu),
            |pipeline| {
                let size = (targets.width, targets.height);
                let chain = UrpSsaoChain::new(&gpu.device, pipeline, size, &targets.depth_view, None);
                let group = super::ssao::screen_group(&gpu.device, screen_layout, &chain.visibility);
                (chain, group)
            },
        )?;
        chain.write_frame(&gpu.queue, &UrpSsaoFrame::new(camera, targets.width, targets.height, feature));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_corners_reconstruct_the_view_ray_and_project_back() {
        let camera =
            Camera { position: [1.0, 2.0, 5.0], target: [0.0, 0.5, 0.0], fov_y_deg: 50.0, near: 0.3, far: 80.0 };
        let f = UrpSsaoFrame::new(&camera, 320, 200, &UrpSsaoFeature::HIGH_FIDELITY);
        let v = |a: [f32; 4]| glam::DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
        // ReconstructViewPos at uv (0.5, 0.5) and depth d: d along the view direction.
        let centre = (v(f.top_left) + v(f.x_extent) * 0.5 + v(f.y_extent) * 0.5) * (7.0 / camera.near);
        let dir = (glam::DVec3::from(camera.target) - glam::DVec3::from(camera.position)).normalize();
        assert!((centre - dir * 7.0).length() < 1e-4, "{centre:?}");
        // A point at uv (0.8, 0.3) projects back to it through the view-projection rows.
        let (u, w) = (0.8, 0.3);
        let p = (v(f.top_left) + v(f.x_extent) * u + v(f.y_extent) * (1.0 - w)) * (4.0 * f.camera[0] as f64);
        let z = -v(f.view_z).dot(p);
        assert!((z - 4.0).abs() < 1e-4, "{z}");
        let back = ((v(f.view_proj0).dot(p) / z + 1.0) * 0.5, (v(f.view_proj1).dot(p) / z + 1.0) * 0.5);
        assert!((back.0 - u).abs() < 1e-5 && (back.1 - w).abs() < 1e-5, "{back:?}");
        assert_eq!(f.params, [0.5, 0.25, 1.0, 100.0]);
        assert_eq!(f.camera[3], 12.0);
    }
}
