//! HDRP's diffusion profile: Burley's normalised diffusion as HDRP evaluates and importance-samples
//! it (DiffusionProfile.hlsl EvalBurleyDiffusionProfile, SampleBurleyDiffusionProfile) and the
//! default profile's kernel (DiffusionProfileSettings.cs ResetToDefault, UpdateKernel). Distances
//! in millimetres; the shape parameter S = 1 / scattering distance per millimetre. Shared by the
//! translucent transmission's constants (`twin::hdrp`), the plan's filter settings and the screen-
//! space filter's twin (`images::subsurface`).

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

/// A diffusion profile's kernel as HDRP's DiffusionProfileSettings.UpdateKernel derives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiffusionProfile {
    /// S per colour channel, 1/mm: 1 / (scattering distance × multiplier), at most 2²⁴.
    pub shape: [f64; 3],
    /// The widest channel's scattering distance, mm: the channel the filter samples.
    pub max_scattering_distance: f64,
    /// The filter's radius, mm: where the widest channel's CDF reaches 0.997 ("three sigma").
    pub filter_radius: f64,
    /// Metres per world unit (the profile's World Scale).
    pub world_scale: f64,
}

impl DiffusionProfile {
    /// The profile of a scattering distance per channel (mm) and world scale.
    pub fn of(scattering_distance: [f64; 3], world_scale: f64) -> DiffusionProfile {
        let shape = scattering_distance.map(|d| (1.0 / d).min(16_777_216.0));
        let max_scattering_distance = scattering_distance.iter().copied().fold(0.0, f64::max);
        let filter_radius = sample_burley_diffusion_profile(0.997, max_scattering_distance).0;
        DiffusionProfile { shape, max_scattering_distance, filter_radius, world_scale }
    }

    /// HDRP's default profile (ResetToDefault): scattering distance Color.grey (0.5) × 1, world
    /// scale 1, PreAndPostScatter texturing, thickness remap 0–5 mm, IOR 1.4, Thin Object.
    pub fn hdrp_default() -> DiffusionProfile {
        DiffusionProfile::of([0.5; 3], 1.0)
    }
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
            }
        }
    }

    #[test]
    fn the_default_profiles_filter_holds_its_three_sigma() {
        let p = DiffusionProfile::hdrp_default();
        assert_eq!(p.shape, [2.0; 3]);
        assert!((cdf(p.filter_radius, 2.0) - 0.997).abs() < 1e-12);
        // The slow e^(−S·r/3) tail holds the last 0.3 %: r ≈ 3·d·ln(0.75/0.003), 8.28 mm for 0.5 mm.
        assert!((p.filter_radius - 1.5 * 250f64.ln()).abs() < 1e-4, "{}", p.filter_radius);
    }
}
