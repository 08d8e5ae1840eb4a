//! f64 twin of URP's SSAO renderer feature as `render::passes::urp_ssao` runs it
//! (shaders/pass/urp_ssao.wgsl): the Alchemy obscurance with interleaved gradient noise, the
//! horizontal and vertical bilateral blurs over bilinear taps and the final 5-tap blur, each
//! stored at 8 bits per channel. Same names as the WGSL; the tests hold the GPU steps against it.

use glam::{DVec2, DVec3, DVec4};

use crate::render::passes::urp_ssao::UrpSsaoFrame;

/// kContrast, kGeometryCoeff, kBeta, kEpsilon, SKY_DEPTH_VALUE (SSAO.hlsl).
const K_CONTRAST: f64 = 0.6;
const K_GEOMETRY_COEFF: f64 = 0.8;
const K_BETA: f64 = 0.004;
const K_EPSILON: f64 = 0.0001;
const SKY_DEPTH_VALUE: f64 = 0.00001;

/// SSAORandomUV.
const SSAO_RANDOM_UV: [f64; 40] = [
    0.00000000, 0.33984375, 0.75390625, 0.56640625, 0.98437500, 0.07421875, 0.23828125, 0.64062500, 0.35937500,
    0.50781250, 0.38281250, 0.98437500, 0.17578125, 0.53906250, 0.28515625, 0.23137260, 0.45882360, 0.54117650,
    0.12941180, 0.64313730, 0.92968750, 0.76171875, 0.13333330, 0.01562500, 0.00000000, 0.10546875, 0.64062500,
    0.74609375, 0.67968750, 0.35156250, 0.49218750, 0.12500000, 0.26562500, 0.62500000, 0.44531250, 0.17647060,
    0.44705890, 0.93333340, 0.87058830, 0.56862750,
];

fn get_random_val(u: usize, sample_index: usize) -> f64 {
    SSAO_RANDOM_UV[u * 20 + sample_index]
}

fn fract(x: f64) -> f64 {
    x - x.floor()
}

/// InterleavedGradientNoise (core Random.hlsl).
pub fn interleaved_gradient_noise(pixel: DVec2, frame_count: u32) -> f64 {
    let p = pixel + frame_count as f64 * DVec2::new(2.083, 4.867);
    fract(52.9829189 * fract(p.dot(DVec2::new(0.06711056, 0.00583715))))
}

/// round(x·255)/255 after saturation: an 8-bit UNORM store.
fn unorm8(x: f64) -> f64 {
    (x.clamp(0.0, 1.0) * 255.0).round() / 255.0
}

fn v3(a: [f32; 4]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}

struct Inputs<'a> {
    f: &'a UrpSsaoFrame,
    size: (usize, usize),
    depth: &'a [f64],
    normals: &'a [DVec3],
}

impl Inputs<'_> {
    /// The clamped texel at Unity's uv (bottom-up), point-sampled.
    fn texel(&self, uv: DVec2) -> usize {
        let (w, h) = self.size;
        let x = ((uv.x * w as f64).floor() as i64).clamp(0, w as i64 - 1) as usize;
        let y = (((1.0 - uv.y) * h as f64).floor() as i64).clamp(0, h as i64 - 1) as usize;
        y * w + x
    }

    fn sample_depth(&self, uv: DVec2) -> f64 {
        self.depth[self.texel(uv)]
    }

    fn sample_normal(&self, uv: DVec2) -> DVec3 {
        let n = self.normals[self.texel(uv)] * 2.0 - DVec3::ONE;
        (n.clamp(-DVec3::ONE, DVec3::ONE) * 127.0).round() / 127.0
    }

    fn linear_eye_depth(&self, raw: f64) -> f64 {
        let (n, far) = (self.f.camera[1] as f64, self.f.camera[2] as f64);
        n * far / (far - raw * (far - n))
    }

    fn reconstruct_view_pos(&self, uv: DVec2, linear_depth: f64) -> DVec3 {
        let p = v3(self.f.top_left) + v3(self.f.x_extent) * uv.x + v3(self.f.y_extent) * (1.0 - uv.y);
        p * (linear_depth * self.f.camera[0] as f64)
    }

    fn pick_sample_point(&self, uv: DVec2, sample_index: usize, rcp_sample_count: f64, normal: DVec3) -> DVec3 {
        let size = DVec2::new(self.f.source_size[0] as f64, self.f.source_size[1] as f64);
        let position_ss = uv * size * self.f.params[2] as f64;
        let noise = interleaved_gradient_noise(position_ss, sample_index as u32);
        let u = fract(get_random_val(0, sample_index) + noise) * 2.0 - 1.0;
        let theta = (get_random_val(1, sample_index) + noise) * 2.0 * std::f64::consts::PI;
        let u2 = (1.0 - u * u).sqrt();
        let mut v = DVec3::new(u2 * theta.cos(), u2 * theta.sin(), u);
        v *= ((sample_index as f64 + 1.0) * rcp_sample_count).sqrt();
        v = -v * sign(-normal.dot(v));
        v * self.f.params[1] as f64
    }

    /// SSAO: the packed (obscurance, n·½ + ½) before the 8-bit store.
    fn alchemy_obscurance(&self, uv: DVec2) -> DVec4 {
        let raw_o = self.sample_depth(uv);
        if 1.0 - raw_o < SKY_DEPTH_VALUE {
            return pack_ao_normal(0.0, DVec3::ZERO);
        }
        let depth_o = self.linear_eye_depth(raw_o);
        let falloff_distance = self.f.params[3] as f64;
        if depth_o > falloff_distance {
            return pack_ao_normal(0.0, DVec3::ZERO);
        }
        let normal_o = self.sample_normal(uv);
        let vpos_o = self.reconstruct_view_pos(uv, depth_o);
        let sample_count = self.f.camera[3] as usize;
        let rcp_sample_count = 1.0 / sample_count as f64;
        let radius = self.f.params[1] as f64;
        let mut ao = 0.0;
        for s in 0..sample_count {
            let vpos_s1 = vpos_o + self.pick_sample_point(uv, s, rcp_sample_count, normal_o);
            let spos = DVec2::new(v3(self.f.view_proj0).dot(vpos_s1), v3(self.f.view_proj1).dot(vpos_s1));
            let z_dist = -v3(self.f.view_z).dot(vpos_s1);
            let uv_s1 = ((spos / z_dist + DVec2::ONE) * 0.5).clamp(DVec2::ZERO, DVec2::ONE);
            let raw_s = self.sample_depth(uv_s1);
            let depth_s = self.linear_eye_depth(raw_s);
            let inside = ((z_dist - depth_s).abs() < radius && 1.0 - raw_s > SKY_DEPTH_VALUE) as u32 as f64;
            let v_s2 = self.reconstruct_view_pos(uv_s1, depth_s) - vpos_o;
            let a1 = (v_s2.dot(normal_o) - K_BETA * depth_o).max(0.0);
            let a2 = v_s2.dot(v_s2) + K_EPSILON;
            ao += a1 / a2 * inside;
        }
        ao *= radius;
        let falloff = (1.0 - depth_o / falloff_distance).powi(2);
        ao = (ao * self.f.params[0] as f64 * falloff * rcp_sample_count).clamp(0.0, 1.0).powf(K_CONTRAST);
        pack_ao_normal(ao, normal_o)
    }
}

/// HLSL sign: −1, 0 or 1.
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// PackAONormal: (ao, n·½ + ½) as the texture's r, g, b, a.
fn pack_ao_normal(ao: f64, n: DVec3) -> DVec4 {
    let m = n * 0.5 + DVec3::splat(0.5);
    DVec4::new(ao, m.x, m.y, m.z)
}

fn get_packed_normal(p: DVec4) -> DVec3 {
    DVec3::new(p.y, p.z, p.w) * 2.0 - DVec3::ONE
}

fn compare_normal(d1: DVec3, d2: DVec3) -> f64 {
    let t = ((d1.dot(d2) - K_GEOMETRY_COEFF) / (1.0 - K_GEOMETRY_COEFF)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// An 8-bit RGBA target, row-major, top row first.
struct Target {
    size: (usize, usize),
    texels: Vec<DVec4>,
}

impl Target {
    fn load(&self, x: i64, y: i64) -> DVec4 {
        let (w, h) = self.size;
        self.texels[y.clamp(0, h as i64 - 1) as usize * w + x.clamp(0, w as i64 - 1) as usize]
    }

    /// SAMPLE_BASEMAP: bilinear, clamped, at Unity's uv.
    fn sample_basemap(&self, uv: DVec2) -> DVec4 {
        let (w, h) = self.size;
        let p = DVec2::new(uv.x * w as f64, (1.0 - uv.y) * h as f64) - DVec2::splat(0.5);
        let i = p.floor();
        let t = p - i;
        let (x, y) = (i.x as i64, i.y as i64);
        let top = self.load(x, y).lerp(self.load(x + 1, y), t.x);
        let bottom = self.load(x, y + 1).lerp(self.load(x + 1, y + 1), t.x);
        top.lerp(bottom, t.y)
    }

    fn bilateral_blur(&self, uv: DVec2, delta: DVec2) -> DVec4 {
        let p0 = self.sample_basemap(uv);
        let p1a = self.sample_basemap(uv - delta * 1.3846153846);
        let p1b = self.sample_basemap(uv + delta * 1.3846153846);
        let p2a = self.sample_basemap(uv - delta * 3.2307692308);
        let p2b = self.sample_basemap(uv + delta * 3.2307692308);
        let n0 = get_packed_normal(p0);
        let w0 = 0.2270270270;
        let w1a = compare_normal(n0, get_packed_normal(p1a)) * 0.3162162162;
        let w1b = compare_normal(n0, get_packed_normal(p1b)) * 0.3162162162;
        let w2a = compare_normal(n0, get_packed_normal(p2a)) * 0.0702702703;
        let w2b = compare_normal(n0, get_packed_normal(p2b)) * 0.0702702703;
        let s = p0.x * w0 + p1a.x * w1a + p1b.x * w1b + p2a.x * w2a + p2b.x * w2b;
        pack_ao_normal(s / (w0 + w1a + w1b + w2a + w2b), n0)
    }

    fn blur_small(&self, uv: DVec2, delta: DVec2) -> f64 {
        let p0 = self.sample_basemap(uv);
        let taps = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
            .map(|(sx, sy)| self.sample_basemap(uv + DVec2::new(sx * delta.x, sy * delta.y)));
        let n0 = get_packed_normal(p0);
        let (mut s, mut w) = (p0.x, 1.0);
        for p in taps {
            let wi = compare_normal(n0, get_packed_normal(p));
            s += p.x * wi;
            w += wi;
        }
        s / w
    }

    fn map(&self, step: impl Fn(DVec2) -> DVec4) -> Target {
        let (w, h) = self.size;
        let texels = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let uv = DVec2::new((x as f64 + 0.5) / w as f64, 1.0 - (y as f64 + 0.5) / h as f64);
                let v = step(uv);
                DVec4::new(unorm8(v.x), unorm8(v.y), unorm8(v.z), unorm8(v.w))
            })
            .collect();
        Target { size: self.size, texels }
    }
}

/// The visibility the lighting reads, per pixel (row-major, top row first), from a raw depth
/// buffer (wgpu's 0..1) and world normals encoded as the prepass writes them (n·0.5 + 0.5).
pub fn visibility(width: u32, height: u32, depth: &[f64], encoded_normals: &[DVec3], f: &UrpSsaoFrame) -> Vec<f64> {
    let size = (width as usize, height as usize);
    let inputs = Inputs { f, size, depth, normals: encoded_normals };
    let blank = Target { size, texels: vec![DVec4::ZERO; size.0 * size.1] };
    let occlusion = blank.map(|uv| inputs.alchemy_obscurance(uv));
    let texel = DVec2::new(f.source_size[2] as f64, f.source_size[3] as f64) / f.params[2] as f64;
    let horizontal = occlusion.map(|uv| occlusion.bilateral_blur(uv, DVec2::new(texel.x, 0.0)));
    let vertical = horizontal.map(|uv| horizontal.bilateral_blur(uv, DVec2::new(0.0, texel.y)));
    let last = vertical.map(|uv| DVec4::new(1.0 - vertical.blur_small(uv, texel), 0.0, 0.0, 1.0));
    last.texels.iter().map(|t| t.x).collect()
}

/// The obscurance step alone (before any blur), per pixel: what the blurs smooth.
pub fn obscurance(width: u32, height: u32, depth: &[f64], encoded_normals: &[DVec3], f: &UrpSsaoFrame) -> Vec<f64> {
    let size = (width as usize, height as usize);
    let inputs = Inputs { f, size, depth, normals: encoded_normals };
    let blank = Target { size, texels: vec![DVec4::ZERO; size.0 * size.1] };
    blank.map(|uv| inputs.alchemy_obscurance(uv)).texels.iter().map(|t| t.x).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_and_the_packing_follow_ssao_hlsl() {
        // frac(52.9829189·frac(0.5·0.06711056 + 0.5·0.00583715)), frame 0
        let n = interleaved_gradient_noise(DVec2::new(0.5, 0.5), 0);
        let inner = fract(0.5 * 0.06711056 + 0.5 * 0.00583715);
        assert!((n - fract(52.9829189 * inner)).abs() < 1e-12);
        let p = pack_ao_normal(0.3, DVec3::new(0.0, 1.0, 0.0));
        assert_eq!(p, DVec4::new(0.3, 0.5, 1.0, 0.5));
        assert_eq!(get_packed_normal(p), DVec3::new(0.0, 1.0, 0.0));
        // CompareNormal is smoothstep(0.8, 1, ·): 0 at 0.8, 1 at 1, ½ halfway.
        let unit = DVec3::Y;
        assert_eq!(compare_normal(unit, unit), 1.0);
        assert!((compare_normal(unit, DVec3::new(0.6, 0.8, 0.0)) - 0.0).abs() < 1e-12);
        assert!((compare_normal(unit, DVec3::new(0.0, 0.9, 0.0)) - 0.5).abs() < 1e-12);
    }
}
