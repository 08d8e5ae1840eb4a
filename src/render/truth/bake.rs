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
pub(crate) const PATHS_PER_DISPATCH: u64 = 1 << 14;
pub(crate) const SAMPLES_PER_DISPATCH: u64 = 8;

/// How long a bake gathers: `samples` per probe and at most per texel, paths of `bounces`
/// bounces, texels in rounds until their noise (`texel_noise`) falls to `noise` (0: every texel
/// takes `samples`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BakeBudget {
    pub samples: u32,
    pub bounces: u32,
    pub noise: f64,
}

/// A gathered bake: every point's sums and the samples its texels took.
#[derive(Debug, Clone)]
pub struct GatheredBake {
    pub sums: BakeSums,
    pub texel_samples: u32,
}

/// Texel samples of a converging bake's first round.
const FIRST_ROUND: u32 = 32;

/// The relative noise of texels' sums: the mean over them of their luminance's standard error,
/// over the mean of their luminance (None: no texel, or no light).
pub fn texel_noise(sums: &[[[f32; 4]; BAKE_STRIDE]]) -> Option<f64> {
    let lum = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let (mut se_sum, mut lum_sum) = (0.0, 0.0);
    for s in sums {
        let n = (s[0][3] as f64).max(1.0);
        let mean: [f64; 3] = std::array::from_fn(|k| s[0][k] as f64 / n);
        let sd: [f64; 3] = std::array::from_fn(|k| (s[1][k] as f64 / n - mean[k] * mean[k]).max(0.0).sqrt());
        se_sum += lum(sd) / (n - 1.0).max(1.0).sqrt();
        lum_sum += lum(mean);
    }
    (!sums.is_empty() && lum_sum > 0.0).then(|| se_sum / lum_sum)
}

/// The texel samples a converging bake takes next: what the noise measured after `done` predicts
/// the target needs (noise falls as 1/√samples), a tenth over, in whole dispatches; at least one
/// more dispatch, at most `samples`.
fn next_round(done: u32, noise: f64, budget: &BakeBudget) -> u32 {
    let predicted = done as f64 * (noise / budget.noise).powi(2) * 1.1;
    let step = SAMPLES_PER_DISPATCH as u32;
    let rounded = (predicted.min(budget.samples as f64).ceil() as u32).div_ceil(step) * step;
    rounded.max(done + step).min(budget.samples)
}

/// Gather the bake at `points`: the first `texels` are lightmap texels, the rest probes.
#[allow(clippy::too_many_arguments)]
pub fn gather(
    gpu: &GpuContext,
    pipeline: &TruthPipeline,
    frame_group: &wgpu::BindGroup,
    scene: &TruthScene,
    objects: &[u8],
    points: &[BakePoint],
    texels: usize,
    lights: &[BakeLight],
    budget: BakeBudget,
) -> Result<GatheredBake, Error> {
    let device = &gpu.device;
    let samples = budget.samples.max(1);
    if points.is_empty() {
        return Ok(GatheredBake { sums: Vec::new(), texel_samples: samples });
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
    // Samples [from, to) at points [lo, hi), cut into short dispatches.
    let run = |(lo, hi): (u32, u32), (from, to): (u32, u32)| -> Result<(), Error> {
        let chunk = ((hi - lo) as u64).clamp(1, PATHS_PER_DISPATCH) as u32;
        let batch = (PATHS_PER_DISPATCH / chunk as u64).clamp(1, SAMPLES_PER_DISPATCH) as u32;
        let mut done = from;
        while done < to {
            let count = batch.min(to - done);
            for first in (lo..hi).step_by(chunk as usize) {
                // dims: the end of the points taken, the chunk's first point, the batch's first
                // sample, its samples; settings.w: a probe's samples, over which its directions
                // are stratified
                let p = TruthParams { dims: [hi, first, done, count], settings: [budget.bounces, 0, 0, samples] };
                let groups = [frame_group, &group, &scene.group];
                super::dispatch(gpu, pipeline, groups, (&params, &p), [chunk.min(hi - first).div_ceil(64), 1])?;
            }
            done += count;
        }
        Ok(())
    };
    let t = texels as u32;
    if t < n {
        run((t, n), (0, samples))?;
    }
    let read = || -> Result<BakeSums, Error> {
        let bytes = super::read_buffer(gpu, &accum, accum_bytes)?;
        gpu.check_errors("baking lightmaps and probes")?;
        Ok(bytemuck::cast_slice::<u8, [[f32; 4]; BAKE_STRIDE]>(&bytes).to_vec())
    };
    let converging = budget.noise > 0.0;
    let mut done = 0;
    let mut target = if converging { FIRST_ROUND.min(samples) } else { samples };
    let sums = loop {
        if t > 0 {
            run((0, t), (done, target))?;
        }
        done = target;
        let sums = read()?;
        if !converging || done >= samples || t == 0 {
            break sums;
        }
        match texel_noise(&sums[..texels]) {
            Some(noise) if noise > budget.noise => target = next_round(done, noise, &budget),
            _ => break sums,
        }
    };
    // Every point must have taken every sample: a bake missing some would look complete.
    for (point, s) in points.iter().zip(&sums) {
        let (count, asked) = if point.position[3] < 0.5 { (s[0][3], done) } else { (s[9][3], samples) };
        if count != asked as f32 {
            return Err(Error::Other(format!(
                "the bake on {} took {count} of {asked} samples at a point: the adapter ended the work early",
                gpu.adapter.get_info().name,
            )));
        }
    }
    Ok(GatheredBake { sums, texel_samples: if t > 0 { done } else { samples } })
}

#[cfg(test)]
mod round_tests {
    use super::*;

    #[test]
    fn rounds_aim_at_the_noise_target_in_whole_dispatches() {
        let budget = BakeBudget { samples: 512, bounces: 2, noise: 0.02 };
        // Twice the target after 32 samples: four times the samples, a tenth over, in eights.
        assert_eq!(next_round(32, 0.04, &budget), 144);
        // Barely above it: one more dispatch at least.
        assert_eq!(next_round(32, 0.02001, &budget), 40);
        // Far above it: no more than the budget.
        assert_eq!(next_round(128, 0.5, &budget), 512);
    }

    #[test]
    fn texel_noise_is_the_mean_standard_error_over_the_mean_light() {
        // Two texels of 4 samples each: values {1, 3, 1, 3} (mean 2, sd 1) and {2, 2, 2, 2}.
        let texel = |sum: f32, sq: f32| {
            let mut s = [[0f32; 4]; BAKE_STRIDE];
            s[0] = [sum, sum, sum, 4.0];
            s[1] = [sq, sq, sq, 0.0];
            s
        };
        let noise = texel_noise(&[texel(8.0, 20.0), texel(8.0, 16.0)]).unwrap();
        // (1/√3 + 0)/(2 + 2)
        assert!((noise - 1.0 / 3f64.sqrt() / 4.0).abs() < 1e-6, "{noise}");
        assert_eq!(texel_noise(&[]), None);
    }
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
