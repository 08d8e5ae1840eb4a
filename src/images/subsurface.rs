//! f64 twin of HDRP's screen-space subsurface scattering filter as `render::passes::subsurface`
//! runs it (shaders/pass/subsurface.wgsl, after SubsurfaceScattering.compute): per pixel that
//! holds split diffuse lighting, `n = min(⌊π(filterRadius·pixelsPerMm)²/4⌋, budget)` samples of the
//! default profile along a golden-angle disc rotated by a hashed phase, each weighted by Burley's
//! profile at the sample's 3-D distance over its density (the bilateral weight), renormalised and
//! multiplied by the post-scatter albedo √albedo. Same names as the WGSL; the tests hold the GPU
//! pass against it on the same read-back buffers.

use glam::DVec3;
use std::f64::consts::PI;

use crate::render::passes::subsurface::SubsurfaceFrame;
use crate::shading::diffusion_profile::{eval_burley_diffusion_profile, sample_burley_diffusion_profile};

/// GOLDEN_RATIO (core Sampling.hlsl).
const GOLDEN_RATIO: f64 = 1.618_033_988_749_895;
/// HDRP's SSS_PIXELS_PER_SAMPLE.
const SSS_PIXELS_PER_SAMPLE: f64 = 4.0;
const MILLIMETERS_PER_METER: f64 = 1000.0;

/// ComputeBilateralWeight (SubsurfaceScattering.compute, SSS_CLAMP_ARTIFACT 0): the profile at
/// the 3-D distance between the two surface points — screen offset² `xy2` in mm², depth difference
/// `z` in world units × `mm_per_unit` — over the sample's density.
pub fn compute_bilateral_weight(xy2: f64, z: f64, mm_per_unit: f64, s: f64, rcp_pdf: f64) -> f64 {
    let r = (xy2 + (z * mm_per_unit) * (z * mm_per_unit)).sqrt();
    eval_burley_diffusion_profile(r, s) * rcp_pdf
}

/// Core Random.hlsl JenkinsHash.
pub fn jenkins_hash(x: u32) -> u32 {
    let mut x = x;
    x = x.wrapping_add(x << 10);
    x ^= x >> 6;
    x = x.wrapping_add(x << 3);
    x ^= x >> 11;
    x = x.wrapping_add(x << 15);
    x
}

/// GenerateHashedRandomFloat(uint3): ConstructFloat(JenkinsHash(v.x ^ JenkinsHash(v.yz))), the
/// hash's 23 low bits as a float in [0, 1).
pub fn generate_hashed_random_float(v: [u32; 3]) -> f64 {
    let h = jenkins_hash(v[0] ^ jenkins_hash(v[1] ^ jenkins_hash(v[2])));
    (f32::from_bits((h & 0x007F_FFFF) | 0x3F80_0000) - 1.0) as f64
}

/// SampleDiskGolden(i, n).y: the golden-angle azimuth 2π·frac(i / φ).
pub fn sample_disk_golden_angle(i: u32) -> f64 {
    2.0 * PI * (i as f64 / GOLDEN_RATIO).fract()
}

/// ApplySubsurfaceScatteringTexturingMode for PreAndPostScatter (the default profile's): √albedo,
/// applied before the filter (the lighting's diffuse colour) and after it.
pub fn apply_subsurface_scattering_texturing_mode(albedo: DVec3) -> DVec3 {
    DVec3::new(albedo.x.sqrt(), albedo.y.sqrt(), albedo.z.sqrt())
}

/// TestLightingForSSS: split lighting was written here (TagLightingForSSS keeps blue above 0).
pub fn test_lighting_for_sss(irradiance: [f32; 4]) -> bool {
    irradiance[2] > 0.0
}

/// What the filter reads of a frame: per pixel (row-major, top row first) the split diffuse
/// lighting, the SSS buffer's albedo and the depth (wgpu's 0..1).
pub struct SubsurfaceBuffers<'a> {
    pub diffuse: &'a [[f32; 4]],
    pub albedo: &'a [[f32; 4]],
    pub depth: &'a [f32],
}

/// One pixel's filtered light, and whether a sample's position lay within rounding of a pixel
/// boundary (where f32 and f64 may pick different neighbours).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scattered {
    pub light: DVec3,
    pub borderline: bool,
}

/// LinearEyeDepth of a wgpu 0..1 depth under the frame's perspective projection.
fn linear_eye_depth(d: f64, near: f64, far: f64) -> f64 {
    near * far / (far - d * (far - near))
}

/// The light the filter adds at every pixel (zero where no split lighting was written).
pub fn subsurface_scattering(frame: &SubsurfaceFrame, b: &SubsurfaceBuffers) -> Vec<Scattered> {
    let (w, h) = (frame.dims[0] as i64, frame.dims[1] as i64);
    let budget = frame.dims[2];
    let [near, far, pixel_size, mask] = frame.camera.map(|v| v as f64);
    let shape = DVec3::new(frame.shape[0] as f64, frame.shape[1] as f64, frame.shape[2] as f64);
    let max_distance = frame.shape[3] as f64;
    let (filter_radius, world_scale) = (frame.kernel[0] as f64, frame.kernel[1] as f64);
    let mut out = vec![Scattered { light: DVec3::ZERO, borderline: false }; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let at = (y * w + x) as usize;
            let center = b.diffuse[at];
            if !test_lighting_for_sss(center) {
                continue;
            }
            let center_irradiance = DVec3::new(center[0] as f64, center[1] as f64, center[2] as f64);
            let a = b.albedo[at];
            let albedo = apply_subsurface_scattering_texturing_mode(DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64));
            let center_depth = b.depth[at];
            let linear_depth = linear_eye_depth(center_depth as f64, near, far);
            let mm_per_unit = MILLIMETERS_PER_METER * (world_scale / mask);
            let units_per_pixel = (pixel_size * linear_depth).max(0.0001);
            let pixels_per_mm = 1.0 / units_per_pixel / mm_per_unit;
            let filter_area = PI * (filter_radius * pixels_per_mm).powi(2);
            let sample_count = (filter_area / SSS_PIXELS_PER_SAMPLE) as u32;
            if mask == 0.0 || sample_count < 1 {
                out[at].light = albedo * center_irradiance;
                continue;
            }
            // HDRP hashes its reversed-Z device depth, 1 − wgpu's, in f32 as the GPU does.
            let reversed = ((1.0f32 - center_depth) * 16_777_216.0f32) as u32;
            let phase = 2.0 * PI * generate_hashed_random_float([x as u32, y as u32, reversed]);
            let n = sample_count.min(budget);
            let (mut total_irradiance, mut total_weight) = (DVec3::ZERO, DVec3::ZERO);
            let mut borderline = false;
            for i in 0..n {
                let (r, rcp_pdf) = sample_burley_diffusion_profile(i as f64 / n as f64 + 0.5 / n as f64, max_distance);
                let psi = phase + sample_disk_golden_angle(i);
                let offset = [pixels_per_mm * r * psi.cos(), pixels_per_mm * r * psi.sin()];
                borderline |= offset.iter().any(|v| (v.abs().fract() - 0.5).abs() < 1e-4);
                let (sx, sy) = (x + offset[0].round_ties_even() as i64, y + offset[1].round_ties_even() as i64);
                if sx < 0 || sy < 0 || sx >= w || sy >= h {
                    continue;
                }
                let sample_at = (sy * w + sx) as usize;
                let irradiance = b.diffuse[sample_at];
                if !test_lighting_for_sss(irradiance) {
                    continue;
                }
                let rel_z = linear_eye_depth(b.depth[sample_at] as f64, near, far) - linear_depth;
                let weight = DVec3::new(
                    compute_bilateral_weight(r * r, rel_z, mm_per_unit, shape.x, rcp_pdf),
                    compute_bilateral_weight(r * r, rel_z, mm_per_unit, shape.y, rcp_pdf),
                    compute_bilateral_weight(r * r, rel_z, mm_per_unit, shape.z, rcp_pdf),
                );
                total_irradiance +=
                    weight * DVec3::new(irradiance[0] as f64, irradiance[1] as f64, irradiance[2] as f64);
                total_weight += weight;
            }
            let total_weight = total_weight.max(DVec3::splat(f32::MIN_POSITIVE as f64));
            out[at] = Scattered { light: albedo * (total_irradiance / total_weight), borderline };
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn in_the_plane_a_sample_weighs_one_and_depth_lowers_it() {
        for s in [0.5, 2.0, 8.0] {
            for k in 1..100 {
                let (r, rcp_pdf) = sample_burley_diffusion_profile(k as f64 / 100.0, 1.0 / s);
                assert!((compute_bilateral_weight(r * r, 0.0, 1000.0, s, rcp_pdf) - 1.0).abs() < 1e-10);
                assert!(compute_bilateral_weight(r * r, 0.002, 1000.0, s, rcp_pdf) < 1.0);
            }
        }
    }

    #[test]
    fn the_hash_is_core_randoms() {
        // JenkinsHash(0) = 0, and the float keeps 23 bits: [0, 1).
        assert_eq!(jenkins_hash(0), 0);
        // x = 1 through the five steps by hand: 1025, 1041, 9369, 9373, 9373·(1 + 2¹⁵).
        assert_eq!(jenkins_hash(1), 307_143_837);
        for v in 0..200u32 {
            let f = generate_hashed_random_float([v, 3 * v, 7]);
            assert!((0.0..1.0).contains(&f));
        }
    }

    #[test]
    fn a_flat_field_stays_flat_and_the_albedo_is_applied_once_more() {
        // A 32×32 plane facing the camera, lit 2.0 everywhere, albedo 0.25: the renormalised filter
        // returns the same light, times √0.25.
        let (w, h) = (32u32, 32u32);
        let frame = SubsurfaceFrame {
            dims: [w, h, 40, 0],
            camera: [0.1, 10.0, 0.0005, 1.0],
            shape: [2.0, 2.0, 2.0, 0.5],
            kernel: [2.85, 1.0, 0.0, 0.0],
        };
        let diffuse = vec![[2.0f32, 2.0, 2.0, 1.0]; (w * h) as usize];
        let albedo = vec![[0.25f32, 0.25, 0.25, 1.0]; (w * h) as usize];
        let depth = vec![0.5f32; (w * h) as usize];
        let out =
            subsurface_scattering(&frame, &SubsurfaceBuffers { diffuse: &diffuse, albedo: &albedo, depth: &depth });
        for p in &out {
            assert!((p.light - DVec3::splat(1.0)).abs().max_element() < 1e-12, "{:?}", p.light);
        }
    }
}
