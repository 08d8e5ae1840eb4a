// URP Simple Lit (models.md#urp-simple-lit): Blinn-Phong without normalisation, Fresnel or NL on the specular.
// diffuse = albedo·sat(NL); spec = specColor·pow(sat(NH), exp2(10·s + 1)); ambient = bakedGI·albedo.
// The specular colour is `specular` (URP's _SpecColor). Light units: no 1/π, as URP.

// pow(sat(NH), shininess), shininess = exp2(10s + 1) ∈ [2, 2048]
fn spec_simple_lit(nh: f32, smoothness: f32) -> f32 {
    return pow(nh, shininess_from_smoothness(smoothness));
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let h = safe_normalize(l + v, 1.175494e-38);
    let nh = sat(dot(n, h));
    return s.base_color * sat(dot(n, l)) + s.specular * spec_simple_lit(nh, s.smoothness);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return gi_diffuse * s.base_color;
}
