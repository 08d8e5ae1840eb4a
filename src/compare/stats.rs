//! Pixel statistics: RMSE, PSNR and the counts of NaN, Inf and negative values.

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

/// PSNR in dB for a peak value; None when the images are identical (infinite PSNR).
pub fn psnr(rmse: f64, peak: f64) -> Option<f64> {
    (rmse > 0.0).then(|| 20.0 * (peak / rmse).log10())
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
