// The custom roughness/metallic PBR shader of models.md#torrance-sparrow, final (IBL) stage, CORRECTED: a colour
// Fresnel, the reflection reflect(−V, N), ambient not scaled by the light, lit by every light. The shader
// as written is `torrance_sparrow`; the quirks both keep are named.
// Inputs: roughness r = 1 − smoothness; params0.x IOR (default 1.45), params0.y Fresnel power p
// (default 5); specular: the metallic tint colour (default white). Built-in convention (no 1/π).

// F0 = ((1 − IOR)/(1 + IOR))², then lerp(F0, albedo, metallic)
fn ts_f0(s: Surface) -> vec3<f32> {
    let f = (1.0 - s.params0.x) / (1.0 + s.params0.x);
    return mix(vec3<f32>(f * f), s.base_color, s.metallic);
}

// D = a²/(π(NH²(a² − 1) + 1)²), a = r² ("UE4 roughness")
fn ts_d(nh: f32, r: f32) -> f32 {
    return d_ggx(nh, r * r);
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let r = 1.0 - s.smoothness;
    let nl = sat(dot(n, l));
    let nv = sat(dot(n, v));
    let h = safe_normalize(l + v, 1.175494e-38);
    let nh = sat(dot(n, h));
    // Visibility: Smith-Schlick with k = r²/2 (the shader's own choice)
    let vis = v_smith_schlick(nl, nv, r * r * 0.5);
    let specular = max(0.0, ts_d(nh, r) * vis * PI * nl);
    // QUIRK: the final stage drops F from the direct specular, and multiplies the specular by
    // albedo even for dielectrics.
    return s.base_color * nl * (1.0 - s.metallic) + s.base_color * s.specular * specular;
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
    return s.base_color * gi_diffuse * (1.0 - s.metallic) + s.base_color * s.specular * surface_reduction * env * f;
}
