// Oren-Nayar, qualitative model with its trigonometric form (models.md#oren-nayar): σ in radians (params0.x),
// A = 1 − 0.5σ²/(σ² + 0.33), B = 0.45σ²/(σ² + 0.09),
// radiance = ρ/π·E·NL·(A + B·max(0, cos(φi − φr))·sin a·tan b), a = max(θi, θr), b = min(θi, θr).

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = dot(n, l);
    if (nl <= 0.0) {
        return vec3<f32>(0.0);
    }
    let nv = clamp(dot(n, v), 0.0, 1.0);
    let sigma2 = s.params0.x * s.params0.x;
    let a = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33);
    let b = 0.45 * sigma2 / (sigma2 + 0.09);
    let theta_i = acos(clamp(nl, -1.0, 1.0));
    let theta_r = acos(nv);
    let alpha = max(theta_i, theta_r);
    let beta = min(theta_i, theta_r);
    let c = max(0.0, cos_azimuth_difference(n, v, l, nl, nv));
    // tan b with cos b ≥ ε: b ≤ a < π/2 on the visible hemisphere (models.md#stability)
    let tan_beta = sin(beta) / max(cos(beta), 1e-4);
    return direct_diffuse(fd_lambert(s.base_color) * irradiance_per_intensity() * nl * (a + b * c * sin(alpha) * tan_beta));
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(s.base_color * gi_diffuse);
}
