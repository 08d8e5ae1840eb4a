// HDRP Lit (models.md#hdrp-lit): renormalised Disney diffuse, height-correlated Smith GGX (DV_SmithJointGGX),
// F_Schlick with F90 = 1, GGX energy compensation from the pre-integrated FGD table (fgd_lookup,
// computed by the tool). params0.x: energy compensation on (1, default) or off (0); params0.y: the
// Specular Color material type (1) or Standard (0, default); params0.z: the coat mask (clear coat
// on above 0); params0.w: the iridescence mask (the Iridescence material type above 0); params1.x:
// the iridescence thickness (HDRP's _IridescenceThickness, 0–1, default 1); params1.y: the anisotropy
// (the Anisotropy material type where it is not 0; −1..1 along the tangent); params2.x: the
// Translucent material type (transmission, 1) or not (0); params2.y: its thickness (_Thickness, 0–1);
// params1.z: the Subsurface Scattering material type (1) or not (0); params1.w: its _SubsurfaceMask
// (read by the filter, plan::subsurface).
// Physical units: E in lux, radiance = f·E·NL.

const HDRP_FLT_EPS: f32 = 5.960464478e-8;
const HDRP_REAL_MIN: f32 = 1.175494351e-38;

// F0·(1 − x⁵) + F90·x⁵, x = 1 − LH
fn f_schlick_f90(f0: vec3<f32>, f90: f32, lh: f32) -> vec3<f32> {
    let x5 = pow5(1.0 - lh);
    return f0 * (1.0 - x5) + vec3<f32>(f90 * x5);
}

// GetSmithJointGGXPartLambdaV: √((−NV·α² + NV)·NV + α²), from the material's roughness before the per-light clamp (Lit.hlsl)
fn smith_joint_ggx_part_lambda_v(nv: f32, a: f32) -> f32 {
    let a2 = a * a;
    return sqrt((-nv * a2 + nv) * nv + a2);
}

// (1/π)·0.5·α²/max(s²(λV + λL), REAL_MIN), s = (NH·α² − NH)·NH + 1, λV = NL·partLambdaV, λL = NV·√((−NL·α² + NL)·NL + α²)
fn dv_smith_joint_ggx(nh: f32, nl: f32, nv: f32, a: f32, part_lambda_v: f32) -> f32 {
    let a2 = a * a;
    let s = (nh * a2 - nh) * nh + 1.0;
    let lambda_v = nl * part_lambda_v;
    let lambda_l = nv * sqrt((-nl * a2 + nl) * nl + a2);
    return INV_PI * 0.5 * a2 / max(s * s * (lambda_v + lambda_l), HDRP_REAL_MIN);
}

// (1/1.03571)(1 + (fd90−1)(1−NL)⁵)(1 + (fd90−1)(1−NV)⁵), fd90 = 0.5 + pr + pr·LV, no 1/π
fn fd_disney_renormalized_no_pi(nl: f32, nv: f32, lv: f32, pr: f32) -> f32 {
    let fd90 = 0.5 + pr + pr * lv;
    return (1.0 / 1.03571) * (1.0 + (fd90 - 1.0) * pow5(1.0 - nl)) * (1.0 + (fd90 - 1.0) * pow5(1.0 - nv));
}

// ClampNdotV: max(NV, 1e-4). HDRP Lit keeps N as is (no GetViewReflectedNormal).
fn clamp_n_dot_v(nv: f32) -> f32 {
    return max(nv, 1e-4);
}

// fresnel0: ComputeFresnel0(baseColor, metallic, 0.04), or the specular colour for the Specular
// Color material type (params0.y = 1; Lit.hlsl ConvertSurfaceDataToBSDFData)
fn hdrp_f0(s: Surface) -> vec3<f32> {
    if (s.params2.x > 0.5 || s.params1.z > 0.5) {
        // FillMaterialTransmission, FillMaterialSSS: the diffusion profile's F0
        return vec3<f32>(DIFFUSION_PROFILE_FRESNEL0);
    }
    if (s.params0.y > 0.5) {
        return s.specular;
    }
    return mix(vec3<f32>(0.04), s.base_color, s.metallic);
}

// diffuseColor: baseColor·(1 − metallic), or for Specular Color with its default Energy Conserving
// Specular Color, baseColor·(1 − max(specularColor)) (LitData.hlsl _ENERGY_CONSERVING_SPECULAR)
// × diffuse_weight: a transparent surface's ApplyBlendMode multiplies the diffuse lighting by
// opacity and keeps the specular (_EnableBlendModePreserveSpecularLighting, Material.hlsl).
fn hdrp_diffuse_color(s: Surface) -> vec3<f32> {
    if (SUBSURFACE_PRE_SCATTER == 1u && s.params1.z > 0.5) {
        // GetModifiedDiffuseColorForSSS: PreAndPostScatter's √albedo where the lighting is split
        return sqrt(s.base_color) * diffuse_weight;
    }
    if (s.params2.x > 0.5 || s.params1.z > 0.5) {
        // There is no metallic with SSS or transmission (ConvertSurfaceDataToBSDFData)
        return s.base_color * diffuse_weight;
    }
    if (s.params0.y > 0.5) {
        return s.base_color * (1.0 - max(max(s.specular.r, s.specular.g), s.specular.b)) * diffuse_weight;
    }
    return s.base_color * (1.0 - s.metallic) * diffuse_weight;
}

// bsdfData.diffuseColor and fresnel0 as HDRP's ambient-occlusion multi-bounce reads them (Lit.hlsl
// PostEvaluateBSDF, GetScreenSpaceAmbientOcclusionMultibounce): the diffuse colour before the
// blend's opacity and the split lighting's √albedo
fn model_occlusion_albedo(s: Surface) -> vec3<f32> {
    if (s.params2.x > 0.5 || s.params1.z > 0.5) {
        return s.base_color;
    }
    if (s.params0.y > 0.5) {
        return s.base_color * (1.0 - max(max(s.specular.r, s.specular.g), s.specular.b));
    }
    return s.base_color * (1.0 - s.metallic);
}

fn model_occlusion_fresnel0(s: Surface) -> vec3<f32> {
    return hdrp_f0(s);
}

// Specular multiplier 1 + F0·(1/y − 1), y = reflectivity from the FGD table at the material's perceptual
// roughness, F0 the fresnel0 its features left (models.md#hdrp-lit; PostEvaluateBSDF)
fn hdrp_energy_compensation(s: Surface, b: HdrpBsdfData, clamped_nv: f32) -> vec3<f32> {
    if (s.params0.x < 0.5) {
        return vec3<f32>(1.0);
    }
    let y = fgd_lookup(clamped_nv, b.perceptual_roughness).y;
    return vec3<f32>(1.0) + b.fresnel0 * (1.0 / y - 1.0);
}

// HDRP's default diffusion profile (DiffusionProfileSettings.cs ResetToDefault): scattering distance
// 0.5 (grey) × 1, so shape parameter S = 1/0.5 per mm; transmission tint white, premultiplied by
// 1/4; thickness remap 0–5 mm; IOR 1.4, F0 = ((1.4 − 1)/(1.4 + 1))²; Thin Object transmission
const DIFFUSION_PROFILE_SHAPE: f32 = 2.0;
const DIFFUSION_PROFILE_TINT: f32 = 0.25;
const DIFFUSION_PROFILE_THICKNESS_MM: f32 = 5.0;
const DIFFUSION_PROFILE_FRESNEL0: f32 = 0.027777778;
// TRANSMISSION_WRAP_LIGHT: cos(π/2 − π/12) (SubsurfaceScattering.hlsl)
const TRANSMISSION_WRAP_LIGHT: f32 = 0.25881904;

// ComputeWrappedDiffuseLighting (core CommonLighting.hlsl): sat((NL + w)/(1 + w)²)
fn compute_wrapped_diffuse_lighting(nl: f32, w: f32) -> f32 {
    return sat((nl + w) / ((1.0 + w) * (1.0 + w)));
}

// ComputeTransmittanceDisney (DiffusionProfile.hlsl): A·e^(−S·t/3)·(e^(−2S·t/3) + 3), A the tint
// premultiplied by 1/4: the transmittance of a slab t mm thick under the Burley profile
fn compute_transmittance_disney(shape: vec3<f32>, volume_albedo: vec3<f32>, thickness: f32) -> vec3<f32> {
    let exp_13 = exp2(((LOG2_E * (-1.0 / 3.0)) * thickness) * shape);
    return volume_albedo * (exp_13 * (exp_13 * exp_13 + 3.0));
}

// The Translucent type reads the ambient at −N (the pass evaluates it only where a model asks)
fn model_back_ambient(s: Surface) -> bool {
    return s.params2.x > 0.5;
}

// FillMaterialTransmission with the default profile: thickness remap.x + remap.y·_Thickness (mm)
fn hdrp_transmittance(s: Surface) -> vec3<f32> {
    let thickness = DIFFUSION_PROFILE_THICKNESS_MM * s.params2.y;
    return compute_transmittance_disney(vec3<f32>(DIFFUSION_PROFILE_SHAPE), vec3<f32>(DIFFUSION_PROFILE_TINT), thickness);
}

// The clear coat (core CommonMaterial.hlsl): IOR 1.5, F0 = IorToFresnel0(1.5), GGX roughness 0.01
const CLEAR_COAT_IOR: f32 = 1.5;
const CLEAR_COAT_F0: f32 = 0.04;
const CLEAR_COAT_ROUGHNESS: f32 = 0.01;

// (1 − F0)·x⁵ + F0, x = 1 − u: F_Schlick for a scalar F0, F90 = 1 (core BSDF.hlsl)
fn f_schlick_scalar(f0: f32, u: f32) -> f32 {
    return (1.0 - f0) * pow5(1.0 - u) + f0;
}

// RoughnessToVariance: 2/α² − 2 (CommonMaterial.hlsl)
fn roughness_to_variance(a: f32) -> f32 {
    return 2.0 / (a * a) - 2.0;
}

// VarianceToRoughness: √(2/(σ + 2)) (CommonMaterial.hlsl)
fn variance_to_roughness(variance: f32) -> f32 {
    return sqrt(2.0 / (variance + 2.0));
}

// FillMaterialClearCoatData: √VarianceToRoughness(RoughnessToVariance(pr²)·ieta²), ieta = lerp(1, 1/1.5, mask)
fn clear_coat_perceptual_roughness(pr: f32, coat_mask: f32) -> f32 {
    let ieta = 1.0 + (1.0 / CLEAR_COAT_IOR - 1.0) * coat_mask;
    return sqrt(variance_to_roughness(roughness_to_variance(pr * pr) * ieta * ieta));
}

// ConvertF0ForAirInterfaceToF0ForClearCoat15: sat(−0.0256868 + F0·(0.326846 + (0.978946 − 0.283835·F0)·F0)) (core BSDF.hlsl)
fn convert_f0_for_air_interface_to_f0_for_clear_coat15(f0: vec3<f32>) -> vec3<f32> {
    return sat3(vec3<f32>(-0.0256868) + f0 * (vec3<f32>(0.326846) + (vec3<f32>(0.978946) - 0.283835 * f0) * f0));
}

// EvalSensitivity (Belcour & Barla 2017, core BSDF.hlsl): XYZ matching Gaussians in Fourier space at OPD (µm), in linear Rec. 709
fn eval_sensitivity(opd: f32, shift: f32) -> vec3<f32> {
    let phase = 2.0 * PI * opd * 1e-6;
    let val = vec3<f32>(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let pos = vec3<f32>(1.6810e+06, 1.7953e+06, 2.2084e+06);
    let var_ = vec3<f32>(4.3278e+09, 9.3046e+09, 6.6121e+09);
    var xyz = val * sqrt(2.0 * PI * var_) * cos(pos * phase + vec3<f32>(shift)) * exp(-var_ * phase * phase);
    xyz.x += 9.7470e-14 * sqrt(2.0 * PI * 4.5282e+09) * cos(2.2399e+06 * phase + shift) * exp(-4.5282e+09 * phase * phase);
    xyz /= 1.0685e-7;
    // XYZ_2_REC709_MAT (core Color.hlsl), by rows
    return vec3<f32>(
        dot(vec3<f32>(3.2409699419, -1.5373831776, -0.4986107603), xyz),
        dot(vec3<f32>(-0.9692436363, 1.8759675015, 0.0415550574), xyz),
        dot(vec3<f32>(0.0556300797, -0.2039769589, 1.0569715142), xyz),
    );
}

// EvalIridescence (core BSDF.hlsl): a film of optical thickness 3·t µm and IOR lerp(2, 1, t) under IOR eta_1,
// over F0; Schlick at both interfaces, the Airy sum to m = 2, clamped at 0; 1 under total internal reflection
fn eval_iridescence(eta_1: f32, cos_theta1: f32, thickness: f32, f0: vec3<f32>) -> vec3<f32> {
    let d_inc = 3.0 * thickness;
    let eta_2 = 2.0 + (1.0 - 2.0) * thickness;
    let ratio = eta_1 / eta_2;
    let sin_theta2_sq = ratio * ratio * (1.0 - cos_theta1 * cos_theta1);
    let cos_theta2_sq = 1.0 - sin_theta2_sq;
    if (cos_theta2_sq < 0.0) {
        return vec3<f32>(1.0);
    }
    let cos_theta2 = sqrt(cos_theta2_sq);
    let r0_ratio = (eta_2 - eta_1) / (eta_2 + eta_1);
    let r12 = f_schlick_scalar(r0_ratio * r0_ratio, cos_theta1);
    let t121 = 1.0 - r12;
    let phi = PI;
    let r23 = f_schlick_f90(f0, 1.0, cos_theta2);
    let opd = d_inc * cos_theta2;
    let r123 = clamp(r12 * r23, vec3<f32>(1e-5), vec3<f32>(0.9999));
    let r123_sqrt = sqrt(r123);
    let rs = t121 * t121 * r23 / (vec3<f32>(1.0) - r123);
    var i = vec3<f32>(r12) + rs;
    var cm = rs - vec3<f32>(t121);
    for (var m = 1; m <= 2; m++) {
        cm *= r123_sqrt;
        let sm = 2.0 * eval_sensitivity(f32(m) * opd, f32(m) * phi);
        i += cm * sm;
    }
    return max(i, vec3<f32>(0.0));
}

// BSDFData after the material features, with the PreLightData terms they set (Lit.hlsl
// ConvertSurfaceDataToBSDFData, FillMaterialClearCoatData, GetPreLightData)
struct HdrpBsdfData {
    // fresnel0 after iridescence, then the coat, changed it
    fresnel0: vec3<f32>,
    // perceptualRoughness after the coat's: the FGD, LTC and diffuse read it
    perceptual_roughness: f32,
    coat_mask: f32,
    // coatIblF = F_Schlick(CLEAR_COAT_F0, clampedNdotV)·coatMask
    coat_ibl_f: f32,
    iridescence_mask: f32,
    anisotropy: f32,
    // The tangent frame: the surface's tangent made orthonormal to N (GetLocalFrame's where there is
    // none), bitangent = N × T (FillMaterialAnisotropy)
    tangent: vec3<f32>,
    bitangent: vec3<f32>,
};

// Orthonormalize(T, N), or GetLocalFrame(N)'s x where the mesh has no tangent
fn hdrp_tangent(t: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let t_raw = t - n * dot(n, t);
    if (dot(t_raw, t_raw) < 1e-12) {
        return local_frame(n)[0];
    }
    return normalize(t_raw);
}

// A feature is on where its mask is above 0 (the inspector compiles _MATERIAL_FEATURE_CLEAR_COAT so);
// at mask 0 the surface is left as it is
fn hdrp_bsdf_data(s: Surface, n: vec3<f32>, nv: f32) -> HdrpBsdfData {
    let clamped_nv = clamp_n_dot_v(nv);
    let coat_mask = s.params0.z;
    let iridescence_mask = s.params0.w;
    var b: HdrpBsdfData;
    b.fresnel0 = hdrp_f0(s);
    b.perceptual_roughness = 1.0 - s.smoothness;
    b.coat_mask = coat_mask;
    b.coat_ibl_f = 0.0;
    b.iridescence_mask = iridescence_mask;
    b.anisotropy = s.params1.y;
    if (b.anisotropy != 0.0) {
        b.tangent = hdrp_tangent(s.tangent, n);
        b.bitangent = cross(n, b.tangent);
    }
    if (coat_mask > 0.0) {
        b.perceptual_roughness = clear_coat_perceptual_roughness(b.perceptual_roughness, coat_mask);
    }
    if (iridescence_mask > 0.0) {
        // Under the coat the film sees the view direction refracted into IOR lerp(1, 1.5, mask)
        var top_ior = 1.0;
        var view_angle = clamped_nv;
        if (coat_mask > 0.0) {
            top_ior = 1.0 + (CLEAR_COAT_IOR - 1.0) * coat_mask;
            view_angle = sqrt(1.0 + (1.0 / top_ior) * (1.0 / top_ior) * (nv * nv - 1.0));
        }
        let film = eval_iridescence(top_ior, view_angle, s.params1.x, b.fresnel0);
        b.fresnel0 = mix(b.fresnel0, film, iridescence_mask);
    }
    if (coat_mask > 0.0) {
        b.fresnel0 = mix(b.fresnel0, convert_f0_for_air_interface_to_f0_for_clear_coat15(b.fresnel0), coat_mask);
        b.coat_ibl_f = f_schlick_scalar(CLEAR_COAT_F0, clamped_nv) * coat_mask;
    }
    return b;
}

// ConvertAnisotropyToRoughness: αT = α(1 + anisotropy), αB = α(1 − anisotropy) (Imageworks' parametrisation)
fn anisotropic_roughness(a: f32, anisotropy: f32) -> vec2<f32> {
    return vec2<f32>(a * (1.0 + anisotropy), a * (1.0 - anisotropy));
}

// GetSmithJointGGXAnisoPartLambdaV: |(αT·TV, αB·BV, NV)|
fn smith_joint_ggx_aniso_part_lambda_v(tv: f32, bv: f32, nv: f32, rt: f32, rb: f32) -> f32 {
    return length(vec3<f32>(rt * tv, rb * bv, nv));
}

// DV_SmithJointGGXAniso: (1/π)·0.5·a2³/max(s²(λV + λL), REAL_MIN), a2 = αT·αB, s = |(αB·TH, αT·BH, a2·NH)|²,
// λV = NL·partLambdaV, λL = NV·|(αT·TL, αB·BL, NL)| (core BSDF.hlsl)
fn dv_smith_joint_ggx_aniso(th: f32, bh: f32, nh: f32, nv: f32, tl: f32, bl: f32, nl: f32, rt: f32, rb: f32, part_lambda_v: f32) -> f32 {
    let a2 = rt * rb;
    let w = vec3<f32>(rb * th, rt * bh, a2 * nh);
    let s = dot(w, w);
    let lambda_v = nl * part_lambda_v;
    let lambda_l = nv * length(vec3<f32>(rt * tl, rb * bl, nl));
    return INV_PI * 0.5 * (a2 * a2 * a2) / max(s * s * (lambda_v + lambda_l), HDRP_REAL_MIN);
}

// GetGGXAnisotropicModifiedNormalAndRoughness (core ImageBasedLighting.hlsl): the normal bent towards
// the grain's view-facing normal normalize(V − (V·g)g) by |anisotropy|·sat(1.5√pr), g the bitangent
// for anisotropy ≥ 0 (the tangent else); returns iblR = reflect(−V, iblN)
fn anisotropic_ibl_reflection(b: HdrpBsdfData, n: vec3<f32>, v: vec3<f32>, pr: f32) -> vec3<f32> {
    let grain = select(b.tangent, b.bitangent, b.anisotropy >= 0.0);
    let stretch = abs(b.anisotropy) * sat(1.5 * sqrt(pr));
    let grain_normal = normalize(v - dot(v, grain) * grain);
    let ibl_n = normalize(mix(n, grain_normal, stretch));
    return reflect(-v, ibl_n);
}

// F_Schlick(CLEAR_COAT_F0, LH)·coatMask: the coat's Fresnel per light (EvaluateBSDF)
fn coat_fresnel(lh: f32, coat_mask: f32) -> f32 {
    return f_schlick_scalar(CLEAR_COAT_F0, lh) * coat_mask;
}

// GetSpecularDominantDir (Frostbite, p. 69): a = 1 − pr², lerp(N, R, (√a + pr²)·sat(a² + lerp(0, a, NV²)))
fn get_specular_dominant_dir(n: vec3<f32>, r: vec3<f32>, pr: f32, clamped_nv: f32) -> vec3<f32> {
    let a = 1.0 - pr * pr;
    let lerp_factor = (sqrt(a) + pr * pr) * sat(a * a + mix(0.0, a, clamped_nv * clamped_nv));
    return mix(n, r, lerp_factor);
}

// EvaluateBSDF_Env's fetch direction: the dominant direction, lerped back to iblR by sat(smoothstep(0, 1, α²));
// normalised here because the probe is an equirectangular map (a cubemap fetch ignores the length)
fn hdrp_ibl_direction(n: vec3<f32>, ibl_r: vec3<f32>, pr: f32, clamped_nv: f32) -> vec3<f32> {
    let a = pr * pr;
    let r = mix(get_specular_dominant_dir(n, ibl_r, pr, clamped_nv), ibl_r, sat(smoothstep(0.0, 1.0, a * a)));
    return r * inverseSqrt(max(dot(r, r), HDRP_FLT_EPS));
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = dot(n, l);
    // With transmission every light is evaluated (IsNonZeroBSDF); its diffuse reaches through
    let transmits = s.params2.x > 0.5;
    if (nl <= 0.0 && !transmits) {
        return vec3<f32>(0.0);
    }
    // GetBSDFAngle takes the unclamped NV; V, FGD and the diffuse take ClampNdotV
    let nv = dot(n, v);
    let clamped_nv = clamp_n_dot_v(nv);
    let lv = dot(l, v);
    let inv_len = inverseSqrt(max(2.0 * lv + 2.0, HDRP_FLT_EPS));
    let nh = sat((nl + nv) * inv_len);
    let lh = sat(inv_len * lv + inv_len);
    let b = hdrp_bsdf_data(s, n, nv);
    let pr = b.perceptual_roughness;
    let a_material = pr * pr;
    let a = max(a_material, light_min_roughness);
    var f = f_schlick_f90(b.fresnel0, 1.0, lh);
    if (b.iridescence_mask > 0.0) {
        // The film's Fresnel is taken at NV once (GetPreLightData), not per light at LH
        f = mix(f, b.fresnel0, b.iridescence_mask);
    }
    var dv: f32;
    if (b.anisotropy != 0.0) {
        // For anisotropy the angles to T and B are not saturated (EvaluateBSDF)
        let h = (l + v) * inv_len;
        let r = anisotropic_roughness(a_material, b.anisotropy);
        let part_lambda_v = smith_joint_ggx_aniso_part_lambda_v(dot(b.tangent, v), dot(b.bitangent, v), clamped_nv, r.x, r.y);
        let rl = max(r, vec2<f32>(light_min_roughness));
        dv = dv_smith_joint_ggx_aniso(dot(b.tangent, h), dot(b.bitangent, h), nh, clamped_nv, dot(b.tangent, l), dot(b.bitangent, l), abs(nl), rl.x, rl.y, part_lambda_v);
    } else {
        dv = dv_smith_joint_ggx(nh, abs(nl), clamped_nv, a, smith_joint_ggx_part_lambda_v(clamped_nv, a_material));
    }
    var spec = f * dv;
    var diffuse = hdrp_diffuse_color(s) * INV_PI * fd_disney_renormalized_no_pi(abs(nl), clamped_nv, lv, pr);
    if (b.coat_mask > 0.0) {
        let coat_f = coat_fresnel(lh, b.coat_mask);
        let coat_a = max(CLEAR_COAT_ROUGHNESS, light_min_roughness);
        let coat_part_lambda_v = smith_joint_ggx_part_lambda_v(clamped_nv, CLEAR_COAT_ROUGHNESS);
        spec = spec * ((1.0 - coat_f) * (1.0 - coat_f))
            + vec3<f32>(coat_f * dv_smith_joint_ggx(nh, abs(nl), clamped_nv, coat_a, coat_part_lambda_v));
        diffuse *= 1.0 - coat_f * b.coat_mask;
    }
    spec *= hdrp_energy_compensation(s, b, clamped_nv);
    // diffR·NL + diffT·transmittance, diffT the diffuse term at the wrapped −NL (EvaluateBSDF,
    // ShadeSurface_Infinitesimal)
    var diffuse_nl = vec3<f32>(sat(nl));
    if (transmits) {
        diffuse_nl += compute_wrapped_diffuse_lighting(-nl, TRANSMISSION_WRAP_LIGHT) * hdrp_transmittance(s);
    }
    return direct_diffuse(diffuse * diffuse_nl) + direct_specular(spec * sat(nl));
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let nv = dot(n, v);
    let clamped_nv = clamp_n_dot_v(nv);
    let b = hdrp_bsdf_data(s, n, nv);
    let pr = b.perceptual_roughness;
    let fgd = fgd_lookup(clamped_nv, pr);
    let f0 = b.fresnel0;
    // specularFGD = (F90 − F0)·x + F0·y; diffuseFGD = z + 0.5 (the table stores z − 0.5)
    let specular_fgd = (vec3<f32>(1.0) - f0) * fgd.x + f0 * fgd.y;
    let diffuse_fgd = fgd.z + 0.5;
    var coat = vec3<f32>(0.0);
    if (b.coat_mask > 0.0) {
        // EvaluateBSDF_Env: the coat's mirror fetch along reflect(−V, N) at mip 0, fetched before the
        // base's so that the probe pass records the base's direction
        coat = b.coat_ibl_f * env_specular(reflect(-v, n), 0.0);
    }
    // The FGD takes the roughness before anisotropy narrows it; the fetch after (GetPreLightData)
    var ibl_r = reflect(-v, n);
    var ibl_pr = pr;
    if (b.anisotropy != 0.0) {
        ibl_r = anisotropic_ibl_reflection(b, n, v, pr);
        ibl_pr = pr * sat(1.2 - abs(b.anisotropy));
    }
    var spec = specular_fgd * env_specular(hdrp_ibl_direction(n, ibl_r, ibl_pr, clamped_nv), ibl_pr);
    if (b.coat_mask > 0.0) {
        // The base through the coat twice; the baked diffuse is not attenuated
        spec = spec * ((1.0 - b.coat_ibl_f) * (1.0 - b.coat_ibl_f)) + coat;
    }
    // ModifyBakedDiffuseLighting: the light baked at −N through the transmittance joins the baked diffuse
    var baked = gi_diffuse;
    if (s.params2.x > 0.5) {
        baked += gi_back_diffuse * hdrp_transmittance(s);
    }
    return indirect_diffuse(hdrp_diffuse_color(s) * baked * diffuse_fgd)
        + indirect_specular(spec * hdrp_energy_compensation(s, b, clamped_nv));
}

// The LTC tables below the FGD table (`fgd_lut`, declared by the pass)
fn ltc_lookup(row: i32, clamped_nv: f32, pr: f32) -> mat3x3<f32> {
    return ltc_sample(fgd_lut, row, clamped_nv, pr);
}

// EvaluateBSDF_Rect: the corners (relative to the shaded point) in the view–normal frame through the
// Disney-diffuse and GGX inverse LTCs, each PolygonIrradiance times its FGD magnitude
// (diffuseFGD; specularFGD with the energy compensation PostEvaluateBSDF applies); per unit luminance
fn model_rect(s: Surface, n: vec3<f32>, v: vec3<f32>, corners: array<vec3<f32>, 4>) -> vec3<f32> {
    let nv = dot(n, v);
    let clamped_nv = clamp_n_dot_v(nv);
    let b = hdrp_bsdf_data(s, n, nv);
    let pr = b.perceptual_roughness;
    let basis = ortho_basis_view_normal(v, n, nv);
    let ltc_diffuse = polygon_irradiance(polygon_form_factor(ltc_transform(corners, ltc_lookup(LTC_DISNEY_ROW, clamped_nv, pr) * basis)));
    let ltc_specular = polygon_irradiance(polygon_form_factor(ltc_transform(corners, ltc_lookup(LTC_GGX_ROW, clamped_nv, pr) * basis)));
    let fgd = fgd_lookup(clamped_nv, pr);
    let f0 = b.fresnel0;
    let specular_fgd = (vec3<f32>(1.0) - f0) * fgd.x + f0 * fgd.y;
    let diffuse_fgd = fgd.z + 0.5;
    var diffuse_ltc = vec3<f32>(diffuse_fgd * ltc_diffuse);
    if (s.params2.x > 0.5) {
        // Transmission: the polygon seen from −N (the frame flipped about its bitangent), Lambertian,
        // through the transmittance, without the diffuse FGD (EvaluateBSDF_Rect)
        let flip = mat3x3<f32>(vec3<f32>(-1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, -1.0));
        let ltc_back = polygon_irradiance(polygon_form_factor(ltc_transform(corners, flip * basis)));
        diffuse_ltc = diffuse_ltc + hdrp_transmittance(s) * ltc_back;
    }
    var diffuse = hdrp_diffuse_color(s) * diffuse_ltc;
    var spec = specular_fgd * ltc_specular;
    if (b.coat_mask > 0.0) {
        // EvaluateBSDF_Rect: both lobes × (1 − coatIblF), the coat's GGX LTC at its own roughness
        let coat_pr = sqrt(CLEAR_COAT_ROUGHNESS);
        let ltc_coat = polygon_irradiance(polygon_form_factor(ltc_transform(corners, ltc_lookup(LTC_GGX_ROW, clamped_nv, coat_pr) * basis)));
        diffuse *= 1.0 - b.coat_ibl_f;
        spec = spec * (1.0 - b.coat_ibl_f) + vec3<f32>(b.coat_ibl_f * ltc_coat);
    }
    return direct_diffuse(diffuse) + direct_specular(spec * hdrp_energy_compensation(s, b, clamped_nv));
}

// The detail map on (the `detail` parameter, slot 10): the passes overlay it on the base colour and
// blend its normal as LitDataIndividualLayer.hlsl does (materials::detail)
fn model_detail(params0: vec4<f32>, params1: vec4<f32>, params2: vec4<f32>) -> f32 {
    return params2.z;
}
