//! SSIM (Wang et al. 2004) exactly as scikit-image's `structural_similarity(gaussian_weights=True,
//! sigma=1.5, use_sample_covariance=False, data_range=1)` computes it: an 11-tap Gaussian window
//! (σ = 1.5, truncated at 3.5σ) applied separably with scipy's `reflect` boundary, K1 = 0.01,
//! K2 = 0.03, population covariance, and the mean over the window-valid region (a 5-pixel border
//! cropped). Written by hand because the crates measured for the issue disagree with the reference
//! (`image-compare`), give no map (`iqa`), or downsample large images (`blazediff-ssim`).

pub const SIGMA: f64 = 1.5;
pub const RADIUS: usize = 5;
pub const K1: f64 = 0.01;
pub const K2: f64 = 0.03;

#[derive(Debug, Clone)]
pub struct SsimResult {
    pub mean: f64,
    /// Per-pixel SSIM, row-major.
    pub map: Vec<f64>,
    pub width: usize,
    pub height: usize,
}

/// The window's weights (`compare::gpu` runs the same window).
pub fn window() -> [f64; 2 * RADIUS + 1] {
    kernel()
}

/// The mean of an SSIM map over the window-valid region (a 5-pixel border cropped), as
/// scikit-image reports it.
pub fn window_mean(map: &[f64], w: usize, h: usize) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for y in RADIUS..h - RADIUS {
        for x in RADIUS..w - RADIUS {
            sum += map[y * w + x];
            n += 1;
        }
    }
    sum / n as f64
}

/// scipy.ndimage.gaussian_filter1d weights: exp(−x²/2σ²), x = −5..5, normalised.
fn kernel() -> [f64; 2 * RADIUS + 1] {
    let mut k = [0.0; 2 * RADIUS + 1];
    for (i, w) in k.iter_mut().enumerate() {
        let x = i as f64 - RADIUS as f64;
        *w = (-0.5 * x * x / (SIGMA * SIGMA)).exp();
    }
    let sum: f64 = k.iter().sum();
    k.map(|w| w / sum)
}

/// scipy's `reflect`: (d c b a | a b c d | d c b a).
fn reflect(i: isize, n: usize) -> usize {
    let n = n as isize;
    let period = 2 * n;
    let m = i.rem_euclid(period);
    (if m < n { m } else { period - 1 - m }) as usize
}

fn filter(src: &[f64], w: usize, h: usize) -> Vec<f64> {
    let k = kernel();
    let mut tmp = vec![0.0; w * h];
    for y in 0..h {
        for x in 0..w {
            tmp[y * w + x] = k
                .iter()
                .enumerate()
                .map(|(j, kj)| kj * src[y * w + reflect(x as isize + j as isize - RADIUS as isize, w)])
                .sum();
        }
    }
    let mut out = vec![0.0; w * h];
    for y in 0..h {
        for x in 0..w {
            out[y * w + x] = k
                .iter()
                .enumerate()
                .map(|(j, kj)| kj * tmp[reflect(y as isize + j as isize - RADIUS as isize, h) * w + x])
                .sum();
        }
    }
    out
}

/// SSIM of two single-channel images with values in [0, 1].
pub fn ssim(a: &[f64], b: &[f64], w: usize, h: usize) -> Result<SsimResult, String> {
    if a.len() != w * h || b.len() != w * h {
        return Err("images differ in size".into());
    }
    if w < 2 * RADIUS + 1 || h < 2 * RADIUS + 1 {
        return Err(format!("{w}×{h} is smaller than the 11×11 SSIM window"));
    }
    let mul = |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(x, y)| x * y).collect::<Vec<f64>>();
    let (ux, uy) = (filter(a, w, h), filter(b, w, h));
    let (uxx, uyy, uxy) = (filter(&mul(a, a), w, h), filter(&mul(b, b), w, h), filter(&mul(a, b), w, h));
    let (c1, c2) = (K1 * K1, K2 * K2);
    let map: Vec<f64> = (0..w * h)
        .map(|i| {
            let (vx, vy, vxy) = (uxx[i] - ux[i] * ux[i], uyy[i] - uy[i] * uy[i], uxy[i] - ux[i] * uy[i]);
            let (a1, a2) = (2.0 * ux[i] * uy[i] + c1, 2.0 * vxy + c2);
            let (b1, b2) = (ux[i] * ux[i] + uy[i] * uy[i] + c1, vx + vy + c2);
            a1 * a2 / (b1 * b2)
        })
        .collect();
    Ok(SsimResult { mean: window_mean(&map, w, h), map, width: w, height: h })
}

/// Y′ = 0.2126 R′ + 0.7152 G′ + 0.0722 B′ of sRGB-encoded RGBA8 values in [0, 1], no requantisation.
pub fn luma(rgba8: &[u8]) -> Vec<f64> {
    rgba8
        .chunks_exact(4)
        .map(|p| (0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64) / 255.0)
        .collect()
}

/// One channel of RGBA8 as [0, 1] values.
pub fn channel(rgba8: &[u8], c: usize) -> Vec<f64> {
    rgba8.chunks_exact(4).map(|p| p[c] as f64 / 255.0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_score_one_and_reflect_matches_scipy() {
        let img: Vec<f64> = (0..16 * 12).map(|i| ((i * 37) % 101) as f64 / 100.0).collect();
        let r = ssim(&img, &img, 16, 12).unwrap();
        assert!((r.mean - 1.0).abs() < 1e-12);
        assert_eq!([reflect(-1, 4), reflect(-2, 4), reflect(4, 4), reflect(5, 4)], [0, 1, 3, 2]);
        let k = kernel();
        assert!((k.iter().sum::<f64>() - 1.0).abs() < 1e-15 && k[5] > k[4]);
        assert!(ssim(&img[..100], &img[..100], 10, 10).is_err(), "10×10 is below the window");
    }
}
