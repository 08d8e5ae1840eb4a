// Blinn-Phong (models.md#blinn-phong, models.md#blinn-phong): diffuse kd·NL plus ks·max(0, N·H)ⁿ, per unit of E/π.
// params0.x: normalise the lobe by (n + 8)/8 (1) or not (0, the textbook form, default).

// max(0, N·H)ⁿ, with the optional ≈(n + 8)/8 normalisation
fn spec_blinn_phong(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, shininess: f32, normalized: f32) -> f32 {
    let h = safe_normalize(l + v, 1.175494e-38);
    let lobe = pow(max(0.0, dot(n, h)), shininess);
    return select(lobe, lobe * (shininess + 8.0) * 0.125, normalized > 0.5);
}

// DEPARTURE from the reading note (spec §4c): the lobe is gated by NL > 0 with the diffuse term.
fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = max(0.0, dot(n, l));
    if (nl <= 0.0) {
        return vec3<f32>(0.0);
    }
    let spec = spec_blinn_phong(n, v, l, shininess_from_smoothness(s.smoothness), s.params0.x);
    let k = INV_PI * irradiance_per_intensity();
    return direct_diffuse(s.base_color * nl * k) + direct_specular(s.specular * spec * k);
}

// DEPARTURE from the reading note (spec §4c): the ambient is scaled by kd, not added as is.
fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(s.base_color * gi_diffuse);
}
