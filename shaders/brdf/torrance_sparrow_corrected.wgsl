// The custom roughness/metallic PBR shader of models.md#torrance-sparrow, final (IBL) stage, CORRECTED: a colour
// Fresnel, the reflection reflect(−V, N), ambient not scaled by the light, lit by every light. The shader
// as written is `torrance_sparrow`; the quirks both keep are named.
// Inputs: roughness r = 1 − smoothness; params0.x IOR (default 1.45), params0.y Fresnel power p
// (default 5); specular: the metallic tint colour (default white). Built-in convention (no 1/π).

// The final stage's direct term, shared with the other variant (shaders/common/brdf.wgsl ts_direct)
fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    return ts_direct(s, n, v, l);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let r = 1.0 - s.smoothness;
    let nv = sat(dot(n, v));
    let f0 = ts_f0(s);
    // F = F0 + (max(1 − r, F0) − F0)(1 − NV)^p — N·V, not V·H (QUIRK); p ≥ 1 so pow is safe
    let f = f0 + (max(vec3<f32>(1.0 - r), f0) - f0) * pow(1.0 - nv, s.params0.y);
    let surface_reduction = 1.0 / (r * r + 1.0);
    // The shader's mip uses r like perceptual roughness: r(1.7 − 0.7r)·6
    let env = env_specular(reflect(-v, n), r);
    // Corrected: the source multiplies ambient SH by the light colour; here ambient stands alone.
    return indirect_diffuse(s.base_color * gi_diffuse * (1.0 - s.metallic))
        + indirect_specular(s.base_color * s.specular * surface_reduction * env * f);
}
