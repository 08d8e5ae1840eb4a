//! Twins of the classic models (models.md#classic): half-Lambert, Phong, Blinn-Phong, Oren-Nayar (both
//! forms), Cook-Torrance.

use glam::DVec3;
use std::f64::consts::{FRAC_1_PI, PI};

use super::{f_schlick, irradiance_per_intensity as e_per_i, safe_normalize, sat, Lobes, Surface, SurfaceTwin};
use crate::pipelines::Pipeline;

pub fn shininess_from_smoothness(s: f64) -> f64 {
    (10.0 * s + 1.0).exp2()
}

fn ambient(s: &Surface, gi_diffuse: DVec3) -> DVec3 {
    s.base_color * gi_diffuse
}

/// h = 0.5·NL + 0.5, not squared (Unity's directional-lightmap decode).
pub fn half_lambert_wrap(nl: f64) -> f64 {
    0.5 * nl + 0.5
}

/// R = 2·NL·N − L.
pub fn phong_reflect(n: DVec3, l: DVec3) -> DVec3 {
    2.0 * n.dot(l) * n - l
}

/// max(0, R·V)ⁿ, with the optional (n + 2)/2 normalisation.
pub fn spec_phong(n: DVec3, v: DVec3, l: DVec3, shininess: f64, normalized: f64) -> f64 {
    let lobe = phong_reflect(n, l).dot(v).max(0.0).powf(shininess);
    if normalized > 0.5 {
        lobe * (shininess + 2.0) * 0.5
    } else {
        lobe
    }
}

/// max(0, N·H)ⁿ, with the optional ≈(n + 8)/8 normalisation.
pub fn spec_blinn_phong(n: DVec3, v: DVec3, l: DVec3, shininess: f64, normalized: f64) -> f64 {
    let h = safe_normalize(l + v, f32::MIN_POSITIVE as f64);
    let lobe = n.dot(h).max(0.0).powf(shininess);
    if normalized > 0.5 {
        lobe * (shininess + 8.0) * 0.125
    } else {
        lobe
    }
}

pub struct HalfLambert;

impl SurfaceTwin for HalfLambert {
    fn diffuse_only(&self) -> bool {
        true
    }

    fn direct_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, _v: DVec3, l: DVec3) -> Lobes {
        Lobes::diffuse(super::lambert::fd_lambert(s.base_color) * e_per_i(p) * half_lambert_wrap(n.dot(l)))
    }
    fn indirect_lobes(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, gi_d: DVec3, _: DVec3) -> Lobes {
        Lobes::diffuse(ambient(s, gi_d))
    }
}

pub struct Phong;

impl SurfaceTwin for Phong {
    fn direct_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let nl = n.dot(l).max(0.0);
        if nl <= 0.0 {
            return Lobes::ZERO;
        }
        let spec = spec_phong(n, v, l, shininess_from_smoothness(s.smoothness), s.params[0]);
        let k = FRAC_1_PI * e_per_i(p);
        Lobes::split(s.base_color * nl * k, s.specular * spec * k)
    }
    fn indirect_lobes(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, gi_d: DVec3, _: DVec3) -> Lobes {
        Lobes::diffuse(ambient(s, gi_d))
    }
}

pub struct BlinnPhong;

impl SurfaceTwin for BlinnPhong {
    fn direct_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let nl = n.dot(l).max(0.0);
        if nl <= 0.0 {
            return Lobes::ZERO;
        }
        let spec = spec_blinn_phong(n, v, l, shininess_from_smoothness(s.smoothness), s.params[0]);
        let k = FRAC_1_PI * e_per_i(p);
        Lobes::split(s.base_color * nl * k, s.specular * spec * k)
    }
    fn indirect_lobes(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, gi_d: DVec3, _: DVec3) -> Lobes {
        Lobes::diffuse(ambient(s, gi_d))
    }
}

/// Oren-Nayar; `interreflection_constant` 0.33 (qualitative model) or 0.57 (the custom shader's).
pub struct OrenNayar {
    pub trig_form: bool,
}

/// cos(φi − φr): the tangent-plane projections of L and V, normalised; 0 when either is along N.
pub fn cos_azimuth_difference(n: DVec3, v: DVec3, l: DVec3, nl: f64, nv: f64) -> f64 {
    let (lp, vp) = (l - n * nl, v - n * nv);
    let d = lp.length_squared() * vp.length_squared();
    if d < 1e-12 {
        0.0
    } else {
        lp.dot(vp) / d.sqrt()
    }
}

impl SurfaceTwin for OrenNayar {
    fn diffuse_only(&self) -> bool {
        true
    }

    fn direct_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let nl = n.dot(l);
        if nl <= 0.0 {
            return Lobes::ZERO;
        }
        let nv = n.dot(v).clamp(0.0, 1.0);
        let sigma2 = s.params[0] * s.params[0];
        let b = 0.45 * sigma2 / (sigma2 + 0.09);
        let c = cos_azimuth_difference(n, v, l, nl, nv).max(0.0);
        let term = if self.trig_form {
            let a = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33);
            let (ti, tr) = (nl.clamp(-1.0, 1.0).acos(), nv.acos());
            let (alpha, beta) = (ti.max(tr), ti.min(tr));
            a + b * c * alpha.sin() * beta.sin() / beta.cos().max(1e-4)
        } else {
            let a = 1.0 - 0.5 * sigma2 / (sigma2 + 0.57);
            let sin_product = ((1.0 - nl * nl).max(0.0) * (1.0 - nv * nv).max(0.0)).sqrt();
            a + b * c * sin_product / nl.max(nv).max(1e-4)
        };
        Lobes::diffuse(s.base_color * FRAC_1_PI * e_per_i(p) * nl * term)
    }
    fn indirect_lobes(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, gi_d: DVec3, _: DVec3) -> Lobes {
        Lobes::diffuse(ambient(s, gi_d))
    }
}

/// Cook-Torrance as the 1982 paper writes it: (F/π)·D_u·G/(NL·NV), D_u = π·D_Beckmann.
pub struct CookTorrance1982;

impl SurfaceTwin for CookTorrance1982 {
    fn direct_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let Some(a) = cook_torrance_angles(s, n, v, l) else { return Lobes::ZERO };
        let g = g_cook_torrance(a.nh, a.nv, a.nl, a.vh);
        let spec = a.f * FRAC_1_PI * d_beckmann_unnormalised(a.nh, a.m) * g / (a.nl * a.nv);
        cook_torrance_sum(p, s, &a, spec)
    }
    fn indirect_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> Lobes {
        CookTorrance.indirect_lobes(p, s, n, v, gi_d, gi_s)
    }
}

/// exp((NH² − 1)/(m²NH²))/(m²NH⁴): Beckmann without its 1/π normalisation (Cook & Torrance 1982).
pub fn d_beckmann_unnormalised(nh: f64, m: f64) -> f64 {
    d_beckmann(nh, m) * PI
}

pub fn d_beckmann(nh: f64, m: f64) -> f64 {
    let m2 = m.max(1e-3).powi(2);
    let nh2 = (nh * nh).max(1e-8);
    ((nh2 - 1.0) / (m2 * nh2)).exp() / (PI * m2 * nh2 * nh2)
}

pub fn g_cook_torrance(nh: f64, nv: f64, nl: f64, vh: f64) -> f64 {
    (2.0 * nh * nv.min(nl) / vh.max(1e-4)).min(1.0)
}

pub fn f_fresnel_dielectric(c: f64, eta: f64) -> f64 {
    let g2 = eta * eta + c * c - 1.0;
    if g2 < 0.0 {
        return 1.0;
    }
    let g = g2.sqrt();
    let a = (g - c) / (g + c);
    let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    0.5 * a * a * (1.0 + b * b)
}

pub struct CookTorrance;

/// What both Cook-Torrance forms share at one (n, v, l): F (`ct_fresnel`), NH, VH, NL, NV and
/// m = α; None below the horizon.
struct CookTorranceAngles {
    f: DVec3,
    nh: f64,
    vh: f64,
    nl: f64,
    nv: f64,
    m: f64,
}

fn cook_torrance_angles(s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Option<CookTorranceAngles> {
    let (nl, nv) = (n.dot(l), n.dot(v));
    if nl <= 0.0 || nv <= 0.0 {
        return None;
    }
    let h = safe_normalize(l + v, f32::MIN_POSITIVE as f64);
    let (nh, vh) = (sat(n.dot(h)), sat(v.dot(h)));
    let pr = 1.0 - s.smoothness;
    Some(CookTorranceAngles { f: ct_fresnel(s, vh), nh, vh, nl, nv, m: pr * pr })
}

/// The dielectric Fresnel at VH from the IOR, lerped by metallic to Schlick(base colour).
pub fn ct_fresnel(s: &Surface, vh: f64) -> DVec3 {
    DVec3::splat(f_fresnel_dielectric(vh, s.params[0])).lerp(f_schlick(s.base_color, vh), s.metallic)
}

/// Both forms' diffuse kd·ρ/π plus `spec`, times NL and the pipeline's irradiance per intensity.
fn cook_torrance_sum(p: Pipeline, s: &Surface, a: &CookTorranceAngles, spec: DVec3) -> Lobes {
    let k = a.nl * e_per_i(p);
    Lobes::split(s.base_color * (1.0 - s.metallic) * FRAC_1_PI * k, spec * k)
}

impl SurfaceTwin for CookTorrance {
    fn direct_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let Some(a) = cook_torrance_angles(s, n, v, l) else { return Lobes::ZERO };
        let spec = a.f * d_beckmann(a.nh, a.m) * g_cook_torrance(a.nh, a.nv, a.nl, a.vh) / (4.0 * a.nl * a.nv);
        cook_torrance_sum(p, s, &a, spec)
    }
    fn indirect_lobes(&self, _: Pipeline, s: &Surface, _: DVec3, _: DVec3, gi_d: DVec3, _: DVec3) -> Lobes {
        Lobes::diffuse(s.base_color * (1.0 - s.metallic) * gi_d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_1982_form_is_four_times_the_modern_specular() {
        let n = DVec3::Y;
        let v = DVec3::new(0.3, 0.8, 0.1).normalize();
        let l = DVec3::new(-0.4, 0.7, 0.2).normalize();
        // Black dielectric: no diffuse, so the ratio is the specular's.
        let mut s = Surface::basic(DVec3::ZERO, 0.0, 0.4);
        s.params[0] = 1.5;
        let old = CookTorrance1982.direct(Pipeline::Builtin, &s, n, v, l);
        let modern = CookTorrance.direct(Pipeline::Builtin, &s, n, v, l);
        assert!(modern.x > 0.0);
        assert!((old.x / modern.x - 4.0).abs() < 1e-12, "{}", old.x / modern.x);
        // The un-normalised D does not integrate to 1 over projected solid angle: ∫D·cosθ dω = π.
        let m = 0.3;
        let steps = 20000;
        let integral: f64 = (0..steps)
            .map(|i| {
                let t = (i as f64 + 0.5) / steps as f64 * std::f64::consts::FRAC_PI_2;
                d_beckmann_unnormalised(t.cos(), m) * t.cos() * t.sin() * 2.0 * PI * std::f64::consts::FRAC_PI_2
                    / steps as f64
            })
            .sum();
        assert!((integral - PI).abs() < 1e-3, "{integral}");
    }

    #[test]
    fn dielectric_fresnel_reference_values() {
        // η = 1.5 at normal incidence: ((η − 1)/(η + 1))² = 0.04; grazing → 1; TIR below 1.
        assert!((f_fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-12);
        assert!((f_fresnel_dielectric(1e-9, 1.5) - 1.0).abs() < 1e-6);
        assert_eq!(f_fresnel_dielectric(0.1, 0.5), 1.0);
    }

    #[test]
    fn oren_nayar_forms_agree_apart_from_the_constant() {
        // Both forms compute sin a·tan b = sinθi·sinθr/max(cosθi, cosθr); only A differs.
        let n = DVec3::Y;
        let v = DVec3::new(0.5, 0.6, 0.2).normalize();
        let l = DVec3::new(0.4, 0.7, 0.3).normalize();
        let mut s = Surface::basic(DVec3::ONE, 0.0, 0.0);
        s.params[0] = 0.0;
        let trig = OrenNayar { trig_form: true }.direct(Pipeline::Hdrp, &s, n, v, l);
        let free = OrenNayar { trig_form: false }.direct(Pipeline::Hdrp, &s, n, v, l);
        assert!((trig - free).length() < 1e-12, "σ = 0 is Lambert in both");
        s.params[0] = 0.5;
        let sigma2: f64 = 0.25;
        let a33 = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33);
        let a57 = 1.0 - 0.5 * sigma2 / (sigma2 + 0.57);
        let trig = OrenNayar { trig_form: true }.direct(Pipeline::Hdrp, &s, n, v, l).x;
        let free = OrenNayar { trig_form: false }.direct(Pipeline::Hdrp, &s, n, v, l).x;
        let scale = FRAC_1_PI * n.dot(l);
        assert!(((trig - free) / scale - (a33 - a57)).abs() < 1e-9, "{trig} {free}");
    }
}
