//! Lightmaps from the bake's sums, stored as each pipeline stores them and read back as its
//! shaders decode them (scene.wgsl `lightmap_gi`; the f64 twins below use the same names).
//!
//! - Layer 0, the irradiance/π, as the Lightmap Encoding stores it (plan::gi): Normal Quality,
//!   built-in's and URP's desktop default, RGBM in 8 bits (core EntityLighting.hlsl: in linear
//!   colour space rgb·a^2.2·34.493242, the RGBM range 5 to the power 2.2); Low Quality double LDR
//!   in 8 bits (rgb·4.59); High Quality, which HDRP requires, half floats (BC6H's block
//!   compression is not emulated).
//! - Layer 1, the Directional mode's dominant direction: rgb = d·0.5 + 0.5 where d is the
//!   luminance-weighted mean direction of the texel's incoming light (|d| ≤ 1, its
//!   directionality), a = the half-Lambert term at the texel's own normal, so that
//!   DecodeDirectionalLightmap returns the baked irradiance exactly there; 8 bits a channel.
//! - Layer 2, the shadow mask: each Shadowmask light's visibility in its channel; 8 bits.
//!
//! Texels no chart covers take the mean of their covered neighbours, `padding + 1` rings deep
//! (dilation), so that bilinear reads at a chart's edge never mix in black.

use glam::DVec3;

use super::super::truth::bake::{texel_noise, BakeSums, BAKE_STRIDE};
use crate::geometry::lightmap_uv::LightmapAtlas;

/// 5^2.2: the RGBM range in linear colour space (core EntityLighting.hlsl LIGHTMAP_RGBM_MAX_LINEAR).
pub const LIGHTMAP_RGBM_MAX_LINEAR: f64 = 34.493242;
/// The layers of the lightmap array.
pub const LIGHTMAP_LAYERS: u32 = 3;

/// 2^2.2 rounded as core EntityLighting.hlsl rounds it: the double-LDR range in linear colour
/// space (LIGHTMAP_HDR_MULTIPLIER under UNITY_LIGHTMAP_DLDR_ENCODING).
pub const LIGHTMAP_DLDR_MAX_LINEAR: f64 = 4.59;

/// How a pipeline stores its lightmap's irradiance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightmapEncoding {
    DoubleLdr,
    Rgbm,
    Hdr,
}

impl LightmapEncoding {
    pub fn name(self) -> &'static str {
        match self {
            LightmapEncoding::DoubleLdr => "dldr",
            LightmapEncoding::Rgbm => "rgbm",
            LightmapEncoding::Hdr => "hdr",
        }
    }

    /// The encoding of a Lightmap Encoding quality.
    pub fn of_quality(q: crate::declarations::gi::LightmapQuality) -> LightmapEncoding {
        match q {
            crate::declarations::gi::LightmapQuality::Low => LightmapEncoding::DoubleLdr,
            crate::declarations::gi::LightmapQuality::Normal => LightmapEncoding::Rgbm,
            crate::declarations::gi::LightmapQuality::High => LightmapEncoding::Hdr,
        }
    }

    /// The value the shaders read in `Object.bake.z` (scene.wgsl `lightmap_gi`).
    pub fn shader_value(self) -> f32 {
        match self {
            LightmapEncoding::Hdr => 0.0,
            LightmapEncoding::Rgbm => 1.0,
            LightmapEncoding::DoubleLdr => 2.0,
        }
    }
}

/// A baked lightmap: LIGHTMAP_LAYERS × height × width texels (layer-major, rows top first) as
/// the texture holds them, and what its noise reached.
#[derive(Debug, Clone, PartialEq)]
pub struct Lightmap {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
    /// The decoded irradiance/π per texel of layer 0 (before encoding), for reports and tests.
    pub irradiance: Vec<[f32; 3]>,
    /// The mean over covered texels of the standard error of their luminance over its mean.
    pub noise: Option<f64>,
}

/// UnpackLightmapDoubleLDR in linear colour space: rgb · 4.59.
pub fn unpack_lightmap_double_ldr(c: [f64; 4]) -> DVec3 {
    DVec3::new(c[0], c[1], c[2]) * LIGHTMAP_DLDR_MAX_LINEAR
}

/// The double-LDR texel nearest `v` in 8 bits a channel (values above 4.59 clip).
pub fn pack_lightmap_double_ldr(v: DVec3) -> [f64; 4] {
    let q = |x: f64| ((x / LIGHTMAP_DLDR_MAX_LINEAR).clamp(0.0, 1.0) * 255.0).round() / 255.0;
    [q(v.x), q(v.y), q(v.z), 1.0]
}

/// UnpackLightmapRGBM in linear colour space: rgb · a^2.2 · 5^2.2.
pub fn unpack_lightmap_rgbm(c: [f64; 4]) -> DVec3 {
    DVec3::new(c[0], c[1], c[2]) * (c[3].powf(2.2) * LIGHTMAP_RGBM_MAX_LINEAR)
}

/// The RGBM texel that unpacks closest to `v` in 8 bits a channel: the multiplier's alpha rounded
/// up so that the largest channel fits, the colour rounded to the nearest step.
pub fn pack_lightmap_rgbm(v: DVec3) -> [f64; 4] {
    let q = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() / 255.0;
    let m = v.max_element().max(0.0);
    if m <= 0.0 {
        return [0.0, 0.0, 0.0, 1.0 / 255.0];
    }
    let a = ((m / LIGHTMAP_RGBM_MAX_LINEAR).powf(1.0 / 2.2).min(1.0) * 255.0).ceil().max(1.0) / 255.0;
    let scale = a.powf(2.2) * LIGHTMAP_RGBM_MAX_LINEAR;
    [q(v.x / scale), q(v.y / scale), q(v.z / scale), a]
}

/// DecodeDirectionalLightmap: the half-Lambert term against the baked direction, rebalanced by w.
pub fn decode_directional_lightmap(color: DVec3, dir: [f64; 4], n: DVec3) -> DVec3 {
    let half_lambert = n.dot(DVec3::new(dir[0], dir[1], dir[2]) - 0.5) + 0.5;
    color * half_lambert / dir[3].max(1e-4)
}

fn quantize8(x: f64) -> f32 {
    ((x.clamp(0.0, 1.0) * 255.0).round() / 255.0) as f32
}

/// The lightmap of `atlas` from the sums of its texels (`sums[first..]`, in `atlas.texels` order).
pub fn lightmap_from_sums(
    atlas: &LightmapAtlas,
    sums: &BakeSums,
    first: usize,
    encoding: LightmapEncoding,
    padding: u32,
) -> Lightmap {
    let (w, h) = (atlas.width as usize, atlas.height as usize);
    let mut value = vec![None::<(DVec3, [f64; 4], [f64; 4])>; w * h];
    for (t, s) in atlas.texels.iter().zip(&sums[first..first + atlas.texels.len()]) {
        let s: &[[f32; 4]; BAKE_STRIDE] = s;
        let n = (s[0][3] as f64).max(1.0);
        let mean = DVec3::new(s[0][0] as f64, s[0][1] as f64, s[0][2] as f64) / n;
        let d = if s[2][3] > 0.0 {
            DVec3::new(s[2][0] as f64, s[2][1] as f64, s[2][2] as f64) / s[2][3] as f64
        } else {
            DVec3::ZERO
        };
        let normal = DVec3::from(t.normal.map(f64::from));
        let dir = [d.x * 0.5 + 0.5, d.y * 0.5 + 0.5, d.z * 0.5 + 0.5, normal.dot(d) * 0.5 + 0.5];
        let mask = s[3].map(|v| v as f64 / n);
        value[t.y as usize * w + t.x as usize] = Some((mean, dir, mask));
    }
    // Dilation: each ring takes the mean of its covered 8-neighbours.
    for _ in 0..=padding {
        let before = value.clone();
        for y in 0..h {
            for x in 0..w {
                if before[y * w + x].is_some() {
                    continue;
                }
                let mut acc = (DVec3::ZERO, [0.0; 4], [0.0; 4], 0.0);
                for (dx, dy) in [(-1i64, -1i64), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                        continue;
                    }
                    if let Some((c, d, m)) = before[ny as usize * w + nx as usize] {
                        acc.0 += c;
                        for k in 0..4 {
                            acc.1[k] += d[k];
                            acc.2[k] += m[k];
                        }
                        acc.3 += 1.0;
                    }
                }
                if acc.3 > 0.0 {
                    let k = acc.3;
                    value[y * w + x] = Some((acc.0 / k, acc.1.map(|v| v / k), acc.2.map(|v| v / k)));
                }
            }
        }
    }
    let mut texels = vec![[0.0f32; 4]; LIGHTMAP_LAYERS as usize * w * h];
    let mut irradiance = vec![[0.0f32; 3]; w * h];
    for (i, v) in value.iter().enumerate() {
        let (c, dir, mask) = v.unwrap_or((DVec3::ZERO, [0.5, 0.5, 0.5, 0.5], [1.0; 4]));
        irradiance[i] = c.as_vec3().to_array();
        texels[i] = match encoding {
            LightmapEncoding::Rgbm => pack_lightmap_rgbm(c).map(|x| x as f32),
            LightmapEncoding::DoubleLdr => pack_lightmap_double_ldr(c).map(|x| x as f32),
            LightmapEncoding::Hdr => [c.x as f32, c.y as f32, c.z as f32, 1.0],
        };
        texels[w * h + i] = dir.map(quantize8);
        texels[2 * w * h + i] = mask.map(quantize8);
    }
    let noise = texel_noise(&sums[first..first + atlas.texels.len()]);
    Lightmap { width: atlas.width, height: atlas.height, texels, irradiance, noise }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgbm_round_trips_within_its_8_bit_step_and_clamps_at_its_range() {
        for v in [0.001, 0.02, 0.3, 1.0, 4.0, 20.0, 34.0] {
            let c = DVec3::new(v, v * 0.5, v * 0.25);
            let back = unpack_lightmap_rgbm(pack_lightmap_rgbm(c));
            // One 8-bit step of the colour at the chosen multiplier: ≤ 1/255 of the multiplier.
            let step = pack_lightmap_rgbm(c)[3].powf(2.2) * LIGHTMAP_RGBM_MAX_LINEAR / 255.0;
            assert!((back - c).abs().max_element() <= step * 0.51, "{c} → {back}");
        }
        let over = unpack_lightmap_rgbm(pack_lightmap_rgbm(DVec3::splat(100.0)));
        assert!((over.x - LIGHTMAP_RGBM_MAX_LINEAR).abs() < 1e-9, "{over}");
    }

    #[test]
    fn double_ldr_round_trips_within_its_8_bit_step_and_clips_at_4_59() {
        for v in [0.0, 0.01, 0.5, 1.0, 3.0, 4.5] {
            let c = DVec3::new(v, v * 0.5, v * 0.25);
            let back = unpack_lightmap_double_ldr(pack_lightmap_double_ldr(c));
            assert!((back - c).abs().max_element() <= 0.51 * LIGHTMAP_DLDR_MAX_LINEAR / 255.0, "{c} → {back}");
        }
        let over = unpack_lightmap_double_ldr(pack_lightmap_double_ldr(DVec3::splat(10.0)));
        assert_eq!(over, DVec3::splat(LIGHTMAP_DLDR_MAX_LINEAR));
    }

    #[test]
    fn the_directional_decode_returns_the_bake_at_the_baked_normal() {
        let n = DVec3::new(0.0, 1.0, 0.0);
        let d = DVec3::new(0.3, 0.6, -0.2);
        let dir = [d.x * 0.5 + 0.5, d.y * 0.5 + 0.5, d.z * 0.5 + 0.5, n.dot(d) * 0.5 + 0.5];
        let c = DVec3::new(0.4, 0.5, 0.6);
        assert!((decode_directional_lightmap(c, dir, n) - c).abs().max_element() < 1e-12);
        // A normal turned towards the light's direction reads more.
        let towards = (n + d).normalize();
        assert!(decode_directional_lightmap(c, dir, towards).x > c.x);
    }
}
