// Wrapped diffuse, an example user model: ρ/π·E·max(0, (NL + w)/(1 + w)), w = params0.x ("wrap").
// Copy this file and wrap_diffuse.toml into shaders/brdf/ of the folder you run shadematrix in.
// Available: Surface (base_color, metallic, smoothness, specular, params0, params1), PI, INV_PI,
// sat, pow5, safe_normalize, fd_lambert, f_schlick, d_ggx, irradiance_per_intensity(),
// env_specular(r, perceptual_roughness), fgd_lookup(nv, pr).

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let w = s.params0.x;
    return fd_lambert(s.base_color) * irradiance_per_intensity() * max(0.0, (dot(n, l) + w) / (1.0 + w));
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return s.base_color * gi_diffuse;
}
