//! The variance-aware comparison of an image with a noisy reference (a path-traced truth whose
//! per-pixel standard error is known): a per-pixel Z-test, as Mitsuba's render tests use.

use serde::{Deserialize, Serialize};

/// A per-pixel two-sided Z-test of the cell against a path-traced truth, on luminance:
/// z = |cell − truth| / (the truth's standard error), as Mitsuba's render tests test an image
/// against a reference of known variance. A pixel rejects where |z| > `z_critical` (α two-sided);
/// the cell's own half-float target adds its rounding (uniform over one ulp, 2⁻¹⁰ relative) to the
/// variance, so a pixel whose truth has no variance rejects only where the two differ by more
/// than the cell's storage can explain.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ZTest {
    pub alpha: f64,
    pub z_critical: f64,
    /// Share of pixels that reject: the image differs from the light the scene makes there.
    pub rejected: f64,
    /// With Bonferroni's correction over all pixels (α/N): whether any pixel rejects, i.e. the
    /// whole image is distinguishable from the truth at level α.
    pub image_rejects: bool,
    /// Mean |z| over pixels with a finite z.
    pub mean_abs_z: f64,
    /// What the truth's own noise adds to the relative MSE against it, in expectation
    /// (compare::stats::relative_mse_noise): the error bar of that relMSE.
    #[serde(default)]
    pub noise_relative_mse: Option<f64>,
}

/// The two-sided critical value of the standard normal for `alpha` (Acklam's inverse normal,
/// relative error below 1.2e-9).
pub fn z_critical(alpha: f64) -> f64 {
    inverse_normal(1.0 - alpha / 2.0)
}

fn inverse_normal(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] =
        [-5.447609879822406e1, 1.615858368580409e2, -1.556989798598866e2, 6.680131188771972e1, -1.328068155288572e1];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [7.784695709041462e-3, 3.224671290700398e-1, 2.445134137142996, 3.754408661907416];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// A half float's spacing relative to its value, at most (10 mantissa bits).
const HALF_ULP: f64 = 1.0 / 1024.0;

fn luminance(p: &[f32]) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

/// The Z-test of `image` against `truth` (RGBA f32, same size) whose luminance has standard error
/// `std_error` (its first channel per pixel), at level `alpha`.
pub fn ztest(image: &[f32], truth: &[f32], std_error: &[f32], alpha: f64) -> ZTest {
    let n = image.len() / 4;
    let crit = z_critical(alpha);
    let bonferroni = z_critical(alpha / n.max(1) as f64);
    let (mut rejected, mut worst, mut sum, mut finite) = (0usize, 0.0f64, 0.0, 0usize);
    for i in 0..n {
        let (a, b) = (luminance(&image[4 * i..]), luminance(&truth[4 * i..]));
        let rounding = a.abs() * HALF_ULP / 12f64.sqrt();
        let se = ((std_error[4 * i] as f64).powi(2) + rounding * rounding).sqrt();
        let diff = (a - b).abs();
        let z = if se > 0.0 {
            diff / se
        } else if diff == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
        rejected += (z > crit) as usize;
        worst = worst.max(z);
        if z.is_finite() {
            sum += z;
            finite += 1;
        }
    }
    ZTest {
        alpha,
        z_critical: crit,
        rejected: rejected as f64 / n.max(1) as f64,
        image_rejects: worst > bonferroni,
        mean_abs_z: if finite > 0 { sum / finite as f64 } else { 0.0 },
        noise_relative_mse: super::stats::relative_mse_noise(truth, std_error),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn critical_values_are_the_normal_quantiles() {
        assert!((z_critical(0.05) - 1.959964).abs() < 1e-5);
        assert!((z_critical(0.01) - 2.575829).abs() < 1e-5);
        assert!((z_critical(1e-6) - 4.891638).abs() < 1e-4);
    }

    #[test]
    fn an_image_drawn_from_the_truths_noise_passes_and_a_biased_one_fails() {
        // Deterministic "noise": ±1 SE alternating stays well inside 2.58 SE.
        let n = 1000;
        let truth: Vec<f32> = (0..n).flat_map(|_| [0.5, 0.5, 0.5, 1.0]).collect();
        let se: Vec<f32> = (0..n).flat_map(|_| [0.01, 0.01, 0.01, 1.0]).collect();
        let near: Vec<f32> = (0..n)
            .flat_map(|i| {
                let v = 0.5 + if i % 2 == 0 { 0.01 } else { -0.01 };
                [v, v, v, 1.0]
            })
            .collect();
        let t = ztest(&near, &truth, &se, 0.01);
        assert_eq!(t.rejected, 0.0);
        assert!(!t.image_rejects);
        let biased: Vec<f32> = (0..n).flat_map(|_| [0.56, 0.56, 0.56, 1.0]).collect();
        let t = ztest(&biased, &truth, &se, 0.01);
        assert_eq!(t.rejected, 1.0);
        assert!(t.image_rejects && (t.mean_abs_z - 6.0).abs() < 1e-3);
    }
}
