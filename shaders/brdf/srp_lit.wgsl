// The custom scriptable pipeline tutorial's Lit shader (models.md#srp-lit, shading.md §4d): the minimal
// Cook-Torrance of URP without its roughness floors, and environment reflections whose Fresnel is
// scaled by a slider (fresnel_strength, params0.x).

const MIN_REFLECTIVITY: f32 = 0.04;

struct SrpBrdf {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
    roughness: f32,
    perceptual_roughness: f32,
    fresnel: f32,
};

// oneMinusReflectivity = 0.96 − 0.96·metallic; specular = lerp(0.04, albedo, metallic);
// roughness = (1 − smoothness)², no floor; fresnel = sat(smoothness + 1 − oneMinusReflectivity)
fn srp_brdf(s: Surface) -> SrpBrdf {
    var b: SrpBrdf;
    let one_minus_reflectivity = (1.0 - MIN_REFLECTIVITY) - s.metallic * (1.0 - MIN_REFLECTIVITY);
    b.diffuse = s.base_color * one_minus_reflectivity;
    b.specular = mix(vec3<f32>(MIN_REFLECTIVITY), s.base_color, s.metallic);
    b.perceptual_roughness = 1.0 - s.smoothness;
    b.roughness = b.perceptual_roughness * b.perceptual_roughness;
    b.fresnel = sat(s.smoothness + 1.0 - one_minus_reflectivity);
    return b;
}

// SpecularStrength: r²/(d²·max(0.1, LH²)·(4r + 2)), d = NH²(r² − 1) + 1.00001
fn specular_strength(nh: f32, lh: f32, b: SrpBrdf) -> f32 {
    let r2 = b.roughness * b.roughness;
    let d = nh * nh * (r2 - 1.0) + 1.00001;
    return r2 / (d * d * max(0.1, lh * lh) * (b.roughness * 4.0 + 2.0));
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let b = srp_brdf(s);
    let h = safe_normalize(l + v, 1.175494e-38);
    let nl = sat(dot(n, l));
    return direct_specular(b.specular * specular_strength(sat(dot(n, h)), sat(dot(l, h)), b) * nl) + direct_diffuse(b.diffuse * nl);
}

// IndirectBRDF: reflection = envSpecular·lerp(specular, fresnel, fresnel_strength·(1 − NV)⁴)/(r² + 1)
fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let b = srp_brdf(s);
    let x = 1.0 - sat(dot(n, v));
    let fresnel_strength = s.params0.x * x * x * x * x;
    let env = env_specular(reflect(-v, n), b.perceptual_roughness);
    let reflection = env * mix(b.specular, vec3<f32>(b.fresnel), fresnel_strength) / (b.roughness * b.roughness + 1.0);
    return indirect_diffuse(gi_diffuse * b.diffuse) + indirect_specular(reflection);
}
