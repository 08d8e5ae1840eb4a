//! Linear HDR → display-referred sRGB 8-bit: exposure (HDRP), the pipeline's tonemapper, sRGB
//! encode (models.md#display).

use serde::{Deserialize, Serialize};

use super::aces::aces_display;
use super::exposure::{meter, ExposureRecord};
use crate::color::linear_to_srgb;
use crate::pipelines::{DisplayTransform, Tonemap};

/// Narkowicz's ACES fit (models.md#display): sat(x(2.51x + 0.03)/(x(2.43x + 0.59) + 0.14)).
pub fn aces_narkowicz(x: f64) -> f64 {
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// Unity's Neutral curve (core Color.hlsl NeutralCurve): (x(ax + cb) + de)/(x(ax + b) + df) − e/f.
fn neutral_curve(x: f64) -> f64 {
    let (a, b, c, d, e, f) = (0.2, 0.29, 0.24, 0.272, 0.02, 0.3);
    (x * (a * x + c * b) + d * e) / (x * (a * x + b) + d * f) - e / f
}

/// NeutralTonemap: whiteScale = 1/Curve(5.3); Curve(x·whiteScale)·whiteScale; whiteClip 1.
pub fn neutral_tonemap(x: f64) -> f64 {
    let white_scale = 1.0 / neutral_curve(5.3);
    neutral_curve(x * white_scale) * white_scale
}

/// The tonemapper applied to one exposed linear colour: display-linear, not yet clamped.
pub fn apply(tonemap: Tonemap, rgb: [f64; 3]) -> [f64; 3] {
    match tonemap {
        Tonemap::None => rgb,
        Tonemap::Aces => aces_display(rgb),
        Tonemap::Neutral => rgb.map(neutral_tonemap),
        Tonemap::Narkowicz => rgb.map(aces_narkowicz),
    }
}

/// What the display transform did to a cell, recorded in `cell.json`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DisplayRecord {
    pub tonemap: Tonemap,
    /// HDRP's exposure; None in pipelines without one (the multiplier is 1).
    pub exposure: Option<ExposureRecord>,
    /// Mean of the PNG's R, G and B values over all pixels, 0–255.
    pub png_mean: f64,
    /// Share of pixels with a channel within 2 % of the tonemapper's white (its value at HALF_MAX,
    /// or 1 where it clips): highlights at the curve's top, or over-exposure. ACES never reaches
    /// 255, so "at 255" would miss it.
    pub png_saturated: f64,
}

const MEMO_SIZE: usize = 4096;

/// Tonemapped RGBA8 (alpha 255) of a w×h image. Non-finite and negative values map to 0 (the EXR
/// keeps them); the result is clamped to [0, 1] and sRGB-encoded as an sRGB render target would.
pub fn to_srgb8(hdr: &[f32], width: u32, height: u32, display: &DisplayTransform) -> (Vec<u8>, DisplayRecord) {
    let exposure = display.exposure.as_ref().map(|s| meter(hdr, width, height, s));
    to_srgb8_at(hdr, display, exposure)
}

/// The same at a given exposure (None: none, as in pipelines without one) instead of metering
/// this image: a reference shown as its cell was.
pub fn to_srgb8_at(
    hdr: &[f32],
    display: &DisplayTransform,
    exposure: Option<ExposureRecord>,
) -> (Vec<u8>, DisplayRecord) {
    let k = exposure.map_or(1.0, |e| e.exposure);
    let clean = |v: f32| {
        let v = v as f64 * k;
        if v.is_finite() {
            v.max(0.0)
        } else {
            0.0
        }
    };
    let encode = |v: f64| (linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0 + 0.5).floor().clamp(0.0, 255.0) as u8;
    let white = apply(display.tonemap, [65504.0; 3]).into_iter().fold(0.0, f64::max).min(1.0);
    let mut out = Vec::with_capacity(hdr.len());
    let (mut sum, mut saturated) = (0u64, 0usize);
    // Flat backgrounds repeat the same HDR value many times; Unity's ACES costs a few hundred ns a
    // pixel in f64, so a small direct-mapped memo of exact inputs skips the repeats.
    let mut memo = vec![([u32::MAX; 3], [0u8; 3], false); MEMO_SIZE];
    for px in hdr.chunks_exact(4) {
        let key = [px[0].to_bits(), px[1].to_bits(), px[2].to_bits()];
        let slot = (key[0].wrapping_mul(0x9E37_79B1)
            ^ key[1].wrapping_mul(0x85EB_CA77)
            ^ key[2].wrapping_mul(0xC2B2_AE3D)) as usize
            % MEMO_SIZE;
        let (v, at_white) = if memo[slot].0 == key {
            (memo[slot].1, memo[slot].2)
        } else {
            let rgb = apply(display.tonemap, [clean(px[0]), clean(px[1]), clean(px[2])]);
            let v = [encode(rgb[0]), encode(rgb[1]), encode(rgb[2])];
            let at_white = rgb.into_iter().fold(0.0, f64::max) >= 0.98 * white;
            memo[slot] = (key, v, at_white);
            (v, at_white)
        };
        sum += v.iter().map(|&c| c as u64).sum::<u64>();
        saturated += at_white as usize;
        out.extend_from_slice(&[v[0], v[1], v[2], 255]);
    }
    let n = (hdr.len() / 4).max(1);
    let record = DisplayRecord {
        tonemap: display.tonemap,
        exposure,
        png_mean: sum as f64 / (3 * n) as f64,
        png_saturated: saturated as f64 / n as f64,
    };
    (out, record)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn narkowicz_reference_points() {
        assert_eq!(aces_narkowicz(0.0), 0.0);
        assert!((aces_narkowicz(1.0) - 0.8038).abs() < 1e-3, "1 → ≈0.8 (models.md#display)");
        assert_eq!(aces_narkowicz(1e6), 1.0);
        // The spec's comparison: at the exposure target Narkowicz is ×2.8 Unity's ACES.
        let ratio = aces_narkowicz(0.104) / aces_display([0.104; 3])[1];
        assert!((ratio - 2.8).abs() < 0.15, "{ratio}");
    }

    #[test]
    fn neutral_maps_white_level_to_one() {
        // whiteScale = 1/Curve(5.3) scales the input too, so the input reaching white is 5.3·Curve(5.3).
        assert!((neutral_tonemap(5.3 * neutral_curve(5.3)) - 1.0).abs() < 1e-12);
        assert!(neutral_tonemap(0.0).abs() < 1e-12);
        let ys: Vec<f64> = (1..100).map(|i| neutral_tonemap(i as f64 * 0.1)).collect();
        assert!(ys.windows(2).all(|w| w[1] > w[0]), "monotonic");
    }

    #[test]
    fn no_tonemap_clamps_and_encodes() {
        let display = DisplayTransform { tonemap: Tonemap::None, exposure: None };
        let (px, r) = to_srgb8(&[0.0, 0.5, 2.0, 1.0, f32::NAN, -1.0, 1.0, 1.0], 2, 1, &display);
        assert!(r.exposure.is_none(), "no exposure stage without HDRP");
        assert_eq!(&px[0..4], &[0, 188, 255, 255], "linear 0.5 encodes to sRGB 0.735");
        assert_eq!(&px[4..7], &[0, 0, 255]);
    }
}
