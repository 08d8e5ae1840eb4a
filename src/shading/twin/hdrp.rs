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
/// iblR (reflect(−V, N), or about the anisotropic normal) by sat(smoothstep(0, 1, α²)).
pub fn hdrp_ibl_direction(n: DVec3, ibl_r: DVec3, pr: f64, clamped_nv: f64) -> DVec3 {
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
    if s.params[TRANSMISSION_SLOT] > 0.5 || s.params[SUBSURFACE_SLOT] > 0.5 {
        // FillMaterialTransmission, FillMaterialSSS: the diffusion profile's F0.
        return DVec3::splat(DIFFUSION_PROFILE_FRESNEL0);
    }
    if s.params[1] > 0.5 {
        return s.specular;
    }
    DVec3::splat(0.04).lerp(s.base_color, s.metallic)
}

/// The diffuse colour: albedo·(1 − metallic), or for Specular Color with Energy Conserving
/// Specular Color (its default), albedo·(1 − max(specular)); × the diffuse weight a transparent
/// surface's ApplyBlendMode gives the diffuse lighting.
pub fn hdrp_diffuse_color(s: &Surface) -> DVec3 {
    if s.params[TRANSMISSION_SLOT] > 0.5 || s.params[SUBSURFACE_SLOT] > 0.5 {
        // There is no metallic with SSS or transmission (ConvertSurfaceDataToBSDFData).
        return s.base_color * s.diffuse_weight;
    }
    if s.params[1] > 0.5 {
        return s.base_color * (1.0 - s.specular.max_element()) * s.diffuse_weight;
    }
    s.base_color * (1.0 - s.metallic) * s.diffuse_weight
}

/// bsdfData.diffuseColor as HDRP's ambient-occlusion multi-bounce reads it (hdrp_lit.wgsl
/// `model_occlusion_albedo`): `hdrp_diffuse_color` before the blend's opacity.
pub fn model_occlusion_albedo(s: &Surface) -> DVec3 {
    hdrp_diffuse_color(&Surface { diffuse_weight: 1.0, ..*s })
}

/// fresnel0 as HDRP's ambient-occlusion multi-bounce reads it (`model_occlusion_fresnel0`).
pub fn model_occlusion_fresnel0(s: &Surface) -> DVec3 {
    hdrp_f0(s)
}

/// Specular multiplier 1 + F0·(1/y − 1), y = reflectivity from the FGD table at the material's
/// perceptual roughness, F0 the fresnel0 its features left (models.md#hdrp-lit; PostEvaluateBSDF).
pub fn hdrp_energy_compensation(s: &Surface, b: &HdrpBsdfData, clamped_nv: f64) -> DVec3 {
    if s.params[0] < 0.5 {
        return DVec3::ONE;
    }
    let y = FgdTable::get().lookup(clamped_nv, b.perceptual_roughness).y;
    DVec3::ONE + b.fresnel0 * (1.0 / y - 1.0)
}

/// The clear coat's constants (core CommonMaterial.hlsl): IOR 1.5, F0 = IorToFresnel0(1.5) = 0.04,
/// GGX roughness 0.01.
pub const CLEAR_COAT_IOR: f64 = 1.5;
pub const CLEAR_COAT_F0: f64 = 0.04;
pub const CLEAR_COAT_ROUGHNESS: f64 = 0.01;

/// HDRP Lit's feature parameters by slot (registry: `coat_mask`, `iridescence_mask`,
/// `iridescence_thickness`).
pub const COAT_MASK_SLOT: usize = 2;
pub const IRIDESCENCE_MASK_SLOT: usize = 3;
pub const IRIDESCENCE_THICKNESS_SLOT: usize = 4;
pub const ANISOTROPY_SLOT: usize = 5;
/// The Translucent material type's transmission switch and its `_Thickness`.
pub const TRANSMISSION_SLOT: usize = 8;
pub const THICKNESS_SLOT: usize = 9;
/// The Subsurface Scattering material type's switch and its `_SubsurfaceMask`.
pub const SUBSURFACE_SLOT: usize = 6;
pub const SUBSURFACE_MASK_SLOT: usize = 7;

/// HDRP's default diffusion profile (DiffusionProfileSettings.cs ResetToDefault): scattering
/// distance 0.5 (grey) × 1, so the shape parameter S = 1/0.5 per mm; a white transmission tint,
/// premultiplied by 1/4; thickness remap 0–5 mm; IOR 1.4, F0 = ((1.4 − 1)/(1.4 + 1))²; Thin Object.
pub const DIFFUSION_PROFILE_SHAPE: f64 = 2.0;
pub const DIFFUSION_PROFILE_TINT: f64 = 0.25;
pub const DIFFUSION_PROFILE_THICKNESS_MM: f64 = 5.0;
pub const DIFFUSION_PROFILE_FRESNEL0: f64 = (0.4 / 2.4) * (0.4 / 2.4);
/// TRANSMISSION_WRAP_LIGHT: cos(π/2 − π/12) (SubsurfaceScattering.hlsl).
pub const TRANSMISSION_WRAP_LIGHT: f64 = 0.258_819_045_102_520_74;

/// ComputeWrappedDiffuseLighting (core CommonLighting.hlsl): sat((NL + w)/(1 + w)²).
pub fn compute_wrapped_diffuse_lighting(nl: f64, w: f64) -> f64 {
    sat((nl + w) / ((1.0 + w) * (1.0 + w)))
}

/// ComputeTransmittanceDisney (DiffusionProfile.hlsl): A·e^(−S·t/3)·(e^(−2S·t/3) + 3), A the tint
/// premultiplied by 1/4: the transmittance of a slab t mm thick under the Burley profile.
pub fn compute_transmittance_disney(shape: DVec3, volume_albedo: DVec3, thickness: f64) -> DVec3 {
    let exp_13 = (shape * (-thickness / 3.0)).exp();
    volume_albedo * (exp_13 * (exp_13 * exp_13 + 3.0))
}

/// FillMaterialTransmission with the default profile: thickness remap.x + remap.y·_Thickness (mm).
pub fn hdrp_transmittance(s: &Surface) -> DVec3 {
    let thickness = DIFFUSION_PROFILE_THICKNESS_MM * s.params[THICKNESS_SLOT];
    compute_transmittance_disney(DVec3::splat(DIFFUSION_PROFILE_SHAPE), DVec3::splat(DIFFUSION_PROFILE_TINT), thickness)
}

/// F_Schlick for a scalar F0 and F90 = 1: (1 − F0)·x⁵ + F0, x = 1 − u (core BSDF.hlsl).
pub fn f_schlick_scalar(f0: f64, u: f64) -> f64 {
    (1.0 - f0) * pow5(1.0 - u) + f0
}

/// RoughnessToVariance: 2/α² − 2, Blinn-Phong's power as a Beckmann variance (CommonMaterial.hlsl).
pub fn roughness_to_variance(a: f64) -> f64 {
    2.0 / (a * a) - 2.0
}

/// VarianceToRoughness: √(2/(σ + 2)) (CommonMaterial.hlsl).
pub fn variance_to_roughness(variance: f64) -> f64 {
    (2.0 / (variance + 2.0)).sqrt()
}

/// FillMaterialClearCoatData: the base layer seen through the coat looks rougher; its perceptual
/// roughness √VarianceToRoughness(RoughnessToVariance(pr²)·ieta²), ieta = lerp(1, 1/1.5, mask).
pub fn clear_coat_perceptual_roughness(pr: f64, coat_mask: f64) -> f64 {
    let ieta = 1.0 + (1.0 / CLEAR_COAT_IOR - 1.0) * coat_mask;
    variance_to_roughness(roughness_to_variance(pr * pr) * ieta * ieta).sqrt()
}

/// ConvertF0ForAirInterfaceToF0ForClearCoat15: sat(−0.0256868 + F0·(0.326846 + (0.978946 −
/// 0.283835·F0)·F0)), core BSDF.hlsl's fit of IorToFresnel0(Fresnel0ToIor(F0), 1.5).
pub fn convert_f0_for_air_interface_to_f0_for_clear_coat15(f0: DVec3) -> DVec3 {
    let fit = |x: f64| sat(-0.0256868 + x * (0.326846 + (0.978946 - 0.283835 * x) * x));
    DVec3::new(fit(f0.x), fit(f0.y), fit(f0.z))
}

/// EvalSensitivity (Belcour & Barla 2017, core BSDF.hlsl): the CIE XYZ matching functions as
/// Gaussians in Fourier space at optical path difference `opd` (µm) and phase `shift`, in linear
/// Rec. 709.
pub fn eval_sensitivity(opd: f64, shift: f64) -> DVec3 {
    let phase = 2.0 * std::f64::consts::PI * opd * 1e-6;
    let val = DVec3::new(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let pos = DVec3::new(1.6810e+06, 1.7953e+06, 2.2084e+06);
    let var = DVec3::new(4.3278e+09, 9.3046e+09, 6.6121e+09);
    let gaussian = |val: f64, pos: f64, var: f64| {
        val * (2.0 * std::f64::consts::PI * var).sqrt() * (pos * phase + shift).cos() * (-var * phase * phase).exp()
    };
    let mut xyz =
        DVec3::new(gaussian(val.x, pos.x, var.x), gaussian(val.y, pos.y, var.y), gaussian(val.z, pos.z, var.z));
    xyz.x += gaussian(9.7470e-14, 2.2399e+06, 4.5282e+09);
    xyz /= 1.0685e-7;
    let m = crate::color::XYZ_TO_REC709;
    DVec3::new(
        m[0][0] * xyz.x + m[0][1] * xyz.y + m[0][2] * xyz.z,
        m[1][0] * xyz.x + m[1][1] * xyz.y + m[1][2] * xyz.z,
        m[2][0] * xyz.x + m[2][1] * xyz.y + m[2][2] * xyz.z,
    )
}

/// EvalIridescence (core BSDF.hlsl, after Belcour & Barla 2017 with Schlick's Fresnel): a thin
/// film of optical thickness 3·`thickness` µm and IOR lerp(2, 1, thickness) under a medium of IOR
/// `eta_1`, over a base of F0 `f0`; the Airy sum to m = 2, clamped at 0; 1 under total internal
/// reflection.
pub fn eval_iridescence(eta_1: f64, cos_theta1: f64, thickness: f64, f0: DVec3) -> DVec3 {
    let d_inc = 3.0 * thickness;
    let eta_2 = 2.0 + (1.0 - 2.0) * thickness;
    let sin_theta2_sq = (eta_1 / eta_2).powi(2) * (1.0 - cos_theta1 * cos_theta1);
    let cos_theta2_sq = 1.0 - sin_theta2_sq;
    if cos_theta2_sq < 0.0 {
        return DVec3::ONE;
    }
    let cos_theta2 = cos_theta2_sq.sqrt();
    // First interface: IorToFresnel0(eta_2, eta_1), Schlick at θ1; no phase shift on reflection.
    let r0 = ((eta_2 - eta_1) / (eta_2 + eta_1)).powi(2);
    let r12 = f_schlick_scalar(r0, cos_theta1);
    let t121 = 1.0 - r12;
    let phi21 = std::f64::consts::PI;
    // Second interface: the base's own F0 at θ2.
    let r23 = f_schlick_f90(f0, 1.0, cos_theta2);
    let opd = d_inc * cos_theta2;
    let phi = phi21;
    let r123 = (r12 * r23).clamp(DVec3::splat(1e-5), DVec3::splat(0.9999));
    let r123_sqrt = DVec3::new(r123.x.sqrt(), r123.y.sqrt(), r123.z.sqrt());
    let rs = t121 * t121 * r23 / (DVec3::ONE - r123);
    let mut i = DVec3::splat(r12) + rs;
    let mut cm = rs - DVec3::splat(t121);
    for m in 1..=2 {
        cm *= r123_sqrt;
        let sm = 2.0 * eval_sensitivity(m as f64 * opd, m as f64 * phi);
        i += cm * sm;
    }
    i.max(DVec3::ZERO)
}

/// HDRP Lit's BSDFData after its material features, with the PreLightData terms they set
/// (Lit.hlsl ConvertSurfaceDataToBSDFData, FillMaterialClearCoatData, GetPreLightData).
#[derive(Debug, Clone, Copy)]
pub struct HdrpBsdfData {
    /// fresnel0 after iridescence, then the coat, changed it.
    pub fresnel0: DVec3,
    /// perceptualRoughness after the coat's (the IBL, FGD, LTC and diffuse read it).
    pub perceptual_roughness: f64,
    pub coat_mask: f64,
    /// coatIblF = F_Schlick(CLEAR_COAT_F0, clampedNdotV)·coatMask.
    pub coat_ibl_f: f64,
    pub iridescence_mask: f64,
    pub anisotropy: f64,
    /// The tangent frame: the surface's tangent made orthonormal to N (GetLocalFrame's where
    /// there is none) and N × T (FillMaterialAnisotropy); zero without anisotropy.
    pub tangent: DVec3,
    pub bitangent: DVec3,
}

/// Orthonormalize(T, N), or GetLocalFrame(N)'s x where the mesh has no tangent.
pub fn hdrp_tangent(t: DVec3, n: DVec3) -> DVec3 {
    let t_raw = t - n * n.dot(t);
    if t_raw.length_squared() < 1e-12 {
        return super::local_frame(n)[0];
    }
    t_raw.normalize()
}

/// ConvertAnisotropyToRoughness: αT = α(1 + anisotropy), αB = α(1 − anisotropy).
pub fn anisotropic_roughness(a: f64, anisotropy: f64) -> (f64, f64) {
    (a * (1.0 + anisotropy), a * (1.0 - anisotropy))
}

/// GetSmithJointGGXAnisoPartLambdaV: |(αT·TV, αB·BV, NV)|.
pub fn smith_joint_ggx_aniso_part_lambda_v(tv: f64, bv: f64, nv: f64, rt: f64, rb: f64) -> f64 {
    DVec3::new(rt * tv, rb * bv, nv).length()
}

/// DV_SmithJointGGXAniso: (1/π)·0.5·a2³/max(s²(λV + λL), REAL_MIN), a2 = αT·αB,
/// s = |(αB·TH, αT·BH, a2·NH)|², λV = NL·partLambdaV, λL = NV·|(αT·TL, αB·BL, NL)|.
#[allow(clippy::too_many_arguments)]
pub fn dv_smith_joint_ggx_aniso(
    th: f64,
    bh: f64,
    nh: f64,
    nv: f64,
    tl: f64,
    bl: f64,
    nl: f64,
    rt: f64,
    rb: f64,
    part_lambda_v: f64,
) -> f64 {
    let a2 = rt * rb;
    let s = DVec3::new(rb * th, rt * bh, a2 * nh).length_squared();
    let lambda_v = nl * part_lambda_v;
    let lambda_l = nv * DVec3::new(rt * tl, rb * bl, nl).length();
    FRAC_1_PI * 0.5 * (a2 * a2 * a2) / (s * s * (lambda_v + lambda_l)).max(f32::MIN_POSITIVE as f64)
}

/// GetGGXAnisotropicModifiedNormalAndRoughness (core ImageBasedLighting.hlsl): N bent towards
/// the grain's view-facing normal normalize(V − (V·g)g) by |anisotropy|·sat(1.5√pr), g the
/// bitangent for anisotropy ≥ 0 (the tangent else); returns iblR = reflect(−V, iblN).
pub fn anisotropic_ibl_reflection(b: &HdrpBsdfData, n: DVec3, v: DVec3, pr: f64) -> DVec3 {
    let grain = if b.anisotropy >= 0.0 { b.bitangent } else { b.tangent };
    let stretch = b.anisotropy.abs() * sat(1.5 * pr.sqrt());
    let grain_normal = (v - v.dot(grain) * grain).normalize();
    let ibl_n = n.lerp(grain_normal, stretch).normalize();
    2.0 * ibl_n.dot(v) * ibl_n - v
}

/// The environment's fetch: iblR and the perceptual roughness of the mip, about the anisotropic
/// normal where there is anisotropy (GetPreLightData).
fn ibl_fetch(b: &HdrpBsdfData, n: DVec3, v: DVec3) -> (DVec3, f64) {
    if b.anisotropy != 0.0 {
        // The fetch's mip narrows with anisotropy: pr·sat(1.2 − |anisotropy|).
        let pr = b.perceptual_roughness;
        return (anisotropic_ibl_reflection(b, n, v, pr), pr * sat(1.2 - b.anisotropy.abs()));
    }
    (2.0 * n.dot(v) * n - v, b.perceptual_roughness)
}

/// The material features are on where their masks are above 0, as the inspector compiles
/// `_MATERIAL_FEATURE_CLEAR_COAT` for a coat mask above 0; at mask 0 they leave the surface as it is.
pub fn hdrp_bsdf_data(s: &Surface, n: DVec3, nv: f64) -> HdrpBsdfData {
    let clamped_nv = clamp_n_dot_v(nv);
    let coat_mask = s.params[COAT_MASK_SLOT];
    let iridescence_mask = s.params[IRIDESCENCE_MASK_SLOT];
    let mut b = HdrpBsdfData {
        fresnel0: hdrp_f0(s),
        perceptual_roughness: 1.0 - s.smoothness,
        coat_mask,
        coat_ibl_f: 0.0,
        iridescence_mask,
        anisotropy: s.params[ANISOTROPY_SLOT],
        tangent: DVec3::ZERO,
        bitangent: DVec3::ZERO,
    };
    if b.anisotropy != 0.0 {
        b.tangent = hdrp_tangent(s.tangent, n);
        b.bitangent = n.cross(b.tangent);
    }
    if coat_mask > 0.0 {
        b.perceptual_roughness = clear_coat_perceptual_roughness(b.perceptual_roughness, coat_mask);
    }
    if iridescence_mask > 0.0 {
        // Under the coat the film sees the view direction refracted into IOR lerp(1, 1.5, mask).
        let (top_ior, view_angle) = if coat_mask > 0.0 {
            let top = 1.0 + (CLEAR_COAT_IOR - 1.0) * coat_mask;
            (top, (1.0 + (1.0 / top).powi(2) * (nv * nv - 1.0)).sqrt())
        } else {
            (1.0, clamped_nv)
        };
        let film = eval_iridescence(top_ior, view_angle, s.params[IRIDESCENCE_THICKNESS_SLOT], b.fresnel0);
        b.fresnel0 = b.fresnel0.lerp(film, iridescence_mask);
    }
    if coat_mask > 0.0 {
        b.fresnel0 = b.fresnel0.lerp(convert_f0_for_air_interface_to_f0_for_clear_coat15(b.fresnel0), coat_mask);
        b.coat_ibl_f = f_schlick_scalar(CLEAR_COAT_F0, clamped_nv) * coat_mask;
    }
    b
}

/// The coat's Fresnel per light: F_Schlick(CLEAR_COAT_F0, LH)·coatMask (EvaluateBSDF).
pub fn coat_fresnel(lh: f64, coat_mask: f64) -> f64 {
    f_schlick_scalar(CLEAR_COAT_F0, lh) * coat_mask
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
        // With transmission every light is evaluated (IsNonZeroBSDF); its diffuse reaches through.
        let transmits = s.params[TRANSMISSION_SLOT] > 0.5;
        if nl <= 0.0 && !transmits {
            return Lobes::ZERO;
        }
        let nv = n.dot(v);
        let clamped_nv = clamp_n_dot_v(nv);
        let lv = l.dot(v);
        let inv_len = 1.0 / (2.0 * lv + 2.0).max(FLT_EPS).sqrt();
        let nh = sat((nl + nv) * inv_len);
        let lh = sat(inv_len * lv + inv_len);
        let b = hdrp_bsdf_data(s, n, nv);
        let pr = b.perceptual_roughness;
        let a_material = pr * pr;
        let a = a_material.max(min_roughness);
        let mut f = f_schlick_f90(b.fresnel0, 1.0, lh);
        if b.iridescence_mask > 0.0 {
            // The film's Fresnel is taken at NV once (GetPreLightData), not per light at LH.
            f = f.lerp(b.fresnel0, b.iridescence_mask);
        }
        let dv = if b.anisotropy != 0.0 {
            // For anisotropy the angles to T and B are not saturated (EvaluateBSDF).
            let h = (l + v) * inv_len;
            let (t, bt) = (b.tangent, b.bitangent);
            let (rt, rb) = anisotropic_roughness(a_material, b.anisotropy);
            let part_lambda_v = smith_joint_ggx_aniso_part_lambda_v(t.dot(v), bt.dot(v), clamped_nv, rt, rb);
            let (rt, rb) = (rt.max(min_roughness), rb.max(min_roughness));
            dv_smith_joint_ggx_aniso(
                t.dot(h),
                bt.dot(h),
                nh,
                clamped_nv,
                t.dot(l),
                bt.dot(l),
                nl.abs(),
                rt,
                rb,
                part_lambda_v,
            )
        } else {
            dv_smith_joint_ggx(nh, nl.abs(), clamped_nv, a, smith_joint_ggx_part_lambda_v(clamped_nv, a_material))
        };
        let mut spec = f * dv;
        let mut diffuse =
            hdrp_diffuse_color(s) * FRAC_1_PI * fd_disney_renormalized_no_pi(nl.abs(), clamped_nv, lv, pr);
        if b.coat_mask > 0.0 {
            let coat_f = coat_fresnel(lh, b.coat_mask);
            let coat_a = CLEAR_COAT_ROUGHNESS.max(min_roughness);
            let coat_part_lambda_v = smith_joint_ggx_part_lambda_v(clamped_nv, CLEAR_COAT_ROUGHNESS);
            spec = spec * (1.0 - coat_f).powi(2)
                + DVec3::splat(coat_f * dv_smith_joint_ggx(nh, nl.abs(), clamped_nv, coat_a, coat_part_lambda_v));
            diffuse *= 1.0 - coat_f * b.coat_mask;
        }
        spec *= hdrp_energy_compensation(s, &b, clamped_nv);
        // diffR·NL + diffT·transmittance, diffT at the wrapped −NL (EvaluateBSDF, ShadeSurface_Infinitesimal).
        let mut diffuse_nl = DVec3::splat(sat(nl));
        if transmits {
            diffuse_nl += compute_wrapped_diffuse_lighting(-nl, TRANSMISSION_WRAP_LIGHT) * hdrp_transmittance(s);
        }
        Lobes::split(diffuse * diffuse_nl, spec * sat(nl))
    }

    fn indirect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> Lobes {
        let nv = n.dot(v);
        let clamped_nv = clamp_n_dot_v(nv);
        let b = hdrp_bsdf_data(s, n, nv);
        let fgd = FgdTable::get().lookup(clamped_nv, b.perceptual_roughness);
        let f0 = b.fresnel0;
        let specular_fgd = (DVec3::ONE - f0) * fgd.x + f0 * fgd.y;
        let mut spec = specular_fgd * gi_s;
        if b.coat_mask > 0.0 {
            // EvaluateBSDF_Env: the base through the coat twice, the coat's mirror fetch (mip 0)
            // on top; the baked diffuse is not attenuated.
            spec = spec * (1.0 - b.coat_ibl_f).powi(2) + b.coat_ibl_f * gi_s;
        }
        Lobes::split(hdrp_diffuse_color(s) * gi_d * (fgd.z + 0.5), spec * hdrp_energy_compensation(s, &b, clamped_nv))
    }

    fn rect_lobes(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3, corners: &[DVec3; 4]) -> Option<Lobes> {
        use crate::shading::ltc::{ltc_evaluate, ltc_lookup, ortho_basis_view_normal, LtcLobe};
        let nv = n.dot(v);
        let clamped_nv = clamp_n_dot_v(nv);
        let b = hdrp_bsdf_data(s, n, nv);
        let pr = b.perceptual_roughness;
        let basis = ortho_basis_view_normal(v, n, nv);
        let ltc_diffuse = ltc_evaluate(corners, &basis, &ltc_lookup(LtcLobe::DisneyDiffuse, clamped_nv, pr));
        let ltc_specular = ltc_evaluate(corners, &basis, &ltc_lookup(LtcLobe::Ggx, clamped_nv, pr));
        let fgd = FgdTable::get().lookup(clamped_nv, pr);
        let f0 = b.fresnel0;
        let specular_fgd = (DVec3::ONE - f0) * fgd.x + f0 * fgd.y;
        let mut diffuse_ltc = DVec3::splat((fgd.z + 0.5) * ltc_diffuse);
        if s.params[TRANSMISSION_SLOT] > 0.5 {
            // Transmission: the polygon seen from −N (the frame flipped about its bitangent),
            // Lambertian, through the transmittance, without the diffuse FGD (EvaluateBSDF_Rect).
            let flip = glam::DMat3::from_diagonal(DVec3::new(-1.0, 1.0, -1.0));
            diffuse_ltc += hdrp_transmittance(s) * ltc_evaluate(corners, &basis, &flip);
        }
        let mut diffuse = hdrp_diffuse_color(s) * diffuse_ltc;
        let mut spec = specular_fgd * ltc_specular;
        if b.coat_mask > 0.0 {
            // EvaluateBSDF_Rect: both lobes × (1 − coatIblF), the coat's GGX LTC at its roughness.
            let coat_pr = CLEAR_COAT_ROUGHNESS.sqrt();
            let ltc_coat = ltc_evaluate(corners, &basis, &ltc_lookup(LtcLobe::Ggx, clamped_nv, coat_pr));
            diffuse *= 1.0 - b.coat_ibl_f;
            spec = spec * (1.0 - b.coat_ibl_f) + DVec3::splat(b.coat_ibl_f * ltc_coat);
        }
        Some(Lobes::split(diffuse, spec * hdrp_energy_compensation(s, &b, clamped_nv)))
    }

    fn env_direction(&self, _: Pipeline, s: &Surface, n: DVec3, v: DVec3) -> Option<DVec3> {
        let b = hdrp_bsdf_data(s, n, n.dot(v));
        let (ibl_r, ibl_pr) = ibl_fetch(&b, n, v);
        Some(hdrp_ibl_direction(n, ibl_r, ibl_pr, clamp_n_dot_v(n.dot(v))))
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

/// HDRP Lit's occlusion of the indirect light (forward.wgsl `indirect_light`): the factors on the
/// indirect diffuse and on the reflected environment for a material occlusion and an SSAO
/// visibility, from its BSDF data's diffuse colour and fresnel0.
pub fn indirect_occlusion(s: &Surface, nv: f64, material_ao: f64, screen_ao: f64) -> (DVec3, DVec3) {
    let nv = nv.max(1e-4);
    let roughness = (1.0 - s.smoothness).powi(2);
    let so = specular_occlusion_from_ao(nv, material_ao, roughness)
        .min(specular_occlusion_from_ao(nv, screen_ao, roughness));
    (
        gtao_multi_bounce(material_ao.min(screen_ao), model_occlusion_albedo(s)),
        gtao_multi_bounce(so, model_occlusion_fresnel0(s)),
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
        let ibl_r = 2.0 * nv * n - v;
        let r = hdrp_ibl_direction(n, ibl_r, pr, nv);
        assert!(r.dot(n) > ibl_r.dot(n), "towards N: {r} vs iblR {ibl_r}");
        // A mirror fetches along iblR itself.
        let mirror = hdrp_ibl_direction(n, ibl_r, 0.0, nv);
        assert!((mirror - ibl_r).length() < 1e-12);
    }

    #[test]
    fn the_coat_f0_fit_follows_the_ior_relation_it_fits() {
        // IorToFresnel0(Fresnel0ToIor(F0), 1.5) = ((1 − 5√F0)/(5 − √F0))², exactly.
        let exact = |f0: f64| ((1.0 - 5.0 * f0.sqrt()) / (5.0 - f0.sqrt())).powi(2);
        let mut worst: f64 = 0.0;
        for i in 0..=96 {
            let f0 = 0.04 + 0.96 * i as f64 / 96.0;
            worst =
                worst.max((convert_f0_for_air_interface_to_f0_for_clear_coat15(DVec3::splat(f0)).x - exact(f0)).abs());
        }
        // The fit's stated range: 0.04 (IOR 1.5 under IOR 1.5: nothing left) to 1.
        assert!(worst < 0.03, "{worst}");
        assert!(convert_f0_for_air_interface_to_f0_for_clear_coat15(DVec3::splat(0.04)).x < 0.002);
    }

    #[test]
    fn a_coat_roughens_the_base_and_mask_zero_leaves_the_surface() {
        for pr in [0.05, 0.3, 0.6, 0.95] {
            assert!((clear_coat_perceptual_roughness(pr, 0.0) - pr).abs() < 1e-12, "{pr}");
            let coated = clear_coat_perceptual_roughness(pr, 1.0);
            assert!(coated > pr && coated <= 1.0, "{pr} → {coated}");
        }
        // A fully rough base stays fully rough: variance 0 scales to 0.
        assert!((clear_coat_perceptual_roughness(1.0, 1.0) - 1.0).abs() < 1e-12);
        let mut s = Surface::basic(DVec3::new(0.9, 0.5, 0.2), 0.5, 0.6);
        s.params[0] = 1.0;
        let plain = hdrp_bsdf_data(&s, DVec3::Y, 0.7);
        s.params[IRIDESCENCE_THICKNESS_SLOT] = 0.3;
        let masked = hdrp_bsdf_data(&s, DVec3::Y, 0.7);
        assert_eq!((plain.fresnel0, plain.perceptual_roughness), (masked.fresnel0, masked.perceptual_roughness));
        assert_eq!(plain.coat_ibl_f, 0.0);
    }

    #[test]
    fn an_index_matched_film_leaves_the_base_and_total_reflection_gives_one() {
        // Thickness 1: the film's IOR is lerp(2, 1, 1) = 1, the air's; head-on Schlick gives R12 = 0
        // and only the two Airy terms are left, each |Cm|·√R123·|Sm| with R123 clamped to 1e-5 from
        // below: F0 within 2·√1e-5·max|Sm| < 0.01.
        let f0 = DVec3::new(0.04, 0.5, 0.9);
        let i = eval_iridescence(1.0, 1.0, 1.0, f0);
        assert!((i - f0).abs().max_element() < 0.01, "{i} vs {f0}");
        // From IOR 1.5 above into a film of IOR 1.2 at grazing incidence: total internal reflection.
        assert_eq!(eval_iridescence(1.5, 0.1, 0.8, f0), DVec3::ONE);
        // At zero path difference the sensitivity is the matching functions' integrals, normalised
        // so that Y is 1: illuminant E's white, luminance 1 in Rec. 709.
        let white = eval_sensitivity(0.0, 0.0);
        let y = crate::color::luminance([white.x, white.y, white.z]);
        assert!((y - 1.0).abs() < 1e-3, "{white}: luminance {y}");
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
