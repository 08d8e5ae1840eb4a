// Half-Lambert (models.md#half-lambert, models.md#half-lambert): h = 0.5·NL + 0.5, NOT squared (Unity's directional-lightmap decode;
// Valve's Source paper squares it). radiance = ρ/π·E·h. Not energy conserving: a look, not a BRDF.

// h = 0.5·NL + 0.5
fn half_lambert_wrap(nl: f32) -> f32 {
    return 0.5 * nl + 0.5;
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    return direct_diffuse(fd_lambert(s.base_color) * irradiance_per_intensity() * half_lambert_wrap(dot(n, l)));
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(s.base_color * gi_diffuse);
}
