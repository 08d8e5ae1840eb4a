// Cook-Torrance (models.md#cook-torrance), modern normalised form f = kd·ρ/π + F·D·G/(4·NL·NV): Beckmann D with
// m = α = pr², full dielectric Fresnel at c = VH from the IOR (params0.x), the Cook-Torrance G.
// Metallic blends the dielectric Fresnel towards Schlick with F0 = base colour, and removes diffuse.

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
    let spec = f * d_beckmann(nh, m) * g_cook_torrance(nh, nv, nl, vh) / (4.0 * nl * nv);
    let diffuse = s.base_color * (1.0 - s.metallic) * INV_PI;
    return (diffuse + spec) * nl * irradiance_per_intensity();
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return s.base_color * (1.0 - s.metallic) * gi_diffuse;
}
