//! Linear HDR → display-referred sRGB 8-bit, per pipeline convention (pipelines::Tonemap).

use crate::color::{linear_to_srgb, luminance};
use crate::pipelines::Tonemap;

/// Narkowicz's ACES fit (models.md#display): sat(x(2.51x + 0.03)/(x(2.43x + 0.59) + 0.14)).
pub fn aces_narkowicz(x: f64) -> f64 {
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// HDRP's default histogram range: pixels between these luminance percentiles set the exposure.
pub const METERING_PERCENTILES: (f64, f64) = (0.40, 0.90);

/// HDRP automatic exposure (models.md#hdrp): the mean log2 luminance of the pixels between the 40th and
/// 90th percentile (HDRP's default histogram percentages; black backgrounds and highlights do not
/// drag it), EV100 = log2(L·100/12.5) clamped to −10..10, exposure = 1/(1.2·2^EV). APPROXIMATION of
/// HDRP's histogram: exact percentiles instead of its 128 bins, and no temporal adaptation.
pub fn auto_exposure(hdr: &[f32]) -> f64 {
    let mut logs: Vec<f64> = hdr
        .chunks_exact(4)
        .map(|px| luminance([px[0] as f64, px[1] as f64, px[2] as f64]))
        .filter(|l| l.is_finite())
        .map(|l| l.max(1e-10).log2())
        .collect();
    if logs.is_empty() {
        return 1.0;
    }
    logs.sort_by(|a, b| a.total_cmp(b));
    let n = logs.len();
    let lo = ((n as f64 * METERING_PERCENTILES.0) as usize).min(n - 1);
    let hi = ((n as f64 * METERING_PERCENTILES.1) as usize).clamp(lo + 1, n);
    let mean_log = logs[lo..hi].iter().sum::<f64>() / (hi - lo) as f64;
    let ev = (mean_log.exp2() * 100.0 / 12.5).log2().clamp(-10.0, 10.0);
    1.0 / (1.2 * ev.exp2())
}

/// Tonemapped RGBA8 (alpha 255). Non-finite and negative values map to 0: the EXR keeps them.
pub fn to_srgb8(hdr: &[f32], tonemap: Tonemap) -> (Vec<u8>, f64) {
    let exposure = match tonemap {
        Tonemap::None => 1.0,
        Tonemap::AutoExposureAcesFit => auto_exposure(hdr),
    };
    let map = |v: f32| -> u8 {
        let v = v as f64 * exposure;
        let v = if v.is_finite() { v.max(0.0) } else { 0.0 };
        let v = match tonemap {
            Tonemap::None => v.min(1.0),
            Tonemap::AutoExposureAcesFit => aces_narkowicz(v),
        };
        (linear_to_srgb(v) * 255.0 + 0.5).floor().clamp(0.0, 255.0) as u8
    };
    let mut out = Vec::with_capacity(hdr.len());
    for px in hdr.chunks_exact(4) {
        out.extend_from_slice(&[map(px[0]), map(px[1]), map(px[2]), 255]);
    }
    (out, exposure)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aces_fit_reference_points() {
        assert_eq!(aces_narkowicz(0.0), 0.0);
        assert!((aces_narkowicz(1.0) - 0.8038).abs() < 1e-3, "1 → ≈0.8 (models.md#display)");
        assert_eq!(aces_narkowicz(1e6), 1.0);
    }

    #[test]
    fn no_tonemap_clamps_and_encodes() {
        let (px, e) = to_srgb8(&[0.0, 0.5, 2.0, 1.0, f32::NAN, -1.0, 1.0, 1.0], Tonemap::None);
        assert_eq!(e, 1.0);
        assert_eq!(&px[0..4], &[0, 188, 255, 255], "linear 0.5 encodes to sRGB 0.735");
        assert_eq!(&px[4..7], &[0, 0, 255]);
    }

    #[test]
    fn exposure_ignores_a_black_majority_below_the_40th_percentile() {
        // 30 % black pixels, 70 % at luminance 100: metering sees only the lit ones.
        let mut img = vec![0.0f32; 30 * 4];
        img.extend(std::iter::repeat_n(100.0f32, 70 * 4));
        let e = auto_exposure(&img);
        assert!((e * 100.0 - 12.5 / 120.0).abs() < 1e-3, "{e}");
    }

    #[test]
    fn auto_exposure_maps_average_to_mid_grey() {
        let img = vec![100.0f32; 16];
        let e = auto_exposure(&img);
        assert!((e * 100.0 - 12.5 / 120.0 * 1.0).abs() < 1e-3, "{e}");
    }
}
