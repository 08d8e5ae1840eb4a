// Lambert (models.md#lambert): f = ρ/π, so radiance = ρ/π·E·max(0, NL); E per unit intensity is the pipeline's.
// Reads the base colour only (no metallic, no smoothness).

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    return direct_diffuse(fd_lambert(s.base_color) * irradiance_per_intensity() * max(0.0, dot(n, l)));
}

// gi_diffuse is E/π of the environment, so a Lambert surface reflects ρ·gi_diffuse.
fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(s.base_color * gi_diffuse);
}

// A rect light: ρ/π·E with E = π·L·(1/π)∫max(0, NL)dω over the rectangle, the exact horizon-clipped
// integral (the identity transform of the LTC method); per unit luminance
fn model_rect(s: Surface, n: vec3<f32>, v: vec3<f32>, corners: array<vec3<f32>, 4>) -> vec3<f32> {
    let basis = ortho_basis_view_normal(v, n, dot(n, v));
    let form_factor = polygon_irradiance_clipped(ltc_transform(corners, basis));
    return direct_diffuse(fd_lambert(s.base_color) * irradiance_per_intensity() * PI * form_factor);
}
