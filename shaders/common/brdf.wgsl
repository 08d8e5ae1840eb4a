// BRDF terms shared by several models (models.md#builtin, models.md#classic).

// ρ/π (models.md#classic Lambert)
fn fd_lambert(albedo: vec3<f32>) -> vec3<f32> {
    return albedo * INV_PI;
}

// F = F0 + (1 − F0)(1 − c)⁵ (models.md#builtin FresnelTerm, models.md#classic Schlick)
fn f_schlick(f0: vec3<f32>, c: f32) -> vec3<f32> {
    return f0 + (vec3<f32>(1.0) - f0) * pow5(1.0 - c);
}

// lerp(F0, F90, (1 − c)⁵) (models.md#builtin FresnelLerp)
fn f_schlick_lerp(f0: vec3<f32>, f90: vec3<f32>, c: f32) -> vec3<f32> {
    return mix(f0, f90, pow5(1.0 - c));
}

// cos(φi − φr): the tangent-plane projections of L and V, normalised; 0 when either is along N (models.md#classic Oren-Nayar)
fn cos_azimuth_difference(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, nl: f32, nv: f32) -> f32 {
    let lp = l - n * nl;
    let vp = v - n * nv;
    let d = dot(lp, lp) * dot(vp, vp);
    if (d < 1e-12) {
        return 0.0;
    }
    return dot(lp, vp) * inverseSqrt(d);
}

// D_GGX = α²/(π(NH²(α² − 1) + 1)²) (models.md#classic GGX / Torrance-Sparrow)
fn d_ggx(nh: f32, a: f32) -> f32 {
    let a2 = a * a;
    let d = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// D_Beckmann = exp((NH² − 1)/(m²NH²))/(π m² NH⁴), NH² ≥ ε, m ≥ 1e-3 (models.md#classic Beckmann, models.md#stability)
fn d_beckmann(nh: f32, m: f32) -> f32 {
    let m2 = max(m, 1e-3) * max(m, 1e-3);
    let nh2 = max(nh * nh, 1e-8);
    return exp((nh2 - 1.0) / (m2 * nh2)) / (PI * m2 * nh2 * nh2);
}

// G = min(1, 2NH·NV/VH, 2NH·NL/VH), VH ≥ ε (models.md#classic Cook-Torrance G, models.md#stability)
fn g_cook_torrance(nh: f32, nv: f32, nl: f32, vh: f32) -> f32 {
    return min(1.0, 2.0 * nh * min(nv, nl) / max(vh, 1e-4));
}

// Full dielectric Fresnel, c = VH, g = √(η² + c² − 1); g² < 0 is TIR, F = 1 (models.md#classic, models.md#stability)
fn f_fresnel_dielectric(c: f32, eta: f32) -> f32 {
    let g2 = eta * eta + c * c - 1.0;
    if (g2 < 0.0) {
        return 1.0;
    }
    let g = sqrt(g2);
    let a = (g - c) / (g + c);
    let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * a * a * (1.0 + b * b);
}

// G1(x) = x/(x(1 − k) + k): Vis = G1(NL)G1(NV)/(4NL·NV) = 1/(4(NL(1−k)+k)(NV(1−k)+k)) (models.md#classic Smith-Schlick)
fn v_smith_schlick(nl: f32, nv: f32, k: f32) -> f32 {
    return 0.25 / ((nl * (1.0 - k) + k) * (nv * (1.0 - k) + k));
}

// exp2(10·s + 1): URP Simple Lit shininess, 2..2048 (models.md#urp); the classic models use it too
fn shininess_from_smoothness(s: f32) -> f32 {
    return exp2(10.0 * s + 1.0);
}

// HDRP's FGD table at (√NV, pr), texel centres at i/63, bilinear by hand so the f64 twin can do
// exactly the same (twin: shading::fgd::FgdTable::lookup). x: F90 weight, y: reflectivity, z: diffuse − 0.5.
fn fgd_sample(lut: texture_2d<f32>, nv: f32, pr: f32) -> vec3<f32> {
    let fx = clamp(sqrt(clamp(nv, 0.0, 1.0)) * 63.0, 0.0, 63.0);
    let fy = clamp(clamp(pr, 0.0, 1.0) * 63.0, 0.0, 63.0);
    let x0 = min(floor(fx), 62.0);
    let y0 = min(floor(fy), 62.0);
    let tx = fx - x0;
    let ty = fy - y0;
    let i = vec2<i32>(i32(x0), i32(y0));
    let a = mix(textureLoad(lut, i, 0).xyz, textureLoad(lut, i + vec2<i32>(1, 0), 0).xyz, tx);
    let b = mix(textureLoad(lut, i + vec2<i32>(0, 1), 0).xyz, textureLoad(lut, i + vec2<i32>(1, 1), 0).xyz, tx);
    return mix(a, b, ty);
}

// The custom roughness/metallic shader's terms, shared by `torrance_sparrow` (as written) and
// `torrance_sparrow_corrected` (models.md#torrance-sparrow). F0 = ((1 − IOR)/(1 + IOR))², lerped to albedo by metallic
fn ts_f0(s: Surface) -> vec3<f32> {
    let f = (1.0 - s.params0.x) / (1.0 + s.params0.x);
    return mix(vec3<f32>(f * f), s.base_color, s.metallic);
}

// The final stage's direct term: albedo·NL·(1 − metallic) + albedo·tint·max(0, D·Vis·π·NL), D GGX with
// a = r², Vis Smith-Schlick with k = r²/2. QUIRKS: no F on the direct specular, and the specular is
// multiplied by albedo even for dielectrics
fn ts_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let r = 1.0 - s.smoothness;
    let nl = sat(dot(n, l));
    let nv = sat(dot(n, v));
    let h = safe_normalize(l + v, 1.175494e-38);
    let nh = sat(dot(n, h));
    let specular = max(0.0, d_ggx(nh, r * r) * v_smith_schlick(nl, nv, r * r * 0.5) * PI * nl);
    return direct_diffuse(s.base_color * nl * (1.0 - s.metallic)) + direct_specular(s.base_color * s.specular * specular);
}

// Cook-Torrance's Fresnel as both forms use it: the full dielectric Fresnel at VH from the IOR,
// lerped by metallic to Schlick with F0 = base colour (models.md#cook-torrance)
fn ct_fresnel(s: Surface, vh: f32) -> vec3<f32> {
    return mix(vec3<f32>(f_fresnel_dielectric(vh, s.params0.x)), f_schlick(s.base_color, vh), s.metallic);
}

// What both Cook-Torrance forms share at one (n, v, l): F, NH, VH, NL, NV, m = α = pr²; valid = false
// below the horizon (twin: shading::twin::classic::cook_torrance_angles)
struct CookTorranceAngles {
    f: vec3<f32>,
    nh: f32,
    vh: f32,
    nl: f32,
    nv: f32,
    m: f32,
    valid: bool,
};

fn cook_torrance_angles(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> CookTorranceAngles {
    var a: CookTorranceAngles;
    a.nl = dot(n, l);
    a.nv = dot(n, v);
    a.valid = a.nl > 0.0 && a.nv > 0.0;
    let h = safe_normalize(l + v, 1.175494e-38);
    a.nh = sat(dot(n, h));
    a.vh = sat(dot(v, h));
    let pr = 1.0 - s.smoothness;
    a.m = pr * pr;
    a.f = ct_fresnel(s, a.vh);
    return a;
}

// Both forms' kd·ρ/π plus the specular, times NL and the pipeline's irradiance per intensity
fn cook_torrance_sum(s: Surface, a: CookTorranceAngles, spec: vec3<f32>) -> vec3<f32> {
    let k = a.nl * irradiance_per_intensity();
    return direct_diffuse(s.base_color * (1.0 - s.metallic) * INV_PI * k) + direct_specular(spec * k);
}

// GTAOMultiBounce (Jimenez et al. 2016; core AmbientOcclusion.hlsl): max(x, ((x·a + b)·x + c)·x),
// a = 2.0404·ρ − 0.3324, b = −4.7951·ρ + 0.6417, c = 2.7552·ρ + 0.6903
fn gtao_multi_bounce(visibility: f32, albedo: vec3<f32>) -> vec3<f32> {
    let a = 2.0404 * albedo - 0.3324;
    let b = -4.7951 * albedo + 0.6417;
    let c = 2.7552 * albedo + 0.6903;
    let x = visibility;
    return max(vec3<f32>(x), ((x * a + b) * x + c) * x);
}

// GetSpecularOcclusionFromAmbientOcclusion (Lagarde and de Rousiers 2014; core
// CommonLighting.hlsl): sat((NV + ao)^exp2(−16·α − 1) − 1 + ao), α the roughness
fn specular_occlusion_from_ao(nv: f32, ao: f32, roughness: f32) -> f32 {
    return sat(pow(nv + ao, exp2(-16.0 * roughness - 1.0)) - 1.0 + ao);
}
