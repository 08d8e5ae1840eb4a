// Built-in Standard shader (metallic), BRDF1_Unity_PBS in linear colour space (models.md#standard).
// Unity convention: diffuse not divided by π, specular multiplied by π (light intensity = π·irradiance).

// unity_ColorSpaceDielectricSpec in linear space: rgb 0.04, a 0.96 (models.md#standard)
const DIELECTRIC_SPEC: vec4<f32> = vec4<f32>(0.04, 0.04, 0.04, 0.96);

struct StandardSetup {
    diff_color: vec3<f32>,
    spec_color: vec3<f32>,
    one_minus_reflectivity: f32,
    perceptual_roughness: f32,
};

// MetallicSetup: specColor = lerp(0.04, albedo, m); oneMinusReflectivity = 0.96(1 − m); diffColor = albedo·that (models.md#standard).
// SpecularSetup (params0.x = 1, StandardSpecular.shader): specColor = _SpecColor; oneMinusReflectivity =
// 1 − max(specColor) (SpecularStrength); diffColor = albedo·that (EnergyConservationBetweenDiffuseAndSpecular,
// UNITY_CONSERVE_ENERGY_MONOCHROME; UnityStandardUtils.cginc)
fn standard_setup(s: Surface) -> StandardSetup {
    var st: StandardSetup;
    if (s.params0.x > 0.5) {
        st.spec_color = s.specular;
        st.one_minus_reflectivity = 1.0 - max(max(s.specular.r, s.specular.g), s.specular.b);
    } else {
        st.spec_color = mix(DIELECTRIC_SPEC.rgb, s.base_color, s.metallic);
        st.one_minus_reflectivity = DIELECTRIC_SPEC.a - s.metallic * DIELECTRIC_SPEC.a;
    }
    st.diff_color = s.base_color * st.one_minus_reflectivity * diffuse_weight;
    st.perceptual_roughness = 1.0 - s.smoothness;
    return st;
}

// 1 − oneMinusReflectivity: what built-in's Transparent keeps of the background's share
// (PreMultiplyAlpha: outAlpha = 1 − oneMinusReflectivity + alpha·oneMinusReflectivity)
fn model_reflectivity(s: Surface) -> f32 {
    return 1.0 - standard_setup(s).one_minus_reflectivity;
}

// α = max(pr², 0.002) (models.md#standard roughness clamp, "to match HDRP")
fn roughness_clamped(pr: f32) -> f32 {
    return max(pr * pr, 0.002);
}

// (1 + (fd90−1)(1−nl)⁵)(1 + (fd90−1)(1−nv)⁵), fd90 = 0.5 + 2·lh²·pr, no 1/π (models.md#standard Disney diffuse)
fn fd_disney_unity(nv: f32, nl: f32, lh: f32, pr: f32) -> f32 {
    let fd90 = 0.5 + 2.0 * lh * lh * pr;
    let light_scatter = 1.0 + (fd90 - 1.0) * pow5(1.0 - nl);
    let view_scatter = 1.0 + (fd90 - 1.0) * pow5(1.0 - nv);
    return light_scatter * view_scatter;
}

// V = 0.5/(λV + λL + 1e-5), λV = nl(nv(1−α)+α), λL = nv(nl(1−α)+α) (models.md#standard approximate SmithJointGGX)
fn v_smith_joint_approx(nl: f32, nv: f32, a: f32) -> f32 {
    let lambda_v = nl * (nv * (1.0 - a) + a);
    let lambda_l = nv * (nl * (1.0 - a) + a);
    return 0.5 / (lambda_v + lambda_l + 1e-5);
}

// D = (1/π)·α²/(d² + 1e-7), d = nh²(α² − 1) + 1 (models.md#standard GGXTerm)
fn d_ggx_unity(nh: f32, a: f32) -> f32 {
    let a2 = a * a;
    let d = (nh * a2 - nh) * nh + 1.0;
    return INV_PI * a2 / (d * d + 1e-7);
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let st = standard_setup(s);
    let h = safe_normalize(l + v, 0.001);
    let nv = abs(dot(n, v));
    let nl = sat(dot(n, l));
    let nh = sat(dot(n, h));
    let lh = sat(dot(l, h));
    let diffuse_term = fd_disney_unity(nv, nl, lh, st.perceptual_roughness) * nl;
    let a = roughness_clamped(st.perceptual_roughness);
    var specular_term = max(0.0, v_smith_joint_approx(nl, nv, a) * d_ggx_unity(nh, a) * PI * nl);
    // Pure Lambert is possible: no specular when specColor is black (models.md#standard).
    // _SPECULARHIGHLIGHTS_OFF (params0.y = 1): specularTerm = 0 (BRDF1_Unity_PBS).
    if (all(st.spec_color == vec3<f32>(0.0)) || s.params0.y > 0.5) {
        specular_term = 0.0;
    }
    return direct_diffuse(st.diff_color * diffuse_term) + direct_specular(specular_term * f_schlick(st.spec_color, lh));
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let st = standard_setup(s);
    let nv = abs(dot(n, v));
    let a = roughness_clamped(st.perceptual_roughness);
    // surfaceReduction = 1/(α² + 1), linear space (models.md#standard)
    let surface_reduction = 1.0 / (a * a + 1.0);
    let grazing_term = sat(s.smoothness + (1.0 - st.one_minus_reflectivity));
    let gi_specular = env_specular(reflect(-v, n), st.perceptual_roughness);
    return indirect_diffuse(st.diff_color * gi_diffuse)
        + indirect_specular(surface_reduction * gi_specular * f_schlick_lerp(st.spec_color, vec3<f32>(grazing_term), nv));
}

// The Height Map's scale (`_Parallax`; registry PARALLAX, slot 3): the passes offset the maps'
// uv by ParallaxOffset1Step with it (conventions.wgsl parallax_offset)
fn model_height_scale(params0: vec4<f32>, params1: vec4<f32>) -> f32 {
    return params0.w;
}

// Secondary maps on (the `detail` parameter, slot 4): the passes blend them in (materials::detail)
fn model_detail(params0: vec4<f32>, params1: vec4<f32>, params2: vec4<f32>) -> f32 {
    return params1.x;
}
