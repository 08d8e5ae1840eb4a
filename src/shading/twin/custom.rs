//! Twins of the custom roughness/metallic PBR shader of models.md#torrance-sparrow (`torrance_sparrow`) and of its
//! Fresnel term shown as colour (`fresnel`). Quirks kept, as in the WGSL.

use glam::DVec3;
use std::f64::consts::PI;

use super::{safe_normalize, sat, Lobes, Surface, SurfaceTwin};
use crate::pipelines::Pipeline;

pub fn d_ggx(nh: f64, a: f64) -> f64 {
    let a2 = a * a;
    let d = nh * nh * (a2 - 1.0) + 1.0;
    a2 / (PI * d * d)
}

pub fn v_smith_schlick(nl: f64, nv: f64, k: f64) -> f64 {
    0.25 / ((nl * (1.0 - k) + k) * (nv * (1.0 - k) + k))
}

/// F0 = ((1 − IOR)/(1 + IOR))², lerped to albedo by metallic (models.md#torrance-sparrow).
pub fn ts_f0(s: &Surface) -> DVec3 {
    let f = (1.0 - s.params[0]) / (1.0 + s.params[0]);
    DVec3::splat(f * f).lerp(s.base_color, s.metallic)
}

/// The final stage's direct term: albedo·NL·(1 − metallic) + albedo·tint·max(0, D·Vis·π·NL), D GGX
/// with a = r², Vis Smith-Schlick with k = r²/2 (no F on the direct specular: a quirk kept).
pub fn ts_direct(s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
    let r = 1.0 - s.smoothness;
    let (nl, nv) = (sat(n.dot(l)), sat(n.dot(v)));
    let h = safe_normalize(l + v, f32::MIN_POSITIVE as f64);
    let nh = sat(n.dot(h));
    let specular = (d_ggx(nh, r * r) * v_smith_schlick(nl, nv, r * r * 0.5) * PI * nl).max(0.0);
    Lobes::split(s.base_color * nl * (1.0 - s.metallic), s.base_color * s.specular * specular)
}

/// The custom shader's final stage; `as_written` keeps the source's quirks (scalar Fresnel from F0's
/// red channel, reflect(v, n), ambient × the main light's colour), otherwise the corrected variant.
pub struct TorranceSparrow {
    pub as_written: bool,
}

/// QUIRK of the source: its Fresnel returns a float, F0 truncated to red.
pub fn ts_fresnel_scalar(f0: DVec3, r: f64, nv: f64, p: f64) -> f64 {
    f0.x + ((1.0 - r).max(f0.x) - f0.x) * (1.0 - nv).powf(p)
}

impl SurfaceTwin for TorranceSparrow {
    fn direct_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        ts_direct(s, n, v, l)
    }

    fn indirect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> Lobes {
        let r = 1.0 - s.smoothness;
        let nv = sat(n.dot(v));
        let f0 = ts_f0(s);
        let f = if self.as_written {
            // The main light's colour scales ambient in the source; the twin's light has colour 1.
            DVec3::splat(ts_fresnel_scalar(f0, r, nv, s.params[1]))
        } else {
            f0 + (DVec3::splat(1.0 - r).max(f0) - f0) * (1.0 - nv).powf(s.params[1])
        };
        let surface_reduction = 1.0 / (r * r + 1.0);
        Lobes::split(s.base_color * gi_d * (1.0 - s.metallic), s.base_color * s.specular * surface_reduction * gi_s * f)
    }

    fn env_direction(&self, _: Pipeline, _: &Surface, n: DVec3, v: DVec3) -> Option<DVec3> {
        // reflect(i, n) = i − 2(n·i)n: as written i = v (towards the eye), corrected i = −v.
        let i = if self.as_written { v } else { -v };
        Some(i - 2.0 * n.dot(i) * n)
    }
}

pub struct FresnelView;

impl SurfaceTwin for FresnelView {
    fn direct_lobes(&self, _: Pipeline, _: &Surface, _: DVec3, _: DVec3, _: DVec3) -> Lobes {
        Lobes::ZERO
    }

    /// The reflectance itself, drawn as the reflection term (WGSL `indirect_specular`).
    fn indirect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, _: DVec3, _: DVec3) -> Lobes {
        let f0 = ts_f0(s);
        Lobes::split(DVec3::ZERO, f0 + (DVec3::ONE - f0) * (1.0 - sat(n.dot(v))).powf(s.params[1]))
    }
}
