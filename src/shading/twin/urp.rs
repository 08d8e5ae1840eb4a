//! Twins of URP Lit and URP Simple Lit (models.md#urp), and of Unlit.

use glam::DVec3;

use super::classic::shininess_from_smoothness;
use super::{safe_normalize, sat, Lobes, Surface, SurfaceTwin};
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
    // _SPECULAR_SETUP (params[0] = 1): reflectivity = max(specular), specular as given.
    let (omr, specular) = match s.params[0] > 0.5 {
        true => (1.0 - s.specular.max_element(), s.specular),
        false => (0.96 - s.metallic * 0.96, DVec3::splat(0.04).lerp(s.base_color, s.metallic)),
    };
    let pr = 1.0 - s.smoothness;
    let roughness = (pr * pr).max(HALF_MIN_SQRT);
    UrpBrdfData {
        diffuse: s.base_color * omr * s.diffuse_weight,
        specular,
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
    fn direct_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let b = urp_brdf_data(s);
        let nl = sat(n.dot(l));
        // _SPECULARHIGHLIGHTS_OFF (params[1] = 1): the diffuse alone.
        if s.params[1] > 0.5 {
            return Lobes::diffuse(b.diffuse * nl);
        }
        let h = safe_normalize(l + v, f32::MIN_POSITIVE as f64);
        Lobes::split(b.diffuse * nl, b.specular * spec_urp(sat(n.dot(h)), sat(l.dot(h)), &b) * nl)
    }

    /// `gi_s` is what the surface reflects: the probes' and sky's radiance, or with environment
    /// reflections off (params[2] = 1) the constant _GlossyEnvironmentColor.
    fn indirect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> Lobes {
        let b = urp_brdf_data(s);
        let fresnel = (1.0 - sat(n.dot(v))).powi(4);
        Lobes::split(
            gi_d * b.diffuse,
            gi_s * (1.0 / (b.roughness2 + 1.0)) * b.specular.lerp(DVec3::splat(b.grazing_term), fresnel),
        )
    }
}

pub struct UrpSimpleLit;

/// pow(sat(NH), shininess), shininess = exp2(10s + 1) ∈ [2, 2048].
pub fn spec_simple_lit(nh: f64, smoothness: f64) -> f64 {
    nh.powf(shininess_from_smoothness(smoothness))
}

impl SurfaceTwin for UrpSimpleLit {
    fn direct_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let h = safe_normalize(l + v, f32::MIN_POSITIVE as f64);
        let nh = sat(n.dot(h));
        let highlights = if s.params[0] > 0.5 { 1.0 } else { 0.0 };
        // × the diffuse weight: CalculateBlinnPhong's _ALPHAPREMULTIPLY_ON; the GI below keeps it whole.
        Lobes::split(
            s.base_color * s.diffuse_weight * sat(n.dot(l)),
            s.specular * highlights * spec_simple_lit(nh, s.smoothness),
        )
    }

    fn indirect_lobes(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, gi_d: DVec3, _: DVec3) -> Lobes {
        Lobes::diffuse(gi_d * s.base_color)
    }
}

pub struct Unlit;

impl SurfaceTwin for Unlit {
    fn direct_lobes(&self, _: Pipeline, _: &Surface, _: DVec3, _: DVec3, _: DVec3) -> Lobes {
        Lobes::ZERO
    }

    /// The colour is given off, not reflected (HDRP's Unlit writes it as its emissive).
    fn indirect_lobes(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, _: DVec3, _: DVec3) -> Lobes {
        Lobes { emitted: s.base_color * s.diffuse_weight, ..Lobes::ZERO }
    }
}

/// The custom scriptable pipeline tutorial's Lit (shading.md §4d): URP's minimal Cook-Torrance
/// without roughness floors, reflections with a Fresnel slider (`fresnel_strength`, slot 0).
pub struct SrpLit;

const MIN_REFLECTIVITY: f64 = 0.04;

pub struct SrpBrdf {
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub roughness: f64,
    pub fresnel: f64,
}

pub fn srp_brdf(s: &Surface) -> SrpBrdf {
    let omr = (1.0 - MIN_REFLECTIVITY) - s.metallic * (1.0 - MIN_REFLECTIVITY);
    let pr = 1.0 - s.smoothness;
    SrpBrdf {
        diffuse: s.base_color * omr,
        specular: DVec3::splat(MIN_REFLECTIVITY).lerp(s.base_color, s.metallic),
        roughness: pr * pr,
        fresnel: sat(s.smoothness + 1.0 - omr),
    }
}

pub fn specular_strength(nh: f64, lh: f64, b: &SrpBrdf) -> f64 {
    let r2 = b.roughness * b.roughness;
    let d = nh * nh * (r2 - 1.0) + 1.00001;
    r2 / (d * d * (lh * lh).max(0.1) * (b.roughness * 4.0 + 2.0))
}

impl SurfaceTwin for SrpLit {
    fn direct_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let b = srp_brdf(s);
        let h = safe_normalize(l + v, f32::MIN_POSITIVE as f64);
        let nl = sat(n.dot(l));
        Lobes::split(b.diffuse * nl, b.specular * specular_strength(sat(n.dot(h)), sat(l.dot(h)), &b) * nl)
    }

    fn indirect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> Lobes {
        let b = srp_brdf(s);
        let fresnel_strength = s.params[0] * (1.0 - sat(n.dot(v))).powi(4);
        let reflection =
            gi_s * b.specular.lerp(DVec3::splat(b.fresnel), fresnel_strength) / (b.roughness * b.roughness + 1.0);
        Lobes::split(gi_d * b.diffuse, reflection)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fresnel_slider_moves_grazing_reflections_to_brdf_fresnel() {
        // A dielectric (specular 0.04, fresnel = smoothness + 0.04) under a white environment.
        let mut s = Surface::basic(DVec3::splat(0.5), 0.0, 0.8);
        let n = DVec3::Y;
        let grazing = DVec3::new(0.999, 0.0447, 0.0).normalize();
        let reflection = |s: &Surface, v: DVec3| SrpLit.indirect(Pipeline::Urp, s, n, v, DVec3::ZERO, DVec3::ONE).x;
        s.params[0] = 0.0;
        let (off_normal, off_grazing) = (reflection(&s, n), reflection(&s, grazing));
        s.params[0] = 1.0;
        let (on_normal, on_grazing) = (reflection(&s, n), reflection(&s, grazing));
        // Straight on, (1 − NV)⁴ = 0: the slider changes nothing.
        assert!((off_normal - on_normal).abs() < 1e-12);
        // r = 0.04: 1/(r² + 1) = 1/1.0016; at grazing (1 − 0.0447)⁴ = 0.832 of the way to 0.84.
        let expect = |k: f64| (0.04 + (0.84 - 0.04) * k * (1.0 - 0.0447f64).powi(4)) / (0.04f64.powi(2) + 1.0);
        assert!((off_grazing - expect(0.0)).abs() < 1e-6, "{off_grazing}");
        assert!((on_grazing - expect(1.0)).abs() < 1e-3, "{on_grazing} vs {}", expect(1.0));
    }
}
