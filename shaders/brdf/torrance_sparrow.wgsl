// The custom roughness/metallic PBR shader of models.md#torrance-sparrow AS WRITTEN, final (IBL) stage, every
// quirk kept and named. Inputs: roughness r = 1 − smoothness; params0.x IOR (default 1.45), params0.y Fresnel
// power p (default 5); specular: the metallic tint colour (default white). Built-in convention (no 1/π).
// A ForwardBase shader: the pass lights it with the main directional light only (MAIN_LIGHT_ONLY).
// The corrected variant is `torrance_sparrow_corrected`.

// QUIRK: the source's Fresnel function returns a float, so F0 (a colour) is truncated to its red channel:
// F = F0.r + (max(1 − r, F0.r) − F0.r)(1 − NV)^p, N·V rather than V·H
fn ts_fresnel_scalar(f0: vec3<f32>, r: f32, nv: f32, p: f32) -> f32 {
    return f0.x + (max(1.0 - r, f0.x) - f0.x) * pow(1.0 - nv, p);
}

// The final stage's direct term, shared with the other variant (shaders/common/brdf.wgsl ts_direct)
fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    return ts_direct(s, n, v, l);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let r = 1.0 - s.smoothness;
    let nv = sat(dot(n, v));
    let f = ts_fresnel_scalar(ts_f0(s), r, nv, s.params0.y);
    let surface_reduction = 1.0 / (r * r + 1.0);
    // QUIRK: reflect(v, n) with v towards the eye is −reflect(−v, n): it fetches the opposite direction
    let env = env_specular(reflect(v, n), r);
    // QUIRK: ambient SH is multiplied by the light colour (_LightColor0, the main directional light)
    return indirect_diffuse(s.base_color * main_light_color * gi_diffuse * (1.0 - s.metallic))
        + indirect_specular(s.base_color * s.specular * surface_reduction * env * f);
}
