//! The bake's gathering on the GPU (shaders/pass/truth.wgsl `cs_bake`): the tracer's own paths
//! started at lightmap texels and at light probes, so that baked light is the same light the truth
//! traces, weighed per light by what the bake holds of it (plan::gi).

use bytemuck::{Pod, Zeroable};

use super::{storage, TruthParams, TruthPipeline, TruthScene};
use crate::error::Error;
use crate::gpu::GpuContext;

/// The vec4 sums kept per point (truth.wgsl `BAKE_STRIDE`). A texel: [0] Σc (rgb) and the count,
/// [1] Σc², [2] the luminance-weighted Σ direction (xyz) and Σ luminance, [3] Σ visibility per
/// shadow-mask channel. A probe: [0..9] Σ radiance·Y_i·4π per SH coefficient, [9] the count in w,
/// [10] Σ visibility per shadow-mask channel.
pub const BAKE_STRIDE: usize = 12;

/// A lightmap texel (position.w = 0, normal.xyz its normal) or a probe (position.w = 1).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct BakePoint {
    pub position: [f32; 4],
    pub normal: [f32; 4],
}

impl BakePoint {
    pub fn texel(p: [f32; 3], n: [f32; 3]) -> BakePoint {
        BakePoint { position: [p[0], p[1], p[2], 0.0], normal: [n[0], n[1], n[2], 0.0] }
    }

    pub fn probe(p: [f32; 3]) -> BakePoint {
        BakePoint { position: [p[0], p[1], p[2], 1.0], normal: [0.0; 4] }
    }
}

/// What the bake holds of one light: weights (direct at a texel, direct at a probe, bounced,
/// shadow-mask channel or −1) and its baked shadow's shape (radius, tan of half the angle).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct BakeLight {
    pub weights: [f32; 4],
    pub shape: [f32; 4],
}

/// The sums of every point after `samples` samples each.
pub type BakeSums = Vec<[[f32; 4]; BAKE_STRIDE]>;

/// Paths per dispatch: enough to fill a GPU, few enough that one dispatch stays short. Lavapipe
/// was measured to end long dispatches early (a 4096-sample loop kept 158–1525 samples per point;
/// 32 samples over the composite's 10⁴ texels lost some), so dispatches are cut by points and by
/// samples, and the counts are checked after.
const PATHS_PER_DISPATCH: u64 = 1 << 14;
const SAMPLES_PER_DISPATCH: u64 = 8;

/// Gather `samples` samples at every point with paths of `bounces` bounces.
#[allow(clippy::too_many_arguments)]
pub fn gather(
    gpu: &GpuContext,
    pipeline: &TruthPipeline,
    frame_group: &wgpu::BindGroup,
    scene: &TruthScene,
    objects: &[u8],
    points: &[BakePoint],
    lights: &[BakeLight],
    (samples, bounces): (u32, u32),
) -> Result<BakeSums, Error> {
    let device = &gpu.device;
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let objects = storage(device, "bake objects", objects);
    let point_buffer = storage(device, "bake points", bytemuck::cast_slice(points));
    let light_buffer = storage(device, "bake lights", bytemuck::cast_slice(lights));
    let accum_bytes = (points.len() * BAKE_STRIDE * 16) as u64;
    let accum = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("bake sums"),
        size: accum_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let no_roles = storage(device, "bake: no roles", &[0; 16]);
    let buffers = [&objects, &accum, &no_roles, &point_buffer, &light_buffer];
    let (group, params) = super::tracer_group(gpu, pipeline, "bake", buffers);
    let n = points.len() as u32;
    let chunk = (n as u64).min(PATHS_PER_DISPATCH) as u32;
    let batch = (PATHS_PER_DISPATCH / chunk as u64).clamp(1, SAMPLES_PER_DISPATCH.min(samples.max(1) as u64)) as u32;
    let mut done = 0u32;
    while done < samples.max(1) {
        let count = batch.min(samples.max(1) - done);
        for first in (0..n).step_by(chunk as usize) {
            // dims: points, the chunk's first point, the batch's first sample, its samples
            let p = TruthParams { dims: [n, first, done, count], settings: [bounces, 0, 0, samples.max(1)] };
            gpu.queue.write_buffer(&params, 0, bytemuck::bytes_of(&p));
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline.pipeline);
                pass.set_bind_group(0, frame_group, &[]);
                pass.set_bind_group(1, &group, &[]);
                pass.set_bind_group(3, &scene.group, &[]);
                pass.dispatch_workgroups(chunk.min(n - first).div_ceil(64), 1, 1);
            }
            gpu.queue.submit([encoder.finish()]);
            gpu.wait_idle()?;
        }
        done += count;
    }
    let bytes = super::read_buffer(gpu, &accum, accum_bytes)?;
    gpu.check_errors("baking lightmaps and probes")?;
    let sums: &[[[f32; 4]; BAKE_STRIDE]] = bytemuck::cast_slice(&bytes);
    // Every point must have taken every sample: a bake missing some would look complete.
    for (point, s) in points.iter().zip(sums) {
        let count = if point.position[3] < 0.5 { s[0][3] } else { s[9][3] };
        if count != samples.max(1) as f32 {
            return Err(Error::Other(format!(
                "the bake on {} took {count} of {} samples at a point: the adapter ended the work early",
                gpu.adapter.get_info().name,
                samples.max(1)
            )));
        }
    }
    Ok(sums.to_vec())
}

#[cfg(test)]
mod layout_tests {
    use super::*;

    #[test]
    fn bake_structs_mirror_the_wgsl() {
        let registry = crate::shading::Registry::builtin();
        let fixed = registry.find(crate::pipelines::Pipeline::Builtin, "standard").unwrap();
        let source = crate::shading::wgsl::compose_truth(fixed, fixed);
        let (size, fields) = crate::mirror_layout!(BakePoint, [position, normal]);
        crate::gpu::layout::check_mirror(&source, "BakePoint", size, &fields).unwrap();
        let (size, fields) = crate::mirror_layout!(BakeLight, [weights, shape]);
        crate::gpu::layout::check_mirror(&source, "BakeLight", size, &fields).unwrap();
    }
}
