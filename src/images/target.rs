//! The camera target's range. Every pipeline emulated here stores its lit colour in a half-float
//! target (built-in's HDR camera ARGBHalf, URP's and HDRP's R11G11B10/RGBA16F), so a finite value
//! above HALF_MAX = 65504 (after the pre-exposure the pipeline writes with) cannot be stored. URP
//! clamps it explicitly ("Clamp any half.inf+ to HALF_MAX": `min(CalculateFinalColor(…), HALF_MAX)`
//! in UniversalFragmentPBR, Lighting.hlsl, under REAL_IS_HALF); a float→half conversion that rounds
//! toward zero (D3D, and Vulkan allows it) lands on the same value. The renderer keeps f32 targets so
//! the overflow can be counted (`stats::PixelStats::overflow`); this is the store that follows:
//! the written images hold the saturated values. NaN and ±Inf pass through unchanged — they are
//! findings, and an infinity is not an overflow of a finite formula.

use super::stats::HALF_MAX;

/// Saturate the finite colour values above the half-float range at `HALF_MAX / pre_exposure` (the
/// value that becomes HALF_MAX once pre-exposed); returns how many channel values it changed.
/// Alpha is left alone.
pub fn store_half_float(hdr: &mut [f32], pre_exposure: f64) -> usize {
    let limit = (HALF_MAX as f64 / pre_exposure.max(f64::MIN_POSITIVE)) as f32;
    let mut saturated = 0;
    for px in hdr.chunks_exact_mut(4) {
        for v in &mut px[..3] {
            if v.is_finite() && *v > limit {
                *v = limit;
                saturated += 1;
            }
        }
    }
    saturated
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saturates_finite_values_above_the_half_range_and_keeps_the_rest() {
        let mut hdr = vec![7.4e5, 65504.0, 1.0, 9e9, f32::INFINITY, f32::NAN, -1.0, 2e5];
        assert_eq!(store_half_float(&mut hdr, 1.0), 1);
        assert_eq!(&hdr[..4], &[65504.0, 65504.0, 1.0, 9e9]);
        assert!(hdr[4].is_infinite() && hdr[5].is_nan() && hdr[6] == -1.0);
        // pre-exposed by 0.01: the stored limit is 6.5504e6 in scene units
        let mut hdr = vec![1e6, 1e7, 0.0, 1.0];
        assert_eq!(store_half_float(&mut hdr, 0.01), 1);
        assert_eq!(hdr[1], 6.5504e6);
    }
}
