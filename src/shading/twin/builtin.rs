//! Twins of the built-in Standard shader's BRDF2 and BRDF3 (models.md#builtin).

use glam::DVec3;

use super::{safe_normalize, sat, Lobes, Surface, SurfaceTwin};
use crate::pipelines::Pipeline;

/// specColor = lerp(0.04, albedo, metallic) (models.md#standard-brdf2 material setup).
pub fn brdf2_spec_color(s: &Surface) -> DVec3 {
    DVec3::splat(0.04).lerp(s.base_color, s.metallic)
}

/// oneMinusReflectivity = 0.96(1 − metallic).
pub fn brdf2_one_minus_reflectivity(s: &Surface) -> f64 {
    0.96 - s.metallic * 0.96
}

pub fn spec_brdf2(nh: f64, lh: f64, a: f64) -> f64 {
    let a2 = a * a;
    let d = nh * nh * (a2 - 1.0) + 1.00001;
    a2 / ((lh * lh).max(0.1) * (a + 0.5) * d * d * 4.0)
}

pub struct StandardBrdf2;

impl SurfaceTwin for StandardBrdf2 {
    fn direct_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let h = safe_normalize(l + v, 0.001);
        let (nl, nh, lh) = (sat(n.dot(l)), sat(n.dot(h)), sat(l.dot(h)));
        let pr = 1.0 - s.smoothness;
        Lobes::split(
            s.base_color * brdf2_one_minus_reflectivity(s) * s.diffuse_weight * nl,
            spec_brdf2(nh, lh, pr * pr) * brdf2_spec_color(s) * nl,
        )
    }

    fn indirect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> Lobes {
        let nv = sat(n.dot(v));
        let pr = 1.0 - s.smoothness;
        let a = pr * pr;
        let omr = brdf2_one_minus_reflectivity(s);
        let surface_reduction = 1.0 - a * pr * (0.6 - 0.08 * pr);
        let grazing = sat(s.smoothness + (1.0 - omr));
        let fresnel = (1.0 - nv).powi(4);
        Lobes::split(
            gi_d * s.base_color * omr * s.diffuse_weight,
            surface_reduction * gi_s * brdf2_spec_color(s).lerp(DVec3::splat(grazing), fresnel),
        )
    }

    fn reflectivity(&self, s: &Surface) -> f64 {
        1.0 - brdf2_one_minus_reflectivity(s)
    }
}

/// The approximated lookup lobe: min(16, (n + 2)/2·rlPow4^(n/4)), n = 2/α² − 2 (see the WGSL).
pub fn spec_brdf3(rl_pow4: f64, pr: f64) -> f64 {
    let a = pr * pr;
    let n = (2.0 / (a * a).max(1e-4) - 2.0).max(1e-4);
    ((n + 2.0) * 0.5 * rl_pow4.max(0.0).powf(n * 0.25)).min(16.0)
}

pub struct StandardBrdf3;

impl SurfaceTwin for StandardBrdf3 {
    fn direct_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let nl = sat(n.dot(l));
        let r = v - 2.0 * n.dot(v) * n;
        let rl_pow4 = r.dot(l).powi(4);
        Lobes::split(
            s.base_color * brdf2_one_minus_reflectivity(s) * s.diffuse_weight * nl,
            spec_brdf3(rl_pow4, 1.0 - s.smoothness) * brdf2_spec_color(s) * nl,
        )
    }

    fn indirect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> Lobes {
        let nv = sat(n.dot(v));
        let omr = brdf2_one_minus_reflectivity(s);
        let grazing = sat(s.smoothness + (1.0 - omr));
        Lobes::split(
            gi_d * s.base_color * omr * s.diffuse_weight,
            gi_s * brdf2_spec_color(s).lerp(DVec3::splat(grazing), (1.0 - nv).powi(4)),
        )
    }

    fn reflectivity(&self, s: &Surface) -> f64 {
        1.0 - brdf2_one_minus_reflectivity(s)
    }
}
