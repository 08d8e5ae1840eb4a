//! The environment as the CPU truth samples it: the GPU's tables, laid out and prefetched so that
//! a sample waits on memory as little as it can (render::truth::cpu).

use glam::DVec3;
use std::f64::consts::PI;

use super::Rng;
use crate::environment::prefilter::EquirectImage;

/// The environment as the CPU tracer samples it: the same texels and tables as the GPU's
/// (`super::environment_tables`), unscaled, laid out so that a sample costs one or two cache
/// lines, not the ten of a binary search over the tables plus the texel's: a guide table per
/// distribution starts the search for a bin at it (Chen and Asau 1974, as many guide entries as
/// bins), and each texel's record holds its radiance beside its bin's start and end in the row's cdf.
/// The bin found is the one the GPU's binary search finds.
pub struct CpuEnvironment {
    width: usize,
    height: usize,
    /// The marginal cdf over rows (height + 1 entries).
    rows: Vec<f32>,
    /// Per texel, row by row.
    texels: Vec<EnvironmentTexel>,
    /// The marginal's guide (`height` entries), then each row's (`width` entries): entry j of n
    /// is the bin that holds u = j/n.
    guide: Vec<u16>,
}

/// One texel: its radiance (unscaled) and the row's conditional cdf at its start and end — the
/// start a copy of the texel before's end, so that a density reads one record, not two.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(32))]
struct EnvironmentTexel {
    radiance: DVec3,
    cdf_start: f32,
    cdf_end: f32,
}

impl EnvironmentTexel {
    pub(super) fn radiance(&self) -> DVec3 {
        self.radiance
    }
}

/// A direction drawn from the environment: its density (solid angle) and radiance (unscaled).
pub(super) struct EnvironmentSample {
    pub direction: DVec3,
    pub pdf: f64,
    pub radiance: DVec3,
}

impl CpuEnvironment {
    pub fn new(image: &EquirectImage) -> CpuEnvironment {
        let (_, cdf) = crate::render::truth::environment_tables(image);
        let (w, h) = (image.width, image.height);
        assert!(w <= 1 << 16 && h <= 1 << 16, "an environment of {w}×{h} outgrows the guide's u16 bins");
        let conditional = |y: usize, x: usize| cdf[(h + 1) + y * (w + 1) + x];
        let texels = (0..w * h)
            .map(|i| EnvironmentTexel {
                radiance: image.texels[i],
                cdf_start: conditional(i / w, i % w),
                cdf_end: conditional(i / w, i % w + 1),
            })
            .collect();
        let search = |at: &dyn Fn(usize) -> f32, n: usize, u: f64| {
            // The bin k with cdf[k] ≤ u < cdf[k + 1]: rays.wgsl `find_bin`, a binary search.
            let (mut lo, mut hi) = (0, n);
            while lo + 1 < hi {
                let mid = (lo + hi) / 2;
                if at(mid) as f64 <= u {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo as u16
        };
        let mut guide: Vec<u16> = (0..h).map(|j| search(&|k| cdf[k], h, j as f64 / h as f64)).collect();
        for y in 0..h {
            guide.extend((0..w).map(|j| search(&|k| conditional(y, k), w, j as f64 / w as f64)));
        }
        CpuEnvironment { width: w, height: h, rows: cdf[..=h].to_vec(), texels, guide }
    }

    /// Its width and height, and texel i's radiance (unscaled).
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    pub fn texel(&self, i: usize) -> DVec3 {
        self.texels[i].radiance()
    }

    fn texel_index(&self, d: DVec3) -> usize {
        // scene.wgsl `equirect_uv`.
        let [u, v] = crate::environment::dir_to_uv(d);
        let x = ((u * self.width as f64) as usize).min(self.width - 1);
        let y = ((v * self.height as f64) as usize).min(self.height - 1);
        y * self.width + x
    }

    /// Solid-angle density of drawing d from texel i (rays.wgsl `env_pdf`).
    fn pdf_at(&self, i: usize, d: DVec3) -> f64 {
        let (w, h) = (self.width, self.height);
        let y = i / w;
        let row = (self.rows[y + 1] - self.rows[y]) as f64;
        let texel = &self.texels[i];
        let col = (texel.cdf_end - texel.cdf_start) as f64;
        let sin_theta = (1.0 - d.y * d.y).max(1e-12).sqrt();
        row * col * (w * h) as f64 / (2.0 * PI * PI * sin_theta)
    }

    /// The radiance along d and the density with which `sample` draws d.
    pub(super) fn lookup(&self, d: DVec3) -> (DVec3, f64) {
        let i = self.texel_index(d);
        (self.texels[i].radiance(), self.pdf_at(i, d))
    }

    /// The radiance along d.
    pub(super) fn radiance(&self, d: DVec3) -> DVec3 {
        self.texels[self.texel_index(d)].radiance()
    }

    /// The row that u falls in: from the guide's bin, forward to the one k with
    /// rows[k] ≤ u < rows[k + 1] (unique where the cdf does not fall, so the binary search's).
    fn find_row(&self, u: f64) -> usize {
        let h = self.height;
        let mut k = self.guide[((u * h as f64) as usize).min(h - 1)] as usize;
        while k + 1 < h && self.rows[k + 1] as f64 <= u {
            k += 1;
        }
        k
    }

    /// The texel of row y that u falls in, as `find_row`.
    #[cfg(test)]
    fn find_column(&self, y: usize, u: f64) -> usize {
        let w = self.width;
        self.walk_column(y, self.guide[self.height + y * w + ((u * w as f64) as usize).min(w - 1)] as usize, u)
    }

    /// From texel k of row y forward to the one that u falls in.
    fn walk_column(&self, y: usize, mut k: usize, u: f64) -> usize {
        let w = self.width;
        let row = &self.texels[y * w..(y + 1) * w];
        while k + 1 < w && row[k].cdf_end as f64 <= u {
            k += 1;
        }
        k
    }

    /// A direction drawn in proportion to the texels' luminance × sin θ, its density and radiance.
    pub(super) fn sample(&self, rng: &mut Rng) -> EnvironmentSample {
        let pending = self.begin_sample(rng);
        self.prefetch_texel(&pending);
        self.finish_sample(&pending)
    }

    /// The random numbers of a sample, its row, and a prefetch of the guide entry that starts its
    /// search in the row: the tracer draws them before the work that the two cache misses of a
    /// sample can then overlap (`prefetch_texel` once the guide entry is in, `finish_sample` last).
    pub(super) fn begin_sample(&self, rng: &mut Rng) -> PendingEnvironmentSample {
        let y = self.find_row(rng.next());
        let u = [rng.next(), rng.next(), rng.next()];
        let guide = self.height + y * self.width + ((u[0] * self.width as f64) as usize).min(self.width - 1);
        prefetch(&self.guide[guide]);
        PendingEnvironmentSample { y, guide, u }
    }

    /// Prefetches the texel record the guide names for a pending sample.
    pub(super) fn prefetch_texel(&self, p: &PendingEnvironmentSample) {
        prefetch(&self.texels[p.y * self.width + self.guide[p.guide] as usize]);
    }

    pub(super) fn finish_sample(&self, p: &PendingEnvironmentSample) -> EnvironmentSample {
        let (w, h, y) = (self.width, self.height, p.y);
        let x = self.walk_column(y, self.guide[p.guide] as usize, p.u[0]);
        let d = crate::environment::uv_to_dir((x as f64 + p.u[1]) / w as f64, (y as f64 + p.u[2]) / h as f64);
        // The texel drawn, not the one d's rounding names: the density of what was drawn.
        let i = y * w + x;
        EnvironmentSample { direction: d, pdf: self.pdf_at(i, d), radiance: self.texels[i].radiance() }
    }

    /// Prefetches the texel record a ray leaving along d will read (its radiance and density)
    /// while the ray is traced: the index from approximations of `dir_to_uv`'s atan2 and acos
    /// (within 1e-4 rad: the same texel or its neighbour, whose record shares a line or is next).
    pub(super) fn prefetch_direction(&self, d: DVec3) {
        let u = fast_atan2(d.x, -d.z) / std::f64::consts::TAU + 0.5;
        let v = fast_acos(d.y.clamp(-1.0, 1.0)) / PI;
        let x = ((u * self.width as f64) as usize).min(self.width - 1);
        let y = ((v * self.height as f64) as usize).min(self.height - 1);
        prefetch(&self.texels[y * self.width + x]);
    }
}

/// An environment sample between `begin_sample` and `finish_sample`: its row, its guide entry,
/// and its three remaining random numbers (the column's, then the jitter's u and v).
pub(super) struct PendingEnvironmentSample {
    y: usize,
    guide: usize,
    u: [f64; 3],
}

/// A hint that `value` is read soon (x86-64's prefetcht0); nothing on other targets.
#[inline(always)]
fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    #[allow(unused_unsafe)]
    // SAFETY: a prefetch of a valid reference's address reads nothing and cannot fault.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>((value as *const T).cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// atan2 within 1e-5 rad (the odd minimax polynomial of NVIDIA's Cg reference `atan2`): only for
/// prefetch addresses, never for a value the estimator reads.
fn fast_atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let a = ax.min(ay) / ax.max(ay).max(1e-300);
    let s = a * a;
    let p = ((((-0.013_480_470 * s + 0.057_477_314) * s - 0.121_239_071) * s + 0.195_635_925) * s - 0.332_994_597) * s
        + 0.999_995_630;
    let mut r = p * a;
    if ay > ax {
        r = std::f64::consts::FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = PI - r;
    }
    if y < 0.0 {
        -r
    } else {
        r
    }
}

/// acos within 7e-5 rad (Abramowitz and Stegun 4.4.45, as Cg's reference `acos`): only for
/// prefetch addresses.
fn fast_acos(x: f64) -> f64 {
    let a = x.abs();
    let r = (1.0 - a).sqrt() * (((-0.018_729_3 * a + 0.074_261_0) * a - 0.212_114_4) * a + 1.570_728_8);
    if x < 0.0 {
        PI - r
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_guided_search_finds_the_binary_searchs_bin() {
        // A sky with black rows and texels (zero-weight bins the cdf stays flat over), a bright
        // spot, and a smooth rest: the guide's walk must end on the GPU's bin for every u.
        let (w, h) = (64, 32);
        let texels = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                match (x, y) {
                    (_, 0..=5) | (20..=39, _) => DVec3::ZERO,
                    (50, 12) => DVec3::splat(5000.0),
                    _ => DVec3::splat(1.0 + (x * y) as f64 * 0.01),
                }
            })
            .collect();
        let image = EquirectImage { width: w, height: h, texels };
        let env = CpuEnvironment::new(&image);
        let (_, cdf) = crate::render::truth::environment_tables(&image);
        let binary = |start: usize, n: usize, u: f64| {
            let (mut lo, mut hi) = (0, n);
            while lo + 1 < hi {
                let mid = (lo + hi) / 2;
                if cdf[start + mid] as f64 <= u {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        let mut rng = Rng::new(3, 9);
        let mut us: Vec<f64> = (0..20_000).map(|_| rng.next()).collect();
        us.extend(cdf.iter().map(|&c| c as f64).filter(|&c| c < 1.0));
        for &u in &us {
            let y = env.find_row(u);
            assert_eq!(y, binary(0, h, u), "row for u = {u}");
            for row in [y, 0, 12, h - 1] {
                assert_eq!(env.find_column(row, u), binary((h + 1) + row * (w + 1), w, u), "row {row}, u = {u}");
            }
        }
    }

    #[test]
    fn the_prefetch_approximations_stay_within_their_stated_error() {
        // fast_atan2 within 1e-5 rad and fast_acos within 7e-5 rad: a prefetch then names the
        // texel `dir_to_uv` finds or its neighbour.
        let (mut worst_atan, mut worst_acos) = (0f64, 0f64);
        for i in 0..20_000 {
            let a = i as f64 / 20_000.0 * std::f64::consts::TAU;
            let (y, x) = (a.sin() * (1.0 + i as f64 * 1e-3), a.cos() * (1.0 + i as f64 * 1e-3));
            worst_atan = worst_atan.max((fast_atan2(y, x) - y.atan2(x)).abs());
            let c = i as f64 / 10_000.0 - 1.0;
            worst_acos = worst_acos.max((fast_acos(c) - c.acos()).abs());
        }
        assert!(worst_atan < 1e-5, "atan2 off by {worst_atan}");
        assert!(worst_acos < 7e-5, "acos off by {worst_acos}");
    }
}
