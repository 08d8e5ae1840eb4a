// HDRP Lit (models.md#hdrp-lit): renormalised Disney diffuse, height-correlated Smith GGX (DV_SmithJointGGX),
// F_Schlick with F90 = 1, GGX energy compensation from the pre-integrated FGD table (fgd_lookup,
// computed by the tool). params0.x: energy compensation on (1, default) or off (0); params0.y: the
// Specular Color material type (1) or Standard (0, default).
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
    if (s.params0.y > 0.5) {
        return s.base_color * (1.0 - max(max(s.specular.r, s.specular.g), s.specular.b)) * diffuse_weight;
    }
    return s.base_color * (1.0 - s.metallic) * diffuse_weight;
}

// Specular multiplier 1 + F0·(1/y − 1), y = reflectivity from the FGD table (models.md#hdrp-lit)
fn hdrp_energy_compensation(s: Surface, clamped_nv: f32) -> vec3<f32> {
    if (s.params0.x < 0.5) {
        return vec3<f32>(1.0);
    }
    let y = fgd_lookup(clamped_nv, 1.0 - s.smoothness).y;
    return vec3<f32>(1.0) + hdrp_f0(s) * (1.0 / y - 1.0);
}

// GetSpecularDominantDir (Frostbite, p. 69): a = 1 − pr², lerp(N, R, (√a + pr²)·sat(a² + lerp(0, a, NV²)))
fn get_specular_dominant_dir(n: vec3<f32>, r: vec3<f32>, pr: f32, clamped_nv: f32) -> vec3<f32> {
    let a = 1.0 - pr * pr;
    let lerp_factor = (sqrt(a) + pr * pr) * sat(a * a + mix(0.0, a, clamped_nv * clamped_nv));
    return mix(n, r, lerp_factor);
}

// EvaluateBSDF_Env's fetch direction: the dominant direction, lerped back to iblR by sat(smoothstep(0, 1, α²));
// normalised here because the probe is an equirectangular map (a cubemap fetch ignores the length)
fn hdrp_ibl_direction(n: vec3<f32>, v: vec3<f32>, pr: f32, clamped_nv: f32) -> vec3<f32> {
    let ibl_r = reflect(-v, n);
    let a = pr * pr;
    let r = mix(get_specular_dominant_dir(n, ibl_r, pr, clamped_nv), ibl_r, sat(smoothstep(0.0, 1.0, a * a)));
    return r * inverseSqrt(max(dot(r, r), HDRP_FLT_EPS));
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = dot(n, l);
    if (nl <= 0.0) {
        return vec3<f32>(0.0);
    }
    // GetBSDFAngle takes the unclamped NV; V, FGD and the diffuse take ClampNdotV
    let nv = dot(n, v);
    let clamped_nv = clamp_n_dot_v(nv);
    let lv = dot(l, v);
    let inv_len = inverseSqrt(max(2.0 * lv + 2.0, HDRP_FLT_EPS));
    let nh = sat((nl + nv) * inv_len);
    let lh = sat(inv_len * lv + inv_len);
    let pr = 1.0 - s.smoothness;
    let a_material = pr * pr;
    let a = max(a_material, light_min_roughness);
    let f0 = hdrp_f0(s);
    let part_lambda_v = smith_joint_ggx_part_lambda_v(clamped_nv, a_material);
    let dv = dv_smith_joint_ggx(nh, abs(nl), clamped_nv, a, part_lambda_v);
    let spec = f_schlick_f90(f0, 1.0, lh) * dv * hdrp_energy_compensation(s, clamped_nv);
    let diffuse = hdrp_diffuse_color(s) * INV_PI * fd_disney_renormalized_no_pi(abs(nl), clamped_nv, lv, pr);
    return direct_diffuse(diffuse * sat(nl)) + direct_specular(spec * sat(nl));
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let clamped_nv = clamp_n_dot_v(dot(n, v));
    let pr = 1.0 - s.smoothness;
    let fgd = fgd_lookup(clamped_nv, pr);
    let f0 = hdrp_f0(s);
    // specularFGD = (F90 − F0)·x + F0·y; diffuseFGD = z + 0.5 (the table stores z − 0.5)
    let specular_fgd = (vec3<f32>(1.0) - f0) * fgd.x + f0 * fgd.y;
    let diffuse_fgd = fgd.z + 0.5;
    let env = env_specular(hdrp_ibl_direction(n, v, pr, clamped_nv), pr);
    return indirect_diffuse(hdrp_diffuse_color(s) * gi_diffuse * diffuse_fgd)
        + indirect_specular(specular_fgd * env * hdrp_energy_compensation(s, clamped_nv));
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
    let pr = 1.0 - s.smoothness;
    let basis = ortho_basis_view_normal(v, n, nv);
    let ltc_diffuse = polygon_irradiance(polygon_form_factor(ltc_transform(corners, ltc_lookup(LTC_DISNEY_ROW, clamped_nv, pr) * basis)));
    let ltc_specular = polygon_irradiance(polygon_form_factor(ltc_transform(corners, ltc_lookup(LTC_GGX_ROW, clamped_nv, pr) * basis)));
    let fgd = fgd_lookup(clamped_nv, pr);
    let f0 = hdrp_f0(s);
    let specular_fgd = (vec3<f32>(1.0) - f0) * fgd.x + f0 * fgd.y;
    let diffuse_fgd = fgd.z + 0.5;
    return direct_diffuse(hdrp_diffuse_color(s) * diffuse_fgd * ltc_diffuse)
        + direct_specular(specular_fgd * ltc_specular * hdrp_energy_compensation(s, clamped_nv));
}
