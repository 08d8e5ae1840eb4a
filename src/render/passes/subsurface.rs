//! HDRP's screen-space subsurface scattering for a Subsurface Scattering subject (plan::subsurface;
//! shaders/pass/subsurface.wgsl; f64 twin: `images::subsurface`), in two passes:
//! - the split lighting (`Pass::SubsurfaceLighting`): the forward pass drew the subject's specular
//!   alone (its pipeline's TERMS); this draws the subject again over its own depth (LEqual, no
//!   depth write: the positions are invariant) with its diffuse lighting and emission at the
//!   pre-scatter albedo into the SSS lighting buffer, and its albedo into the SSS buffer, as HDRP's
//!   forward pass writes both targets at once (ShaderPassForward.hlsl OUTPUT_SPLIT_LIGHTING) — one
//!   extra draw of the subject here;
//! - the filter (`Pass::SubsurfaceScattering`): SubsurfaceScattering.compute's sampling, its result
//!   added to the frame's colour as CombineLighting blends it, written to its own texture and
//!   copied back (a 32-bit float target is not read-write storage everywhere).
//!
//! A deferred HDRP cell draws such a subject in the forward-only pass (plan::cell: the G-buffer
//! here has no SSS buffer); its light loop is the deferred one's, so only the timing moves.

use bytemuck::{Pod, Zeroable};

use super::forward::{draw_objects, ForwardPipelines};
use super::FrameDraw;
use crate::declarations::scene::{Camera, Role};
use crate::error::Error;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
use crate::plan::subsurface::SubsurfacePlan;
use crate::plan::Pass;
use crate::render::formats::HDR_FORMAT;
use crate::render::prepared::PreparedScene;
use crate::render::targets::Targets;

/// What the filter reads of the frame and the profile (shaders/pass/subsurface.wgsl
/// `SubsurfaceFrame`; the twin reads it too).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct SubsurfaceFrame {
    pub dims: [u32; 4],
    pub camera: [f32; 4],
    pub shape: [f32; 4],
    pub kernel: [f32; 4],
}

impl SubsurfaceFrame {
    /// The filter's constants for a `width`×`height` frame seen by `camera`.
    pub fn new(camera: &Camera, (width, height): (u32, u32), plan: &SubsurfacePlan) -> SubsurfaceFrame {
        let p = &plan.profile;
        let pixel_size = 2.0 * (camera.fov_y_deg.to_radians() * 0.5).tan() / height as f64;
        SubsurfaceFrame {
            dims: [width, height, plan.sample_budget, 0],
            camera: [camera.near, camera.far, pixel_size, plan.mask].map(|v| v as f32),
            shape: [p.shape[0], p.shape[1], p.shape[2], p.max_scattering_distance].map(|v| v as f32),
            kernel: [p.filter_radius, p.world_scale, 0.0, 0.0].map(|v| v as f32),
        }
    }
}

/// The filter's compute pipeline, made once per renderer.
pub struct SubsurfacePipeline {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    space: crate::gpu::ConstantSpace,
}

impl SubsurfacePipeline {
    pub fn new(gpu: &GpuContext) -> Result<SubsurfacePipeline, Error> {
        let device = &gpu.device;
        let name = Pass::SubsurfaceScattering.name();
        let source = crate::shading::wgsl::with_math(include_str!("../../../shaders/pass/subsurface.wgsl"));
        let module = gpu.shader_module(name, &source)?;
        use crate::render::resources::compute_entry::{constants, float_2d, storage_2d};
        // The depth as an unfilterable float texture: a Depth32Float view binds there too (WebGPU's
        // depth formats are compatible with it), and a test feeds an R32Float one.
        let depth = float_2d(3);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(name),
            entries: &[
                constants(gpu.constants, 0),
                float_2d(1),
                float_2d(2),
                depth,
                float_2d(4),
                storage_2d(5, HDR_FORMAT),
            ],
        });
        let pipeline = crate::render::resources::compute_pipeline(device, name, &layout, &module, "cs_subsurface");
        Ok(SubsurfacePipeline { pipeline, layout, space: gpu.constants })
    }
}

/// The buffers of one frame size: the SSS lighting buffer, the SSS buffer (albedo), the filtered
/// frame, and the filter's bind group on the frame's colour and depth.
pub struct SubsurfaceBuffers {
    pub diffuse: wgpu::Texture,
    pub albedo: wgpu::Texture,
    pub output: wgpu::Texture,
    diffuse_view: wgpu::TextureView,
    albedo_view: wgpu::TextureView,
    params: wgpu::Buffer,
    group: wgpu::BindGroup,
    size: (u32, u32),
}

impl SubsurfaceBuffers {
    /// The buffers that filter into `color` with `depth` (both `size`, TEXTURE_BINDING).
    pub fn new(
        device: &wgpu::Device,
        pipeline: &SubsurfacePipeline,
        (color, depth): (&wgpu::Texture, &wgpu::Texture),
        size: (u32, u32),
    ) -> SubsurfaceBuffers {
        use wgpu::TextureUsages as U;
        let make = |label: &str, usage: U| crate::render::resources::texture_2d(device, label, size, HDR_FORMAT, usage);
        let diffuse =
            make("sss lighting buffer", U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST);
        let albedo = make("sss buffer", U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST);
        let output = make("subsurface scattered frame", U::STORAGE_BINDING | U::COPY_SRC);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("subsurface frame"),
            size: std::mem::size_of::<SubsurfaceFrame>() as u64,
            usage: pipeline.space.usage() | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let depth_view = view(depth);
        let (diffuse_view, albedo_view) = (view(&diffuse), view(&albedo));
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(Pass::SubsurfaceScattering.name()),
            layout: &pipeline.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&diffuse_view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&albedo_view) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&depth_view) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&view(color)) },
                wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::TextureView(&view(&output)) },
            ],
        });
        SubsurfaceBuffers { diffuse, albedo, output, diffuse_view, albedo_view, params, group, size }
    }

    pub fn write_frame(&self, queue: &wgpu::Queue, frame: &SubsurfaceFrame) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(frame));
    }

    /// The filter: `color` plus the scattered light into `output`, then copied into `color`
    /// (None: left in `output`).
    pub fn encode_scattering(
        &self,
        pipeline: &SubsurfacePipeline,
        encoder: &mut wgpu::CommandEncoder,
        color: Option<&wgpu::Texture>,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(Pass::SubsurfaceScattering.name()),
                timestamp_writes: timestamps,
            });
            pass.set_pipeline(&pipeline.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        }
        if let Some(color) = color {
            let extent = wgpu::Extent3d { width: self.size.0, height: self.size.1, depth_or_array_layers: 1 };
            encoder.copy_texture_to_texture(self.output.as_image_copy(), color.as_image_copy(), extent);
        }
    }
}

/// The split lighting: the subject's meshes drawn over the frame's depth with the pipelines of
/// `pipelines.subject` (forward.wgsl `fs_subsurface`) into the two SSS buffers, cleared first.
pub(in crate::render) fn encode_lighting(
    encoder: &mut wgpu::CommandEncoder,
    (prepared, draw): (&PreparedScene, &FrameDraw),
    pipelines: &ForwardPipelines,
    (buffers, depth): (&SubsurfaceBuffers, &wgpu::TextureView),
    timed: Option<(&PassTimer, u32)>,
) {
    let cleared = |view| {
        Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
        })
    };
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(Pass::SubsurfaceLighting.name()),
        color_attachments: &[cleared(&buffers.diffuse_view), cleared(&buffers.albedo_view)],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: timed.map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, draw.group, &[]);
    pass.set_bind_group(2, draw.screen, &[]);
    let subject = |i: usize| prepared.layout.meshes[i].role == Role::Subject;
    draw_objects(&mut pass, (prepared, draw), pipelines, &[], |i| draw.drawn[i] && subject(i));
}

/// The pass as a frame runs it: its pipeline (made for the first cell that scatters) and its
/// buffers on the frame's targets.
#[derive(Default)]
pub(in crate::render) struct SubsurfacePass {
    pipeline: Option<SubsurfacePipeline>,
    /// (the targets' generation, the buffers on their colour and depth)
    buffers: Option<(u64, SubsurfaceBuffers)>,
}

impl SubsurfacePass {
    /// Ready the pass for a frame on `targets` with the filter's constants.
    pub(in crate::render) fn prepare(
        &mut self,
        gpu: &GpuContext,
        targets: &Targets,
        frame: &SubsurfaceFrame,
    ) -> Result<(), Error> {
        if self.pipeline.is_none() {
            self.pipeline = Some(SubsurfacePipeline::new(gpu)?);
        }
        let pipeline = self.pipeline.as_ref().expect("just made");
        if self.buffers.as_ref().is_none_or(|(generation, _)| *generation != targets.generation) {
            let size = (targets.width, targets.height);
            let buffers = SubsurfaceBuffers::new(&gpu.device, pipeline, (&targets.color, &targets.depth), size);
            self.buffers = Some((targets.generation, buffers));
        }
        self.buffers.as_ref().expect("just made").1.write_frame(&gpu.queue, frame);
        Ok(())
    }

    pub(in crate::render) fn ready(&self) -> Option<(&SubsurfaceBuffers, &SubsurfacePipeline)> {
        Some((&self.buffers.as_ref()?.1, self.pipeline.as_ref()?))
    }
}

/// What the GPU filter adds to a black frame from given buffers (row-major, top row first; depth
/// wgpu's 0..1): what the tests hold against the twin.
pub fn scattered_of(
    gpu: &GpuContext,
    frame: &SubsurfaceFrame,
    (diffuse, albedo, depth): (&[[f32; 4]], &[[f32; 4]], &[f32]),
) -> Result<Vec<[f32; 4]>, Error> {
    let device = &gpu.device;
    let size = (frame.dims[0], frame.dims[1]);
    let pipeline = SubsurfacePipeline::new(gpu)?;
    use wgpu::TextureUsages as U;
    let color = crate::render::resources::texture_2d(device, "black frame", size, HDR_FORMAT, U::TEXTURE_BINDING);
    let depth_texture = crate::render::resources::texture_2d(
        device,
        "test depth",
        size,
        wgpu::TextureFormat::R32Float,
        U::TEXTURE_BINDING | U::COPY_DST,
    );
    let buffers = SubsurfaceBuffers::new(device, &pipeline, (&color, &depth_texture), size);
    let write = |texture: &wgpu::Texture, bytes: &[u8], texel: u32| {
        super::ssao::write_whole(gpu, texture, bytes, texel);
    };
    write(&buffers.diffuse, bytemuck::cast_slice(diffuse), 16);
    write(&buffers.albedo, bytemuck::cast_slice(albedo), 16);
    write(&depth_texture, bytemuck::cast_slice(depth), 4);
    buffers.write_frame(&gpu.queue, frame);
    let readback = crate::gpu::readback::TextureReadback::new(device, "subsurface scattered", size.0, size.1, 16);
    let mut encoder = device.create_command_encoder(&Default::default());
    buffers.encode_scattering(&pipeline, &mut encoder, None, None);
    readback.encode_copy(&mut encoder, &buffers.output);
    gpu.queue.submit([encoder.finish()]);
    gpu.wait_idle()?;
    let bytes = readback.read(device)?;
    gpu.check_errors("running the subsurface scattering filter on test input")?;
    Ok(bytemuck::cast_slice(&bytes).to_vec())
}
