// Forward pass: one draw per object, every light summed per pixel, ambient from the environment.

@group(1) @binding(0) var<uniform> object: Object;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    // The lightmap's uv (geometry::lightmap_uv), zero for an object without one
    @location(4) uv2: vec2<f32>,
    // Built-in's ForwardAdd draws one instance whose index is the scene light it adds
    @builtin(instance_index) instance: u32,
};

struct VertexOut {
    // Invariant: ForwardBase and ForwardAdd are different pipelines, and an additive draw's depth
    // test (LEqual against the base draw's depth) needs bit-identical positions from both.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    // The object's per-vertex lights, added to the ambient term
    @location(3) vertex_gi: vec3<f32>,
    // World tangent, w the bitangent sign (zero: none)
    @location(4) tangent: vec4<f32>,
    // ForwardAdd: the light this draw adds (the draw's instance index)
    @location(5) @interpolate(flat) add_light: u32,
    // The view direction in the tangent frame, for parallax (zero without a tangent)
    @location(6) view_ts: vec3<f32>,
    @location(7) uv2: vec2<f32>,
};

struct FragmentOut {
    @location(0) color: vec4<f32>,
    @location(1) role: u32,
};

// A vertex's world normal, normalised; a zero normal (a mesh that has them) faces the camera
// instead: normalize(0) is NaN in WGSL (spec §6)
fn vertex_normal(n: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    if (dot(n, n) > 1e-30) {
        return normalize(n);
    }
    return safe_normalize(frame.camera_pos.xyz - p, 1e-30);
}

// The shading normal of a fragment: the interpolated normal, normalised; on a back face (drawn
// where the mesh's render face says) flipped in HDRP, whose Double-Sided Normal Mode (Mirror by
// default) turns it to the viewer, and kept in built-in and URP, whose lit shaders read the
// mesh's normal as it is. Where it is zero (zero normals in the mesh) the triangle's own normal,
// turned to the viewer (spec §6: normalize(0) is NaN). `face` = cross(dpdx(p), dpdy(p)), taken
// in uniform control flow.
fn shading_normal(interpolated: vec3<f32>, face: vec3<f32>, p: vec3<f32>, front: bool) -> vec3<f32> {
    if (dot(interpolated, interpolated) > 1e-30) {
        let n = normalize(interpolated);
        return select(n, -n, !front && PIPELINE == PIPELINE_HDRP);
    }
    let to_eye = frame.camera_pos.xyz - p;
    if (dot(face, face) > 1e-30) {
        return normalize(select(-face, face, dot(face, to_eye) >= 0.0));
    }
    return safe_normalize(to_eye, 1e-30);
}

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    let world = object.model * vec4<f32>(in.position, 1.0);
    out.world_pos = world.xyz;
    out.clip = frame.view_proj * world;
    out.normal = (object.normal_matrix * vec4<f32>(in.normal, 0.0)).xyz;
    out.uv = in.uv;
    out.uv2 = in.uv2;
    out.vertex_gi = vec3<f32>(0.0);
    if (FORWARD_PASS != FORWARD_ADD) {
        out.vertex_gi = vertex_lights(world.xyz, vertex_normal(out.normal, world.xyz));
    }
    out.add_light = in.instance;
    out.tangent = vec4<f32>((object.model * vec4<f32>(in.tangent.xyz, 0.0)).xyz, in.tangent.w);
    out.view_ts = tangent_view(out.tangent, out.normal, frame.camera_pos.xyz - world.xyz);
    return out;
}

// The vertex's view direction in its tangent frame (t, b = cross(n, t)·w, n), interpolated and
// normalised per fragment as both engines do: built-in's TANGENT_SPACE_ROTATION of the
// unnormalised ObjSpaceViewDir, URP's GetViewDirectionTangentSpace of the normalised view
// direction with the frame scaled by 1/|n|. Zero where the mesh has no tangent.
fn tangent_view(tangent: vec4<f32>, n: vec3<f32>, to_eye: vec3<f32>) -> vec3<f32> {
    if (tangent.w == 0.0 || dot(n, n) <= 1e-30) {
        return vec3<f32>(0.0);
    }
    let b = cross(n, tangent.xyz) * sign(tangent.w);
    if (PIPELINE == PIPELINE_URP) {
        let v = normalize(to_eye) / length(n);
        return vec3<f32>(dot(tangent.xyz, v), dot(b, v), dot(n, v));
    }
    return vec3<f32>(dot(tangent.xyz, to_eye), dot(b, to_eye), dot(n, to_eye));
}

// The uv the subject's maps are read at: offset by its height map where its model has a Height
// Map input and a scale (Standard's and URP Lit's `_PARALLAXMAP`; the height in the normal map's
// alpha, materials::MapLevel). Fixed objects and flat cells read at uv.
fn parallax_uv(uv: vec2<f32>, view_ts: vec3<f32>) -> vec2<f32> {
    // Branches on uniforms only: the height is sampled with derivatives.
    if (!is_textured() || object.flags.x != 1u) {
        return uv;
    }
    let height = model_height_scale(frame.subject.model0, frame.subject.model1);
    if (height <= 0.0) {
        return uv;
    }
    let h = map_texel(1, uv).a;
    return select(uv + parallax_offset(h, height, view_ts), uv, all(view_ts == vec3<f32>(0.0)));
}

// Built-in's Shade4PointLights (UnityCG.cginc): for each vertex light, Lambert with
// atten = 1/(1 + max(d², 1e-6)·25/range²) and no range cut-off, summed into the ambient term
// (models.md#vertex-lights). Only built-in forward assigns vertex lights (plan::lights).
fn vertex_lights(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    var c = vec3<f32>(0.0);
    if (VERTEX_LIT == 1u) {
        return c;
    }
    for (var i = 0u; i < frame.counts.x; i++) {
        if (light_mode(object.flags.z, i) != 1u) {
            continue;
        }
        let light = lights[i];
        let to_light = light.position.xyz - p;
        let d2 = max(dot(to_light, to_light), 1e-6);
        let ndotl = max(0.0, dot(n, to_light * inverseSqrt(d2)));
        let k = 25.0 / (light.params.x * light.params.x);
        c += light.color.rgb * (ndotl / (1.0 + d2 * k));
    }
    return c * irradiance_per_intensity() * INV_PI;
}

// The material's occlusion at the shaded point (the mask's g; 1 without maps): it dims the indirect
// terms, as Unity's occlusion map does (built-in and URP scale indirect diffuse and specular by it).
var<private> material_occlusion: f32 = 1.0;

// The material's alpha at the shaded point (its base colour's alpha × the albedo map's) and where
// it clips (0: nothing clips; the subject's cutoff when its surface is a cutout).
var<private> material_alpha: f32 = 1.0;
var<private> material_cutoff: f32 = 0.0;

// The subject's surface type (pipelines::surface::SurfaceType; 0 for fixed objects): its blend is
// the pipeline's, the shader's part is here.
override SURFACE: u32 = 0u;

// Whether the surface multiplies the diffuse reflectance by alpha before lighting (built-in's and
// URP's _ALPHAPREMULTIPLY_ON, HDRP's preserved specular lighting; SurfaceType::premultiplies_diffuse)
fn premultiplies_diffuse() -> bool {
    return SURFACE == SURFACE_TRANSPARENT || (SURFACE == SURFACE_ADDITIVE && PIPELINE != PIPELINE_BUILTIN);
}

// 1: the subject's alpha test resolves by alpha-to-coverage (plan::draws::alpha_to_coverage): URP's
// AlphaClip under IsAlphaToMaskAvailable exports SharpenAlpha instead of clipping
override ALPHA_TO_COVERAGE: u32 = 0u;

// SharpenAlpha (URP ShaderVariablesFunctions.hlsl): sat((alpha − cutoff)/max(fwidth(alpha), 10⁻⁴) + ½),
// the alpha the MSAA coverage takes; 1 where the cutoff is 0 (no clipping) or nothing covers
fn coverage_alpha() -> f32 {
    if (ALPHA_TO_COVERAGE == 0u || material_cutoff <= 0.0) {
        return 1.0;
    }
    return sat((material_alpha - material_cutoff) / max(fwidth(material_alpha), 1e-4) + 0.5);
}

// A cutout's alpha test, after every derivative of the fragment is taken: clip(alpha − _Cutoff),
// or under alpha-to-coverage clip(SharpenAlpha − 0.0001) (AlphaClip)
fn clip_alpha() {
    if (ALPHA_TO_COVERAGE == 1u) {
        if (coverage_alpha() < 1e-4) {
            discard;
        }
    } else if (material_alpha < material_cutoff) {
        discard;
    }
}

// The colour and alpha a surface outputs from its lit colour c (SurfaceType::output_color,
// output_alpha): a cutout's coverage alpha under alpha-to-coverage (1 else), built-in Transparent's alpha' = 1 − (1 − alpha)(1 − reflectivity) (PreMultiplyAlpha),
// URP Multiply's lerp(1, c, alpha) (AlphaModulate), alpha for the other transparent surfaces.
fn surface_output(s: Surface, c: vec3<f32>) -> vec4<f32> {
    let a = material_alpha;
    switch SURFACE {
        case SURFACE_OPAQUE: { return vec4<f32>(c, 1.0); }
        case SURFACE_CUTOUT: { return vec4<f32>(c, coverage_alpha()); }
        case SURFACE_MULTIPLY: { return vec4<f32>(mix(vec3<f32>(1.0), c, a), a); }
        case SURFACE_TRANSPARENT: {
            if (PIPELINE == PIPELINE_BUILTIN) {
                return vec4<f32>(c, 1.0 - (1.0 - a) * (1.0 - model_reflectivity(s)));
            }
            return vec4<f32>(c, a);
        }
        default: { return vec4<f32>(c, a); }
    }
}

// The material of the drawn object at uv: the swept one for the subject, the object's own else;
// maps modulate it (the albedo map multiplies the colour; the mask's smoothness offset adds to the
// smoothness; for the presets' maps their means are 1 and 0). Fragment stages sample with
// derivatives.
fn material_at(uv: vec2<f32>) -> Surface {
    // Sampled only where the object has maps (the branch is on uniforms, so uniform control
    // flow): on a CPU rasteriser three samples per fragment of every object cost a third of the frame.
    var albedo = vec4<f32>(1.0);
    var mask = vec4<f32>(1.0, 1.0, 1.0, 0.5);
    var detail = vec4<f32>(0.0);
    if (is_textured()) {
        albedo = map_texel(0, uv);
        mask = map_texel(2, uv);
        if (draws_detail()) {
            detail = textureSample(material_detail, material_sampler, uv * DETAIL_TILING);
            albedo = vec4<f32>(albedo.rgb * detail_albedo_factor(detail.w, mask.b), albedo.a);
        }
    }
    var s = material_from(uv, albedo, mask);
    if (PIPELINE == PIPELINE_HDRP && draws_detail()) {
        s.base_color = hdrp_detail_albedo(s.base_color, detail.w, mask.b);
    }
    return s;
}

// Whether the drawn object blends its model's secondary maps in (Standard's, URP Lit's): the subject, textured, its model's
// `detail` on (uniform, so the samples stay in uniform control flow)
fn draws_detail() -> bool {
    return object.flags.x == 1u && is_textured() && model_detail(frame.subject.model0, frame.subject.model1, frame.subject.model2) > 0.5;
}

// The same at a vertex (the vertex-lit path): the finest level, as a vertex stage has no derivatives.
fn material_at_vertex(uv: vec2<f32>) -> Surface {
    var albedo = vec4<f32>(1.0);
    var mask = vec4<f32>(1.0, 1.0, 1.0, 0.5);
    if (is_textured()) {
        albedo = map_texel_level0(0, uv);
        mask = map_texel_level0(2, uv);
    }
    return material_from(uv, albedo, mask);
}

// Map k (0 albedo, 1 normal, 2 mask, 3 emission) of the drawn object at uv: the subject's from
// the frame's maps, a fixed object's from its layers of fixed_maps.
fn map_texel(k: i32, uv: vec2<f32>) -> vec4<f32> {
    if (object.flags.x == 1u) {
        switch k {
            case 0: { return textureSample(material_albedo, material_sampler, uv); }
            case 1: { return textureSample(material_normal, material_sampler, uv); }
            case 2: { return textureSample(material_mask, material_sampler, uv); }
            default: { return textureSample(material_emission, material_sampler, uv); }
        }
    }
    return textureSample(fixed_maps, material_sampler, uv, fixed_map_layer(object.material, k));
}

fn map_texel_level0(k: i32, uv: vec2<f32>) -> vec4<f32> {
    if (object.flags.x == 1u) {
        switch k {
            case 0: { return textureSampleLevel(material_albedo, material_sampler, uv, 0.0); }
            case 1: { return textureSampleLevel(material_normal, material_sampler, uv, 0.0); }
            case 2: { return textureSampleLevel(material_mask, material_sampler, uv, 0.0); }
            default: { return textureSampleLevel(material_emission, material_sampler, uv, 0.0); }
        }
    }
    return fixed_map_level0(object.material, k, uv);
}

// The drawn object's emitted radiance: the subject's where its model emits, a fixed object's own
// (zero for most), times its emission map, added to the lit colour before tonemapping as Unity's
// emission is.
fn emission(uv: vec2<f32>) -> vec3<f32> {
    var e = object.material.emission.rgb;
    if (object.flags.x == 1u) {
        e = frame.subject.emission.rgb;
    }
    if (all(e == vec3<f32>(0.0))) {
        return e;
    }
    var map = vec3<f32>(1.0);
    if (is_textured()) {
        map = map_texel(3, uv).rgb;
    }
    return e * map;
}

// 1: the pipeline draws objects that may have maps (the subject's preset or glTF maps, or fixed
// objects' maps); 0 compiles the map sampling away.
override TEXTURED: u32 = 0u;

fn is_textured() -> bool {
    if (TEXTURED != 1u) {
        return false;
    }
    if (object.flags.x == 1u) {
        return frame.subject.params.w > 0.5;
    }
    return object.material.params.w > 0.5;
}

// The drawn object's material: the swept one for the subject, the object's own else
fn drawn_material() -> Material {
    if (object.flags.x == 1u) {
        return frame.subject;
    }
    return object.material;
}

fn material_from(uv: vec2<f32>, albedo: vec4<f32>, mask: vec4<f32>) -> Surface {
    let m = drawn_material();
    material_occlusion = select(1.0, mask.g, is_textured());
    material_alpha = alpha_from_maps(m, albedo.a, is_textured());
    material_cutoff = m.specular.w;
    return surface_from(m, uv, albedo, mask, is_textured());
}

// The normal map applied to a shading normal: the tangent frame (MikkTSpace, bitangent =
// cross(n, t)·w, as Unity's TransformTangentToWorld) carries the map's tangent-space normal to
// world space. Without maps, or where the mesh has no tangent, n as it is.
fn mapped_normal(n: vec3<f32>, tangent: vec4<f32>, uv: vec2<f32>) -> vec3<f32> {
    if (!is_textured()) {
        return n;
    }
    var ts = map_texel(1, uv).xyz;
    if (draws_detail()) {
        // Standard's NormalInTangentSpace or URP's ApplyDetailNormal (detail_blended_normal)
        let d = textureSample(material_detail, material_sampler, uv * DETAIL_TILING).xyz;
        ts = detail_blended_normal(ts, d, map_texel(2, uv).b);
    }
    return tangent_to_world(n, tangent, ts);
}

// Visibility of `light` at p (1 lit, 0 in shadow), mixed by the light's strength: the receiver
// offset along n by the normal bias and towards the light by the bias, both in texels; HDRP's
// n×n tent where shadow_bias.w is n, its PCSS where it is −1, else 3×3 bilinear comparison taps
// when soft (plan::shadows)
fn shadow_visibility(light: Light, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, receives: bool) -> f32 {
    if (light.shadow.x < 0.0 || !receives) {
        return 1.0;
    }
    var index = u32(light.shadow.x);
    if (u32(light.position.w) == 0u) {
        // Directional: the first cascade whose sphere holds p; beyond the last, no shadow
        let count = u32(light.shadow.y);
        var found = false;
        for (var c = 0u; c < count; c++) {
            let sphere = shadow_layers[index + c].sphere;
            let d = p - sphere.xyz;
            if (dot(d, d) < sphere.w * sphere.w) {
                index += c;
                found = true;
                break;
            }
        }
        if (!found) {
            return 1.0;
        }
    } else if (u32(light.position.w) == 1u) {
        // A point light's cube: the face of the major axis
        index += cube_face(p - light.position.xyz);
    }
    let info = shadow_layers[index];
    var texel = info.params.x;
    if (info.params.y > 0.5) {
        texel *= (info.view_proj * vec4<f32>(p, 1.0)).w;
    }
    let q = p + n * (light.shadow_bias.y * texel) + l * (light.shadow_bias.x * texel);
    let clip = info.view_proj * vec4<f32>(q, 1.0);
    let ndc = clip.xyz / clip.w;
    let map_uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (clip.w <= 0.0 || any(map_uv < vec2<f32>(0.0)) || any(map_uv > vec2<f32>(1.0)) || ndc.z > 1.0) {
        return 1.0;
    }
    // The light's map fills the top-left params.w of the layer
    let uv = map_uv * info.params.w;
    var vis = 0.0;
    // HDRP alone filters with a tent or PCSS: the other pipelines' frames compile them out
    if (PIPELINE == PIPELINE_HDRP && light.shadow_bias.w > 0.5) {
        vis = shadow_tent(index, uv, ndc.z, light.shadow_bias.w);
    } else if (PIPELINE == PIPELINE_HDRP && HDRP_PCSS == 1u && light.shadow_bias.w < -0.5) {
        vis = shadow_pcss(index, info, uv, ndc.z);
    } else if (light.shadow.w > 0.5) {
        let step = 1.0 / f32(textureDimensions(shadow_maps).x);
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let o = vec2<f32>(f32(dx), f32(dy)) * step;
                vis += textureSampleCompareLevel(shadow_maps, shadow_sampler, uv + o, index, ndc.z);
            }
        }
        vis /= 9.0;
    } else {
        vis = textureSampleCompareLevel(shadow_maps, shadow_sampler, uv, index, ndc.z);
    }
    return mix(1.0, vis, light.shadow.z);
}

// 1: built-in's legacy vertex-lit path: shade() runs at the vertices and its lights are the ones
// the plan marks per-vertex (up to 8, ShadeVertexLightsFull's count), evaluated with the model; no
// shadows.
override VERTEX_LIT: u32 = 0u;

// 1: the model is a built-in ForwardBase-only shader, lit by the main directional light alone
// (points and spots would need its ForwardAdd pass, which it does not have).
override MAIN_LIGHT_ONLY: u32 = 0u;

// Built-in's forward passes (plan::draws): 0 every per-pixel light in one draw (URP, HDRP, and
// built-in with `forward_add = false`); 1 ForwardBase: the main directional light with the
// ambient, SH and vertex lights and emission; 2 ForwardAdd: one more light's direct term alone,
// blended One One onto the base (Standard.shader FORWARD_DELTA).
const FORWARD_ALL: u32 = 0u;
const FORWARD_BASE: u32 = 1u;
const FORWARD_ADD: u32 = 2u;
override FORWARD_PASS: u32 = 0u;

// 0: a built-in shader compiled without `fullforwardshadows`: only the main directional light
// casts shadows on it (multi_compile_fwdadd has no shadowed point or spot variants).
override ADDITIONAL_SHADOWS: u32 = 1u;

// ForwardAdd: the scene light this draw adds.
var<private> add_light_index: u32 = 0u;

// Whether the pass draws the lights' direct terms, and the ambient and environment (with an unlit
// colour, which a model gives as emitted light): a model that does not wrap its lobes
// (MODEL_SPLITS_LOBES false) gives its indirect light whole, drawn with the indirect bits alone.
fn draws_direct() -> bool {
    return term_kept(TERM_DIRECT_DIFFUSE | TERM_DIRECT_SPECULAR);
}

fn draws_indirect() -> bool {
    let indirect = TERM_INDIRECT_DIFFUSE | TERM_INDIRECT_SPECULAR;
    return term_kept(select(indirect, indirect | TERM_EMISSION, MODEL_SPLITS_LOBES));
}

// The occlusion layer (TERMS = TERM_OCCLUSION): what dims the indirect light at this fragment,
// min(material AO, SSAO): in HDRP the diffuse's visibility before the multi-bounce, in URP what
// GlobalIllumination scales by; built-in has no SSAO (its visibility is the neutral 1).
fn draws_occlusion() -> bool {
    return TERMS == TERM_OCCLUSION;
}

fn ambient_occlusion() -> f32 {
    if (occlusion_in_bake()) {
        return material_occlusion * screen_ao;
    }
    return min(material_occlusion, screen_ao);
}

// The share of the SSAO the direct light takes: URP's AmbientOcclusionFactor
// directAmbientOcclusion = lerp(1, SSAO, DirectLightingStrength) (AmbientOcclusion.hlsl
// GetScreenSpaceAmbientOcclusion), which GetMainLight and GetAdditionalLight multiply every light's
// colour by (Lighting.hlsl; StencilDeferred's lighting passes too). frame.screen.w is 0 in HDRP
// (its lit shaders leave the direct light alone) and built-in.
fn direct_occlusion(visibility: f32) -> f32 {
    return mix(1.0, visibility, frame.screen.w);
}

// How the drawn object's shader reads the screen occlusion (plan::ao::OcclusionRead): 0 it does
// not (the frame has none, or the shader compiles none: the load is compiled out and the
// visibility is 1), 1 the lit rule, 2 URP's Unlit (UnlitForwardPass.hlsl: its colour times the
// direct factor, nothing through the indirect rule). Passes without a key (the G-buffer) read it.
const OCCLUSION_NONE: u32 = 0u;
const OCCLUSION_UNLIT: u32 = 2u;
override SCREEN_OCCLUSION: u32 = 1u;

// The lighting sum at one point: the object's per-pixel lights' direct terms plus the ambient
// (environment SH, the object's SH lights and its vertex lights) and the environment; in a
// ForwardAdd draw, only its one light's direct term.
fn shade(s: Surface, n: vec3<f32>, p: vec3<f32>, vertex_gi: vec3<f32>) -> vec3<f32> {
    let v = normalize(frame.camera_pos.xyz - p);
    shading_position = p;
    renderer_probe = i32(object.reflection_probe.x) - 1;
    // counts.y: 1 + index of the main directional light (the brightest), 0 when there is none
    main_light_color = vec3<f32>(0.0);
    if (frame.counts.y > 0u) {
        main_light_color = lights[frame.counts.y - 1u].color.rgb;
    }
    var c = vec3<f32>(0.0);
    // A ForwardAdd draw evaluates its one light, not a loop over the others
    let additive = FORWARD_PASS == FORWARD_ADD;
    let first = select(0u, add_light_index, additive);
    let end = select(frame.counts.x, add_light_index + 1u, additive);
    let direct_ao = direct_occlusion(screen_ao);
    for (var i = first; i < select(first, end, draws_direct()); i++) {
        // The model's own lights: per-pixel ones, or on the vertex-lit path the per-vertex ones
        let own = select(0u, 1u, VERTEX_LIT == 1u);
        let main = i + 1u == frame.counts.y;
        let base_only = MAIN_LIGHT_ONLY == 1u || FORWARD_PASS == FORWARD_BASE;
        if (light_mode(object.flags.z, i) != own || (base_only && !main) || (FORWARD_PASS == FORWARD_ADD && i != add_light_index)) {
            continue;
        }
        let light = lights[i];
        set_light_lobes(light);
        if (AREA_LIGHTS == 1u && u32(light.position.w) >= LIGHT_RECT) {
            c += rect_light(light, s, n, v, p) * direct_ao;
            continue;
        }
        let inc = light_incidence(light, p);
        if (inc.w > 0.0) {
            let receives = object.flags.w != 0u && VERTEX_LIT == 0u && (ADDITIONAL_SHADOWS == 1u || main);
            let shadow = with_baked_occlusion(light, light_visibility(light, i, p, n, inc.xyz, receives));
            // A tinted shadow scales the colour by ComputeShadowColor; an untinted one is the shadow
            let tinted = HDRP_LIGHT_TERMS == 1u && u32(light.features.z) != 0u;
            let visible = select(shadow, 1.0, tinted);
            let tint = select(vec3<f32>(1.0), compute_shadow_color(light, shadow), tinted);
            if (visible > 0.0 && any(tint > vec3<f32>(0.0))) {
                light_min_roughness = light.params.w;
                c += model_direct(s, n, v, inc.xyz) * light.color.rgb * tint * (inc.w * visible * direct_ao);
            }
        }
    }
    light_diffuse_dimmer = 1.0;
    light_specular_dimmer = 1.0;
    if (FORWARD_PASS == FORWARD_ADD || !draws_indirect()) {
        return c;
    }
    let gi = object_ambient(n) + max(sh_eval(object.light_sh, n), vec3<f32>(0.0)) + vertex_gi;
    return c + indirect_light(s, n, v, gi);
}

// The object's ambient light: the sky's SH, or where the scene bakes (render::gi) what the bake
// gives it — its interpolated light probe, whose SH is folded into object.light_sh (lod.z = 1)
// — or its lightmap at `lightmap_uv` (bake.x = 2), which Subtractive's main-light shadow darkens
fn object_ambient(n: vec3<f32>) -> vec3<f32> {
    let flags = u32(object.bake.y + 0.5);
    if (object.bake.x > 1.5) {
        let baked = lightmap_gi(lightmap_uv, n, (flags & 1u) != 0u, object.bake.z);
        if ((flags & 2u) != 0u && frame.counts.y > 0u && subtracts_main_light) {
            return subtract_main_light(baked, n);
        }
        return baked;
    }
    if (object.bake.x > 0.5) {
        return vec3<f32>(0.0);
    }
    return environment_ambient(n);
}

// Whether this pass takes Subtractive's main light out of the lightmap: every forward pass, and
// URP's G-buffer pass (LitGBufferPass.hlsl MixRealtimeAndBakedGI); built-in's is compiled
// without SHADOWS_SCREEN, so its UnityGI_Base leaves the lightmap whole (UnityGlobalIllumination.cginc)
var<private> subtracts_main_light: bool = true;

// SubtractMainLightWithRealtimeAttenuationFromLightmap (URP Lighting.hlsl; built-in UnityGI_Base
// under LIGHTMAP_SHADOW_MIXING without SHADOWS_SHADOWMASK): the main light's Lambert term where
// its real-time shadow falls is taken out of the baked light, no lower than the Realtime Shadow
// Color, blended by the shadow's strength, never above the baked light
fn subtract_main_light(baked: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let index = frame.counts.y - 1u;
    let light = lights[index];
    let inc = light_incidence(light, shading_position);
    let shadow = light_visibility(light, index, shading_position, n, inc.xyz, object.flags.w != 0u);
    let lambert = light.color.rgb * sat(dot(inc.xyz, n));
    var subtracted = max(baked - lambert * (1.0 - shadow), object.shadow_color.rgb);
    subtracted = mix(baked, subtracted, select(light.shadow.z, 0.0, light.shadow.x < 0.0));
    return min(subtracted, baked);
}

// The light's real-time visibility `visible` with what the bake holds of its occlusion at this
// object: a Shadowmask light's (color.w = 2 + c) lightmap shadow-mask channel or probe occlusion,
// and on a probe-lit object Subtractive's main light's (color.w = 6) probe occlusion, channel 0.
// The darker of the two (URP MixRealtimeAndBakedShadows, built-in UnityMixRealtimeAndBakedShadows
// under LIGHTMAP_SHADOW_MIXING), or on a probe-lit object their product where the engine scales
// the light's colour by the probe's occlusion on the CPU (shadow_bias.z = 1:
// plan::gi::ProbeOcclusion::LightColour)
fn with_baked_occlusion(light: Light, visible: f32) -> f32 {
    let probe_lit = object.bake.x > 0.5 && object.bake.x < 1.5;
    var channel = shadow_mask_channel(light);
    if (light.color.w > 5.5 && probe_lit) {
        channel = 0;
    }
    if (channel < 0) {
        return visible;
    }
    let baked = baked_occlusions()[channel];
    if (probe_lit && light.shadow_bias.z > 0.5) {
        return visible * baked;
    }
    return min(visible, baked);
}

// The light's shadow-mask channel (color.w = 2 + c), or −1
fn shadow_mask_channel(light: Light) -> i32 {
    let channel = i32(light.color.w + 0.5) - 2;
    return select(-1, channel, channel >= 0 && channel < 4);
}

// Every shadow-mask channel's baked occlusion at this object (1 where nothing is baked)
fn baked_occlusions() -> vec4<f32> {
    if (object.bake.x > 1.5) {
        return textureSampleLevel(lightmap, env_sampler, lightmap_uv, 2, 0.0);
    }
    if (object.bake.x > 0.5) {
        return object.occlusion;
    }
    return vec4<f32>(1.0);
}

// The fragment's (or vertex's) lightmap uv, set by the entry points before shading
var<private> lightmap_uv: vec2<f32> = vec2<f32>(0.0);

// 1 where the scene has an area light (plan::lights::needs_area_path); 0 compiles the rect-light
// path and the model's LTC integrals out of the light loops
override AREA_LIGHTS: u32 = 1u;

// 1 where a light's shadow is read with HDRP's PCSS (plan::lights::LightPaths::pcss); 0 compiles
// its loops out
override HDRP_PCSS: u32 = 1u;

// A rect light's direct term at p (the model's `model_rect`); 0 where the frame leaves it out
fn rect_light(light: Light, s: Surface, n: vec3<f32>, v: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    if (light.shape.w < 0.5) {
        return vec3<f32>(0.0);
    }
    let atten = rect_attenuation(light, p);
    if (atten <= 0.0) {
        return vec3<f32>(0.0);
    }
    return model_rect(s, n, v, rect_corners(light, p)) * light.color.rgb * atten;
}

// HDRP's screen-space ambient occlusion (render::passes::ssao): the visibility at each pixel, loaded by the
// fragment stages into `screen_ao`; a 1×1 texture of 1 where a cell renders without it.
@group(2) @binding(6) var screen_occlusion: texture_2d<f32>;
var<private> screen_ao: f32 = 1.0;

fn load_screen_occlusion(pixel: vec2<f32>) -> f32 {
    let size = vec2<i32>(textureDimensions(screen_occlusion));
    return textureLoad(screen_occlusion, min(vec2<i32>(pixel), size - 1), 0).r;
}

// The indirect light with its occlusion. HDRP (Lit.hlsl PostEvaluateBSDF:
// GetScreenSpaceAmbientOcclusionMultibounce, then LightLoop.hlsl ApplyAmbientOcclusionFactor):
// the indirect diffuse × GTAOMultiBounce(min(material AO, SSAO), diffuse colour), the reflected
// environment × GTAOMultiBounce(min(SO(material AO), SO(SSAO)), F0), both the model's BSDF data
// (`model_occlusion_albedo`, `model_occlusion_fresnel0`); the direct light stays
// unoccluded (direct lighting strength 0). Built-in and URP scale both by the material's occlusion,
// URP by the lower of it and SSAO's visibility (AmbientOcclusion.hlsl CreateAmbientOcclusionFactor:
// indirectAmbientOcclusion = min(SSAO, occlusion), GlobalIllumination's occlusion).
fn indirect_light(s: Surface, n: vec3<f32>, v: vec3<f32>, gi: vec3<f32>) -> vec3<f32> {
    // Where the study's exact environment replaces them, the probe reflection is off (and the
    // SH ambient left out of gi): the integral takes the environment's whole share.
    let probe = select(1.0, 0.0, environment_replaced());
    let exact = environment_exact(s, n, v);
    if (PIPELINE != PIPELINE_HDRP) {
        indirect_specular_occlusion = vec3<f32>(probe);
        let lit = (model_indirect(s, n, v, gi) + exact) * min(material_occlusion, screen_ao);
        indirect_specular_occlusion = vec3<f32>(1.0);
        return lit;
    }
    let nv = max(dot(n, v), 1e-4);
    let pr = 1.0 - s.smoothness;
    let roughness = pr * pr;
    let ao = min(material_occlusion, screen_ao);
    let so = min(specular_occlusion_from_ao(nv, material_occlusion, roughness), specular_occlusion_from_ao(nv, screen_ao, roughness));
    indirect_specular_occlusion = gtao_multi_bounce(so, model_occlusion_fresnel0(s)) * probe;
    var diffuse_occlusion = gtao_multi_bounce(ao, model_occlusion_albedo(s));
    if (occlusion_in_bake()) {
        diffuse_occlusion = material_occlusion * bake_occlusion(s);
    }
    if (model_back_ambient(s)) {
        gi_back_diffuse = (object_ambient(-n) + max(sh_eval(object.light_sh, -n), vec3<f32>(0.0))) * diffuse_occlusion;
    }
    let lit = model_indirect(s, n, v, gi * diffuse_occlusion);
    indirect_specular_occlusion = vec3<f32>(1.0);
    gi_back_diffuse = vec3<f32>(0.0);
    return lit + exact * ao;
}

// HDRP's deferred Lit (frame.screen.z, plan::ao::AoUse::in_bake): its G-buffer pass multiplies the
// baked diffuse light by the material's occlusion and adds the emission (Lit.hlsl
// EncodeIntoGBuffer); the lighting pass multiplies that sum by SSAO's visibility alone,
// GTAOMultiBounce(min(1, SSAO), diffuse colour) (DecodeFromGBuffer's ambientOcclusion is 1;
// MaterialEvaluation.hlsl ApplyAmbientOcclusionFactor)
// (The plan sets it for HDRP's deferred path alone; the shader takes its word.)
fn occlusion_in_bake() -> bool {
    return frame.screen.z > 0.5;
}

// URP's deferred: the first directional light's pass (or, without one, the SSAO-only pass)
// multiplies the lighting buffer, the G-buffer pass's GI with the material's occlusion plus the
// emission, by SSAO < occlusion ? SSAO/occlusion : 1 (StencilDeferred.shader _DEFERRED_FIRST_LIGHT,
// DeferredLights.cs RenderSSAOBeforeShading). The GI here already takes min(occlusion, SSAO)
// (indirect_light); the emission takes the ratio.
fn urp_lighting_buffer_occlusion() -> f32 {
    return select(1.0, screen_ao / material_occlusion, screen_ao < material_occlusion);
}

fn bake_occlusion(s: Surface) -> vec3<f32> {
    return gtao_multi_bounce(screen_ao, model_occlusion_albedo(s));
}

// Interleaved gradient noise (Jimenez 2014; core Random.hlsl InterleavedGradientNoise, frame 0):
// fract(52.9829189·fract(0.06711056·x + 0.00583715·y)) at the pixel's centre.
fn interleaved_gradient_noise(pixel: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(pixel, vec2<f32>(0.06711056, 0.00583715))));
}

// How the model's shader dithers a LOD cross-fade (plan::lod::CrossFade): 0 it does not (both
// levels draw whole), 1 the SRP tutorial's ClipLOD on interleaved gradient noise, 2 core
// LODDitheringTransition on the hashed view-direction seed (HDRP, URP Lit).
override LOD_DITHER: u32 = 1u;

// Core Random.hlsl GenerateHashedRandomFloat(uint2): ConstructFloat(JenkinsHash(v.x ^ JenkinsHash(v.y))),
// the hash's mantissa bits as a float in [0, 1)
fn hashed_random_float(v: vec2<u32>) -> f32 {
    let m = (jenkins_hash(v.x ^ jenkins_hash(v.y)) & 0x007FFFFFu) | 0x3F800000u;
    return bitcast<f32>(m) - 1.0;
}

// Core Packing.hlsl PackNormalOctQuadEncode: n/|n|₁ folded onto the octahedron's upper half
fn pack_normal_oct_quad(n_in: vec3<f32>) -> vec2<f32> {
    let n = n_in / max(dot(abs(n_in), vec3<f32>(1.0)), 1e-6);
    let t = sat(-n.z);
    return n.xy + vec2<f32>(select(-t, t, n.x >= 0.0), select(-t, t, n.y >= 0.0));
}

// ComputeFadeMaskSeed (perspective): the octahedral view direction × _ScreenSize.xy × P._m00_m11,
// truncated; P's diagonal is the length of view_proj's first two rows (an orthonormal view)
fn fade_mask_seed(v: vec3<f32>) -> vec2<u32> {
    let m = frame.view_proj;
    let p00 = length(vec3<f32>(m[0].x, m[1].x, m[2].x));
    let p11 = length(vec3<f32>(m[0].y, m[1].y, m[2].y));
    let pv = pack_normal_oct_quad(v) * frame.screen.xy * vec2<f32>(p00, p11);
    return bitcast<vec2<u32>>(vec2<i32>(pv));
}

// LOD cross-fade: a level fading out (fade t > 0) keeps the fragments whose dither is below t, the
// level fading in (fade −t) those at or above it, so between them they cover every pixel once
// (LODDitheringTransition: clip(t − CopySign(dither, t))).
fn lod_clip(pixel: vec2<f32>, p: vec3<f32>) {
    if (object.lod.y > 0.5 && LOD_DITHER != 0u) {
        let fade = object.lod.x;
        var dither = interleaved_gradient_noise(pixel);
        if (LOD_DITHER == 2u) {
            dither = hashed_random_float(fade_mask_seed(normalize(frame.camera_pos.xyz - p)));
        }
        if (select(fade - dither, fade + dither, fade < 0.0) < 0.0) {
            discard;
        }
    }
}

// The pixel being shaded: what the exact alternatives seed their samples with and read their
// traced shadow mask at
var<private> shading_pixel: vec2<f32> = vec2<f32>(0.0);

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> FragmentOut {
    return forward_fragment(in, front).out;
}

// HDRP's split lighting for the Subsurface Scattering type (ShaderPassForward.hlsl
// OUTPUT_SPLIT_LIGHTING), drawn over the subject's own depth after the forward pass drew its
// specular (plan::subsurface): the diffuse lighting and the emission (the pipeline's TERMS) with
// the pre-scatter √albedo, blue kept above 0 (TagLightingForSSS: HALF_MIN), and the SSS buffer's
// albedo (EncodeIntoSSSBuffer's baseColor) for the filter.
struct SubsurfaceOut {
    @location(0) diffuse: vec4<f32>,
    @location(1) albedo: vec4<f32>,
};

@fragment
fn fs_subsurface(in: VertexOut, @builtin(front_facing) front: bool) -> SubsurfaceOut {
    let shaded = forward_fragment(in, front);
    let lit = shaded.out.color.rgb;
    var out: SubsurfaceOut;
    out.diffuse = vec4<f32>(lit.rg, max(lit.b, 6.103515625e-5), 1.0);
    out.albedo = vec4<f32>(shaded.albedo, 1.0);
    return out;
}

// A fragment's outputs, and the drawn surface's base colour after its maps (what the SSS buffer holds)
struct ShadedFragment {
    out: FragmentOut,
    albedo: vec3<f32>,
};

fn forward_fragment(in: VertexOut, front: bool) -> ShadedFragment {
    lod_clip(in.clip.xy, in.world_pos);
    lightmap_uv = in.uv2;
    if (SCREEN_OCCLUSION != OCCLUSION_NONE) {
        screen_ao = load_screen_occlusion(in.clip.xy);
    }
    let unlit_occlusion = direct_occlusion(screen_ao);
    if (SCREEN_OCCLUSION == OCCLUSION_UNLIT) {
        screen_ao = 1.0;
    }
    let face = cross(dpdx(in.world_pos), dpdy(in.world_pos));
    shading_pixel = in.clip.xy;
    add_light_index = in.add_light;
    let uv = parallax_uv(in.uv, in.view_ts);
    let n = mapped_normal(shading_normal(in.normal, face, in.world_pos, front), in.tangent, uv);
    var out: FragmentOut;
    var s = carried_specular(material_at(uv), drawn_material());
    s.tangent = in.tangent.xyz;
    var glow = vec3<f32>(0.0);
    if (FORWARD_PASS != FORWARD_ADD) {
        glow = emission(uv);
    }
    if (premultiplies_diffuse()) {
        diffuse_weight = material_alpha;
        // HDRP's diffuse lighting holds the emission (Lit.hlsl PostEvaluateBSDF)
        if (PIPELINE == PIPELINE_HDRP) {
            glow *= material_alpha;
        }
    }
    // A ForwardAdd draw adds its light to the base draw: in the occlusion layer, nothing.
    var lit = vec3<f32>(select(ambient_occlusion(), 0.0, FORWARD_PASS == FORWARD_ADD));
    if (!draws_occlusion()) {
        lit = shade(s, n, in.world_pos, in.vertex_gi) + emitted(glow);
        if (SCREEN_OCCLUSION == OCCLUSION_UNLIT) {
            lit *= unlit_occlusion;
        }
    }
    out.color = surface_output(s, lit);
    out.role = object.flags.y;
    clip_alpha();
    return ShadedFragment(out, s.base_color);
}

// Gouraud shading (models.md#classic): the same sum evaluated per vertex and interpolated. Highlights
// smaller than a triangle are lost or smeared — the expected difference. Back faces are not
// flipped here (the vertex stage cannot know which side is seen).
struct GouraudOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) world_pos: vec3<f32>,
    // The fixed-function fallback's separate specular (FIXED_FUNCTION)
    @location(3) specular: vec3<f32>,
    // The material's occlusion at the vertex, for the occlusion layer
    @location(4) occlusion: f32,
};

// 1: built-in's vertex-lit path drawing a shader without a Vertex pass (Standard), which falls
// back to Legacy Shaders/VertexLit: fixed-function lighting at the vertices (vertex_lit_ffp), no
// reflections, no emission (VertexLit reads _Emission, Standard sets _EmissionColor).
override FIXED_FUNCTION: u32 = 0u;

// Legacy Shaders/VertexLit's material defaults where Standard sets nothing: _SpecColor white,
// _Shininess 0.7 (× 128 in the generated code).
const FFP_SHININESS: f32 = 89.6;

// The fixed-function vertex lighting Unity generates for VertexLit (Lighting On, SeparateSpecular
// On; the code of its "show generated code"): per light att·NL·C·L (min 1 per light) and
// att·sat((N·H)^shininess)·L, both at half the light colour ("passed in light colors are 2x
// brighter than what used to be in FFP"), the ambient C·A/2 (UNITY_LIGHTMODEL_AMBIENT is
// glstate_lightmodel_ambient × 2); returns (sat(diffuse + ambient), sat(specular)). A: the flat
// ambient, the environment's SH band 0 (RenderSettings' skybox ambient has no per-normal term
// in the fixed-function path). att: 1 directional; 1/(1 + 25·d²/range²), 0 beyond the range, for
// points and spots, spots × sat((ρ − cos outer)/(cos inner − cos outer)). Twin:
// shading::twin::vertex_lit.
fn vertex_lit_ffp(c: vec3<f32>, n: vec3<f32>, p: vec3<f32>) -> array<vec3<f32>, 2> {
    let v = normalize(frame.camera_pos.xyz - p);
    let ambient = max(frame.sh[0].rgb * 0.282095, vec3<f32>(0.0)) * frame.env.y;
    var diffuse = c * ambient * 0.5;
    var specular = vec3<f32>(0.0);
    for (var i = 0u; i < frame.counts.x; i++) {
        if (light_mode(object.flags.z, i) != 1u) {
            continue;
        }
        let light = lights[i];
        var l = -normalize(light.direction.xyz);
        var att = 1.0;
        if (u32(light.position.w) != 0u) {
            let to_light = light.position.xyz - p;
            let d2 = dot(to_light, to_light);
            let range2 = light.params.x * light.params.x;
            att = select(1.0 / (1.0 + d2 * 25.0 / range2), 0.0, d2 > range2);
            l = to_light * inverseSqrt(max(d2, 1e-6));
            if (u32(light.position.w) == 2u) {
                let rho = max(dot(l, -normalize(light.direction.xyz)), 0.0);
                att *= sat((rho - light.params.y) / max(light.params.z - light.params.y, 1e-4));
            }
        }
        att *= 0.5;
        let colour = light.color.rgb * irradiance_per_intensity() * INV_PI;
        let nl = max(dot(n, l), 0.0);
        diffuse += min(nl * c * colour * att, vec3<f32>(1.0));
        if (nl > 0.0) {
            let nh = max(dot(n, normalize(l + v)), 0.0);
            specular += att * sat(pow(nh, FFP_SHININESS)) * colour;
        }
    }
    return array<vec3<f32>, 2>(sat3(diffuse), sat3(specular));
}

@vertex
fn vs_gouraud(in: VertexIn) -> GouraudOut {
    lightmap_uv = in.uv2;
    let world = object.model * vec4<f32>(in.position, 1.0);
    let n = vertex_normal((object.normal_matrix * vec4<f32>(in.normal, 0.0)).xyz, world.xyz);
    var out: GouraudOut;
    out.clip = frame.view_proj * world;
    out.specular = vec3<f32>(0.0);
    if (FIXED_FUNCTION == 1u) {
        let lit = vertex_lit_ffp(material_at_vertex(in.uv).base_color, n, world.xyz);
        out.color = lit[0];
        out.specular = lit[1];
    } else {
        out.color = shade(material_at_vertex(in.uv), n, world.xyz, vertex_lights(world.xyz, n));
    }
    out.uv = in.uv;
    out.world_pos = world.xyz;
    // Set by material_at_vertex above (1 without maps)
    out.occlusion = material_occlusion;
    return out;
}

@fragment
fn fs_gouraud(in: GouraudOut) -> FragmentOut {
    lod_clip(in.clip.xy, in.world_pos);
    var out: FragmentOut;
    if (FIXED_FUNCTION == 1u) {
        // SetTexture [_MainTex] { Combine texture * primary DOUBLE }, then the separate specular
        // (the material's colour and maps are in the primary, taken at the vertices)
        out.color = vec4<f32>(in.color * 2.0 + in.specular, 1.0);
    } else {
        out.color = vec4<f32>(in.color + emitted(emission(in.uv)), 1.0);
        // The occlusion layer: what dimmed the ambient at the vertices
        if (draws_occlusion()) {
            out.color = vec4<f32>(vec3<f32>(in.occlusion), 1.0);
        }
    }
    out.role = object.flags.y;
    return out;
}

// HDRP's depth prepass with its normal buffer (render::passes::ssao reads both): the shading normal, normal
// map included, as n·0.5 + 0.5.
@fragment
fn fs_depth_normals(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    lod_clip(in.clip.xy, in.world_pos);
    let uv = parallax_uv(in.uv, in.view_ts);
    let n = mapped_normal(shading_normal(in.normal, cross(dpdx(in.world_pos), dpdy(in.world_pos)), in.world_pos, front), in.tangent, uv);
    material_at(uv);
    clip_alpha();
    return vec4<f32>(n * 0.5 + 0.5, 1.0);
}

// ---- Deferred path (render::passes::deferred): a G-buffer pass, then a screen-space lighting pass per role.

// The G-buffer: base colour + occlusion (8-bit sRGB), metallic + smoothness (8-bit), the normal
// (n·0.5 + 0.5 in the pipeline's normal format; a: receives shadows), the ambient/environment
// term (RT3, half float) and the role.
struct GBufferOut {
    @location(0) albedo: vec4<f32>,
    @location(1) material: vec4<f32>,
    @location(2) normal: vec4<f32>,
    @location(3) lighting: vec4<f32>,
    @location(4) role: u32,
    @location(5) shadow_mask: vec4<f32>,
};

// The tangent as the G-buffer keeps it: its angle γ ∈ [0, π) about N from GetLocalFrame(N)'s x, as
// γ/π in 8 bits (0.7° steps). HDRP's EncodeIntoGBuffer stores the same rotation as an 8-bit sine or
// cosine with a flag; anisotropic GGX is the same for T and −T, so half a turn is enough.
fn encode_tangent_angle(n: vec3<f32>, t: vec3<f32>) -> f32 {
    let frame = local_frame(n);
    let gamma = atan2(dot(t, frame[1]), dot(t, frame[0]));
    return select(gamma, gamma + PI, gamma < 0.0) / PI;
}

fn decode_tangent_angle(n: vec3<f32>, stored: f32) -> vec3<f32> {
    let frame = local_frame(n);
    let gamma = stored * PI;
    return cos(gamma) * frame[0] + sin(gamma) * frame[1];
}

@fragment
fn fs_gbuffer(in: VertexOut, @builtin(front_facing) front: bool) -> GBufferOut {
    lod_clip(in.clip.xy, in.world_pos);
    lightmap_uv = in.uv2;
    let uv = parallax_uv(in.uv, in.view_ts);
    let n = mapped_normal(shading_normal(in.normal, cross(dpdx(in.world_pos), dpdy(in.world_pos)), in.world_pos, front), in.tangent, uv);
    // The G-buffer keeps the metallic workflow's colour and metallic (Unity's keep the specular
    // colour itself; the deferred lighting carries the workflow over from them, `fs_deferred`).
    let written = material_at(uv);
    var s = carried_specular(written, drawn_material());
    s.tangent = in.tangent.xyz;
    let v = normalize(frame.camera_pos.xyz - in.world_pos);
    shading_position = in.world_pos;
    renderer_probe = i32(object.reflection_probe.x) - 1;
    screen_ao = load_screen_occlusion(in.clip.xy);
    main_light_color = vec3<f32>(0.0);
    if (frame.counts.y > 0u) {
        main_light_color = lights[frame.counts.y - 1u].color.rgb;
    }
    subtracts_main_light = PIPELINE != PIPELINE_BUILTIN;
    let gi = object_ambient(n) + max(sh_eval(object.light_sh, n), vec3<f32>(0.0));
    var out: GBufferOut;
    // a: the tangent's angle about N, for HDRP Lit's anisotropy (HDRP's GBuffer2 keeps it so)
    out.albedo = vec4<f32>(written.base_color, encode_tangent_angle(n, s.tangent));
    // w: lightmapped (URP's kMaterialFlagSubtractiveMixedLighting where the scene is Subtractive)
    // z: the pixel's SSAO visibility, for URP's lighting passes' direct factor (the R8 value
    // StencilDeferred samples, at the same 8 bits)
    out.material = vec4<f32>(written.metallic, s.smoothness, screen_ao, select(0.0, 1.0, object.bake.x > 1.5));
    // The object's baked occlusion per shadow-mask channel (built-in's RT4: UnityGetRawBakedOcclusions)
    out.shadow_mask = baked_occlusions();
    out.normal = vec4<f32>(n * 0.5 + 0.5, f32(object.flags.w));
    // Emission joins the indirect light in RT3, as Unity's deferred paths write it; HDRP's SSAO
    // darkens it there too (occlusion_in_bake).
    var lighting = vec3<f32>(ambient_occlusion());
    if (!draws_occlusion()) {
        lighting = emitted(emission(uv));
        if (occlusion_in_bake()) {
            lighting *= bake_occlusion(s);
        }
        if (PIPELINE == PIPELINE_URP) {
            lighting *= urp_lighting_buffer_occlusion();
        }
        if (draws_indirect()) {
            lighting += indirect_light(s, n, v, gi);
        }
    }
    out.lighting = vec4<f32>(lighting, 1.0);
    out.role = object.flags.y;
    clip_alpha();
    return out;
}

@group(2) @binding(0) var gb_albedo: texture_2d<f32>;
@group(2) @binding(1) var gb_material: texture_2d<f32>;
@group(2) @binding(2) var gb_normal: texture_2d<f32>;
@group(2) @binding(3) var gb_lighting: texture_2d<f32>;
@group(2) @binding(4) var gb_role: texture_2d<u32>;
@group(2) @binding(5) var gb_depth: texture_depth_2d;
@group(2) @binding(7) var gb_shadow_mask: texture_2d<f32>;

// The role whose pixels this lighting pipeline shades: 2 subject (the cell's model), 1 fixed, 0
// every G-buffer pixel (one model lights the whole G-buffer; each role's material values).
override DEFERRED_ROLE: u32 = 2u;

// Built-in's legacy Deferred pass whose data the shaded pixels hold (plan::draws::legacy_deferred;
// shading::registry::LegacyLighting): 0 none, 1 LightingLambert_Deferred, 2 LightingBlinnPhong_Deferred.
// The pipeline is the Standard model's: Internal-DeferredShading lights every pixel with BRDF1.
override LEGACY_DEFERRED: u32 = 0u;

// The UnityStandardData a legacy Deferred pass wrote (Lighting.cginc), as the Standard model's
// specular setup reads it: diffuseColor = Albedo (divided here by 1 − max(spec), which the setup
// multiplies back: Internal-DeferredShading takes it as stored), specularColor 0 and smoothness 0
// (Lambert), or _SpecColor·Gloss/π and Specular (Blinn-Phong; Gloss 1, Specular = n/128 for the
// shininess n the model's smoothness gives, at most 1); occlusion 1.
fn legacy_standard_data(g: Surface, m: Material) -> Surface {
    var s = g;
    s.params0.x = 1.0;
    s.params0.y = 0.0;
    s.metallic = 0.0;
    s.specular = vec3<f32>(0.0);
    s.smoothness = 0.0;
    if (LEGACY_DEFERRED == 2u) {
        s.specular = m.specular.rgb * INV_PI;
        s.smoothness = min(shininess_from_smoothness(g.smoothness) / 128.0, 1.0);
    }
    s.base_color = g.base_color / (1.0 - max(max(s.specular.r, s.specular.g), s.specular.b));
    return s;
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// Every light per pixel from the G-buffer (deferred lighting has no per-object limit), plus RT3.
@fragment
fn fs_deferred(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(pos.xy);
    let role = textureLoad(gb_role, px, 0).x;
    if ((DEFERRED_ROLE == 0u && role == 0u) || (DEFERRED_ROLE != 0u && role != DEFERRED_ROLE)) {
        discard;
    }
    let size = vec2<f32>(textureDimensions(gb_role));
    let depth = textureLoad(gb_depth, px, 0);
    let ndc = vec4<f32>(pos.x / size.x * 2.0 - 1.0, 1.0 - pos.y / size.y * 2.0, depth, 1.0);
    let world = frame.inv_view_proj * ndc;
    let p = world.xyz / world.w;
    var m = frame.fixed;
    if (role == 2u) {
        m = frame.subject;
    }
    var s: Surface;
    s.base_color = textureLoad(gb_albedo, px, 0).rgb;
    let mat = textureLoad(gb_material, px, 0);
    s.metallic = mat.x;
    s.smoothness = mat.y;
    s.specular = m.specular.rgb;
    s.params0 = m.model0;
    s.params1 = m.model1;
    s.params2 = m.model2;
    s = carried_specular(s, m);
    // Built-in's Internal-DeferredShading lights the G-buffer with BRDF1 compiled without the
    // material's keywords: Standard's _SPECULARHIGHLIGHTS_OFF (params0.y) does not reach it
    // (fragDeferred writes no such flag); URP's G-buffer carries it.
    if (PIPELINE == PIPELINE_BUILTIN) {
        s.params0.y = 0.0;
    }
    if (LEGACY_DEFERRED != 0u) {
        s = legacy_standard_data(s, m);
    }
    let nb = textureLoad(gb_normal, px, 0);
    let n = normalize(nb.xyz * 2.0 - 1.0);
    s.tangent = decode_tangent_angle(n, textureLoad(gb_albedo, px, 0).a);
    let v = normalize(frame.camera_pos.xyz - p);
    var c = textureLoad(gb_lighting, px, 0).rgb;
    // A legacy pass's RT3 holds the emission and Albedo·indirect diffuse alone
    // (UNITY_LIGHT_FUNCTION_APPLY_INDIRECT); Internal-DeferredReflections adds BRDF1's reflection
    if (LEGACY_DEFERRED != 0u && draws_indirect()) {
        shading_position = p;
        c += model_indirect(s, n, v, vec3<f32>(0.0));
    }
    if (!draws_direct()) {
        return vec4<f32>(c, 1.0);
    }
    let baked = DeferredBake(textureLoad(gb_shadow_mask, px, 0), mat.w > 0.5);
    let direct_ao = direct_occlusion(mat.z);
    if (TILED_LIGHTS == 1u) {
        // HDRP's light loop: only the lights binned into this pixel's tile (cs_light_tiles)
        let words = frame.counts.z;
        let tile = (u32(pos.y) / LIGHT_TILE) * frame.counts.w + u32(pos.x) / LIGHT_TILE;
        for (var w = 0u; w < words; w++) {
            var bits = tile_masks[tile * words + w];
            while (bits != 0u) {
                let i = w * 32u + firstTrailingBit(bits);
                bits &= bits - 1u;
                c += deferred_light(lights[i], s, p, n, v, nb.a > 0.5, baked) * direct_ao;
            }
        }
    } else {
        for (var i = 0u; i < frame.counts.x; i++) {
            c += deferred_light(lights[i], s, p, n, v, nb.a > 0.5, baked) * direct_ao;
        }
    }
    return vec4<f32>(c, 1.0);
}

// What the G-buffer holds of a pixel's bake: its shadow mask and whether it is lightmapped
struct DeferredBake {
    shadow_mask: vec4<f32>,
    lightmapped: bool,
};

// One light's direct term at a G-buffer pixel
fn deferred_light(light: Light, s: Surface, p: vec3<f32>, n: vec3<f32>, v: vec3<f32>, receives: bool, baked: DeferredBake) -> vec3<f32> {
    // A light the frame draws on no object: it reaches the frame through the bake alone (plan::gi)
    if (light.color.w > 0.5 && light.color.w < 1.5) {
        return vec3<f32>(0.0);
    }
    // Subtractive's main light on a lightmapped pixel: URP's StencilDeferred returns before
    // lighting where the light's and the material's SubtractiveMixedLighting flags meet; built-in's
    // deferred lighting has no such flag and draws it
    if (light.color.w > 5.5 && baked.lightmapped && PIPELINE == PIPELINE_URP) {
        return vec3<f32>(0.0);
    }
    set_light_lobes(light);
    if (AREA_LIGHTS == 1u && u32(light.position.w) >= LIGHT_RECT) {
        return rect_light(light, s, n, v, p);
    }
    let inc = light_incidence(light, p);
    if (inc.w <= 0.0) {
        return vec3<f32>(0.0);
    }
    // A Shadowmask light's real-time shadow takes the darker of it and the G-buffer's baked
    // occlusion (built-in UnityDeferredComputeShadow, URP's and HDRP's shadow-mask G-buffer);
    // so does URP's Subtractive main light on a dynamic pixel, whose mask holds its probe's
    // occlusion (unity_ProbesOcclusion, channel 0: with_baked_occlusion)
    var visible = shadow_visibility(light, p, n, inc.xyz, receives);
    let channel = select(shadow_mask_channel(light), 0, light.color.w > 5.5 && PIPELINE == PIPELINE_URP);
    if (channel >= 0) {
        visible = min(visible, baked.shadow_mask[channel]);
    }
    let tinted = HDRP_LIGHT_TERMS == 1u && u32(light.features.z) != 0u;
    let tint = select(vec3<f32>(1.0), compute_shadow_color(light, visible), tinted);
    visible = select(visible, 1.0, tinted);
    if (visible <= 0.0 || all(tint <= vec3<f32>(0.0))) {
        return vec3<f32>(0.0);
    }
    light_min_roughness = light.params.w;
    return model_direct(s, n, v, inc.xyz) * light.color.rgb * tint * (inc.w * visible);
}
