//! Ground truth: a GPU path tracer over the cell's own scene (shaders/pass/truth.wgsl), so a
//! cell's error is measured against the light its lights and materials really make rather than
//! against another real-time pipeline.
//!
//! The `same-brdf` truth evaluates each surface with the model the cell draws it with (the
//! subject's model, the pipeline's fixed-object model) in the cell's light units and attenuation:
//! its difference from the cell isolates the real-time approximations (SH ambient, split-sum
//! probe, shadow maps, light budgets, missing bounces, aliasing). The `physical` truth shades every
//! surface with one physical model (`physical`, shaders/pass/truth_physical.wgsl) under
//! inverse-square light, so its difference adds each model's departure from physics. Every light is exact with
//! ray-traced visibility; the environment is importance-sampled from a 1024×512 equirect of the
//! sky and weighted against surface sampling by the power heuristic; paths continue `bounces`
//! times. Samples are drawn in batches until the subject's mean standard error falls below
//! `noise` × its mean, or `spp` is reached; the per-pixel standard error is kept with the image.
//!
//! Written here rather than taken from a crate: no maintained crate traces WGSL models on wgpu;
//! the BVH comes from `obvhs`.

pub mod bake;
pub mod bvh;
pub mod cpu;
pub mod export;
pub mod physical;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use wgpu::util::DeviceExt;

use crate::environment::prefilter::EquirectImage;
use crate::error::Error;
use crate::gpu::{ConstantSpace, GpuContext};

/// Width of the environment table the truth samples (height is half).
pub const ENV_WIDTH: usize = 1024;

pub use crate::declarations::matrix::{TruthKind, TruthSettings};

/// A rendered truth: the mean radiance per pixel in the cell's linear units, the standard error
/// of that mean per pixel (of its luminance), and what convergence reached.
#[derive(Debug, Clone)]
pub struct Truth {
    pub width: u32,
    pub height: u32,
    pub mean: Vec<[f32; 3]>,
    pub std_error: Vec<f32>,
    /// The role of the first surface per pixel (0 none).
    pub roles: Vec<u8>,
    pub kind: TruthKind,
    pub spp: u32,
    pub bounces: u32,
    /// The subject's mean standard error over its mean luminance (None: no subject pixel).
    pub subject_noise: Option<f64>,
    pub seconds: f64,
    /// Reused from the truth cache rather than traced for this cell.
    pub cached: bool,
    /// The truth store's key and entry digest (`run::truth_cache`), once stored or taken from
    /// there: what the cell's record keeps, so that a cell compared with this truth is not reused
    /// once the truth under that key is another.
    pub stored: Option<(String, String)>,
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct TruthParams {
    dims: [u32; 4],
    settings: [u32; 4],
}

/// The environment's radiance texels and the sampling tables (marginal over rows, then each row's
/// conditional over columns), weighted by luminance × sin θ so that texels are drawn in
/// proportion to the light they send.
fn environment_tables(image: &EquirectImage) -> (Vec<[f32; 4]>, Vec<f32>) {
    let (w, h) = (image.width, image.height);
    let luminance = |c: DVec3| 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
    let mut rows = Vec::with_capacity(h + 1);
    let mut conditional = Vec::with_capacity(h * (w + 1));
    let mut row_total = 0.0;
    rows.push(0.0);
    for y in 0..h {
        let sin = ((y as f64 + 0.5) / h as f64 * std::f64::consts::PI).sin();
        let weights: Vec<f64> = (0..w).map(|x| luminance(image.texels[y * w + x]).max(0.0) * sin).collect();
        let sum: f64 = weights.iter().sum();
        let mut acc = 0.0;
        conditional.push(0.0f32);
        for (x, wgt) in weights.iter().enumerate() {
            acc += if sum > 0.0 { wgt / sum } else { 1.0 / w as f64 };
            conditional.push(if x + 1 == w { 1.0 } else { acc as f32 });
        }
        row_total += sum;
        rows.push(row_total);
    }
    let marginal: Vec<f32> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            if i == h {
                1.0
            } else if row_total > 0.0 {
                (r / row_total) as f32
            } else {
                i as f32 / h as f32
            }
        })
        .collect();
    let texels = image.texels.iter().map(|c| [c.x as f32, c.y as f32, c.z as f32, 0.0]).collect();
    (texels, [marginal, conditional].concat())
}

/// The tracer's pipeline for one (pipeline, subject model, fixed model), and its group layout.
pub struct TruthPipeline {
    pub pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// The layout of the tracer's own group (group 1).
pub fn group_layout(device: &wgpu::Device, space: ConstantSpace) -> wgpu::BindGroupLayout {
    use super::resources::compute_entry::{constants, read_only_storage, read_write_storage};
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("truth"),
        entries: &[
            constants(space, 0),
            read_only_storage(1),
            read_write_storage(2),
            read_write_storage(3),
            read_only_storage(4),
            read_only_storage(5),
        ],
    })
}

/// The layout of the scene as rays see it (shaders/pass/rays.wgsl, group 3 of the tracer and of
/// the forward pipelines with exact alternatives): bindings 10–17.
pub fn ray_layout(device: &wgpu::Device, space: ConstantSpace) -> wgpu::BindGroupLayout {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    };
    let storage = wgpu::BufferBindingType::Storage { read_only: true };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("rays"),
        entries: &[
            entry(10, space.binding()),
            entry(11, storage),
            entry(12, storage),
            entry(13, storage),
            entry(14, storage),
            entry(15, storage),
            entry(16, storage),
            entry(17, storage),
        ],
    })
}

impl TruthPipeline {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &GpuContext,
        frame_layout: &wgpu::BindGroupLayout,
        ray_layout: &wgpu::BindGroupLayout,
        source: &str,
        pipeline_id: u32,
        kind: TruthKind,
        diffuse_only: [bool; 2],
        entry: &str,
    ) -> Result<TruthPipeline, Error> {
        let device = &gpu.device;
        let module = gpu.shader_module("truth", source)?;
        let layout = group_layout(device, gpu.constants);
        let constants = [
            ("PIPELINE", pipeline_id as f64),
            ("TRUTH_KIND", (kind == TruthKind::Physical) as u32 as f64),
            ("SUBJECT_DIFFUSE_ONLY", diffuse_only[0] as u32 as f64),
            ("FIXED_DIFFUSE_ONLY", diffuse_only[1] as u32 as f64),
        ];
        let pipeline =
            ray_compute_pipeline(device, entry, &module, [frame_layout, &layout, ray_layout], entry, &constants);
        gpu.check_errors("creating the truth pipeline")?;
        Ok(TruthPipeline { pipeline, layout })
    }
}

/// A compute pipeline over the frame (group 0), its own group (1) and the rays (3).
pub fn ray_compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    [frame, own, rays]: [&wgpu::BindGroupLayout; 3],
    entry: &str,
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(frame), Some(own), None, Some(rays)],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
        cache: None,
    })
}

/// A composition's geometry on the GPU (BVH, triangles, vertices) with its environment: the rays'
/// bind group (group 3), uploaded once and shared by its cells' truths and exact alternatives.
pub struct TruthScene {
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
    vertices: wgpu::Buffer,
    environment: TruthEnvironment,
    /// The group with no traced shadow mask (the tracer's).
    pub group: wgpu::BindGroup,
}

impl TruthScene {
    pub fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        g: &bvh::TruthGeometry,
        env: &TruthEnvironment,
    ) -> TruthScene {
        let nodes = storage(device, "truth bvh", bytemuck::cast_slice(&g.nodes));
        let triangles = storage(device, "truth triangles", bytemuck::cast_slice(&g.triangles));
        let vertices = storage(device, "truth vertices", bytemuck::cast_slice(&g.vertices));
        let no_mask = storage(device, "no traced shadow mask", &[0; 16]);
        let buffers = [&nodes, &triangles, &vertices];
        let group = rays_group(device, layout, buffers, env, &no_mask);
        TruthScene { nodes, triangles, vertices, environment: env.clone(), group }
    }

    /// The rays' group with a frame's traced shadow mask (render::passes::traced_shadows).
    pub fn group_with_mask(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        mask: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        rays_group(device, layout, [&self.nodes, &self.triangles, &self.vertices], &self.environment, mask)
    }
}

fn rays_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    [nodes, triangles, vertices]: [&wgpu::Buffer; 3],
    env: &TruthEnvironment,
    mask: &wgpu::Buffer,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("rays"),
        layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 10, resource: env.info.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 11, resource: nodes.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 12, resource: triangles.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 13, resource: vertices.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 14, resource: env.texels.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 15, resource: env.cdf.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 16, resource: env.irradiance.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 17, resource: mask.as_entire_binding() },
        ],
    })
}

/// A composition's environment on the GPU: its ENV_WIDTH × ENV_WIDTH/2 texels and sampling
/// tables (`environment_tables`) and its exact irradiance (environment::irradiance), uploaded once.
#[derive(Clone)]
pub struct TruthEnvironment {
    texels: wgpu::Buffer,
    cdf: wgpu::Buffer,
    irradiance: wgpu::Buffer,
    /// rays.wgsl `RaySceneInfo`: the table's and the irradiance map's sizes.
    info: wgpu::Buffer,
}

impl TruthEnvironment {
    pub fn new(device: &wgpu::Device, space: ConstantSpace, image: &EquirectImage) -> TruthEnvironment {
        let (texels, cdf) = environment_tables(image);
        let map = crate::environment::irradiance::irradiance_map(image);
        let irradiance: Vec<[f32; 4]> = map.texels.iter().map(|c| [c.x as f32, c.y as f32, c.z as f32, 0.0]).collect();
        let info = [image.width as u32, image.height as u32, map.width as u32, map.height as u32];
        TruthEnvironment {
            texels: storage(device, "truth environment", bytemuck::cast_slice(&texels)),
            cdf: storage(device, "truth environment tables", bytemuck::cast_slice(&cdf)),
            irradiance: storage(device, "environment irradiance", bytemuck::cast_slice(&irradiance)),
            info: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("rays info"),
                contents: bytemuck::cast_slice(&info),
                usage: space.usage(),
            }),
        }
    }
}

/// Everything one truth render needs besides the frame group (which the renderer owns).
pub struct TruthInputs<'a> {
    pub scene: &'a TruthScene,
    /// Per object: its material and flags (shaders/pass/truth.wgsl `TruthObject`).
    pub objects: &'a [u8],
    pub background: bool,
    pub size: (u32, u32),
    /// The role id of the subject's pixels.
    pub subject_role: u8,
}

pub(crate) fn storage(device: &wgpu::Device, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    let mut contents = bytes.to_vec();
    contents.resize(bytes.len().max(16).next_multiple_of(16), 0);
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &contents,
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// Trace batches until converged (render::truth's module comment) and read the result back.
pub fn trace(
    gpu: &GpuContext,
    pipeline: &TruthPipeline,
    frame_group: &wgpu::BindGroup,
    inputs: &TruthInputs,
    settings: &TruthSettings,
) -> Result<Truth, Error> {
    let start = std::time::Instant::now();
    let device = &gpu.device;
    let (width, height) = inputs.size;
    let pixels = (width * height) as usize;
    let objects = storage(device, "truth objects", inputs.objects);
    let unused = storage(device, "no bake", &[0; 64]);
    let accum_bytes = (pixels * 32) as u64;
    let accum = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("truth accumulation"),
        size: accum_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let roles_bytes = (pixels * 4).next_multiple_of(16) as u64;
    let roles = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("truth roles"),
        size: roles_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    // The bake's points and lights: unread by the truth's entry point.
    let (group, params) = tracer_group(gpu, pipeline, "truth", [&objects, &accum, &roles, &unused, &unused]);
    let readback = |buffer: &wgpu::Buffer, size: u64| read_buffer(gpu, buffer, size);
    let batch = settings.batch.max(1);
    let mut done = 0u32;
    let mut result;
    // On a CPU adapter a batch is traced in short dispatches — bands of rows, a few samples each —
    // of at most bake::PATHS_PER_DISPATCH paths: lavapipe was measured to end longer ones early
    // (a 16-sample batch over 160×120 pixels kept 13 at some). A GPU takes the batch whole.
    let cpu = gpu.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
    let (samples_per, rows_per) = if cpu {
        let samples = (bake::PATHS_PER_DISPATCH / (width as u64 * 8)).clamp(1, bake::SAMPLES_PER_DISPATCH) as u32;
        (samples, ((bake::PATHS_PER_DISPATCH / (width as u64 * samples as u64)) as u32 / 8).max(1) * 8)
    } else {
        (batch, height)
    };
    loop {
        let count = batch.min(settings.spp.max(1) - done);
        let mut first = done;
        while first < done + count {
            let n = samples_per.min(done + count - first);
            for row in (0..height).step_by(rows_per as usize) {
                let p = TruthParams {
                    dims: [width, height, first, n],
                    settings: [settings.bounces, inputs.background as u32, settings.roulette as u32, row],
                };
                let groups = [frame_group, &group, &inputs.scene.group];
                let workgroups = [width.div_ceil(8), rows_per.min(height - row).div_ceil(8)];
                dispatch(gpu, pipeline, groups, (&params, &p), workgroups)?;
            }
            first += n;
        }
        done += count;
        let bytes = readback(&accum, accum_bytes)?;
        let role_bytes = readback(&roles, roles_bytes)?;
        // Every pixel must have taken every sample: a truth short of some would claim spp it lacks
        // (render::truth::bake measured lavapipe ending long dispatches early).
        let sums: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        if let Some(short) = sums.iter().step_by(2).take(pixels).find(|s| s[3] != done as f32) {
            return Err(Error::Other(format!(
                "the truth on {} took {} of {done} samples at a pixel: the adapter ended the work early",
                gpu.adapter.get_info().name,
                short[3]
            )));
        }
        result = summarise(
            bytemuck::cast_slice(&bytes),
            bytemuck::cast_slice(&role_bytes),
            inputs.size,
            inputs.subject_role,
            done,
        );
        let converged = result.subject_noise.is_some_and(|n| n <= settings.noise);
        if converged || done >= settings.spp.max(1) {
            break;
        }
    }
    gpu.check_errors("tracing the truth")?;
    result.seconds = start.elapsed().as_secs_f64();
    result.bounces = settings.bounces;
    result.kind = settings.kind;
    Ok(result)
}

/// One dispatch of the tracer with parameters `p` (written to `params`), waited for: `groups` are
/// the frame's (group 0), the tracer's own (1) and the scene's (3).
fn dispatch(
    gpu: &GpuContext,
    pipeline: &TruthPipeline,
    groups: [&wgpu::BindGroup; 3],
    (params, p): (&wgpu::Buffer, &TruthParams),
    workgroups: [u32; 2],
) -> Result<(), Error> {
    gpu.queue.write_buffer(params, 0, bytemuck::bytes_of(p));
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline.pipeline);
        for (index, group) in [0, 1, 3].into_iter().zip(groups) {
            pass.set_bind_group(index, group, &[]);
        }
        pass.dispatch_workgroups(workgroups[0], workgroups[1], 1);
    }
    gpu.queue.submit([encoder.finish()]);
    gpu.wait_idle()
}

/// The tracer's group (group 1) over its buffers — objects, sums, first roles, the bake's points
/// and lights — with a fresh parameter buffer, which it returns for each batch to write.
pub(crate) fn tracer_group(
    gpu: &GpuContext,
    pipeline: &TruthPipeline,
    label: &str,
    buffers: [&wgpu::Buffer; 5],
) -> (wgpu::BindGroup, wgpu::Buffer) {
    let params = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: std::mem::size_of::<TruthParams>() as u64,
        usage: gpu.constants.usage() | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() }];
    for (binding, buffer) in (1..).zip(buffers) {
        entries.push(wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() });
    }
    let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &pipeline.layout,
        entries: &entries,
    });
    (group, params)
}

/// The first `size` bytes of a GPU buffer, copied out through a staging buffer.
pub(crate) fn read_buffer(gpu: &GpuContext, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>, Error> {
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tracer readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
    gpu.queue.submit([encoder.finish()]);
    crate::gpu::readback::map_read(&gpu.device, &staging)
}

/// Mean and standard error per pixel from the sums; the subject's relative noise.
fn summarise(accum: &[[f32; 4]], roles: &[u32], size: (u32, u32), subject_role: u8, spp: u32) -> Truth {
    let (width, height) = size;
    let pixels = (width * height) as usize;
    let lum = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let mut mean = Vec::with_capacity(pixels);
    let mut std_error = Vec::with_capacity(pixels);
    let (mut se_sum, mut mean_sum, mut count) = (0.0, 0.0, 0usize);
    for i in 0..pixels {
        let (s, q) = (accum[2 * i], accum[2 * i + 1]);
        let n = (s[3] as f64).max(1.0);
        let m = [s[0] as f64 / n, s[1] as f64 / n, s[2] as f64 / n];
        // Variance of the luminance from the per-channel moments (channels treated as independent
        // estimates of one path: an upper bound when they correlate positively, as they do).
        let var: f64 = (0..3)
            .map(|c| (q[c] as f64 / n - m[c] * m[c]).max(0.0).sqrt() * [0.2126, 0.7152, 0.0722][c])
            .sum::<f64>()
            .powi(2);
        let se = (var / (n - 1.0).max(1.0)).sqrt();
        mean.push(m.map(|v| v as f32));
        std_error.push(se as f32);
        if roles[i] == subject_role as u32 {
            se_sum += se;
            mean_sum += lum(m);
            count += 1;
        }
    }
    let subject_noise = (count > 0 && mean_sum > 0.0).then(|| se_sum / mean_sum);
    Truth {
        width,
        height,
        mean,
        std_error,
        roles: roles[..pixels].iter().map(|&r| r as u8).collect(),
        kind: TruthKind::SameBrdf,
        spp,
        bounces: 0,
        subject_noise,
        seconds: 0.0,
        cached: false,
        stored: None,
    }
}

#[cfg(test)]
mod layout_tests {
    use super::*;

    #[test]
    fn params_mirror_the_wgsl_struct() {
        let registry = crate::shading::Registry::builtin();
        let (subject, fixed) = (
            registry.find(crate::pipelines::Pipeline::Urp, "lit").unwrap(),
            registry.find(crate::pipelines::Pipeline::Urp, "lambert").unwrap(),
        );
        let source = crate::shading::wgsl::compose_truth(subject, fixed);
        let (size, fields) = crate::mirror_layout!(TruthParams, [dims, settings]);
        crate::gpu::layout::check_mirror(&source, "TruthParams", size, &fields).unwrap();
    }
}
