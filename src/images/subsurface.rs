//! f64 twin of HDRP's screen-space subsurface scattering filter, its first part: Burley's
//! normalised diffusion profile as HDRP evaluates and importance-samples it (DiffusionProfile.hlsl
//! EvalBurleyDiffusionProfile, SampleBurleyDiffusionProfile; SubsurfaceScattering.compute
//! ComputeBilateralWeight). Same names as the shaders will use; distances in millimetres, the
//! shape parameter S = 1 / scattering distance per millimetre. The filter pass that reads them
//! is not built yet.

use std::f64::consts::PI;

/// r·R(r) of Burley's normalised diffusion, R(r) = S·(e^(−S·r) + e^(−S·r/3)) / (8π·r): what HDRP
/// returns, so that 2π·∫ r·R(r) dr = 1 over the plane.
pub fn eval_burley_diffusion_profile(r: f64, s: f64) -> f64 {
    let exp_13 = (-s * r / 3.0).exp();
    s / (8.0 * PI) * (exp_13 * (1.0 + exp_13 * exp_13))
}

/// The radius at which the profile's radial CDF, 1 − e^(−S·r)/4 − 3·e^(−S·r/3)/4, is `u`, and
/// the reciprocal of the sample's density as HDRP weighs it, 1 / eval_burley_diffusion_profile:
/// the closed-form inverse of the cubic in e^(−S·r/3) that HDRP's SampleBurleyDiffusionProfile
/// evaluates (u taken to the complementary CDF first).
pub fn sample_burley_diffusion_profile(u: f64, rcp_s: f64) -> (f64, f64) {
    let u = 1.0 - u;
    let g = 1.0 + (4.0 * u) * (2.0 * u + (1.0 + (4.0 * u) * u).sqrt());
    let n = g.powf(-1.0 / 3.0);
    let p = g * n * n;
    let c = 1.0 + p + n;
    let x = 3.0 * (c / (4.0 * u)).ln();
    // e^(−x/3) = 4u/c, so e^(−x/3) + e^(−x) = 4u/c · (1 + (4u/c)²).
    let rcp_exp = (c * c * c) / ((4.0 * u) * (c * c + (4.0 * u) * (4.0 * u)));
    (x * rcp_s, 8.0 * PI * rcp_s * rcp_exp)
}

/// A sample's weight in the filter: the profile at the distance between the two surface points
/// (screen offset² `xy2` in mm², depth difference `z` in world units × `mm_per_unit`), over the
/// sample's density, saturated.
pub fn compute_bilateral_weight(xy2: f64, z: f64, mm_per_unit: f64, s: f64, rcp_pdf: f64) -> f64 {
    let r = (xy2 + (z * mm_per_unit) * (z * mm_per_unit)).sqrt();
    (eval_burley_diffusion_profile(r, s) * rcp_pdf).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cdf(r: f64, s: f64) -> f64 {
        1.0 - (-s * r).exp() / 4.0 - 3.0 * (-s * r / 3.0).exp() / 4.0
    }

    #[test]
    fn the_profile_is_normalised_over_the_plane() {
        for s in [0.5, 2.0, 8.0] {
            // 2π ∫ r·R(r) dr by the midpoint rule out to 60 mean free paths.
            let (end, steps) = (60.0 / s, 200_000);
            let h = end / steps as f64;
            let total: f64 =
                (0..steps).map(|i| 2.0 * PI * eval_burley_diffusion_profile((i as f64 + 0.5) * h, s) * h).sum();
            assert!((total - 1.0).abs() < 1e-8, "S {s}: {total}");
        }
    }

    #[test]
    fn samples_invert_the_radial_cdf_and_carry_its_density() {
        for s in [0.5, 2.0, 8.0] {
            for k in 1..1000 {
                let u = k as f64 / 1000.0;
                let (r, rcp_pdf) = sample_burley_diffusion_profile(u, 1.0 / s);
                assert!((cdf(r, s) - u).abs() < 1e-12, "S {s}, u {u}: CDF(r) = {}", cdf(r, s));
                let density = eval_burley_diffusion_profile(r, s);
                assert!((rcp_pdf * density - 1.0).abs() < 1e-10, "S {s}, u {u}");
                // In the plane of the surface, a sample weighs 1 for its own profile.
                assert!((compute_bilateral_weight(r * r, 0.0, 1000.0, s, rcp_pdf) - 1.0).abs() < 1e-10);
            }
        }
    }

    #[test]
    fn depth_lowers_a_samples_weight() {
        let s = 2.0;
        let (r, rcp_pdf) = sample_burley_diffusion_profile(0.5, 1.0 / s);
        let flat = compute_bilateral_weight(r * r, 0.0, 1000.0, s, rcp_pdf);
        let deeper = compute_bilateral_weight(r * r, 0.002, 1000.0, s, rcp_pdf);
        assert!(deeper < flat, "{deeper} against {flat}");
    }
}
