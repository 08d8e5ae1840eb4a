// Cook-Torrance as the 1982 paper writes it (models.md#cook-torrance-1982): f = kd·ρ/π + (F/π)·D·G/(NL·NV) with the
// un-normalised Beckmann D = exp(−tan²θ/m²)/(m²·cos⁴θ). Since the normalised D is this over π, the specular
// is exactly 4× the modern form's (`cook_torrance`). Same Fresnel, G, mapping and diffuse as `cook_torrance`.

// D = exp((NH² − 1)/(m²NH²))/(m²NH⁴): Beckmann without the 1/π (Cook & Torrance 1982, eq. 8)
fn d_beckmann_unnormalised(nh: f32, m: f32) -> f32 {
    return d_beckmann(nh, m) * PI;
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let nl = dot(n, l);
    let nv = dot(n, v);
    if (nl <= 0.0 || nv <= 0.0) {
        return vec3<f32>(0.0);
    }
    let h = safe_normalize(l + v, 1.175494e-38);
    let nh = sat(dot(n, h));
    let vh = sat(dot(v, h));
    let pr = 1.0 - s.smoothness;
    let m = pr * pr;
    let f_dielectric = vec3<f32>(f_fresnel_dielectric(vh, s.params0.x));
    let f = mix(f_dielectric, f_schlick(s.base_color, vh), s.metallic);
    let spec = f * INV_PI * d_beckmann_unnormalised(nh, m) * g_cook_torrance(nh, nv, nl, vh) / (nl * nv);
    let diffuse = s.base_color * (1.0 - s.metallic) * INV_PI;
    return (diffuse + spec) * nl * irradiance_per_intensity();
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return s.base_color * (1.0 - s.metallic) * gi_diffuse;
}
