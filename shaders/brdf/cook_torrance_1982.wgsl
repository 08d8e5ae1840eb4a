// Cook-Torrance as the 1982 paper writes it (models.md#cook-torrance-1982): f = kd·ρ/π + (F/π)·D·G/(NL·NV) with the
// un-normalised Beckmann D = exp(−tan²θ/m²)/(m²·cos⁴θ). Since the normalised D is this over π, the specular
// is exactly 4× the modern form's (`cook_torrance`). Same Fresnel, G, mapping and diffuse as `cook_torrance`.

// D = exp((NH² − 1)/(m²NH²))/(m²NH⁴): Beckmann without the 1/π (Cook & Torrance 1982, eq. 8)
fn d_beckmann_unnormalised(nh: f32, m: f32) -> f32 {
    return d_beckmann(nh, m) * PI;
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let a = cook_torrance_angles(s, n, v, l);
    if (!a.valid) {
        return vec3<f32>(0.0);
    }
    let spec = a.f * INV_PI * d_beckmann_unnormalised(a.nh, a.m) * g_cook_torrance(a.nh, a.nv, a.nl, a.vh) / (a.nl * a.nv);
    return cook_torrance_sum(s, a, spec);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(s.base_color * (1.0 - s.metallic) * gi_diffuse);
}
