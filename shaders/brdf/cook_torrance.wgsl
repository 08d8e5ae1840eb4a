// Cook-Torrance (models.md#cook-torrance), modern normalised form f = kd·ρ/π + F·D·G/(4·NL·NV): Beckmann D with
// m = α = pr², full dielectric Fresnel at c = VH from the IOR (params0.x), the Cook-Torrance G.
// Metallic blends the dielectric Fresnel towards Schlick with F0 = base colour, and removes diffuse.

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let a = cook_torrance_angles(s, n, v, l);
    if (!a.valid) {
        return vec3<f32>(0.0);
    }
    let spec = a.f * d_beckmann(a.nh, a.m) * g_cook_torrance(a.nh, a.nv, a.nl, a.vh) / (4.0 * a.nl * a.nv);
    return cook_torrance_sum(s, a, spec);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(s.base_color * (1.0 - s.metallic) * gi_diffuse);
}
