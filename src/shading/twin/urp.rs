//! Twins of URP Lit and URP Simple Lit (models.md#urp), and of Unlit.

use glam::DVec3;

use super::classic::shininess_from_smoothness;
use super::{safe_normalize, sat, Surface, SurfaceTwin};
use crate::color::HALF_MIN;
use crate::pipelines::Pipeline;

const HALF_MIN_SQRT: f64 = 0.0078125;

pub struct UrpBrdfData {
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub roughness: f64,
    pub roughness2: f64,
    pub grazing_term: f64,
}

pub fn urp_brdf_data(s: &Surface) -> UrpBrdfData {
    let omr = 0.96 - s.metallic * 0.96;
    let pr = 1.0 - s.smoothness;
    let roughness = (pr * pr).max(HALF_MIN_SQRT);
    UrpBrdfData {
        diffuse: s.base_color * omr,
        specular: DVec3::splat(0.04).lerp(s.base_color, s.metallic),
        roughness,
        roughness2: (roughness * roughness).max(HALF_MIN),
        grazing_term: sat(s.smoothness + (1.0 - omr)),
    }
}

pub fn spec_urp(nh: f64, lh: f64, b: &UrpBrdfData) -> f64 {
    let d = nh * nh * (b.roughness2 - 1.0) + 1.00001;
    b.roughness2 / (d * d * (lh * lh).max(0.1) * (b.roughness * 4.0 + 2.0))
}

pub struct UrpLit;

impl SurfaceTwin for UrpLit {
    fn direct(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> DVec3 {
        let b = urp_brdf_data(s);
        let h = safe_normalize(l + v, f32::MIN_POSITIVE as f64);
        (b.diffuse + b.specular * spec_urp(sat(n.dot(h)), sat(l.dot(h)), &b)) * sat(n.dot(l))
    }

    fn indirect(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> DVec3 {
        let b = urp_brdf_data(s);
        let fresnel = (1.0 - sat(n.dot(v))).powi(4);
        gi_d * b.diffuse + gi_s * (1.0 / (b.roughness2 + 1.0)) * b.specular.lerp(DVec3::splat(b.grazing_term), fresnel)
    }
}

pub struct UrpSimpleLit;

impl SurfaceTwin for UrpSimpleLit {
    fn direct(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> DVec3 {
        let h = safe_normalize(l + v, f32::MIN_POSITIVE as f64);
        let nh = sat(n.dot(h));
        let highlights = if s.params[0] > 0.5 { 1.0 } else { 0.0 };
        s.base_color * sat(n.dot(l)) + s.specular * highlights * nh.powf(shininess_from_smoothness(s.smoothness))
    }

    fn indirect(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, gi_d: DVec3, _: DVec3) -> DVec3 {
        gi_d * s.base_color
    }
}

pub struct Unlit;

impl SurfaceTwin for Unlit {
    fn direct(&self, _: Pipeline, _: &Surface, _: DVec3, _: DVec3, _: DVec3) -> DVec3 {
        DVec3::ZERO
    }

    fn indirect(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, _: DVec3, _: DVec3) -> DVec3 {
        s.base_color
    }
}
