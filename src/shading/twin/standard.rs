use glam::DVec3;
use std::f64::consts::{FRAC_1_PI, PI};

use super::{f_schlick, f_schlick_lerp, pow5, safe_normalize, sat, Lobes, Surface, SurfaceTwin};
use crate::pipelines::Pipeline;

/// Built-in Standard, BRDF1_Unity_PBS, linear colour space (models.md#standard). Twin of shaders/brdf/standard.wgsl.
pub struct Standard;

const DIELECTRIC_SPEC_RGB: f64 = 0.04;
const DIELECTRIC_SPEC_A: f64 = 0.96;

pub struct StandardSetup {
    pub diff_color: DVec3,
    pub spec_color: DVec3,
    pub one_minus_reflectivity: f64,
    pub perceptual_roughness: f64,
}

/// specColor, oneMinusReflectivity, diffColor and perceptual roughness (models.md#standard):
/// MetallicSetup, or SpecularSetup where params[0] = 1 (StandardSpecular.shader: oneMinusReflectivity
/// = 1 − max(specColor), diffColor = albedo·that, UNITY_CONSERVE_ENERGY_MONOCHROME).
pub fn standard_setup(s: &Surface) -> StandardSetup {
    let (one_minus_reflectivity, spec_color) = match s.params[0] > 0.5 {
        true => (1.0 - s.specular.max_element(), s.specular),
        false => (
            DIELECTRIC_SPEC_A - s.metallic * DIELECTRIC_SPEC_A,
            DVec3::splat(DIELECTRIC_SPEC_RGB).lerp(s.base_color, s.metallic),
        ),
    };
    StandardSetup {
        spec_color,
        diff_color: s.base_color * one_minus_reflectivity * s.diffuse_weight,
        one_minus_reflectivity,
        perceptual_roughness: 1.0 - s.smoothness,
    }
}

pub fn roughness_clamped(pr: f64) -> f64 {
    (pr * pr).max(0.002)
}

pub fn fd_disney_unity(nv: f64, nl: f64, lh: f64, pr: f64) -> f64 {
    let fd90 = 0.5 + 2.0 * lh * lh * pr;
    (1.0 + (fd90 - 1.0) * pow5(1.0 - nl)) * (1.0 + (fd90 - 1.0) * pow5(1.0 - nv))
}

pub fn v_smith_joint_approx(nl: f64, nv: f64, a: f64) -> f64 {
    let lambda_v = nl * (nv * (1.0 - a) + a);
    let lambda_l = nv * (nl * (1.0 - a) + a);
    0.5 / (lambda_v + lambda_l + 1e-5)
}

pub fn d_ggx_unity(nh: f64, a: f64) -> f64 {
    let a2 = a * a;
    let d = (nh * a2 - nh) * nh + 1.0;
    FRAC_1_PI * a2 / (d * d + 1e-7)
}

impl SurfaceTwin for Standard {
    fn direct_lobes(&self, _p: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        let st = standard_setup(s);
        let h = safe_normalize(l + v, 0.001);
        let nv = n.dot(v).abs();
        let nl = sat(n.dot(l));
        let nh = sat(n.dot(h));
        let lh = sat(l.dot(h));
        let diffuse_term = fd_disney_unity(nv, nl, lh, st.perceptual_roughness) * nl;
        let a = roughness_clamped(st.perceptual_roughness);
        let mut specular_term = (v_smith_joint_approx(nl, nv, a) * d_ggx_unity(nh, a) * PI * nl).max(0.0);
        // _SPECULARHIGHLIGHTS_OFF (params[1] = 1).
        if st.spec_color == DVec3::ZERO || s.params[1] > 0.5 {
            specular_term = 0.0;
        }
        Lobes::split(st.diff_color * diffuse_term, specular_term * f_schlick(st.spec_color, lh))
    }

    fn indirect_lobes(
        &self,
        _p: Pipeline,
        s: &Surface,
        n: DVec3,
        v: DVec3,
        gi_diffuse: DVec3,
        gi_specular: DVec3,
    ) -> Lobes {
        let st = standard_setup(s);
        let nv = n.dot(v).abs();
        let a = roughness_clamped(st.perceptual_roughness);
        let surface_reduction = 1.0 / (a * a + 1.0);
        let grazing_term = sat(s.smoothness + (1.0 - st.one_minus_reflectivity));
        Lobes::split(
            st.diff_color * gi_diffuse,
            surface_reduction * gi_specular * f_schlick_lerp(st.spec_color, DVec3::splat(grazing_term), nv),
        )
    }

    fn reflectivity(&self, s: &Surface) -> f64 {
        1.0 - standard_setup(s).one_minus_reflectivity
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surface(albedo: f64, metallic: f64, smoothness: f64) -> Surface {
        Surface::basic(DVec3::splat(albedo), metallic, smoothness)
    }

    #[test]
    fn black_metal_has_no_direct_light() {
        let n = DVec3::Y;
        let v = DVec3::new(0.3, 0.8, 0.2).normalize();
        let l = DVec3::new(-0.3, 0.9, 0.1).normalize();
        assert_eq!(Standard.direct(Pipeline::Builtin, &surface(0.0, 1.0, 0.9), n, v, l), DVec3::ZERO);
    }

    #[test]
    fn ggx_peak_is_capped_by_the_1e7_epsilon() {
        // At α = 0.002 and NH = 1, d² = α⁴ = 1.6e-11 is far below Unity's +1e-7, so the peak is
        // (1/π)·α²/(α⁴ + 1e-7) ≈ 12.7, not the 1/(π·α²) ≈ 8e4 it would be without the epsilon.
        let a: f64 = 0.002;
        let peak = d_ggx_unity(1.0, a);
        let expected = FRAC_1_PI * a * a / (a.powi(4) + 1e-7);
        assert!((peak - expected).abs() < 1e-9 * expected, "{peak} vs {expected}");
        assert!(peak < 13.0 && peak > 12.0, "{peak}");
        // At α = 0.3 the epsilon no longer matters: the textbook peak 1/(πα²) holds.
        let p = d_ggx_unity(1.0, 0.3);
        assert!((p - 1.0 / (PI * 0.09)).abs() / p < 1e-4);
    }

    #[test]
    fn smoother_surface_has_sharper_mirror_peak() {
        let n = DVec3::Y;
        let v = DVec3::new(0.5, 0.75f64.sqrt(), 0.0);
        let l = DVec3::new(-0.5, 0.75f64.sqrt(), 0.0);
        let rough = Standard.direct(Pipeline::Builtin, &surface(0.5, 0.0, 0.2), n, v, l);
        let smooth = Standard.direct(Pipeline::Builtin, &surface(0.5, 0.0, 0.9), n, v, l);
        assert!(smooth.x > 2.0 * rough.x, "smooth {smooth} rough {rough}");
    }
}
