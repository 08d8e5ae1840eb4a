// Phong (models.md#phong, models.md#phong): diffuse kd·NL plus ks·max(0, R·V)ⁿ with R = 2NL·N − L, per unit of E/π.
// params0.x: normalise the lobe by (n + 2)/2 (1) or not (0, the textbook form, default).

// R = 2·NL·N − L
fn phong_reflect(n: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    return 2.0 * dot(n, l) * n - l;
}

// max(0, R·V)ⁿ, with the optional (n + 2)/2 normalisation
fn spec_phong(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, shininess: f32, normalized: f32) -> f32 {
    let rv = max(0.0, dot(phong_reflect(n, l), v));
    let lobe = pow(rv, shininess);
    return select(lobe, lobe * (shininess + 2.0) * 0.5, normalized > 0.5);
}

// DEPARTURE from the reading note (spec §4c): the lobe is gated by NL > 0 with the diffuse term.
fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = max(0.0, dot(n, l));
    if (nl <= 0.0) {
        return vec3<f32>(0.0);
    }
    let spec = spec_phong(n, v, l, shininess_from_smoothness(s.smoothness), s.params0.x);
    let k = INV_PI * irradiance_per_intensity();
    return direct_diffuse(s.base_color * nl * k) + direct_specular(s.specular * spec * k);
}

// DEPARTURE from the reading note (spec §4c): the ambient is scaled by kd, not added as is.
fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(s.base_color * gi_diffuse);
}
