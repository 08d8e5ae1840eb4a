//! The environment's exact ambient term E(n)/π = (1/π)∫ L(l)·max(0, n·l) dl as an equirect map:
//! what the pipelines' order-2 SH approximates (Ramamoorthi & Hanrahan 2001 bound its error at
//! about 1 % for smooth skies; a sun or a horizon rings). The approximation study's `ambient`
//! alternative reads it (shaders/pass/exact.wgsl `exact_ambient`), and it is the f64 twin of that
//! lookup. Brute-force convolution of a box-downsampled copy of the sky: E(n) is smooth (the
//! cosine lobe spans a hemisphere), so 128×64 source texels of 2.8° and a 64×33 grid read
//! bilinearly hold it within 0.5 % (`map_matches_direct_integration`). The grid's rows include both
//! poles (v = y/(h − 1)), so that interpolation near them does not clamp to a row 2.8° away.

use glam::DVec3;
use rayon::prelude::*;

use super::prefilter::EquirectImage;

/// The map's width (height is half).
pub const IRRADIANCE_WIDTH: usize = 64;
/// The width of the downsampled sky it integrates.
const SOURCE_WIDTH: usize = 128;

/// E(n)/π on a grid: column x at u = x/width (wrapping), row y at v = y/(height − 1).
#[derive(Debug, Clone)]
pub struct IrradianceMap {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<DVec3>,
}

impl IrradianceMap {
    /// Bilinear lookup by direction; shaders/pass/exact.wgsl `exact_ambient` reads the same way.
    pub fn lookup(&self, n: DVec3) -> DVec3 {
        let [u, v] = super::dir_to_uv(n);
        let fx = u * self.width as f64;
        let fy = v * (self.height - 1) as f64;
        let (x0, y0) = (fx.floor(), fy.floor().min((self.height - 2) as f64));
        let (tx, ty) = (fx - x0, fy - y0);
        let at = |x: f64, y: usize| self.texels[y * self.width + (x as i64).rem_euclid(self.width as i64) as usize];
        let y0 = y0 as usize;
        let a = at(x0, y0).lerp(at(x0 + 1.0, y0), tx);
        let b = at(x0, y0 + 1).lerp(at(x0 + 1.0, y0 + 1), tx);
        a.lerp(b, ty)
    }
}

/// E(n)/π of `sky` on a `IRRADIANCE_WIDTH`-wide grid (unscaled radiance units).
pub fn irradiance_map(sky: &EquirectImage) -> IrradianceMap {
    let mut source = sky.clone();
    while source.width > SOURCE_WIDTH && source.width.is_multiple_of(2) && source.height.is_multiple_of(2) {
        source = source.half();
    }
    let texels: Vec<(DVec3, DVec3)> = (0..source.height)
        .flat_map(|y| (0..source.width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (d, d_omega) = source.texel_direction(x, y);
            (d, source.get(x, y) * d_omega)
        })
        .collect();
    let (w, h) = (IRRADIANCE_WIDTH, IRRADIANCE_WIDTH / 2 + 1);
    let out = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let n = super::uv_to_dir((i % w) as f64 / w as f64, (i / w) as f64 / (h - 1) as f64);
            texels.iter().fold(DVec3::ZERO, |acc, (d, l)| acc + *l * n.dot(*d).max(0.0)) * std::f64::consts::FRAC_1_PI
        })
        .collect();
    IrradianceMap { width: w, height: h, texels: out }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A sky with a bright warm sun-like lobe and a dim ground: far from what nine SH
    /// coefficients hold.
    fn sky(d: DVec3) -> DVec3 {
        let sun = DVec3::new(0.3, 0.8, -0.52).normalize();
        let lobe = d.dot(sun).max(0.0).powi(32) * 40.0;
        DVec3::new(1.0, 0.9, 0.7) * lobe + if d.y > 0.0 { DVec3::new(0.2, 0.3, 0.6) } else { DVec3::splat(0.05) }
    }

    /// E(n)/π by a fine midpoint quadrature of the analytic sky over the hemisphere around n.
    fn direct(n: DVec3) -> DVec3 {
        let (t, b) = n.any_orthonormal_pair();
        let (nt, np) = (400, 800);
        let mut acc = DVec3::ZERO;
        for i in 0..nt {
            let theta = (i as f64 + 0.5) / nt as f64 * PI / 2.0;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
                let d = t * (theta.sin() * phi.cos()) + b * (theta.sin() * phi.sin()) + n * theta.cos();
                acc += sky(d) * (theta.cos() * theta.sin());
            }
        }
        acc * (PI / 2.0 / nt as f64) * (2.0 * PI / np as f64) / PI
    }

    #[test]
    fn map_matches_direct_integration() {
        let image = EquirectImage::sample(&sky, 1024, 512, 2);
        let map = irradiance_map(&image);
        let sh = super::super::sh::project_image(&image);
        let mut worst_sh: f64 = 0.0;
        for n in [DVec3::Y, DVec3::new(0.3, 0.8, -0.52), DVec3::new(1.0, 0.1, 0.2), DVec3::new(-0.4, -0.9, 0.1)] {
            let n = n.normalize();
            let exact = direct(n);
            let got = map.lookup(n);
            let rel = (got - exact).abs().max_element() / exact.max_element();
            assert!(rel < 5e-3, "map {got} against {exact} at {n}: {rel}");
            let sh_rel = (super::super::sh::eval(&sh, n) - exact).abs().max_element() / exact.max_element();
            worst_sh = worst_sh.max(sh_rel);
        }
        // The map is the exact term; order-2 SH of this sky is not (which is what the study measures).
        assert!(worst_sh > 0.01, "SH error {worst_sh}");
    }

    #[test]
    fn uniform_sky_is_its_own_irradiance() {
        let image = EquirectImage::sample(&|_| DVec3::new(0.5, 1.0, 2.0), 256, 128, 1);
        let map = irradiance_map(&image);
        for t in &map.texels {
            assert!((*t - DVec3::new(0.5, 1.0, 2.0)).abs().max_element() < 2e-3 * 2.0, "{t}");
        }
    }
}
