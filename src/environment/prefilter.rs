//! The reflection probe: an equirectangular image of the sky prefiltered for GGX at Unity's
//! seven mip levels (mip = pr'·6 with pr' = pr(1.7 − 0.7pr), models.md#builtin), as layers of one array.
//! Brute-force convolution on the CPU (split-sum assumption N = V = R): small images, done once
//! per composition, exact for the lobe and free of sampling noise.

use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

use super::{dir_to_uv, uv_to_dir};

pub const SOURCE_WIDTH: usize = 256;
/// Width of the prefiltered levels (height is half).
pub const PROBE_WIDTH: usize = 128;
pub const LEVELS: usize = 7;

#[derive(Debug, Clone)]
pub struct EquirectImage {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<DVec3>,
}

impl EquirectImage {
    /// Sample `radiance` with `ss`×`ss` sub-samples per texel (captures the small sun disc).
    pub fn sample(radiance: &(dyn Fn(DVec3) -> DVec3 + Sync), width: usize, height: usize, ss: usize) -> Self {
        let texels = (0..width * height)
            .into_par_iter()
            .map(|i| {
                let (x, y) = (i % width, i / width);
                let mut acc = DVec3::ZERO;
                let mut wsum = 0.0;
                for sy in 0..ss {
                    for sx in 0..ss {
                        let u = (x as f64 + (sx as f64 + 0.5) / ss as f64) / width as f64;
                        let v = (y as f64 + (sy as f64 + 0.5) / ss as f64) / height as f64;
                        let w = (v * PI).sin();
                        acc += radiance(uv_to_dir(u, v)) * w;
                        wsum += w;
                    }
                }
                acc / wsum.max(1e-12)
            })
            .collect();
        Self { width, height, texels }
    }

    pub fn get(&self, x: usize, y: usize) -> DVec3 {
        self.texels[y * self.width + x]
    }

    /// Centre direction of a texel and its solid angle.
    pub fn texel_direction(&self, x: usize, y: usize) -> (DVec3, f64) {
        let (u, v) = ((x as f64 + 0.5) / self.width as f64, (y as f64 + 0.5) / self.height as f64);
        let d_omega = (TAU / self.width as f64) * (PI / self.height as f64) * (v * PI).sin();
        (uv_to_dir(u, v), d_omega)
    }

    /// 2×2 box downsample (solid-angle weighted).
    pub(crate) fn half(&self) -> Self {
        let (w, h) = (self.width / 2, self.height / 2);
        let mut texels = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let mut acc = DVec3::ZERO;
                let mut ws = 0.0;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (_, wt) = self.texel_direction(2 * x + dx, 2 * y + dy);
                    acc += self.get(2 * x + dx, 2 * y + dy) * wt;
                    ws += wt;
                }
                texels.push(acc / ws);
            }
        }
        Self { width: w, height: h, texels }
    }

    /// Bilinear lookup by direction (wrapping in u).
    pub fn lookup(&self, d: DVec3) -> DVec3 {
        let [u, v] = dir_to_uv(d);
        let fx = u * self.width as f64 - 0.5;
        let fy = (v * self.height as f64 - 0.5).clamp(0.0, self.height as f64 - 1.0);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let xi = |x: f64| (x as i64).rem_euclid(self.width as i64) as usize;
        let y1 = (y0 as usize + 1).min(self.height - 1);
        let a = self.get(xi(x0), y0 as usize).lerp(self.get(xi(x0 + 1.0), y0 as usize), tx);
        let b = self.get(xi(x0), y1).lerp(self.get(xi(x0 + 1.0), y1), tx);
        a.lerp(b, ty)
    }
}

/// Prefiltered levels, each `width`×`height`, level k for pr' = k/6.
#[derive(Debug, Clone)]
pub struct Probe {
    pub width: usize,
    pub height: usize,
    pub levels: Vec<EquirectImage>,
}

/// GGX α for a probe level: invert pr' = pr(1.7 − 0.7pr) for pr, then α = pr².
pub fn level_alpha(level: usize) -> f64 {
    let target = level as f64 / (LEVELS - 1) as f64;
    // 0.7pr² − 1.7pr + pr' = 0, the root in [0, 1].
    let pr = (1.7 - (1.7f64 * 1.7 - 4.0 * 0.7 * target).sqrt()) / (2.0 * 0.7);
    pr * pr
}

impl Probe {
    pub fn constant(c: DVec3) -> Probe {
        let img = EquirectImage { width: 1, height: 1, texels: vec![c] };
        Probe { width: 1, height: 1, levels: vec![img] }
    }

    pub fn from_source(source: &EquirectImage) -> Probe {
        let mut level0 = source.clone();
        while level0.width > PROBE_WIDTH {
            level0 = level0.half();
        }
        // The source each level convolves, by width: the source itself and its halvings.
        let mut images = vec![source.clone()];
        while images.last().is_some_and(|i| i.width > PROBE_WIDTH / 2) {
            let next = images.last().map(EquirectImage::half).expect("non-empty");
            images.push(next);
        }
        let mut tables: Vec<(usize, TexelTable)> = Vec::new();
        Probe::from_mirror(level0, |_, alpha, output| {
            let want = source_width(alpha);
            if !tables.iter().any(|(tw, _)| *tw == want) {
                let img = images.iter().find(|i| i.width <= want).expect("the halvings reach PROBE_WIDTH / 2");
                tables.push((want, TexelTable::new(img)));
            }
            let src = &tables.iter().find(|(tw, _)| *tw == want).expect("built above").1;
            output.direction.par_iter().map(|d| src.convolve(*d, alpha)).collect()
        })
    }

    /// The seven levels from the mirror image `level0`: a lobe narrower than a texel (level 1's,
    /// α ≈ 0.01, < 1°) copies it, every other level is `convolve(level, α, level0's texels)`.
    pub(crate) fn from_mirror(
        level0: EquirectImage,
        mut convolve: impl FnMut(usize, f64, &TexelTable) -> Vec<DVec3>,
    ) -> Probe {
        let (w, h) = (level0.width, level0.height);
        let output = TexelTable::new(&level0);
        let mut levels = vec![level0];
        for level in 1..LEVELS {
            let alpha = level_alpha(level);
            let texels = if alpha < MIRROR_ALPHA { levels[0].texels.clone() } else { convolve(level, alpha, &output) };
            levels.push(EquirectImage { width: w, height: h, texels });
        }
        Probe { width: w, height: h, levels }
    }
}

/// Below this α the lobe is narrower than a probe texel: the level copies the mirror image.
pub const MIRROR_ALPHA: f64 = 0.02;

/// The width of the source a level of GGX α convolves (w²/2 texels summed per output texel):
/// narrow lobes need a fine source or a sun aliases into them. Chosen from the convergence study
/// (`shadematrix convergence`, audit::convergence): on mitsuba's sun-lit sky the relative error
/// against a 1024-wide reference stays near 5e-3 or below at these widths.
pub fn source_width(alpha: f64) -> usize {
    if alpha < 0.08 {
        SOURCE_WIDTH
    } else if alpha < 0.2 {
        PROBE_WIDTH
    } else {
        PROBE_WIDTH / 2
    }
}

/// Texel directions, solid angles and radiance laid out flat for the convolution's inner loop.
pub(crate) struct TexelTable {
    pub(crate) direction: Vec<DVec3>,
    solid_angle: Vec<f64>,
    radiance: Vec<DVec3>,
}

impl TexelTable {
    pub(crate) fn new(img: &EquirectImage) -> Self {
        let (mut direction, mut solid_angle) = (Vec::new(), Vec::new());
        for y in 0..img.height {
            for x in 0..img.width {
                let (d, w) = img.texel_direction(x, y);
                direction.push(d);
                solid_angle.push(w);
            }
        }
        Self { direction, solid_angle, radiance: img.texels.clone() }
    }

    /// ∫ L(ω)·D(h)·max(0, R·ω) dω / ∫ D(h)·max(0, R·ω) dω with N = V = R (split-sum prefilter).
    pub(crate) fn convolve(&self, r: DVec3, alpha: f64) -> DVec3 {
        let a2 = alpha * alpha;
        let mut acc = DVec3::ZERO;
        let mut wsum = 0.0;
        for ((d, d_omega), l) in self.direction.iter().zip(&self.solid_angle).zip(&self.radiance) {
            let nl = r.dot(*d);
            if nl <= 0.0 {
                continue;
            }
            // N·H² = (1 + N·L)/2 when N = V.
            let t = (1.0 + nl) * 0.5 * (a2 - 1.0) + 1.0;
            let w = a2 / (PI * t * t) * nl * d_omega;
            acc += *l * w;
            wsum += w;
        }
        acc / wsum.max(1e-300)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_alphas_follow_unity_mip_mapping() {
        assert_eq!(level_alpha(0), 0.0);
        assert!((level_alpha(6) - 1.0).abs() < 1e-12);
        let pr = level_alpha(3).sqrt();
        assert!((pr * (1.7 - 0.7 * pr) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn prefiltering_preserves_a_constant_and_blurs_a_step() {
        let step = |d: DVec3| if d.x > 0.0 { DVec3::ONE } else { DVec3::ZERO };
        let src = EquirectImage::sample(&step, 64, 32, 2);
        let probe = Probe::from_source(&src);
        let edge = DVec3::new(0.05, 0.0, -1.0).normalize();
        let sharp = probe.levels[0].lookup(edge).x;
        let blurred = probe.levels[6].lookup(edge).x;
        assert!(sharp > 0.8, "mirror level keeps the edge sharp: {sharp}");
        assert!((blurred - 0.5).abs() < 0.15, "rough level averages across the edge: {blurred}");
        let flat = Probe::from_source(&EquirectImage::sample(&|_| DVec3::splat(0.3), 32, 16, 1));
        for l in &flat.levels {
            assert!(l.texels.iter().all(|t| (t.x - 0.3).abs() < 1e-9));
        }
    }
}
