//! f64 twin of HDRP's screen-space ambient occlusion as `render::passes::ssao` runs it
//! (shaders/pass/ssao.wgsl): the closest-depth pyramid levels, the GTAO horizon search and
//! cosine-weighted integral without temporal history, then at half resolution the bilateral
//! upsample or at full resolution the spatial denoise, with the intensity power. Same names as the
//! WGSL; the tests hold the GPU steps against it.

use glam::{DVec2, DVec3};

use crate::render::passes::ssao::{level_sizes, SsaoFrame};

/// One channel of a texture, row-major, top row first (wgpu's layout).
#[derive(Debug, Clone)]
struct Plane {
    width: usize,
    height: usize,
    texels: Vec<f64>,
}

impl Plane {
    fn new((width, height): (u32, u32)) -> Plane {
        Plane { width: width as usize, height: height as usize, texels: vec![0.0; (width * height) as usize] }
    }

    fn load_clamped(&self, x: i64, y: i64) -> f64 {
        let x = x.clamp(0, self.width as i64 - 1) as usize;
        let y = y.clamp(0, self.height as i64 - 1) as usize;
        self.texels[y * self.width + x]
    }

    /// The texel at HDRP's pixel (x, y), rows counted from the bottom, edges clamped.
    fn hdrp_load(&self, x: i64, y: i64) -> f64 {
        let y = y.clamp(0, self.height as i64 - 1);
        self.load_clamped(x, self.height as i64 - 1 - y)
    }
}

/// round(x·levels)/levels after saturation (PackAOOutput's UnpackInt).
fn quantise(x: f64, levels: f64) -> f64 {
    (x.clamp(0.0, 1.0) * levels + 0.5).floor() / levels
}

struct Gtao<'a> {
    frame: &'a SsaoFrame,
    level0: &'a Plane,
    level1: &'a Plane,
    level2: &'a Plane,
    normals: &'a [DVec3],
    /// Whether the search runs at the frame's resolution (FULL_RES) rather than half of it.
    full_resolution: bool,
}

fn p(v: [f32; 4]) -> [f64; 4] {
    v.map(f64::from)
}

fn linear_eye_depth(f: &SsaoFrame, raw: f64) -> f64 {
    let [n, far, _, _] = p(f.z_buffer);
    n * far / (far - raw * (far - n))
}

fn get_position_vs(f: &SsaoFrame, position_ss: DVec2, raw: f64) -> DVec3 {
    let z = linear_eye_depth(f, raw);
    let d = p(f.depth_to_view);
    DVec3::new((position_ss.x * d[0] - d[2]) * z, (position_ss.y * d[1] - d[3]) * z, z)
}

/// GTAOFastAcos.
pub fn gtao_fast_acos(x: f64) -> f64 {
    let out = (-0.156583 * x.abs() + std::f64::consts::FRAC_PI_2) * (1.0 - x.abs()).sqrt();
    if x >= 0.0 {
        out
    } else {
        std::f64::consts::PI - out
    }
}

/// IntegrateArcCosWeighted.
pub fn integrate_arc_cos_weighted(horizon1: f64, horizon2: f64, n: f64, cos_n: f64) -> f64 {
    let (h1, h2) = (horizon1 * 2.0, horizon2 * 2.0);
    let sin_n = n.sin();
    0.25 * ((-(h1 - n).cos() + cos_n + h1 * sin_n) + (-(h2 - n).cos() + cos_n + h2 * sin_n))
}

fn update_horizon(f: &SsaoFrame, max_h: f64, candidate_h: f64, dist_sq: f64) -> f64 {
    let falloff = (1.0 - dist_sq * f.params1[1] as f64).clamp(0.0, 1.0);
    let t = if candidate_h > max_h { falloff } else { 0.03 };
    max_h + (candidate_h - max_h) * t
}

fn fract(x: f64) -> f64 {
    x - x.floor()
}

/// GTAO.compute's rotations, by direction (non-temporal) or by frame (TEMPORAL).
const ROTATIONS: [f64; 6] = [60.0, 300.0, 180.0, 240.0, 120.0, 0.0];
/// GTAO.compute's temporal offsets (ENABLE_TEMPORAL_OFFSET).
const TEMPORAL_OFFSETS: [f64; 4] = [0.0, 0.5, 0.25, 0.75];

/// One frame of HDRP's temporal GTAO: one direction, rotated by `ROTATIONS[rotation]`, and the
/// sample start shifted by `TEMPORAL_OFFSETS[offset]` (_AOTemporalRotationIdx, _AOTemporalOffsetIdx).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TemporalFrame {
    pub rotation: usize,
    pub offset: usize,
}

fn gtao_direction(x: u32, y: u32, rotation: usize) -> DVec2 {
    let noise = fract(52.9829189 * fract(0.06711056 * x as f64 + 0.00583715 * y as f64));
    let angle = (noise + ROTATIONS[rotation] / 360.0) * std::f64::consts::PI;
    DVec2::new(angle.cos(), angle.sin())
}

fn gtao_offset(x: u32, y: u32, temporal: Option<TemporalFrame>) -> f64 {
    let spatial = 0.25 * (y.wrapping_sub(x) & 3) as f64;
    fract(spatial + temporal.map_or(0.0, |t| TEMPORAL_OFFSETS[t.offset]))
}

impl Gtao<'_> {
    fn depth_for_central(&self, x: i64, y: i64) -> f64 {
        if self.full_resolution {
            return self.level0.hdrp_load(x, y);
        }
        let l = self.level1;
        l.hdrp_load(x - 1, y - 1).max(l.hdrp_load(x, y - 1)).max(l.hdrp_load(x - 1, y).max(l.hdrp_load(x, y)))
    }

    fn depth_sample(&self, position_ss: DVec2, lower_res: bool) -> f64 {
        let (x, y) = (position_ss.x as u32, position_ss.y as u32);
        if self.full_resolution {
            self.level1.hdrp_load((x / 2) as i64, (y / 2) as i64)
        } else if lower_res {
            self.level2.hdrp_load((x / 2) as i64, (y / 2) as i64)
        } else {
            self.level1.hdrp_load(x as i64, y as i64)
        }
    }

    fn normal_vs(&self, x: i64, y: i64) -> DVec3 {
        let (w, h) = (self.level0.width as i64, self.level0.height as i64);
        let (x, y) = (x.clamp(0, w - 1), y.clamp(0, h - 1));
        let n = self.normals[((h - 1 - y) * w + x) as usize] * 2.0 - DVec3::ONE;
        let f = self.frame;
        let row = |r: [f32; 4]| DVec3::new(r[0] as f64, r[1] as f64, r[2] as f64);
        let v = DVec3::new(row(f.view_x).dot(n), row(f.view_y).dot(n), row(f.view_z).dot(n)).normalize();
        DVec3::new(v.x, v.y, -v.z)
    }

    fn horizon_loop(
        &self,
        position_vs: DVec3,
        v: DVec3,
        ray_start: DVec2,
        ray_dir: DVec2,
        offset: f64,
        step: f64,
    ) -> f64 {
        let f = self.frame;
        let mut max_horizon = -1.0;
        let mut t = offset * step + step;
        let step_count = f.params0[2] as u32;
        let start_with_lower_res = ((step_count / 2) as i64 - 2).clamp(0, 3) as u32;
        let size = DVec2::new(f.buffer_size[0] as f64, f.buffer_size[1] as f64);
        for i in 0..step_count {
            let sample_pos = (ray_start + ray_dir * t).min(size - 2.0).max(DVec2::splat(2.0));
            let sample_depth = self.depth_sample(sample_pos, i > start_with_lower_res);
            let delta = get_position_vs(f, sample_pos, sample_depth) - position_vs;
            let delta_len_sq = delta.dot(delta);
            let curr = delta.dot(v) / delta_len_sq.sqrt();
            max_horizon = update_horizon(f, max_horizon, curr, delta_len_sq);
            t += step;
        }
        max_horizon
    }

    /// GTAOMain: (AO, depth), quantised as packed (depth in 24 bits at half resolution, 23 at
    /// full); `temporal`: one frame of the TEMPORAL variant, else every direction of the
    /// non-temporal one.
    fn gtao(&self, x: u32, y_top: u32, temporal: Option<TemporalFrame>) -> (f64, f64) {
        let f = self.frame;
        let running = if self.full_resolution { self.level0 } else { self.level1 };
        let y = running.height as u32 - 1 - y_top;
        let curr_depth = self.depth_for_central(x as i64, y as i64);
        let ray_start = DVec2::new(x as f64, y as f64);
        let position_vs = get_position_vs(f, ray_start, curr_depth);
        let offset = gtao_offset(x, y, temporal);
        let v = (-position_vs).normalize();
        let [fov_correction, radius, step_count, inv_steps] = p(f.params0);
        let radius_ss = (radius * fov_correction / position_vs.z).clamp(step_count, f.params1[3] as f64);
        let step = (radius_ss * inv_steps).max(1.0);
        let dir_count = if temporal.is_some() { 1 } else { f.params1[2] as u32 };
        let scale = if self.full_resolution { 1 } else { 2 };
        let n_vs = self.normal_vs(scale * x as i64, scale * y as i64);
        let mut integral = 0.0;
        for i in 0..dir_count {
            let dir = gtao_direction(x, y, temporal.map_or(i as usize, |t| t.rotation));
            let neg_dir = -dir + 1e-30;
            let mut h = [
                self.horizon_loop(position_vs, v, ray_start, dir, offset, step),
                self.horizon_loop(position_vs, v, ray_start, neg_dir, offset, step),
            ];
            let slice_n = DVec3::new(dir.x, dir.y, 0.0).cross(v).normalize();
            let proj_n = n_vs - slice_n * n_vs.dot(slice_n);
            let cos_n = (proj_n / proj_n.length()).dot(v);
            let tangent = v.cross(slice_n);
            let s = proj_n.dot(tangent);
            let sign = if s > 0.0 {
                1.0
            } else if s < 0.0 {
                -1.0
            } else {
                0.0
            };
            let n = -sign * gtao_fast_acos(cos_n);
            h[0] = -gtao_fast_acos(h[0]);
            h[1] = gtao_fast_acos(h[1]);
            h[0] = n + (h[0] - n).max(-std::f64::consts::FRAC_PI_2);
            h[1] = n + (h[1] - n).min(std::f64::consts::FRAC_PI_2);
            integral +=
                if h[0].is_nan() || h[1].is_nan() { 1.0 } else { integrate_arc_cos_weighted(h[0], h[1], n, cos_n) };
        }
        integral /= dir_count as f64;
        if curr_depth >= 1.0 || integral < -1e-2 {
            integral = 1.0;
        }
        let depth_levels = if self.full_resolution { 8388607.0 } else { 16777215.0 };
        (quantise(integral, 255.0), quantise(curr_depth, depth_levels))
    }
}

fn closest(finer: &Plane, size: (u32, u32)) -> Plane {
    let mut out = Plane::new(size);
    for y in 0..out.height as i64 {
        for x in 0..out.width as i64 {
            let (px, py) = (2 * x, 2 * y);
            out.texels[(y as usize) * out.width + x as usize] = finer
                .load_clamped(px, py)
                .min(finer.load_clamped(px + 1, py))
                .min(finer.load_clamped(px, py + 1).min(finer.load_clamped(px + 1, py + 1)));
        }
    }
    out
}

/// The visibility (AO^intensity, 8-bit as HDRP stores it) per full-resolution pixel of a frame
/// whose raw depth (0 near .. 1 far) and encoded world normals (n·0.5 + 0.5) are given, row-major,
/// top row first, searched at full or half resolution.
pub fn visibility(
    width: u32,
    height: u32,
    depth: &[f64],
    encoded_normals: &[DVec3],
    frame: &SsaoFrame,
    full_resolution: bool,
) -> Vec<f64> {
    visibility_over((width, height), depth, encoded_normals, frame, &[None], full_resolution)
}

/// What HDRP's default temporal GTAO converges to on a still frame: the half-resolution AO of its
/// 24 frames (rotation frameCount mod 6, offset (frameCount / 6) mod 4; one direction each)
/// averaged, as an exponential history converges to their mean, then upsampled.
pub fn temporal_visibility(
    width: u32,
    height: u32,
    depth: &[f64],
    encoded_normals: &[DVec3],
    frame: &SsaoFrame,
) -> Vec<f64> {
    let frames: Vec<Option<TemporalFrame>> =
        (0..24).map(|k| Some(TemporalFrame { rotation: k % 6, offset: (k / 6) % 4 })).collect();
    visibility_over((width, height), depth, encoded_normals, frame, &frames, false)
}

/// PositivePow(AO, intensity) as HDRP's 8-bit occlusion texture holds its complement.
fn final_visibility(ao: f64, intensity: f64) -> f64 {
    let visibility = ao.abs().max(1.192092896e-7).powf(intensity);
    1.0 - quantise(1.0 - visibility, 255.0)
}

/// BilateralWeight: sat(1 − (aggressiveness·|LinearEyeDepth(d) − central| + 0.01)).
fn bilateral_weight(f: &SsaoFrame, sample_depth: f64, linear_central_depth: f64) -> f64 {
    let delta = (linear_eye_depth(f, sample_depth) - linear_central_depth).abs();
    (1.0 - (f.z_buffer[2] as f64 * delta + 0.01)).clamp(0.0, 1.0)
}

/// GTAOSpatialDenoise without TO_TEMPORAL: the 4×4 texels at HDRP's offsets −1 .. 2 around each
/// pixel (rows from the bottom), the pixel weighted 1 and the rest by their depth; then
/// OutputFinalAO.
fn spatial_denoise(f: &SsaoFrame, ao: &Plane, packed_depth: &Plane) -> Vec<f64> {
    let (w, h) = (ao.width as i64, ao.height as i64);
    let mut out = Vec::with_capacity(ao.texels.len());
    for y_top in 0..h {
        for x in 0..w {
            let y = h - 1 - y_top;
            let linear_central_depth = linear_eye_depth(f, packed_depth.hdrp_load(x, y));
            let (mut total, mut total_weight) = (0.0, 0.0);
            for dy in -1..=2 {
                for dx in -1..=2 {
                    let weight = if (dx, dy) == (0, 0) {
                        1.0
                    } else {
                        bilateral_weight(f, packed_depth.hdrp_load(x + dx, y + dy), linear_central_depth)
                    };
                    total += weight * ao.hdrp_load(x + dx, y + dy);
                    total_weight += weight;
                }
            }
            out.push(final_visibility(total / total_weight, f.params1[0] as f64));
        }
    }
    out
}

/// The visibility from the mean AO of `frames` (None: the non-temporal pass) at the running
/// resolution.
fn visibility_over(
    (width, height): (u32, u32),
    depth: &[f64],
    encoded_normals: &[DVec3],
    frame: &SsaoFrame,
    frames: &[Option<TemporalFrame>],
    full_resolution: bool,
) -> Vec<f64> {
    let [full, l1, l2] = level_sizes(width, height);
    let depth0 = Plane { width: width as usize, height: height as usize, texels: depth.to_vec() };
    let level1 = closest(&depth0, l1);
    let level2 = closest(&level1, l2);
    let g =
        Gtao { frame, level0: &depth0, level1: &level1, level2: &level2, normals: encoded_normals, full_resolution };
    let running = if full_resolution { full } else { l1 };
    let mut ao = Plane::new(running);
    let mut packed_depth = Plane::new(running);
    for y in 0..running.1 {
        for x in 0..running.0 {
            let i = (y * running.0 + x) as usize;
            for t in frames {
                let (a, d) = g.gtao(x, y, *t);
                ao.texels[i] += a / frames.len() as f64;
                packed_depth.texels[i] = d;
            }
        }
    }
    if full_resolution {
        return spatial_denoise(frame, &ao, &packed_depth);
    }
    let intensity = frame.params1[0] as f64;
    let tolerance = 1e-7;
    let noise_filter = 1.0 / (1.0 + tolerance);
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height as i64 {
        for x in 0..width as i64 {
            let (lx, ly) = (x / 2, y / 2);
            let (sx, sy) = (if x & 1 == 1 { 1 } else { -1 }, if y & 1 == 1 { 1 } else { -1 });
            let hi = depth0.load_clamped(x, y);
            let taps = [(lx, ly, 9.0), (lx + sx, ly, 3.0), (lx, ly + sy, 3.0), (lx + sx, ly + sy, 1.0)];
            let (mut sum, mut total) = (noise_filter, noise_filter);
            for (tx, ty, w) in taps {
                let w = w / ((hi - packed_depth.load_clamped(tx, ty)).abs() + tolerance);
                sum += ao.load_clamped(tx, ty) * w;
                total += w;
            }
            out.push(final_visibility(sum / total, intensity));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_acos_stays_near_acos() {
        for i in -100..=100 {
            let x = i as f64 / 100.0;
            assert!((gtao_fast_acos(x) - x.acos()).abs() < 0.07, "{x}");
        }
    }

    #[test]
    fn an_open_horizon_integrates_to_one() {
        // A normal facing the viewer, horizons at ±π/2: the cosine-weighted integral is 1.
        let h = std::f64::consts::FRAC_PI_2;
        assert!((integrate_arc_cos_weighted(-h, h, 0.0, 1.0) - 1.0).abs() < 1e-12);
        // Closed halfway on both sides: ¼·2·(1 − cos(π/2)·...) = 0.5.
        let half = std::f64::consts::FRAC_PI_4;
        assert!((integrate_arc_cos_weighted(-half, half, 0.0, 1.0) - 0.5).abs() < 1e-12);
    }
}
