//! Order-2 real spherical harmonics: projection of the environment and the cosine convolution
//! (Ramamoorthi & Hanrahan 2001), so that the shader's ambient term is E(n)/π.

use glam::DVec3;
use std::f64::consts::{PI, TAU};

use super::prefilter::EquirectImage;

/// Real SH basis Y_0..Y_8 in the order the shader uses (scene.wgsl `ambient_diffuse`).
pub fn basis(n: DVec3) -> [f64; 9] {
    [
        0.282_095,
        0.488_603 * n.y,
        0.488_603 * n.z,
        0.488_603 * n.x,
        1.092_548 * n.x * n.y,
        1.092_548 * n.y * n.z,
        0.315_392 * (3.0 * n.z * n.z - 1.0),
        1.092_548 * n.x * n.z,
        0.546_274 * (n.x * n.x - n.y * n.y),
    ]
}

/// Cosine-lobe convolution divided by π, per band: Â_l/π = 1, 2/3, 1/4.
const BAND_SCALE: [f64; 9] = [1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25, 0.25, 0.25, 0.25, 0.25];

/// The cosine-lobe convolution over π of projected radiance: the coefficients of E(n)/π.
pub fn convolve(mut coeffs: [[f64; 3]; 9]) -> [[f64; 3]; 9] {
    for (c, s) in coeffs.iter_mut().zip(BAND_SCALE) {
        for v in c.iter_mut() {
            *v *= s;
        }
    }
    coeffs
}

/// The projection of a constant radiance: the L0 band alone, exactly (quadrature would leave the
/// other bands a residual: 0.3 % at a 16×32 grid, measured as a white furnace brighter than its sky).
pub fn constant(l: DVec3) -> [[f64; 3]; 9] {
    let mut c = [[0.0; 3]; 9];
    // ∫ L·Y_0 dω = L·4π·Y_0 = L/Y_0 with the exact Y_0 = 1/(2√π); dividing by the basis's own
    // rounded Y_0 makes eval return L to the last bit.
    let k = 1.0 / basis(DVec3::Y)[0];
    c[0] = [l.x * k, l.y * k, l.z * k];
    c
}

/// Project a radiance function by midpoint quadrature on an n×2n (θ, φ) grid, each sample weighted
/// by its cell's exact solid angle (so the weights sum to 4π).
pub fn project(radiance: &dyn Fn(DVec3) -> DVec3, n: usize) -> [[f64; 3]; 9] {
    let mut c = [[0.0; 3]; 9];
    for i in 0..n {
        let theta = (i as f64 + 0.5) / n as f64 * PI;
        let band = (i as f64 / n as f64 * PI).cos() - ((i + 1) as f64 / n as f64 * PI).cos();
        let d_omega = band * (TAU / (2 * n) as f64);
        for j in 0..2 * n {
            let phi = (j as f64 + 0.5) / (2 * n) as f64 * TAU;
            let d = DVec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            accumulate(&mut c, d, radiance(d), d_omega);
        }
    }
    convolve(c)
}

/// Project an equirectangular image (each texel weighted by its solid angle).
pub fn project_image(img: &EquirectImage) -> [[f64; 3]; 9] {
    let mut c = [[0.0; 3]; 9];
    for y in 0..img.height {
        for x in 0..img.width {
            let (d, d_omega) = img.texel_direction(x, y);
            accumulate(&mut c, d, img.get(x, y), d_omega);
        }
    }
    convolve(c)
}

fn accumulate(c: &mut [[f64; 3]; 9], d: DVec3, l: DVec3, w: f64) {
    for (ci, y) in c.iter_mut().zip(basis(d)) {
        ci[0] += l.x * y * w;
        ci[1] += l.y * y * w;
        ci[2] += l.z * y * w;
    }
}

pub fn eval(c: &[[f64; 3]; 9], n: DVec3) -> DVec3 {
    basis(n).iter().zip(c).fold(DVec3::ZERO, |acc, (y, ci)| acc + DVec3::from(*ci) * *y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_projects_exactly() {
        let c = constant(DVec3::new(0.2, 0.4, 0.8));
        for n in [DVec3::Y, DVec3::new(0.3, -0.5, 0.2).normalize(), -DVec3::X] {
            assert!((eval(&c, n) - DVec3::new(0.2, 0.4, 0.8)).abs().max_element() < 1e-12, "{n}");
        }
    }

    #[test]
    fn constant_sky_gives_its_colour() {
        let c = project(&|_| DVec3::new(0.2, 0.4, 0.8), 32);
        let e = eval(&c, DVec3::new(0.3, -0.5, 0.2).normalize());
        assert!((e - DVec3::new(0.2, 0.4, 0.8)).length() < 1e-3, "{e}");
    }

    #[test]
    fn upper_hemisphere_light_gives_cosine_irradiance() {
        // L = 1 above the horizon: E(up)/π = 1, E(down)/π = 0, E(horizontal)/π = 0.5.
        let c = project(&|d| if d.y > 0.0 { DVec3::ONE } else { DVec3::ZERO }, 64);
        assert!((eval(&c, DVec3::Y).x - 1.0).abs() < 0.07);
        assert!((eval(&c, DVec3::X).x - 0.5).abs() < 0.01);
        assert!(eval(&c, -DVec3::Y).x.abs() < 0.07);
    }
}
