// URP Simple Lit (models.md#urp-simple-lit): Blinn-Phong without normalisation, Fresnel or NL on the specular.
// diffuse = albedo·sat(NL); spec = specColor·pow(sat(NH), exp2(10·s + 1)); ambient = bakedGI·albedo.
// The specular colour is `specular` (URP's _SpecColor). Light units: no 1/π, as URP.
// params0.x: specular highlights on (1) or off (0, the default: a new Simple Lit material has
// _SpecularHighlights = 1 = SimpleLitGUI.SpecularSource.NoSpecular, so _SPECULAR_COLOR is not set).

// pow(sat(NH), shininess), shininess = exp2(10s + 1) ∈ [2, 2048]
fn spec_simple_lit(nh: f32, smoothness: f32) -> f32 {
    return pow(nh, shininess_from_smoothness(smoothness));
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let h = safe_normalize(l + v, 1.175494e-38);
    let nh = sat(dot(n, h));
    var spec = vec3<f32>(0.0);
    if (s.params0.x > 0.5) {
        spec = s.specular * spec_simple_lit(nh, s.smoothness);
    }
    // _ALPHAPREMULTIPLY_ON: the lights' diffuse × alpha (Lighting.hlsl CalculateBlinnPhong); the
    // baked GI is not (UniversalFragmentBlinnPhong: bakedGI × albedo alone)
    return direct_diffuse(s.base_color * diffuse_weight * sat(dot(n, l))) + direct_specular(spec);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    return indirect_diffuse(gi_diffuse * s.base_color);
}
