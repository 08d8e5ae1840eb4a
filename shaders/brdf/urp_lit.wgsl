// URP Lit (models.md#urp-lit): InitializeBRDFData, DirectBRDFSpecular (minimal Cook-Torrance), Lambert
// without 1/π, EnvironmentBRDF. Desktop precision (no REAL_IS_HALF clamps).

const HALF_MIN: f32 = 6.103515625e-5;
const HALF_MIN_SQRT: f32 = 0.0078125;

struct UrpBrdfData {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
    perceptual_roughness: f32,
    roughness: f32,
    roughness2: f32,
    grazing_term: f32,
};

// kDielectricSpec = (0.04, 0.96); α = max(pr², 2⁻⁷); α² = max(α², 2⁻¹⁴); grazing = sat(s + reflectivity)
fn urp_brdf_data(s: Surface) -> UrpBrdfData {
    var b: UrpBrdfData;
    // _SPECULAR_SETUP (params0.x = 1): reflectivity = max(specular) (ReflectivitySpecular), specular
    // as given; else oneMinusReflectivity = 0.96(1 − m), specular = lerp(0.04, albedo, m) (BRDF.hlsl
    // InitializeBRDFData)
    var one_minus_reflectivity = 0.96 - s.metallic * 0.96;
    b.specular = mix(vec3<f32>(0.04), s.base_color, s.metallic);
    if (s.params0.x > 0.5) {
        one_minus_reflectivity = 1.0 - max(max(s.specular.r, s.specular.g), s.specular.b);
        b.specular = s.specular;
    }
    // _ALPHAPREMULTIPLY_ON: brdfData.diffuse × alpha (InitializeBRDFDataDirect)
    b.diffuse = s.base_color * one_minus_reflectivity * diffuse_weight;
    b.perceptual_roughness = 1.0 - s.smoothness;
    b.roughness = max(b.perceptual_roughness * b.perceptual_roughness, HALF_MIN_SQRT);
    b.roughness2 = max(b.roughness * b.roughness, HALF_MIN);
    b.grazing_term = sat(s.smoothness + (1.0 - one_minus_reflectivity));
    return b;
}

// spec = α²/(d²·max(0.1, LoH²)·(4α + 2)), d = NoH²(α² − 1) + 1.00001
fn spec_urp(nh: f32, lh: f32, b: UrpBrdfData) -> f32 {
    let d = nh * nh * (b.roughness2 - 1.0) + 1.00001;
    return b.roughness2 / (d * d * max(0.1, lh * lh) * (b.roughness * 4.0 + 2.0));
}

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let b = urp_brdf_data(s);
    let h = safe_normalize(l + v, 1.175494e-38);
    let nh = sat(dot(n, h));
    let lh = sat(dot(l, h));
    // _SPECULARHIGHLIGHTS_OFF (params0.y = 1): DirectBRDF returns the diffuse alone.
    if (s.params0.y > 0.5) {
        return direct_diffuse(b.diffuse * sat(dot(n, l)));
    }
    let nl = sat(dot(n, l));
    return direct_diffuse(b.diffuse * nl) + direct_specular(b.specular * spec_urp(nh, lh, b) * nl);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let b = urp_brdf_data(s);
    let x = 1.0 - sat(dot(n, v));
    let fresnel_term = x * x * x * x;
    // _ENVIRONMENTREFLECTIONS_OFF (params0.z = 1): GlossyEnvironmentReflection returns the
    // constant _GlossyEnvironmentColor, no probe or sky lookup.
    var env = vec3<f32>(0.0);
    if (s.params0.z > 0.5) {
        env = glossy_environment_color();
    } else {
        env = env_specular(reflect(-v, n), b.perceptual_roughness);
    }
    // c = bakedGI·diffuse + envSpec·1/(α² + 1)·lerp(specular, grazing, (1 − NoV)⁴)
    return indirect_diffuse(gi_diffuse * b.diffuse)
        + indirect_specular(env * (1.0 / (b.roughness2 + 1.0)) * mix(b.specular, vec3<f32>(b.grazing_term), fresnel_term));
}

// The Height Map's scale (`_Parallax`; registry PARALLAX, slot 3): the passes offset the maps'
// uv by ParallaxOffset1Step with it (conventions.wgsl parallax_offset)
fn model_height_scale(params0: vec4<f32>, params1: vec4<f32>) -> f32 {
    return params0.w;
}

// Secondary maps on (the `detail` parameter, slot 4): the passes blend them in as URP Lit's
// ApplyDetailAlbedo and ApplyDetailNormal do (materials::detail)
fn model_detail(params0: vec4<f32>, params1: vec4<f32>, params2: vec4<f32>) -> f32 {
    return params1.x;
}
