// HDRP Lit (models.md#hdrp-lit): renormalised Disney diffuse, height-correlated Smith GGX (DV_SmithJointGGX),
// F_Schlick with F90 = 1, GGX energy compensation from the pre-integrated FGD table (fgd_lookup,
// computed by the tool). params0.x: energy compensation on (1, default) or off (0).
// Physical units: E in lux, radiance = f·E·NL.

const HDRP_FLT_EPS: f32 = 5.960464478e-8;
const HDRP_REAL_MIN: f32 = 1.175494351e-38;
// Punctual light, shape radius 0: minRoughness = (1 − clamp01(1.1725/(1.01 + 0.1²) − 0.15))² (models.md#hdrp-lit)
const HDRP_MIN_ROUGHNESS_PUNCTUAL: f32 = 2.402922e-7;

// F0·(1 − x⁵) + F90·x⁵, x = 1 − LH
fn f_schlick_f90(f0: vec3<f32>, f90: f32, lh: f32) -> vec3<f32> {
    let x5 = pow5(1.0 - lh);
    return f0 * (1.0 - x5) + vec3<f32>(f90 * x5);
}

// (1/π)·0.5·α²/max(s²(λV + λL), REAL_MIN), s = (NH·α² − NH)·NH + 1, height-correlated
fn dv_smith_joint_ggx(nh: f32, nl: f32, nv: f32, a: f32) -> f32 {
    let a2 = a * a;
    let s = (nh * a2 - nh) * nh + 1.0;
    let lambda_v = nl * sqrt((-nv * a2 + nv) * nv + a2);
    let lambda_l = nv * sqrt((-nl * a2 + nl) * nl + a2);
    return INV_PI * 0.5 * a2 / max(s * s * (lambda_v + lambda_l), HDRP_REAL_MIN);
}

// (1/1.03571)(1 + (fd90−1)(1−NL)⁵)(1 + (fd90−1)(1−NV)⁵), fd90 = 0.5 + pr + pr·LV, no 1/π
fn fd_disney_renormalized_no_pi(nl: f32, nv: f32, lv: f32, pr: f32) -> f32 {
    let fd90 = 0.5 + pr + pr * lv;
    return (1.0 / 1.03571) * (1.0 + (fd90 - 1.0) * pow5(1.0 - nl)) * (1.0 + (fd90 - 1.0) * pow5(1.0 - nv));
}

struct HdrpAngles {
    n: vec3<f32>,
    nv: f32,
};

// GetViewReflectedNormal: N += 2·sat(−NV)·V; then ClampNdotV: max(NV, 1e-4)
fn hdrp_view_normal(n_in: vec3<f32>, v: vec3<f32>) -> HdrpAngles {
    var a: HdrpAngles;
    let nv = dot(n_in, v);
    a.n = n_in + 2.0 * sat(-nv) * v;
    a.nv = max(abs(nv), 1e-4);
    return a;
}

fn hdrp_f0(s: Surface) -> vec3<f32> {
    return mix(vec3<f32>(0.04), s.base_color, s.metallic);
}

// Specular multiplier 1 + F0·(1/y − 1), y = reflectivity from the FGD table (models.md#hdrp-lit)
fn hdrp_energy_compensation(s: Surface, nv: f32) -> vec3<f32> {
    if (s.params0.x < 0.5) {
        return vec3<f32>(1.0);
    }
    let y = fgd_lookup(nv, 1.0 - s.smoothness).y;
    return vec3<f32>(1.0) + hdrp_f0(s) * (1.0 / y - 1.0);
}

fn model_direct(s: Surface, n_in: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let ang = hdrp_view_normal(n_in, v);
    let n = ang.n;
    let nv = ang.nv;
    let nl = dot(n, l);
    if (nl <= 0.0) {
        return vec3<f32>(0.0);
    }
    let lv = dot(l, v);
    let inv_len = inverseSqrt(max(2.0 * lv + 2.0, HDRP_FLT_EPS));
    let nh = sat((nl + nv) * inv_len);
    let lh = sat(inv_len * lv + inv_len);
    let pr = 1.0 - s.smoothness;
    let a = max(pr * pr, HDRP_MIN_ROUGHNESS_PUNCTUAL);
    let f0 = hdrp_f0(s);
    let spec = f_schlick_f90(f0, 1.0, lh) * dv_smith_joint_ggx(nh, abs(nl), nv, a) * hdrp_energy_compensation(s, nv);
    let diffuse = s.base_color * (1.0 - s.metallic) * INV_PI * fd_disney_renormalized_no_pi(abs(nl), nv, lv, pr);
    return (diffuse + spec) * sat(nl);
}

fn model_indirect(s: Surface, n_in: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let ang = hdrp_view_normal(n_in, v);
    let pr = 1.0 - s.smoothness;
    let fgd = fgd_lookup(ang.nv, pr);
    let f0 = hdrp_f0(s);
    // specularFGD = (F90 − F0)·x + F0·y; diffuseFGD = z + 0.5 (the table stores z − 0.5)
    let specular_fgd = (vec3<f32>(1.0) - f0) * fgd.x + f0 * fgd.y;
    let diffuse_fgd = fgd.z + 0.5;
    let env = env_specular(reflect(-v, ang.n), pr);
    return s.base_color * (1.0 - s.metallic) * gi_diffuse * diffuse_fgd + specular_fgd * env * hdrp_energy_compensation(s, ang.nv);
}
