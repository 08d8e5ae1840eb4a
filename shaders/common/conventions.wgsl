// Pipeline conventions (models.md#conventions). PIPELINE is one of PIPELINE_BUILTIN, PIPELINE_URP and
// PIPELINE_HDRP (generated from pipelines::Pipeline by shading::wgsl::pipeline_ids). It is an override
// constant, so each (pipeline, model) pair compiles to its own specialised pipeline.
override PIPELINE: u32 = 0u;

// Per light, set by the pass before each model_direct call (a model's signature stays (s, n, v, l)):
// HDRP's roughness floor from the light's shape, minRoughness = (1 − maxSmoothness)² (models.md#hdrp-lit;
// twin: pipelines::Emitter::hdrp_min_roughness). Default: a point light of HDRP's radius 0.025.
var<private> light_min_roughness: f32 = 4.617e-5;
// The main directional light's colour × intensity, for models whose ambient term is scaled by it
// (the custom shader as written, models.md#torrance-sparrow); zero when the scene has none.
var<private> main_light_color: vec3<f32> = vec3<f32>(1.0);

// The share of the diffuse lobe a model's terms keep: alpha where a premultiplied surface type
// multiplies the diffuse reflectance (pipelines::surface: built-in's and URP's
// _ALPHAPREMULTIPLY_ON diffColor × alpha, HDRP's preserved specular lighting), 1 else. Set by the
// pass; the models that read it keep their diffuse lobe apart (ShaderModel::splits_diffuse).
// Twin: Surface::diffuse_weight.
var<private> diffuse_weight: f32 = 1.0;

// The terms a pass draws (pipelines::terms; TERM_* generated from it): every light term for the
// image, one group for a term layer (the cell's AOVs), TERM_OCCLUSION alone for the occlusion
// layer. An override, so the image's pipelines fold the masks away.
override TERMS: u32 = TERM_LIGHT;

fn term_kept(bits: u32) -> bool {
    return (TERMS & bits) != 0u;
}

// A model's lobes, each kept where its term is drawn: models wrap their diffuse and specular
// parts in these (ShaderModel::splits_lobes); twin: Surface::lobes.
fn direct_diffuse(c: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), c, term_kept(TERM_DIRECT_DIFFUSE)) * light_diffuse_dimmer;
}

fn direct_specular(c: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), c, term_kept(TERM_DIRECT_SPECULAR)) * light_specular_dimmer;
}

// 1 where the pipeline draws the split diffuse lighting of HDRP's Subsurface Scattering type
// (forward.wgsl fs_subsurface): its diffuse colour is then the pre-scatter √albedo
// (GetModifiedDiffuseColorForSSS, PreAndPostScatter); 0 everywhere else, as where HDRP runs no
// SSS pass (_EnableSubsurfaceScattering 0: the albedo whole). An override, so the other
// pipelines fold the branch away.
override SUBSURFACE_PRE_SCATTER: u32 = 0u;

// The ambient light at −N, as the pass evaluates it at N (HDRP's backBakeDiffuseLighting): what a
// transmitting model lets through; 0 where the pass gives none (the truth, the probes)
var<private> gi_back_diffuse: vec3<f32> = vec3<f32>(0.0);

// The lobes the light being evaluated reaches: HDRP's diffuseDimmer and specularDimmer without
// the lightDimmer (folded into the light's colour); 1 outside a light loop (the truth, probes)
var<private> light_diffuse_dimmer: f32 = 1.0;
var<private> light_specular_dimmer: f32 = 1.0;

fn indirect_diffuse(c: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), c, term_kept(TERM_INDIRECT_DIFFUSE));
}

fn indirect_specular(c: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), c, term_kept(TERM_INDIRECT_SPECULAR));
}

// Light the surface gives off rather than reflects (emission, an unlit colour, the sky)
fn emitted(c: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), c, term_kept(TERM_EMISSION));
}

// Material as the model receives it: metallic already converted by the pipeline (presets.md).
// specular: the models that take a specular colour; params0/params1/params2: the model's own parameters (slots 0–11)
// by slot (registry ParamSpec); tangent: the mesh's world tangent at the point, not yet orthogonal
// to the normal (zero: none), which HDRP Lit's anisotropy reads. Twin: shading::twin::Surface.
struct Surface {
    base_color: vec3<f32>,
    metallic: f32,
    smoothness: f32,
    specular: vec3<f32>,
    params0: vec4<f32>,
    params1: vec4<f32>,
    params2: vec4<f32>,
    tangent: vec3<f32>,
};

// Irradiance delivered per unit of light "intensity": built-in and URP intensities carry π (models.md#builtin "The π convention")
fn irradiance_per_intensity() -> f32 {
    if (PIPELINE == PIPELINE_HDRP) {
        return 1.0;
    }
    return PI;
}

// Unity's legacy falloff (core PathTracing/LightFalloffLUT.cs LegacyUnityFalloff; built-in's
// _LightTextureB0): 1/(1 + 25x²), x = d/range clamped to 1, faded linearly in x² from 0.64 to 1;
// twin: pipelines::BakedFalloff::Legacy
fn legacy_unity_falloff(d: f32, range: f32) -> f32 {
    let x2 = sat(d / range) * sat(d / range);
    return (1.0 / (1.0 + 25.0 * x2)) * select(1.0, 1.0 - (x2 - 0.64) / 0.36, x2 >= 0.64);
}

// Distance attenuation, d in metres (models.md#builtin built-in approximation, models.md#urp URP, models.md#hdrp HDRP); twin: pipelines::Attenuation
fn distance_attenuation(d: f32, range: f32) -> f32 {
    let d2 = d * d;
    if (PIPELINE == PIPELINE_BUILTIN) {
        // _LightTextureB0's legacy curve, as core's LightFalloffLUT.cs LegacyUnityFalloff has it
        return legacy_unity_falloff(d, range);
    }
    if (PIPELINE == PIPELINE_URP) {
        // (1/max(d², HALF_MIN))·sat(1 − (d²/r²)²)²
        let a = 1.0 / max(range * range, 1e-4);
        let f = sat(1.0 - (d2 * a) * (d2 * a));
        return f * f / max(d2, 6.103515625e-5);
    }
    // [min(1/d, 1/0.01)·sat(1 − (d²/r²)²)]²
    let f = sat(1.0 - (d2 / (range * range)) * (d2 / (range * range)));
    let g = min(1.0 / d, 100.0) * f;
    return g * g;
}

// The lightmapper's distance falloff (twin: pipelines::BakedFalloff; core
// PathTracing/LightFalloffLUT.cs): built-in bakes LegacyUnityFalloff (`legacy`), URP and HDRP
// InverseSquaredFalloffSmooth, as their lights delegates set
fn baked_distance_attenuation(legacy: bool, d: f32, range: f32) -> f32 {
    if (legacy) {
        return legacy_unity_falloff(d, range);
    }
    // (1/max(d², 10⁻⁴))·sat(1 − (d²/max(r², 10⁻⁴))²)²
    let d2 = d * d;
    let factor = d2 / max(range * range, 1e-4);
    let window = sat(1.0 - factor * factor);
    return window * window / max(d2, 1e-4);
}

// Spot cone: sat((S·L − cosOuter)/max(ε, cosInner − cosOuter))² (URP models.md#urp; HDRP's form is the same with ε = 1e-4)
fn angle_attenuation(cos_angle: f32, cos_outer: f32, cos_inner: f32) -> f32 {
    let a = sat((cos_angle - cos_outer) / max(0.001, cos_inner - cos_outer));
    return a * a;
}

// ParallaxOffset1Step (built-in UnityCG.cginc, URP ParallaxMapping.hlsl): the height h (0..1) of
// the height map at uv, scaled about its middle, h·height − height/2, along the tangent-space view
// direction, whose z is raised by 0.42 to bound the shift at grazing angles. Twin:
// materials::parallax_offset.
fn parallax_offset(h: f32, height: f32, view_ts: vec3<f32>) -> vec2<f32> {
    let hh = h * height - height / 2.0;
    var v = normalize(view_ts);
    v.z += 0.42;
    return hh * (v.xy / v.z);
}

// Standard's secondary maps (materials::detail): detail tiles per main tile (_DetailAlbedoMap_ST)
const DETAIL_TILING: f32 = 4.0;

// LerpWhiteTo(detailAlbedo·unity_ColorSpaceDouble, mask), 2^2.2 in linear space (UnityStandardInput.cginc Albedo, _DETAIL_MULX2)
fn detail_albedo_mulx2(detail_albedo: f32, mask: f32) -> f32 {
    return 1.0 + (detail_albedo * 4.59479380 - 1.0) * mask;
}

// URP Lit's LerpWhiteTo(2·detailAlbedo, mask) (LitInput.hlsl ApplyDetailAlbedo): its detail albedo is
// linear data, 0.5 neutral, so the grain's texels are read as encoded (linear_to_srgb of the stored
// linear value); twin: materials::detail_albedo_x2_urp
fn detail_albedo_x2_urp(detail_albedo: f32, mask: f32) -> f32 {
    return 1.0 + (2.0 * linear_to_srgb(detail_albedo) - 1.0) * mask;
}

// BlendNormalRNM (core CommonMaterial.hlsl): t = n₁ + (0, 0, 1), u = n₂·(−1, −1, 1), (t/t.z)·(t·u) − u
fn blend_normal_rnm(n1: vec3<f32>, n2: vec3<f32>) -> vec3<f32> {
    let t = n1 + vec3<f32>(0.0, 0.0, 1.0);
    let u = n2 * vec3<f32>(-1.0, -1.0, 1.0);
    return (t / t.z) * dot(t, u) - u;
}

// The pipeline's secondary-map albedo factor: Standard's ×unity_ColorSpaceDouble, URP's ×2; HDRP's
// overlay acts on the base colour instead (hdrp_detail_albedo), so its factor is 1 (twin:
// materials::detail_blend)
fn detail_albedo_factor(detail_albedo: f32, mask: f32) -> f32 {
    if (PIPELINE == PIPELINE_URP) {
        return detail_albedo_x2_urp(detail_albedo, mask);
    }
    if (PIPELINE == PIPELINE_HDRP) {
        return 1.0;
    }
    return detail_albedo_mulx2(detail_albedo, mask);
}

// HDRP Lit's detail albedo overlay (LitDataIndividualLayer.hlsl): d = 2·r − 1 of the detail map's r
// (linear data: the grain's texel as encoded), s = sat(|d|), the colour lerped in √ space towards
// black or white by s², squared back, then lerp(base, sat(overlay), mask)
fn hdrp_detail_albedo(base: vec3<f32>, detail_albedo: f32, mask: f32) -> vec3<f32> {
    let d = linear_to_srgb(detail_albedo) * 2.0 - 1.0;
    let speed = sat(abs(d));
    var overlay = mix(sqrt(base), select(vec3<f32>(1.0), vec3<f32>(0.0), d < 0.0), speed * speed);
    overlay *= overlay;
    return mix(base, sat3(overlay), mask);
}

// The pipeline's secondary-map normal: Standard's lerp(n, BlendNormals(n, d), mask), URP's and
// HDRP's lerp(n, BlendNormalRNM(n, normalize(d)), mask)
fn detail_blended_normal(ts: vec3<f32>, detail: vec3<f32>, mask: f32) -> vec3<f32> {
    if (PIPELINE != PIPELINE_BUILTIN) {
        return mix(ts, blend_normal_rnm(ts, normalize(detail)), mask);
    }
    return mix(ts, blend_normals(ts, detail), mask);
}

// normalize(n₁.xy + n₂.xy, n₁.z·n₂.z) (UnityStandardUtils.cginc BlendNormals)
fn blend_normals(n1: vec3<f32>, n2: vec3<f32>) -> vec3<f32> {
    return normalize(vec3<f32>(n1.xy + n2.xy, n1.z * n2.z));
}
