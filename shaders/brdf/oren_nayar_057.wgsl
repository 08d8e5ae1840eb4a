// Oren-Nayar, the trig-free form of a well-known custom PBR shader (models.md#oren-nayar-057): σ in radians
// (params0.x), A with 0.57 (the interreflection constant), B = 0.45σ²/(σ² + 0.09),
// P = max(0, normalize(L − N·NL)·normalize(V − N·NV)), sinθi·sinθr = √((1 − NL²)(1 − NV²)),
// radiance = ρ/π·E·NL·(A + B·P·sinθi·sinθr/max(NL, NV)).

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = dot(n, l);
    if (nl <= 0.0) {
        return vec3<f32>(0.0);
    }
    let nv = clamp(dot(n, v), 0.0, 1.0);
    let sigma2 = s.params0.x * s.params0.x;
    let a = 1.0 - 0.5 * sigma2 / (sigma2 + 0.57);
    let b = 0.45 * sigma2 / (sigma2 + 0.09);
    let p = max(0.0, cos_azimuth_difference(n, v, l, nl, nv));
    // 1 − NL², 1 − NV² ≥ 0 and max(NL, NV) ≥ ε (models.md#stability)
    let sin_product = sqrt(max(0.0, 1.0 - nl * nl) * max(0.0, 1.0 - nv * nv));
    return direct_diffuse(fd_lambert(s.base_color) * irradiance_per_intensity() * nl * (a + b * p * sin_product / max(max(nl, nv), 1e-4)));
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(s.base_color * gi_diffuse);
}
