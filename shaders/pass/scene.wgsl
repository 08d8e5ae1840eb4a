// Frame and object data shared by the forward and background passes; twin: render::uniforms.

struct Light {
    position: vec4<f32>,   // xyz position (an area light's centre); w: 0 directional, 1 point, 2 spot, 3 rect, 4 disc
    direction: vec4<f32>,  // xyz direction the light travels
    color: vec4<f32>,      // linear colour × intensity in the pipeline's units (an area light: its luminance)
    params: vec4<f32>,     // range, cos outer, cos inner, HDRP minRoughness of the light's shape; area: range, half width, half height
    shadow: vec4<f32>,     // first shadow layer (−1: none), layer count, strength, soft
    shadow_bias: vec4<f32>, // bias, normal bias (shadow-map texels); z 1: a dynamic object's probe occlusion scales the light (plan::gi::ProbeOcclusion); w HDRP's tent width (plan::shadows::hdrp_tent)
    shape: vec4<f32>,      // area lights, pyramid and box spots: right axis; w = 1 where the frame draws it (an HDRP rect)
    features: vec4<f32>,   // HDRP (plan::light_terms): affect diffuse, affect specular (0/1), shadow tint mode (0 none, 1 tint, 2 penumbra), flags (LIGHT_RANGE_STEP, LIGHT_PYRAMID, LIGHT_BOX)
    shadow_tint: vec4<f32>, // rgb: the shadow tint (linear)
};

const LIGHT_RANGE_STEP: u32 = 1u;
const LIGHT_PYRAMID: u32 = 2u;
const LIGHT_BOX: u32 = 4u;

// One shadow-map layer (plan::shadows): view-projection; params.x texel size (world units, or
// per unit of view depth when params.y = 1, perspective), params.z the map's resolution, params.w
// the share of the layer's side it fills (from the top-left)
struct ShadowLayer {
    view_proj: mat4x4<f32>,
    params: vec4<f32>,
    sphere: vec4<f32>,     // directional cascades: the bounding sphere of the frustum slice it covers
    // HDRP's PCSS (plan::shadows::hdrp_pcss): softness, minimum filter radius, and (zBufferParam)
    // a perspective map's 1/z terms, an orthographic one's range scale in z
    pcss: vec4<f32>,
};

struct Material {
    base_color: vec4<f32>,   // linear
    params: vec4<f32>,       // metallic (as the shader receives it), smoothness, checker cell (0: none), w: maps (the subject: 1; a fixed object: 1 + its slot in fixed_maps; 0: none)
    checker_color: vec4<f32>, // w: 1 where the specular workflow is carried over per texel (`carried_specular`)
    specular: vec4<f32>,     // the model's specular colour (the dielectric F0 where checker_color.w is 1)
    model0: vec4<f32>,       // the model's parameters, slots 0–3
    model1: vec4<f32>,       // slots 4–7
    model2: vec4<f32>,       // slots 8–11
    emission: vec4<f32>,     // emitted radiance (the subject's, where its model emits); w: 1 smoothness from the albedo map's alpha
};

// A reflection probe (render::passes::probes): its levels are layers box_max.w … + 6 of env_probe.
struct ReflectionProbe {
    position: vec4<f32>,   // w: 1 box projection + 2 × the weight rule (plan::probes::ProbeWeight)
    box_min: vec4<f32>,    // w: blend distance
    box_max: vec4<f32>,    // w: first layer
};

struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    camera_pos: vec4<f32>,
    counts: vec4<u32>,        // x: light count, y: 1 + main directional light index (0: none)
    sh: array<vec4<f32>, 9>,  // cosine-convolved SH of the environment: E(n)/π = Σ sh[i]·Y_i(n)
    env: vec4<f32>,           // x: probe levels − 1, y: radiance scale
    subject: Material,
    fixed: Material,          // the fixed objects' model inputs besides the G-buffer's (deferred lighting)
    reflection: vec4<u32>,    // x: probes blended (0: the sky alone)
    probes: array<ReflectionProbe, 4>,
    screen: vec4<f32>,        // x, y: the target's size in pixels; z 1: HDRP's deferred Lit folds its occlusion into the baked light (plan::ao::AoUse::in_bake); w: URP's SSAO direct lighting strength
};

struct Object {
    model: mat4x4<f32>,
    normal_matrix: mat4x4<f32>,
    material: Material,
    flags: vec4<u32>,         // x: 1 = subject (uses the swept material), y: role id written to the mask, z: object index
    light_sh: array<vec4<f32>, 9>, // the lights this object takes as SH (plan::lights), unscaled
    lod: vec4<f32>,           // x: LOD cross-fade (plan::lod), y: 1 when dithered
    bake: vec4<f32>,          // x: ambient from 0 the sky, 1 its probe, 2 its lightmap; y: 1 directional | 2 subtractive
    occlusion: vec4<f32>,     // its probe's occlusion of each shadow-mask light
    reflection_probe: vec4<u32>, // x: 1 + the probe it takes at full weight (plan::probes::renderer_probe), 0 none
    shadow_color: vec4<f32>,  // Subtractive's Realtime Shadow Color, linear
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var env_probe: texture_2d_array<f32>;
@group(0) @binding(2) var env_sampler: sampler;
@group(0) @binding(3) var fgd_lut: texture_2d<f32>;
// Every light of the scene, and per object × light how it is rendered (plan::lights::LightMode:
// 0 per-pixel, 1 per-vertex, 2 SH, 3 dropped), index object·counts.x + light.
@group(0) @binding(4) var<storage, read> lights: array<Light>;
@group(0) @binding(5) var<storage, read> light_modes: array<u32>;
@group(0) @binding(6) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(7) var shadow_sampler: sampler_comparison;
@group(0) @binding(8) var<storage, read> shadow_layers: array<ShadowLayer>;
// The subject's material maps (render::material_maps; a neutral 1×1 set for a flat subject):
// albedo modulation (linear), tangent-space normal, mask in HDRP's layout (r metallic, g occlusion,
// b detail mask, a 0.5 + smoothness offset).
@group(0) @binding(9) var material_albedo: texture_2d<f32>;
@group(0) @binding(10) var material_normal: texture_2d<f32>;
@group(0) @binding(11) var material_mask: texture_2d<f32>;
@group(0) @binding(12) var material_sampler: sampler;
// Emission multiplier (a glTF material's emissiveTexture; white otherwise).
@group(0) @binding(13) var material_emission: texture_2d<f32>;
// The fixed objects' maps in the same layouts (render::prepared::GpuFixedMaps): layers 4k … 4k + 3
// the albedo, normal, mask and emission maps of material k, for a fixed object whose
// `material.params.w` is k + 1.
@group(0) @binding(14) var fixed_maps: texture_2d_array<f32>;
// Standard's secondary maps (materials::detail): detail normal xyz, linear detail albedo w;
// the subject's, tiled DETAIL_TILING times over its maps.
@group(0) @binding(15) var material_detail: texture_2d<f32>;
// The static objects' lightmap (render::gi::lightmaps): layer 0 the irradiance/π as the pipeline
// stores it (RGBM in built-in and URP, half floats in HDRP), layer 1 the dominant direction, layer 2
// the shadow mask
@group(0) @binding(16) var lightmap: texture_2d_array<f32>;

// 5^2.2: the RGBM range in linear colour space (core EntityLighting.hlsl LIGHTMAP_RGBM_MAX_LINEAR)
const LIGHTMAP_RGBM_MAX_LINEAR: f32 = 34.493242;

// UnpackLightmapRGBM, linear colour space: rgb·a^2.2·5^2.2 (twin: render::gi::lightmaps)
fn unpack_lightmap_rgbm(c: vec4<f32>) -> vec3<f32> {
    return c.rgb * (pow(c.a, 2.2) * LIGHTMAP_RGBM_MAX_LINEAR);
}

// DecodeDirectionalLightmap (UnityCG.cginc; core EntityLighting.hlsl): half-Lambert against the
// baked dominant direction, rebalanced by w (twin: render::gi::lightmaps)
fn decode_directional_lightmap(color: vec3<f32>, dir: vec4<f32>, n: vec3<f32>) -> vec3<f32> {
    let half_lambert = dot(n, dir.xyz - 0.5) + 0.5;
    return color * half_lambert / max(1e-4, dir.w);
}

// UnpackLightmapDoubleLDR in linear colour space: rgb · 4.59 (core EntityLighting.hlsl
// LIGHTMAP_HDR_MULTIPLIER, 2^2.2 rounded; twin: render::gi::lightmaps::unpack_lightmap_double_ldr)
fn unpack_lightmap_double_ldr(c: vec4<f32>) -> vec3<f32> {
    return c.rgb * 4.59;
}

// The baked diffuse light at uv for normal n: SampleLightmap / SampleDirectionalLightmap
// (URP Lighting, HDRP SampleBakedGI, built-in UnityGI_Base), decoded as the Lightmap Encoding
// stores it (`encoding`: 0 High Quality, 1 Normal Quality RGBM, 2 Low Quality double LDR)
fn lightmap_gi(uv: vec2<f32>, n: vec3<f32>, directional: bool, encoding: f32) -> vec3<f32> {
    let encoded = textureSampleLevel(lightmap, env_sampler, uv, 0, 0.0);
    var color = encoded.rgb;
    if (encoding > 1.5) {
        color = unpack_lightmap_double_ldr(encoded);
    } else if (encoding > 0.5) {
        color = unpack_lightmap_rgbm(encoded);
    }
    if (directional) {
        color = decode_directional_lightmap(color, textureSampleLevel(lightmap, env_sampler, uv, 1, 0.0), n);
    }
    return max(color, vec3<f32>(0.0));
}

// The layer of a fixed material's map `k` (0 albedo, 1 normal, 2 mask, 3 emission) in fixed_maps.
fn fixed_map_layer(m: Material, k: i32) -> i32 {
    return 4 * (i32(m.params.w + 0.5) - 1) + k;
}

// A fixed material's map `k` at uv, finest level.
fn fixed_map_level0(m: Material, k: i32, uv: vec2<f32>) -> vec4<f32> {
    return textureSampleLevel(fixed_maps, material_sampler, uv, fixed_map_layer(m, k), 0.0);
}

fn light_mode(object_index: u32, light: u32) -> u32 {
    return light_modes[object_index * frame.counts.x + light];
}

// Real SH basis, bands 0–2, times nine coefficients (twin: environment::sh)
fn sh_eval(c: array<vec4<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    var r = c[0].rgb * 0.282095;
    r += c[1].rgb * (0.488603 * n.y);
    r += c[2].rgb * (0.488603 * n.z);
    r += c[3].rgb * (0.488603 * n.x);
    r += c[4].rgb * (1.092548 * n.x * n.y);
    r += c[5].rgb * (1.092548 * n.y * n.z);
    r += c[6].rgb * (0.315392 * (3.0 * n.z * n.z - 1.0));
    r += c[7].rgb * (1.092548 * n.x * n.z);
    r += c[8].rgb * (0.546274 * (n.x * n.x - n.y * n.y));
    return r;
}

fn fgd_lookup(nv: f32, pr: f32) -> vec3<f32> {
    return fgd_sample(fgd_lut, nv, pr);
}

const LIGHT_RECT: u32 = 3u;
const LIGHT_DISC: u32 = 4u;

// A rect light's corners relative to p: −right−up, −right+up, +right+up, +right−up with
// up = forward × right (HDRP's LL, UL, UR, LR; twin: ltc::RectLight::vertices)
fn rect_corners(light: Light, p: vec3<f32>) -> array<vec3<f32>, 4> {
    let forward = normalize(light.direction.xyz);
    let r = light.shape.xyz * light.params.y;
    let u = cross(forward, light.shape.xyz) * light.params.z;
    let c = light.position.xyz - p;
    return array<vec3<f32>, 4>(c - r - u, c - r + u, c + r + u, c + r - u);
}

// HDRP's BoxDistanceAttenuation of a rect light, range normalised (rangeAttenuationScale = 1): the
// light-space vector over (range + w/2, range + h/2, range), cube mapped to sphere, sat(1 − d²)²;
// 0 behind the light (twin: ltc::RectLight::attenuation)
fn rect_attenuation(light: Light, p: vec3<f32>) -> f32 {
    let forward = normalize(light.direction.xyz);
    let un_l = light.position.xyz - p;
    if (dot(forward, un_l) >= 1.192092896e-7) {
        return 0.0;
    }
    let range = light.params.x;
    let q = vec3<f32>(dot(un_l, light.shape.xyz), dot(un_l, cross(forward, light.shape.xyz)), dot(un_l, -forward))
        / vec3<f32>(range + light.params.y, range + light.params.z, range);
    if (max(max(abs(q.x), abs(q.y)), abs(q.z)) > 1.0) {
        return 0.0;
    }
    let q2 = q * q;
    let sq = dot(q, q) - q2.x * q2.y - q2.y * q2.z - q2.z * q2.x + q2.x * q2.y * q2.z;
    let w = sat(1.0 - sq * sq);
    return w * w;
}


// The environment's ambient term E(n)/π from its SH (twin: environment::sh)
fn ambient_diffuse(n: vec3<f32>) -> vec3<f32> {
    return max(sh_eval(frame.sh, n), vec3<f32>(0.0)) * frame.env.y;
}

// Equirectangular lookup (u: azimuth from −Z towards +X, v: polar angle from +Y); twin: environment::dir_to_uv
fn equirect_uv(d: vec3<f32>) -> vec2<f32> {
    return vec2<f32>(atan2(d.x, -d.z) * (0.5 * INV_PI) + 0.5, acos(clamp(d.y, -1.0, 1.0)) * INV_PI);
}

fn probe_level(d: vec3<f32>, level: f32) -> vec3<f32> {
    return textureSampleLevel(env_probe, env_sampler, equirect_uv(d), i32(level), 0.0).rgb;
}

// The world position being shaded, for the probes' weights and box projection; set by the
// passes before they evaluate a model (`shade`, the G-buffer pass).
var<private> shading_position: vec3<f32> = vec3<f32>(0.0);
// The probe the shaded renderer takes at full weight where probes are chosen per renderer
// (Object.reflection_probe.x − 1; −1 none), set with shading_position.
var<private> renderer_probe: i32 = -1;

// A probe's seven levels at mip (layers from `first`), blended linearly between levels.
fn probe_levels(d: vec3<f32>, mip: f32, first: f32) -> vec3<f32> {
    let lo = floor(mip);
    let hi = min(lo + 1.0, frame.env.x);
    return mix(probe_level(d, first + lo), probe_level(d, first + hi), mip - lo);
}

// A probe's weight at p by its engine's rule (plan::probes::ProbeWeight; k: its index):
// 0 URP CalculateProbeWeight (GlobalIllumination.hlsl), sat(min over axes of the distance into the
//   box / blend distance);
// 1 built-in Internal-DeferredReflections, saturate(1 − |distance outside the box| / blend distance);
// 2 the renderer's own probe at full weight (URP without probe blending).
fn probe_weight(p: vec3<f32>, probe: ReflectionProbe, k: u32) -> f32 {
    let mode = u32(probe.position.w) >> 1u;
    let blend = max(probe.box_min.w, 1e-4);
    if (mode == 1u) {
        let outside = max(max(p - probe.box_max.xyz, probe.box_min.xyz - p), vec3<f32>(0.0));
        return sat(1.0 - length(outside) / blend);
    }
    if (mode == 2u) {
        return select(0.0, 1.0, i32(k) == renderer_probe);
    }
    let inside = min(p - probe.box_min.xyz, probe.box_max.xyz - p) / blend;
    return sat(min(inside.x, min(inside.y, inside.z)));
}

// BoxProjectedCubemapDirection (UnityStandardUtils.cginc; URP BoxProjectedCubemapDirection): the
// ray from p along r meets the box; the lookup direction is from the probe to that point.
// Built-in deferred box-projects on the box grown by the blend distance, the volume it draws.
fn box_projected_direction(r: vec3<f32>, p: vec3<f32>, probe: ReflectionProbe) -> vec3<f32> {
    let d = normalize(r);
    let grow = select(0.0, probe.box_min.w, (u32(probe.position.w) >> 1u) == 1u);
    let rb = select(probe.box_min.xyz - grow, probe.box_max.xyz + grow, d > vec3<f32>(0.0)) - p;
    let f = rb / d;
    let fa = min(min(f.x, f.y), f.z);
    return p - probe.position.xyz + d * fa;
}

// Prefiltered environment along r; mip = pr(1.7 − 0.7·pr)·6 (models.md#builtin reflection-probe
// mip), levels blended linearly. With probes: each probe in order takes its weight, capped at
// what the earlier ones left, and the sky the rest (URP CalculateIrradianceFromReflectionProbes;
// HDRP's reflection hierarchy likewise ends with the sky). A probe's captured radiance is in the
// pipeline's units already; the sky's is scaled by the environment's intensity.
fn env_specular(r: vec3<f32>, perceptual_roughness: f32) -> vec3<f32> {
    return environment_reflection(r, perceptual_roughness) * indirect_specular_occlusion;
}

// URP's _GlossyEnvironmentColor, what a material with Environment Reflections off reflects
// (_ENVIRONMENTREFLECTIONS_OFF): the ambient probe's L0 coefficients × reflectionIntensity (1)
// (UniversalRenderPipeline.SetupPerFrameShaderConstants), i.e. the environment's mean radiance:
// the L0 term of the ambient SH (E/π's L0 is the mean radiance).
fn glossy_environment_color() -> vec3<f32> {
    return frame.sh[0].rgb * 0.282095 * frame.env.y;
}

// The occlusion of the reflected environment at the shaded point: HDRP's indirect specular
// occlusion (forward.wgsl `indirect_light`), 1 elsewhere.
var<private> indirect_specular_occlusion: vec3<f32> = vec3<f32>(1.0);

fn environment_reflection(r: vec3<f32>, perceptual_roughness: f32) -> vec3<f32> {
    let pr = perceptual_roughness;
    let mip = clamp(pr * (1.7 - 0.7 * pr) * 6.0, 0.0, frame.env.x);
    var c = vec3<f32>(0.0);
    var total = 0.0;
    for (var i = 0u; i < frame.reflection.x; i++) {
        let probe = frame.probes[i];
        let w = min(probe_weight(shading_position, probe, i), 1.0 - total);
        if (w > 0.0) {
            var d = r;
            if ((u32(probe.position.w) & 1u) == 1u) {
                d = box_projected_direction(r, shading_position, probe);
            }
            c += probe_levels(d, mip, probe.box_max.w) * w;
            total += w;
        }
    }
    if (total < 0.99) {
        c += probe_levels(r, mip, 0.0) * frame.env.y * (1.0 - total);
    }
    return c;
}

// 0 where no light of the frame has HDRP's terms beyond its colour (plan::lights::LightPaths):
// the lobe weights, projector windows, range step and shadow tint are compiled out of the loops
override HDRP_LIGHT_TERMS: u32 = 1u;

// Direction to the light and its attenuation at p (distance and cone; directional: 1)
fn light_incidence(light: Light, p: vec3<f32>) -> vec4<f32> {
    let kind = u32(light.position.w);
    if (kind == 0u) {
        return vec4<f32>(-normalize(light.direction.xyz), 1.0);
    }
    if (HDRP_LIGHT_TERMS == 1u && (u32(light.features.w) & (LIGHT_RANGE_STEP | LIGHT_PYRAMID | LIGHT_BOX)) != 0u) {
        return hdrp_light_incidence(light, p);
    }
    let to_light = light.position.xyz - p;
    let d = length(to_light);
    let l = to_light / max(d, 1e-6);
    var atten = distance_attenuation(d, light.params.x);
    if (kind == 2u) {
        atten *= angle_attenuation(dot(normalize(light.direction.xyz), -l), light.params.y, light.params.z);
    }
    return vec4<f32>(l, atten);
}

// HDRP's punctual light with its own settings (LightEvaluation.hlsl EvaluateLight_Punctual,
// PunctualLightCommon.hlsl GetPunctualLightVectors; twin: pipelines::hdrp_light): a box shines
// along its axis with no 1/d, a pyramid or box clips to its projector window, and with Range
// Attenuation off the window is a step at the range
fn hdrp_light_incidence(light: Light, p: vec3<f32>) -> vec4<f32> {
    let flags = u32(light.features.w);
    let forward = normalize(light.direction.xyz);
    let to_sample = p - light.position.xyz;
    let box_light = (flags & LIGHT_BOX) != 0u;
    var l = -forward;
    var d = dot(to_sample, forward);
    var inv_d = 1.0;
    if (!box_light) {
        d = length(to_sample);
        l = -to_sample / max(d, 1e-6);
        inv_d = min(1.0 / d, 100.0);
    }
    var scale = 1.0 / (light.params.x * light.params.x);
    var bias = 1.0;
    if ((flags & LIGHT_RANGE_STEP) != 0u) {
        scale = 4096.0 / (light.params.x * light.params.x);
        bias = 16777216.0;
    }
    var atten = inv_d * distance_windowing(d * d, scale, bias);
    atten *= atten;
    if ((flags & (LIGHT_PYRAMID | LIGHT_BOX)) != 0u) {
        atten *= light_projector_window(light, p);
    } else if (u32(light.position.w) == 2u) {
        atten *= angle_attenuation(dot(forward, -l), light.params.y, light.params.z);
    }
    return vec4<f32>(l, atten);
}

// How far a shadow ray from p travels to the light: to its position, or for HDRP's box to its
// plane along the beam
fn light_distance(light: Light, p: vec3<f32>) -> f32 {
    if (HDRP_LIGHT_TERMS == 1u && (u32(light.features.w) & LIGHT_BOX) != 0u) {
        return dot(p - light.position.xyz, normalize(light.direction.xyz));
    }
    return length(light.position.xyz - p);
}

// A pyramid's or box's window at p in its light space (right = shape.xyz, up = forward × right)
fn light_projector_window(light: Light, p: vec3<f32>) -> f32 {
    let forward = normalize(light.direction.xyz);
    let right = light.shape.xyz;
    let to_sample = p - light.position.xyz;
    let local = vec3<f32>(dot(to_sample, right), dot(to_sample, cross(forward, right)), dot(to_sample, forward));
    return projector_window(local, light.params.yz, light.params.x, (u32(light.features.w) & LIGHT_BOX) != 0u);
}

// DistanceWindowing (core CommonLighting.hlsl): sat(bias − (d²·scale)²)
fn distance_windowing(dist_sq: f32, scale: f32, bias: f32) -> f32 {
    let x = dist_sq * scale;
    return sat(bias - x * x);
}

// EvaluateCookie_Punctual's clip: 1 where |x_cs|, |y_cs| ≤ 1 (x_cs = x/(z·half) for a pyramid,
// x/half for a box) and 0 ≤ z ≤ range, else 0
fn projector_window(local: vec3<f32>, half: vec2<f32>, range: f32, box_light: bool) -> f32 {
    let perspective_z = select(local.z, 1.0, box_light);
    let cs = local.xy / (perspective_z * half);
    let depth = abs(local.z - 0.5 * range) - 0.5 * range + 1.0;
    return select(1.0, 0.0, max(max(abs(cs.x), abs(cs.y)), depth) > 1.0);
}

// ComputeShadowColor (core CommonLighting.hlsl): the light's colour factor at shadow value s,
// lerp(1 − (1 − s)(1 − tint), s³(1 − tint) + s·tint, penumbra); s itself without a tint
fn compute_shadow_color(light: Light, shadow: f32) -> vec3<f32> {
    let mode = u32(light.features.z);
    if (mode == 0u) {
        return vec3<f32>(shadow);
    }
    let inv_tint = vec3<f32>(1.0) - light.shadow_tint.rgb;
    if (mode == 2u) {
        return shadow * shadow * shadow * inv_tint + shadow * light.shadow_tint.rgb;
    }
    return vec3<f32>(1.0) - (1.0 - shadow) * inv_tint;
}

// The lobes light `light` reaches (HDRP's Affect Diffuse and Affect Specular), for the model's
// direct_diffuse and direct_specular to weigh
fn set_light_lobes(light: Light) {
    if (HDRP_LIGHT_TERMS == 0u) {
        return;
    }
    light_diffuse_dimmer = light.features.x;
    light_specular_dimmer = light.features.y;
}

// The Surface a model receives from a material at uv (its checkerboard applied), modulated by the
// material maps' texels when textured: the albedo map (mean 1) multiplies the colour, the mask's r
// moves the metallic (`metallic_from_mask`), its a − 0.5 offsets the smoothness.
fn surface_from(m: Material, uv: vec2<f32>, albedo: vec4<f32>, mask: vec4<f32>, textured: bool) -> Surface {
    var s: Surface;
    s.base_color = m.base_color.rgb;
    s.metallic = m.params.x;
    s.smoothness = m.params.y;
    s.specular = m.specular.rgb;
    s.params0 = m.model0;
    s.params1 = m.model1;
    s.params2 = m.model2;
    if (m.params.z > 0.0) {
        let cell = floor(uv / m.params.z);
        if (((i32(cell.x) + i32(cell.y)) & 1) == 1) {
            s.base_color = m.checker_color.rgb;
        }
    }
    if (textured) {
        s.base_color *= albedo.rgb;
        s.metallic = metallic_from_mask(s.metallic, mask.r);
        s.smoothness = smoothness_from_maps(m, s.smoothness, albedo.a, mask.a);
    }
    return s;
}

// The metallic with the mask's r (materials::metallic_from_mask): r ≤ 1 scales the slider's value
// (a glTF's metallicFactor × texture, HDRP's remap to [0, slider]), r > 1 moves it towards 1 (bare
// metal where a preset's paint chipped off, HDRP's remap to [slider, 1]); r = 1 keeps the slider's
fn metallic_from_mask(metallic: f32, r: f32) -> f32 {
    if (r <= 1.0) {
        return metallic * r;
    }
    return metallic + (1.0 - metallic) * min(r - 1.0, 1.0);
}

// The specular workflow carried over texel by texel where the maps vary the metallic (the preset's
// specular map, Standard's _SpecGlossMap, URP's _SpecGlossMap, HDRP's _SpecularColorMap): the
// material holds the metallic workflow's colour and metallic and, in specular.rgb, the dielectric
// F0; specular colour lerp(F0, colour, metallic), albedo colour·(1 − metallic), metallic 0, as
// shading::registry::apply_workflow_with does per cell
fn carried_specular(s: Surface, m: Material) -> Surface {
    if (m.checker_color.w < 0.5) {
        return s;
    }
    var c = s;
    c.specular = mix(m.specular.rgb, s.base_color, s.metallic);
    c.base_color = s.base_color * (1.0 - s.metallic);
    c.metallic = 0.0;
    return c;
}

// The smoothness with maps: the mask's offset added to the slider's, or where the material reads
// it from the albedo's alpha (Source = Albedo Alpha) that alpha × the slider (URP LitInput.hlsl
// SampleMetallicSpecGloss, UnityStandardInput.cginc MetallicGloss: albedoAlpha * _Smoothness)
fn smoothness_from_maps(m: Material, slider: f32, albedo_alpha: f32, mask_smoothness: f32) -> f32 {
    if (m.emission.w > 0.5) {
        return sat(albedo_alpha * slider);
    }
    return sat(slider + mask_smoothness - 0.5);
}

// The surface's alpha: the material's, times the albedo map's unless that alpha holds the
// smoothness (Standard's Alpha() returns _Color.a, URP's Alpha() color.a, under
// _SMOOTHNESS_TEXTURE_ALBEDO_CHANNEL_A)
fn alpha_from_maps(m: Material, albedo_alpha: f32, textured: bool) -> f32 {
    return m.base_color.w * select(1.0, albedo_alpha, textured && m.emission.w < 0.5);
}

// A tangent-space normal carried to world space by the tangent frame (MikkTSpace, bitangent =
// cross(n, t)·w, as Unity's TransformTangentToWorld); n as it is where the mesh has no tangent.
fn tangent_to_world(n: vec3<f32>, tangent: vec4<f32>, ts: vec3<f32>) -> vec3<f32> {
    let t_raw = tangent.xyz - n * dot(n, tangent.xyz);
    if (dot(t_raw, t_raw) < 1e-12) {
        return n;
    }
    let t = normalize(t_raw);
    let b = cross(n, t) * select(1.0, -1.0, tangent.w < 0.0);
    return safe_normalize(t * ts.x + b * ts.y + n * ts.z, 1e-30);
}
