//! Pixel statistics: RMSE, PSNR, relative MSE and the counts of NaN, Inf and negative values.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq)]
pub struct BadValues {
    pub nan: usize,
    pub inf: usize,
    pub negative: usize,
}

impl BadValues {
    pub fn clean(&self) -> bool {
        *self == BadValues::default()
    }
}

pub fn bad_values(values: impl Iterator<Item = f64>) -> BadValues {
    let mut b = BadValues::default();
    for v in values {
        if v.is_nan() {
            b.nan += 1;
        } else if v.is_infinite() {
            b.inf += 1;
        } else if v < 0.0 {
            b.negative += 1;
        }
    }
    b
}

/// Root mean square difference over RGB (alpha ignored), skipping pairs where either is not finite.
pub fn rmse(a: &[f64], b: &[f64]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        if i % 4 == 3 || !x.is_finite() || !y.is_finite() {
            continue;
        }
        sum += (x - y) * (x - y);
        n += 1;
    }
    (sum / n.max(1) as f64).sqrt()
}

/// Relative mean squared error of linear RGBA images (Rousselle, Knaus & Zwicker 2012): the mean
/// over pixels and colour channels of (t − r)² / (r² + ε), with ε = 0.01 × the reference's mean
/// luminance² where the paper's 0.01 assumes unit-scale radiance, so that the figure does not
/// depend on the images' units (HDRP's physical light against built-in's unitless intensity).
/// Pairs where either value is not finite are skipped; None when none is left or the reference
/// is black.
pub fn relative_mse(reference: &[f32], test: &[f32]) -> Option<f64> {
    let eps = relative_epsilon(reference)?;
    let (mut sum, mut n) = (0.0, 0usize);
    for (r, t) in reference.chunks_exact(4).zip(test.chunks_exact(4)) {
        for c in 0..3 {
            let (r, t) = (r[c] as f64, t[c] as f64);
            if r.is_finite() && t.is_finite() {
                sum += (t - r) * (t - r) / (r * r + eps);
                n += 1;
            }
        }
    }
    (n > 0).then(|| sum / n as f64)
}

/// ε of `relative_mse`: 0.01 × the reference's mean luminance² over its finite pixels; None when
/// the reference is black.
fn relative_epsilon(reference: &[f32]) -> Option<f64> {
    let lum = |p: &[f32]| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
    let finite = |p: &&[f32]| p[..3].iter().all(|v| v.is_finite());
    let lums: Vec<f64> = reference.chunks_exact(4).filter(finite).map(lum).collect();
    let mean = lums.iter().sum::<f64>() / lums.len().max(1) as f64;
    (mean > 0.0).then_some(0.01 * mean * mean)
}

/// What a reference's noise adds to `relative_mse` against it, in expectation: E[(t − r̂)²] =
/// (t − r)² + Var r̂, so the mean over pixels and channels of se² / (r² + ε), with `std_error`
/// the standard error of each pixel's luminance (RGBA, in R) standing for each channel's.
pub fn relative_mse_noise(reference: &[f32], std_error: &[f32]) -> Option<f64> {
    let eps = relative_epsilon(reference)?;
    let (mut sum, mut n) = (0.0, 0usize);
    for (r, se) in reference.chunks_exact(4).zip(std_error.chunks_exact(4)) {
        let var = (se[0] as f64).powi(2);
        for &r in &r[..3] {
            if r.is_finite() && var.is_finite() {
                sum += var / (r as f64 * r as f64 + eps);
                n += 1;
            }
        }
    }
    (n > 0).then(|| sum / n as f64)
}

/// PSNR in dB for a peak value; None when the images are identical (infinite PSNR).
pub fn psnr(rmse: f64, peak: f64) -> Option<f64> {
    (rmse > 0.0).then(|| 20.0 * (peak / rmse).log10())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A noisy reference of known standard error against the exact image: its measured relMSE is
    /// what `relative_mse_noise` says the noise adds.
    #[test]
    fn a_references_noise_adds_what_relative_mse_noise_says() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let n = 20_000;
        let exact: Vec<f32> = (0..n).flat_map(|i| [0.5 + (i % 7) as f32 * 0.1, 0.4, 0.3, 1.0]).collect();
        let se: Vec<f32> = (0..n).flat_map(|i| [0.01 + (i % 3) as f32 * 0.01; 4]).collect();
        let noisy: Vec<f32> = exact
            .chunks_exact(4)
            .zip(se.chunks_exact(4))
            .flat_map(|(p, s)| {
                let mut q = [p[0], p[1], p[2], 1.0];
                for c in q.iter_mut().take(3) {
                    let (u1, u2) = (uniform().max(1e-12), uniform());
                    let g = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
                    *c += (g * s[0] as f64) as f32;
                }
                q
            })
            .collect();
        let measured = relative_mse(&noisy, &exact).unwrap();
        let predicted = relative_mse_noise(&noisy, &se).unwrap();
        assert!((measured / predicted - 1.0).abs() < 0.05, "measured {measured:.3e}, predicted {predicted:.3e}");
    }

    #[test]
    fn rmse_psnr_and_counts() {
        let a = [0.0, 0.0, 0.0, 1.0, 0.5, 0.5, 0.5, 1.0];
        let b = [0.1, 0.1, 0.1, 0.0, 0.5, 0.5, 0.5, 0.0];
        let r = rmse(&a, &b);
        assert!((r - (0.03f64 / 6.0).sqrt()).abs() < 1e-12);
        assert!((psnr(0.1, 1.0).unwrap() - 20.0).abs() < 1e-12);
        assert_eq!(psnr(0.0, 1.0), None);
        assert_eq!(
            bad_values([f64::NAN, -1.0, f64::INFINITY, 2.0].into_iter()),
            BadValues { nan: 1, inf: 1, negative: 1 }
        );
    }

    #[test]
    fn relative_mse_is_scale_free_and_relative() {
        let r = [1.0f32, 1.0, 1.0, 1.0, 3.0, 3.0, 3.0, 1.0];
        let t = [1.1f32, 1.1, 1.1, 1.0, 3.3, 3.3, 3.3, 1.0];
        let e = relative_mse(&r, &t).unwrap();
        // 10 % off everywhere: (0.1r)²/(r² + 0.04) per value, mean luminance 2.
        let want = (0.01 / (1.0 + 0.04) + 0.09 / (9.0 + 0.04)) / 2.0;
        assert!((e - want).abs() < 1e-6, "{e} {want}");
        let scaled = |v: &[f32]| v.iter().map(|x| x * 1e4).collect::<Vec<f32>>();
        assert!((relative_mse(&scaled(&r), &scaled(&t)).unwrap() - e).abs() < 1e-6);
        assert_eq!(relative_mse(&[0.0; 4], &[1.0; 4]), None);
    }
}
