// The custom roughness/metallic PBR shader of models.md#torrance-sparrow AS WRITTEN, final (IBL) stage, every
// quirk kept and named. Inputs: roughness r = 1 − smoothness; params0.x IOR (default 1.45), params0.y Fresnel
// power p (default 5); specular: the metallic tint colour (default white). Built-in convention (no 1/π).
// A ForwardBase shader: the pass lights it with the main directional light only (MAIN_LIGHT_ONLY).
// The corrected variant is `torrance_sparrow_corrected`.

// F0 = ((1 − IOR)/(1 + IOR))², then lerp(F0, albedo, metallic)
fn ts_f0(s: Surface) -> vec3<f32> {
    let f = (1.0 - s.params0.x) / (1.0 + s.params0.x);
    return mix(vec3<f32>(f * f), s.base_color, s.metallic);
}

// D = a²/(π(NH²(a² − 1) + 1)²), a = r² ("UE4 roughness")
fn ts_d(nh: f32, r: f32) -> f32 {
    return d_ggx(nh, r * r);
}

// QUIRK: the source's Fresnel function returns a float, so F0 (a colour) is truncated to its red channel:
// F = F0.r + (max(1 − r, F0.r) − F0.r)(1 − NV)^p, N·V rather than V·H
fn ts_fresnel_scalar(f0: vec3<f32>, r: f32, nv: f32, p: f32) -> f32 {
    return f0.x + (max(1.0 - r, f0.x) - f0.x) * pow(1.0 - nv, p);
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
    let f = ts_fresnel_scalar(ts_f0(s), r, nv, s.params0.y);
    let surface_reduction = 1.0 / (r * r + 1.0);
    // QUIRK: reflect(v, n) with v towards the eye is −reflect(−v, n): it fetches the opposite direction
    let env = env_specular(reflect(v, n), r);
    // QUIRK: ambient SH is multiplied by the light colour (_LightColor0, the main directional light)
    return s.base_color * main_light_color * gi_diffuse * (1.0 - s.metallic)
        + s.base_color * s.specular * surface_reduction * env * f;
}
