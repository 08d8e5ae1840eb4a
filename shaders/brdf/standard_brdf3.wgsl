// Built-in Standard, BRDF3_Unity_PBS (SM2, lowest tier), models.md#standard-brdf3. Unity convention (no 1/π).
// APPROXIMATION: the engine's unity_NHxRoughness lookup texture is not public. It is replaced by
// a normalised Phong lobe in Unity convention, π·(n + 2)/(2π)·(R·L)ⁿ with n = 2/α² − 2
// (PerceptualRoughnessToSpecPower, n ≥ 1e-4), evaluated from rlPow4 = (R·L)⁴ as rlPow4^(n/4) and
// clamped to the LUT's range of 16.

const BRDF3_LUT_RANGE: f32 = 16.0;

// 16·NHxRoughness(rlPow4, pr) ≈ min(16, (n + 2)/2·rlPow4^(n/4))
// 1 − oneMinusReflectivity (built-in Transparent's output alpha, as Standard's)
fn model_reflectivity(s: Surface) -> f32 {
    return 1.0 - (0.96 - s.metallic * 0.96);
}

fn spec_brdf3(rl_pow4: f32, pr: f32) -> f32 {
    let a = pr * pr;
    let n = max(2.0 / max(1e-4, a * a) - 2.0, 1e-4);
    return min(BRDF3_LUT_RANGE, (n + 2.0) * 0.5 * pow(max(rl_pow4, 0.0), n * 0.25));
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = sat(dot(n, l));
    // R = reflect(V, N) = −(true reflection); the even power cancels the sign (models.md#standard-brdf3)
    let r = reflect(v, n);
    let rl = dot(r, l);
    let rl_pow4 = rl * rl * rl * rl;
    let spec_color = mix(vec3<f32>(0.04), s.base_color, s.metallic);
    let diff_color = s.base_color * (0.96 - s.metallic * 0.96) * diffuse_weight;
    return direct_diffuse(diff_color * nl) + direct_specular(spec_brdf3(rl_pow4, 1.0 - s.smoothness) * spec_color * nl);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let nv = sat(dot(n, v));
    let omr = 0.96 - s.metallic * 0.96;
    let spec_color = mix(vec3<f32>(0.04), s.base_color, s.metallic);
    let grazing_term = sat(s.smoothness + (1.0 - omr));
    let x = 1.0 - nv;
    let fresnel_term = x * x * x * x;
    let gi_specular = env_specular(reflect(-v, n), 1.0 - s.smoothness);
    return indirect_diffuse(gi_diffuse * s.base_color * omr * diffuse_weight)
        + indirect_specular(gi_specular * mix(spec_color, vec3<f32>(grazing_term), fresnel_term));
}
