//! Twin of HDRP Lit (models.md#hdrp-lit), term by term with shaders/brdf/hdrp_lit.wgsl.

use glam::DVec3;
use std::f64::consts::FRAC_1_PI;

use super::{pow5, sat, Lobes, Surface, SurfaceTwin};
use crate::pipelines::{Emitter, Pipeline, HDRP_DEFAULT_SHAPE_RADIUS};
use crate::shading::fgd::{fd_disney_renormalized_no_pi, FgdTable};

const FLT_EPS: f64 = 5.960_464_478e-8;

/// minRoughness of a point light of HDRP's default radius (0.025 m): what `direct` assumes.
pub fn default_light_min_roughness() -> f64 {
    Emitter::Point { radius: HDRP_DEFAULT_SHAPE_RADIUS }.hdrp_min_roughness()
}

/// GetSmithJointGGXPartLambdaV: √((−NV·α² + NV)·NV + α²).
pub fn smith_joint_ggx_part_lambda_v(nv: f64, a: f64) -> f64 {
    let a2 = a * a;
    ((-nv * a2 + nv) * nv + a2).sqrt()
}

/// DV_SmithJointGGX with λV = NL·partLambdaV (partLambdaV from the unclamped roughness).
pub fn dv_smith_joint_ggx(nh: f64, nl: f64, nv: f64, a: f64, part_lambda_v: f64) -> f64 {
    let a2 = a * a;
    let s = (nh * a2 - nh) * nh + 1.0;
    let lambda_v = nl * part_lambda_v;
    let lambda_l = nv * ((-nl * a2 + nl) * nl + a2).sqrt();
    FRAC_1_PI * 0.5 * a2 / (s * s * (lambda_v + lambda_l)).max(f32::MIN_POSITIVE as f64)
}

/// ClampNdotV: max(NV, 1e-4). No GetViewReflectedNormal in HDRP Lit.
pub fn clamp_n_dot_v(nv: f64) -> f64 {
    nv.max(1e-4)
}

/// GetSpecularDominantDir: a = 1 − pr², lerp(N, R, (√a + pr²)·sat(a² + lerp(0, a, NV²))).
pub fn get_specular_dominant_dir(n: DVec3, r: DVec3, pr: f64, clamped_nv: f64) -> DVec3 {
    let a = 1.0 - pr * pr;
    let lerp_factor = (a.sqrt() + pr * pr) * sat(a * a + a * clamped_nv * clamped_nv);
    n.lerp(r, lerp_factor)
}

fn smoothstep01(x: f64) -> f64 {
    let t = sat(x);
    t * t * (3.0 - 2.0 * t)
}

/// EvaluateBSDF_Env's fetch direction, normalised: the dominant direction lerped back to
/// iblR = reflect(−V, N) by sat(smoothstep(0, 1, α²)).
pub fn hdrp_ibl_direction(n: DVec3, v: DVec3, pr: f64, clamped_nv: f64) -> DVec3 {
    let ibl_r = 2.0 * n.dot(v) * n - v;
    let a = pr * pr;
    let r = get_specular_dominant_dir(n, ibl_r, pr, clamped_nv).lerp(ibl_r, smoothstep01(a * a));
    r / r.length_squared().max(FLT_EPS).sqrt()
}

/// F0·(1 − x⁵) + F90·x⁵, x = 1 − LH.
pub fn f_schlick_f90(f0: DVec3, f90: f64, lh: f64) -> DVec3 {
    let x5 = pow5(1.0 - lh);
    f0 * (1.0 - x5) + DVec3::splat(f90 * x5)
}

/// F0 = lerp(0.04, albedo, metallic), or the specular colour for the Specular Color material
/// type (params[1] = 1).
pub fn hdrp_f0(s: &Surface) -> DVec3 {
    if s.params[1] > 0.5 {
        return s.specular;
    }
    DVec3::splat(0.04).lerp(s.base_color, s.metallic)
}

/// The diffuse colour: albedo·(1 − metallic), or for Specular Color with Energy Conserving
/// Specular Color (its default), albedo·(1 − max(specular)); × the diffuse weight a transparent
/// surface's ApplyBlendMode gives the diffuse lighting.
pub fn hdrp_diffuse_color(s: &Surface) -> DVec3 {
    if s.params[1] > 0.5 {
        return s.base_color * (1.0 - s.specular.max_element()) * s.diffuse_weight;
    }
    s.base_color * (1.0 - s.metallic) * s.diffuse_weight
}

/// Specular multiplier 1 + F0·(1/y − 1), y = reflectivity from the FGD table (models.md#hdrp-lit).
pub fn hdrp_energy_compensation(s: &Surface, clamped_nv: f64) -> DVec3 {
    if s.params[0] < 0.5 {
        return DVec3::ONE;
    }
    let y = FgdTable::get().lookup(clamped_nv, 1.0 - s.smoothness).y;
    DVec3::ONE + hdrp_f0(s) * (1.0 / y - 1.0)
}

pub struct HdrpLit;

impl SurfaceTwin for HdrpLit {
    fn direct_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes {
        self.direct_lobes_for_light(p, s, n, v, l, default_light_min_roughness() as f32 as f64)
    }

    fn direct_lobes_for_light(
        &self,
        _: Pipeline,
        s: &Surface,
        n: DVec3,
        v: DVec3,
        l: DVec3,
        min_roughness: f64,
    ) -> Lobes {
        let nl = n.dot(l);
        if nl <= 0.0 {
            return Lobes::ZERO;
        }
        let nv = n.dot(v);
        let clamped_nv = clamp_n_dot_v(nv);
        let lv = l.dot(v);
        let inv_len = 1.0 / (2.0 * lv + 2.0).max(FLT_EPS).sqrt();
        let nh = sat((nl + nv) * inv_len);
        let lh = sat(inv_len * lv + inv_len);
        let pr = 1.0 - s.smoothness;
        let a_material = pr * pr;
        let a = a_material.max(min_roughness);
        let f = f_schlick_f90(hdrp_f0(s), 1.0, lh);
        let dv = dv_smith_joint_ggx(nh, nl.abs(), clamped_nv, a, smith_joint_ggx_part_lambda_v(clamped_nv, a_material));
        let spec = f * dv * hdrp_energy_compensation(s, clamped_nv);
        let diffuse = hdrp_diffuse_color(s) * FRAC_1_PI * fd_disney_renormalized_no_pi(nl.abs(), clamped_nv, lv, pr);
        Lobes::split(diffuse * sat(nl), spec * sat(nl))
    }

    fn indirect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> Lobes {
        let clamped_nv = clamp_n_dot_v(n.dot(v));
        let fgd = FgdTable::get().lookup(clamped_nv, 1.0 - s.smoothness);
        let f0 = hdrp_f0(s);
        let specular_fgd = (DVec3::ONE - f0) * fgd.x + f0 * fgd.y;
        Lobes::split(
            hdrp_diffuse_color(s) * gi_d * (fgd.z + 0.5),
            specular_fgd * gi_s * hdrp_energy_compensation(s, clamped_nv),
        )
    }

    fn rect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, corners: &[DVec3; 4]) -> Option<Lobes> {
        use crate::shading::ltc::{ltc_evaluate, ltc_lookup, ortho_basis_view_normal, LtcLobe};
        let nv = n.dot(v);
        let clamped_nv = clamp_n_dot_v(nv);
        let pr = 1.0 - s.smoothness;
        let basis = ortho_basis_view_normal(v, n, nv);
        let ltc_diffuse = ltc_evaluate(corners, &basis, &ltc_lookup(LtcLobe::DisneyDiffuse, clamped_nv, pr));
        let ltc_specular = ltc_evaluate(corners, &basis, &ltc_lookup(LtcLobe::Ggx, clamped_nv, pr));
        let fgd = FgdTable::get().lookup(clamped_nv, pr);
        let f0 = hdrp_f0(s);
        let specular_fgd = (DVec3::ONE - f0) * fgd.x + f0 * fgd.y;
        Some(Lobes::split(
            hdrp_diffuse_color(s) * (fgd.z + 0.5) * ltc_diffuse,
            specular_fgd * ltc_specular * hdrp_energy_compensation(s, clamped_nv),
        ))
    }

    fn env_direction(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3) -> Option<DVec3> {
        Some(hdrp_ibl_direction(n, v, 1.0 - s.smoothness, clamp_n_dot_v(n.dot(v))))
    }
}

/// GTAOMultiBounce (core AmbientOcclusion.hlsl): the visibility with light bounced between the
/// occluders, max(x, ((x·a + b)·x + c)·x) per channel of the albedo.
pub fn gtao_multi_bounce(visibility: f64, albedo: DVec3) -> DVec3 {
    let a = 2.0404 * albedo - DVec3::splat(0.3324);
    let b = -4.7951 * albedo + DVec3::splat(0.6417);
    let c = 2.7552 * albedo + DVec3::splat(0.6903);
    let x = visibility;
    DVec3::splat(x).max(((x * a + b) * x + c) * x)
}

/// GetSpecularOcclusionFromAmbientOcclusion (core CommonLighting.hlsl), α the roughness.
pub fn specular_occlusion_from_ao(nv: f64, ao: f64, roughness: f64) -> f64 {
    sat((nv + ao).max(0.0).powf((-16.0 * roughness - 1.0).exp2()) - 1.0 + ao)
}

/// HDRP's occlusion of the indirect light (forward.wgsl `indirect_light`): the factors on the
/// indirect diffuse and on the reflected environment for a material occlusion and an SSAO
/// visibility.
pub fn indirect_occlusion(s: &Surface, nv: f64, material_ao: f64, screen_ao: f64) -> (DVec3, DVec3) {
    let nv = nv.max(1e-4);
    let roughness = (1.0 - s.smoothness).powi(2);
    let so = specular_occlusion_from_ao(nv, material_ao, roughness)
        .min(specular_occlusion_from_ao(nv, screen_ao, roughness));
    (
        gtao_multi_bounce(material_ao.min(screen_ao), s.base_color * (1.0 - s.metallic)),
        // The metallic form for every model, as the pass computes it (forward.wgsl
        // `indirect_light`): for HDRP Lit's Specular Color type it is 0.04, not the specular
        // colour HDRP's GTAOMultiBounce reads (docs/deviations.md).
        gtao_multi_bounce(so, DVec3::splat(0.04).lerp(s.base_color, s.metallic)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multibounce_keeps_full_visibility_and_brightens_bright_occluders() {
        // At x = 1 the cubic is 0.9996 + 0.0005·ρ: max(1, ·) leaves full visibility at (almost) 1.
        for rho in [0.0, 0.5, 1.0] {
            let m = gtao_multi_bounce(1.0, DVec3::splat(rho));
            assert!((m.x - 1.0).abs() < 2e-4, "{rho}: {m}");
        }
        // Light bounces off white occluders: half visibility looks brighter than 0.5, black stays 0.5.
        assert!(gtao_multi_bounce(0.5, DVec3::ONE).x > 0.6);
        assert_eq!(gtao_multi_bounce(0.5, DVec3::ZERO).x, 0.5);
        // Specular occlusion: none at AO 1, total at AO 0 for a mirror seen head-on.
        assert!((specular_occlusion_from_ao(1.0, 1.0, 0.3) - 1.0).abs() < 1e-12);
        assert_eq!(specular_occlusion_from_ao(1.0, 0.0, 0.0), 0.0);
    }

    #[test]
    fn rough_surfaces_fetch_towards_the_normal() {
        // Spec: pr 0.8, NV 0.5 gives a lerp factor ≈ 0.27 before the blend back to iblR.
        let (pr, nv) = (0.8f64, 0.5f64);
        let a = 1.0 - pr * pr;
        let factor = (a.sqrt() + pr * pr) * sat(a * a + a * nv * nv);
        assert!((factor - 0.27).abs() < 0.01, "{factor}");
        let n = DVec3::Y;
        let v = DVec3::new((1.0 - nv * nv).sqrt(), nv, 0.0);
        let r = hdrp_ibl_direction(n, v, pr, nv);
        let ibl_r = 2.0 * nv * n - v;
        assert!(r.dot(n) > ibl_r.dot(n), "towards N: {r} vs iblR {ibl_r}");
        // A mirror fetches along iblR itself.
        let mirror = hdrp_ibl_direction(n, v, 0.0, nv);
        assert!((mirror - ibl_r).length() < 1e-12);
    }

    #[test]
    fn a_sharper_light_shape_gives_a_higher_peak() {
        let s = Surface::basic(DVec3::ONE, 1.0, 1.0);
        let n = DVec3::Y;
        let v = DVec3::new(0.6, 0.8, 0.0);
        let l = DVec3::new(-0.6, 0.8, 0.0);
        let small = HdrpLit.direct_for_light(Pipeline::Hdrp, &s, n, v, l, 2.4e-7);
        let default = HdrpLit.direct(Pipeline::Hdrp, &s, n, v, l);
        assert!(small.x > 100.0 * default.x, "radius 0 vs 0.025: {small} vs {default}");
    }
}
