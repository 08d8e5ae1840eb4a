//! LDR-FLIP, HDR-FLIP and SSIM as wgpu compute passes (`shaders/metrics/flip.wgsl`,
//! `shaders/metrics/ssim.wgsl`): the images go up once, every pass runs on the device, and only the
//! per-pixel maps come back; means and the pooled statistics are taken from the maps with the CPU
//! reference's own code (`flip_rs::ErrorMap::statistics`, `ssim::window_mean`), so a GPU mean
//! differs from the CPU's only by the per-pixel arithmetic. Written by hand: no crate runs FLIP or
//! SSIM in wgpu. The filter weights and HDR exposures are computed here exactly as flip-rs does
//! (its own are private). Each caller borrows a set of buffers and bind groups of its image size
//! from a pool, so metric workers submit side by side instead of taking turns; sets are kept and
//! reused, one per worker that ran at once.

use std::sync::{Mutex, RwLock, RwLockWriteGuard};

use wgpu::util::DeviceExt;

use crate::error::Error;
use crate::gpu::ConstantSpace;

const FLIP_WGSL: &str = include_str!("../../shaders/metrics/flip.wgsl");
const SSIM_WGSL: &str = include_str!("../../shaders/metrics/ssim.wgsl");
const WORKGROUP: u32 = 256;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FlipParams {
    width: u32,
    height: u32,
    spatial_radius: u32,
    feature_radius: u32,
    mode: u32,
    multiplier: f32,
    first: u32,
    cmax: f32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SsimParams {
    width: u32,
    height: u32,
    _pad0: u32,
    _pad1: u32,
}

/// The metric passes of one device, and their buffers for the last size compared.
pub struct GpuMetrics {
    device: wgpu::Device,
    queue: wgpu::Queue,
    flip_layout: wgpu::BindGroupLayout,
    ssim_layout: wgpu::BindGroupLayout,
    flip: [wgpu::ComputePipeline; 5],
    ssim: [wgpu::ComputePipeline; 2],
    spatial: wgpu::Buffer,
    feature: wgpu::Buffer,
    window: wgpu::Buffer,
    radii: (u32, u32),
    cmax: f32,
    /// Idle buffer sets, all of the last image size compared.
    idle: Mutex<Vec<MetricBuffers>>,
    /// Read by every metric while it runs, written by `hold`.
    turn: RwLock<()>,
    space: ConstantSpace,
}

/// Buffers for one image size.
pub struct MetricBuffers {
    n: usize,
    images: wgpu::Buffer,
    // The intermediate planes live in the bind groups, which keep them.
    flip_map: wgpu::Buffer,
    ssim_map: wgpu::Buffer,
    readback: wgpu::Buffer,
    flip_params: wgpu::Buffer,
    ssim_params: wgpu::Buffer,
    flip_group: wgpu::BindGroup,
    ssim_group: wgpu::BindGroup,
}

fn storage(device: &wgpu::Device, label: &str, bytes: u64, extra: wgpu::BufferUsages) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE | extra,
        mapped_at_creation: false,
    })
}

impl GpuMetrics {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, space: ConstantSpace) -> GpuMetrics {
        use crate::render::resources::compute_entry::{constants, read_only_storage, read_write_storage};
        let flip_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("flip"),
            entries: &[
                constants(space, 0),
                read_only_storage(1),
                read_write_storage(2),
                read_write_storage(3),
                read_write_storage(4),
                read_write_storage(5),
                read_only_storage(6),
                read_only_storage(7),
            ],
        });
        let ssim_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ssim"),
            entries: &[
                constants(space, 0),
                read_only_storage(1),
                read_write_storage(2),
                read_write_storage(3),
                read_only_storage(4),
            ],
        });
        let module = |label: &str, src: &str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(space.wgsl(src)),
            })
        };
        let (flip_module, ssim_module) = (module("flip", FLIP_WGSL), module("ssim", SSIM_WGSL));
        let pipe = |layout, m, entry| crate::render::resources::compute_pipeline(device, entry, layout, m, entry);
        let flip =
            ["convert", "color_h", "color_v", "feature_h", "feature_v"].map(|e| pipe(&flip_layout, &flip_module, e));
        let ssim = ["ssim_h", "ssim_v"].map(|e| pipe(&ssim_layout, &ssim_module, e));
        let weights = FlipWeights::new(super::flip::PPD);
        let init = |label: &str, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let window: Vec<f32> = super::ssim::window().iter().map(|w| *w as f32).collect();
        GpuMetrics {
            spatial: init("flip spatial weights", bytemuck::cast_slice(&weights.spatial)),
            feature: init("flip feature weights", bytemuck::cast_slice(&weights.feature)),
            window: init("ssim window", bytemuck::cast_slice(&window)),
            radii: (weights.spatial.len() as u32 / 2, weights.feature.len() as u32 / 2),
            cmax: max_distance(),
            device: device.clone(),
            queue: queue.clone(),
            flip_layout,
            ssim_layout,
            flip,
            ssim,
            idle: Mutex::new(Vec::new()),
            turn: RwLock::new(()),
            space,
        }
    }

    /// LDR-FLIP and SSIM maps of two sRGB RGBA8 images (alpha ignored).
    pub fn ldr(&self, reference: &[u8], test: &[u8], w: usize, h: usize) -> Result<(Vec<f32>, Vec<f32>), Error> {
        let px: Vec<f32> = reference.iter().chain(test).map(|v| f32::from(*v) / 255.0).collect();
        let _turn = self.turn.read().unwrap_or_else(|e| e.into_inner());
        let lent = self.lend(w * h);
        let b = lent.set();
        self.queue.write_buffer(&b.images, 0, bytemuck::cast_slice(&px));
        self.run_flip(b, w, h, 0, 1.0, true);
        self.run_ssim(b, w, h);
        let flip = self.read(b, &b.flip_map)?;
        let ssim = self.read(b, &b.ssim_map)?;
        Ok((flip, ssim))
    }

    /// The HDR-FLIP map of two linear RGBA images (finite, non-negative), with flip-rs's default
    /// exposures (ACES, from the reference's luminance).
    pub fn hdr_flip(&self, reference: &[f32], test: &[f32], w: usize, h: usize) -> Result<Vec<f32>, String> {
        let (start, stop, count) = exposures(reference)?;
        let _turn = self.turn.read().unwrap_or_else(|e| e.into_inner());
        let lent = self.lend(w * h);
        let b = lent.set();
        let px: Vec<f32> = reference.iter().chain(test).copied().collect();
        self.queue.write_buffer(&b.images, 0, bytemuck::cast_slice(&px));
        let step = (stop - start) / (count - 1) as f32;
        let evaluations = if start == stop { 1 } else { count };
        for i in 0..evaluations {
            let exposure = start + i as f32 * step;
            self.run_flip(b, w, h, 1, 2.0_f32.powf(exposure), i == 0);
        }
        self.read(b, &b.flip_map).map_err(|e| e.to_string())
    }

    /// Hold the metric passes off the device while the caller times frames on it: a metric
    /// submitted meanwhile would land in the frame's submit-to-idle wall time.
    pub fn hold(&self) -> RwLockWriteGuard<'_, ()> {
        self.turn.write().unwrap_or_else(|e| e.into_inner())
    }

    /// An idle set of buffers for n pixels, or a new one; it goes back to the pool when dropped.
    fn lend(&self, n: usize) -> LentBuffers<'_> {
        let idle = {
            let mut idle = self.idle.lock().unwrap_or_else(|e| e.into_inner());
            idle.retain(|s| s.n == n);
            idle.pop()
        };
        LentBuffers { pool: &self.idle, set: Some(idle.unwrap_or_else(|| self.buffers(n))) }
    }

    fn buffers(&self, n: usize) -> MetricBuffers {
        let f = 4 * n as u64;
        let d = &self.device;
        let images = storage(d, "metric images", 2 * 4 * f, wgpu::BufferUsages::COPY_DST);
        let opponent = storage(d, "flip opponent", 6 * f, wgpu::BufferUsages::empty());
        let inter = storage(d, "metric filters", 8 * f, wgpu::BufferUsages::empty());
        let color_error = storage(d, "flip colour error", f, wgpu::BufferUsages::empty());
        let flip_map = storage(d, "flip map", f, wgpu::BufferUsages::COPY_SRC);
        let ssim_map = storage(d, "ssim map", f, wgpu::BufferUsages::COPY_SRC);
        let uniform = |label: &str, size: usize| {
            d.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: self.space.usage() | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let flip_params = uniform("flip params", std::mem::size_of::<FlipParams>());
        let ssim_params = uniform("ssim params", std::mem::size_of::<SsimParams>());
        let flip_group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("flip"),
            layout: &self.flip_layout,
            entries: &[
                entry(0, &flip_params),
                entry(1, &images),
                entry(2, &opponent),
                entry(3, &inter),
                entry(4, &color_error),
                entry(5, &flip_map),
                entry(6, &self.spatial),
                entry(7, &self.feature),
            ],
        });
        let ssim_group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ssim"),
            layout: &self.ssim_layout,
            entries: &[
                entry(0, &ssim_params),
                entry(1, &images),
                entry(2, &inter),
                entry(3, &ssim_map),
                entry(4, &self.window),
            ],
        });
        MetricBuffers {
            n,
            readback: d.create_buffer(&wgpu::BufferDescriptor {
                label: Some("metric readback"),
                size: f.max(16),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
            images,
            flip_map,
            ssim_map,
            flip_params,
            ssim_params,
            flip_group,
            ssim_group,
        }
    }

    fn run_flip(&self, b: &MetricBuffers, w: usize, h: usize, mode: u32, multiplier: f32, first: bool) {
        let params = FlipParams {
            width: w as u32,
            height: h as u32,
            spatial_radius: self.radii.0,
            feature_radius: self.radii.1,
            mode,
            multiplier,
            first: first.into(),
            cmax: self.cmax,
        };
        // Written before this submit, read by it alone: each exposure submits its own passes.
        self.queue.write_buffer(&b.flip_params, 0, bytemuck::bytes_of(&params));
        let group = &b.flip_group;
        let n = (w * h) as u32;
        let mut encoder = self.device.create_command_encoder(&Default::default());
        for (k, pipeline) in self.flip.iter().enumerate() {
            let threads = if k == 0 { 2 * n } else { n };
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(threads.div_ceil(WORKGROUP), 1, 1);
        }
        self.queue.submit([encoder.finish()]);
    }

    fn run_ssim(&self, b: &MetricBuffers, w: usize, h: usize) {
        let params = SsimParams { width: w as u32, height: h as u32, _pad0: 0, _pad1: 0 };
        self.queue.write_buffer(&b.ssim_params, 0, bytemuck::bytes_of(&params));
        let mut encoder = self.device.create_command_encoder(&Default::default());
        for pipeline in &self.ssim {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &b.ssim_group, &[]);
            pass.dispatch_workgroups(((w * h) as u32).div_ceil(WORKGROUP), 1, 1);
        }
        self.queue.submit([encoder.finish()]);
    }

    fn read(&self, b: &MetricBuffers, map: &wgpu::Buffer) -> Result<Vec<f32>, Error> {
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(map, 0, &b.readback, 0, 4 * b.n as u64);
        self.queue.submit([encoder.finish()]);
        let bytes = crate::gpu::readback::map_read(&self.device, &b.readback)?;
        Ok(bytemuck::cast_slice::<u8, f32>(&bytes[..4 * b.n]).to_vec())
    }
}

/// A buffer set borrowed from the pool, given back when dropped (an error's path too).
struct LentBuffers<'a> {
    pool: &'a Mutex<Vec<MetricBuffers>>,
    set: Option<MetricBuffers>,
}

impl LentBuffers<'_> {
    fn set(&self) -> &MetricBuffers {
        self.set.as_ref().expect("lent until dropped")
    }
}

impl Drop for LentBuffers<'_> {
    fn drop(&mut self) {
        if let Some(set) = self.set.take() {
            self.pool.lock().unwrap_or_else(|e| e.into_inner()).push(set);
        }
    }
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
}

/// flip-rs's filters (`Filters::new`): the CSF's spatial weights per tap (Y, Cx, Cz₁, Cz₂) and the
/// feature detector's (Gaussian, first and second derivative), f32 in its order.
struct FlipWeights {
    spatial: Vec<[f32; 4]>,
    feature: Vec<[f32; 4]>,
}

impl FlipWeights {
    fn new(ppd: f32) -> FlipWeights {
        use std::f32::consts::PI;
        let radius = (3.0 * (0.04 / (2.0 * (PI * PI))).sqrt() * ppd).ceil() as isize;
        let sigma = 0.5 * 0.082 * ppd;
        let feature_radius = (3.0 * sigma).ceil() as isize;
        let delta = 1.0 / ppd;
        let mut sum = [0.0f32; 4];
        let mut spatial = Vec::new();
        for i in -radius..=radius {
            let x = i as f32 * delta;
            let x2 = x * x;
            let gaussian = |a: f32, b: f32| a * (PI / b).sqrt() * (-(PI * PI) * x2 / b).exp();
            let gaussian_sqrt = |a: f32, b: f32| (a * (PI / b).sqrt()).sqrt() * (-(PI * PI) * x2 / b).exp();
            let w =
                [gaussian(1.0, 0.0047), gaussian(1.0, 0.0053), gaussian_sqrt(34.1, 0.04), gaussian_sqrt(13.5, 0.025)];
            for c in 0..4 {
                sum[c] += w[c];
            }
            spatial.push(w);
        }
        let norm = [1.0 / sum[0], 1.0 / sum[1], 1.0 / (sum[2] * sum[2] + sum[3] * sum[3]).sqrt()];
        for w in &mut spatial {
            w[0] *= norm[0];
            w[1] *= norm[1];
            w[2] *= norm[2];
            w[3] *= norm[2];
        }
        let (mut gsum, mut dgneg, mut dgpos, mut ddgneg, mut ddgpos) = (0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32);
        let mut feature = Vec::new();
        for i in -feature_radius..=feature_radius {
            let x = i as f32;
            let g = (-(x * x) / (2.0 * sigma * sigma)).exp();
            let dg = -x * g;
            let ddg = (x * x / (sigma * sigma) - 1.0) * g;
            gsum += g;
            if dg > 0.0 {
                dgpos += dg;
            } else {
                dgneg -= dg;
            }
            if ddg > 0.0 {
                ddgpos += ddg;
            } else {
                ddgneg -= ddg;
            }
            feature.push([g, dg, ddg, 0.0]);
        }
        for v in &mut feature {
            v[0] /= gsum;
            v[1] /= if v[1] > 0.0 { dgpos } else { dgneg };
            v[2] /= if v[2] > 0.0 { ddgpos } else { ddgneg };
        }
        FlipWeights { spatial, feature }
    }
}

/// LDR-FLIP's filters and colour distance at the tool's viewing condition (`compare::flip::PPD`),
/// for another evaluator of the same passes (the viewer's page): spatial weights per tap (Y, Cx,
/// Cz₁, Cz₂), feature weights per tap (Gaussian, first, second derivative), and cmax.
pub fn flip_filters() -> (Vec<[f32; 4]>, Vec<[f32; 3]>, f32) {
    let w = FlipWeights::new(super::flip::PPD);
    (w.spatial, w.feature.iter().map(|f| [f[0], f[1], f[2]]).collect(), max_distance())
}

/// color3::computeMaxDistance: HyAB between the Hunt-adjusted Lab of linear green and blue, ^0.7.
/// (FLIP's constants as its source spells them, beyond f32's precision.)
#[allow(clippy::excessive_precision)]
fn max_distance() -> f32 {
    let lab = |v: [f32; 3]| {
        let xyz = [
            (10135552.0 / 24577794.0) * v[0] + (8788810.0 / 24577794.0) * v[1] + (4435075.0 / 24577794.0) * v[2],
            (2613072.0 / 12288897.0) * v[0] + (8788810.0 / 12288897.0) * v[1] + (887015.0 / 12288897.0) * v[2],
            (1425312.0 / 73733382.0) * v[0] + (8788810.0 / 73733382.0) * v[1] + (70074185.0 / 73733382.0) * v[2],
        ];
        let delta = 6.0_f32 / 29.0;
        let f =
            |t: f32| if t > delta * delta * delta { t.powf(1.0 / 3.0) } else { t / (3.0 * delta * delta) + 4.0 / 29.0 };
        let (x, y, z) = (f(xyz[0] * 1.052156925), f(xyz[1]), f(xyz[2] * 0.918357670));
        let l = 116.0 * y - 16.0;
        [l, 0.01 * l * (500.0 * (x - y)), 0.01 * l * (200.0 * (y - z))]
    };
    let (r, t) = (lab([0.0, 1.0, 0.0]), lab([0.0, 0.0, 1.0]));
    let (a, b) = (r[1] - t[1], r[2] - t[2]);
    ((r[0] - t[0]).abs() + (a * a + b * b).sqrt()).powf(0.7)
}

/// flip-rs's default HDR exposures (`hdr::resolve`, ACES): from log2(xmax/ymax) to
/// log2(xmax/median luminance) of the reference, ⌈range⌉ of them (at least 2).
fn exposures(reference: &[f32]) -> Result<(f32, f32, usize), String> {
    let tc = [0.6 * 0.6 * 2.51f32, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14];
    let (a, b, c) = (tc[0] - 0.85 * tc[3], tc[1] - 0.85 * tc[4], tc[2] - 0.85 * tc[5]);
    let xmax = if a == 0.0 {
        -c / b
    } else {
        let d1 = -0.5 * (b / a);
        d1 + (d1 * d1 - c / a).sqrt()
    };
    let mut lum: Vec<f32> = reference.chunks_exact(4).map(|p| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]).collect();
    let ymax = lum.iter().copied().fold(-1e30_f32, f32::max);
    let mid = lum.len() / 2;
    let (_, median, _) = lum.select_nth_unstable_by(mid, f32::total_cmp);
    let median = median.max(f32::EPSILON);
    let start = f64::from(xmax / ymax).log2() as f32;
    let stop = f64::from(xmax / median).log2() as f32;
    let range = stop - start;
    if !start.is_finite() || !stop.is_finite() || !range.is_finite() || range < 0.0 {
        return Err("exposure endpoints must be finite and ordered (an all-black reference has none)".into());
    }
    let count = range.ceil().max(2.0) as usize;
    if count > flip_rs::MAX_EXPOSURES {
        return Err(format!("{count} exposures exceed flip-rs's {}", flip_rs::MAX_EXPOSURES));
    }
    Ok((start, stop, count))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_mirror_the_wgsl_structs() {
        let (size, fields) = crate::mirror_layout!(
            FlipParams,
            [width, height, spatial_radius, feature_radius, mode, multiplier, first, cmax]
        );
        crate::gpu::layout::check_mirror(FLIP_WGSL, "FlipParams", size, &fields).unwrap();
        let (size, fields) = crate::mirror_layout!(SsimParams, [width, height, _pad0, _pad1]);
        crate::gpu::layout::check_mirror(SSIM_WGSL, "SsimParams", size, &fields).unwrap();
    }
}
