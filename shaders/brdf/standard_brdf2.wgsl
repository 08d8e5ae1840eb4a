// Built-in Standard, BRDF2_Unity_PBS ("minimalist Cook-Torrance"), linear colour space (models.md#standard-brdf2).
// No roughness clamp; nv = sat(NV); desktop (no fp16 clamps). Unity convention (no 1/π).

// specColor, oneMinusReflectivity, diffColor as BRDF1 (models.md#standard-brdf2 material setup)
fn brdf2_spec_color(s: Surface) -> vec3<f32> {
    return mix(vec3<f32>(0.04), s.base_color, s.metallic);
}

fn brdf2_one_minus_reflectivity(s: Surface) -> f32 {
    return 0.96 - s.metallic * 0.96;
}

// spec = α²/(max(0.1, lh²)·(α + 0.5)·d²·4), d = nh²(α² − 1) + 1.00001 (models.md#standard-brdf2 BRDF2, linear)
// 1 − oneMinusReflectivity (built-in Transparent's output alpha, as Standard's)
fn model_reflectivity(s: Surface) -> f32 {
    return 1.0 - brdf2_one_minus_reflectivity(s);
}

fn spec_brdf2(nh: f32, lh: f32, a: f32) -> f32 {
    let a2 = a * a;
    let d = nh * nh * (a2 - 1.0) + 1.00001;
    return a2 / (max(0.1, lh * lh) * (a + 0.5) * d * d * 4.0);
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let h = safe_normalize(l + v, 0.001);
    let nl = sat(dot(n, l));
    let nh = sat(dot(n, h));
    let lh = sat(dot(l, h));
    let pr = 1.0 - s.smoothness;
    let diff_color = s.base_color * brdf2_one_minus_reflectivity(s) * diffuse_weight;
    return direct_diffuse(diff_color * nl) + direct_specular(spec_brdf2(nh, lh, pr * pr) * brdf2_spec_color(s) * nl);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let nv = sat(dot(n, v));
    let pr = 1.0 - s.smoothness;
    let a = pr * pr;
    let omr = brdf2_one_minus_reflectivity(s);
    // surfaceReduction = 1 − α·pr·(0.6 − 0.08·pr) (linear space)
    let surface_reduction = 1.0 - a * pr * (0.6 - 0.08 * pr);
    let grazing_term = sat(s.smoothness + (1.0 - omr));
    let x = 1.0 - nv;
    let fresnel = x * x * x * x;
    let gi_specular = env_specular(reflect(-v, n), pr);
    return indirect_diffuse(gi_diffuse * s.base_color * omr * diffuse_weight)
        + indirect_specular(surface_reduction * gi_specular * mix(brdf2_spec_color(s), vec3<f32>(grazing_term), fresnel));
}
