// Shadow-map pass: depth only, one draw per casting object per layer (plan::shadows).

struct ShadowLayerUniform {
    view_proj: mat4x4<f32>,
};

// The prefix of scene.wgsl's Object: its model matrix.
struct ObjectModel {
    model: mat4x4<f32>,
};

@group(0) @binding(0) var<uniform> layer: ShadowLayerUniform;
@group(1) @binding(0) var<uniform> object: ObjectModel;

@vertex
fn vs_shadow(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return layer.view_proj * object.model * vec4<f32>(position, 1.0);
}

// The subject's depth where its alpha decides which fragments cast (plan::shadows::SubjectCaster):
// - clipped (mode 0): its base alpha × its albedo map's alpha clipped at its cutoff, as the
//   engines' ShadowCaster passes clip under _ALPHATEST_ON (clip(alpha − _Cutoff):
//   UnityStandardShadow.cginc fragShadowCaster, URP ShadowCasterPass Alpha(), HDRP's shadow pass
//   with alpha clipping);
// - dithered (mode 1): built-in Fade and Transparent, whose fragShadowCaster clips by
//   _DitherMaskLOD at vpos/4 and slice ⌊15·alpha⌋, alpha being PreMultiplyAlpha's
//   1 − (1 − alpha)(1 − reflectivity) under Transparent.
// x: base alpha, y: cutoff, z: mode, w: reflectivity.
struct AlphaCaster {
    alpha_cutoff: vec4<f32>,
};

@group(2) @binding(0) var<uniform> caster: AlphaCaster;
@group(2) @binding(1) var caster_albedo: texture_2d<f32>;
@group(2) @binding(2) var caster_sampler: sampler;

struct AlphaCasterOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_shadow_alpha(@location(0) position: vec3<f32>, @location(2) uv: vec2<f32>) -> AlphaCasterOut {
    var out: AlphaCasterOut;
    out.clip = layer.view_proj * object.model * vec4<f32>(position, 1.0);
    out.uv = uv;
    return out;
}

// Whether shadow-map texel `texel` of a dithered caster of `alpha` casts: slice ⌊15·alpha⌋ of
// Unity's 4×4×16 _DitherMaskLOD, APPROXIMATED by the 4×4 Bayer matrix keeping the ranks r with
// (r + ½)/16 < slice/15 (the texture's own patterns are not published). Twin:
// plan::shadows::dither_keeps.
fn dither_keeps(texel: vec2<u32>, alpha: f32) -> bool {
    let bayer = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    let rank = bayer[(texel.y % 4u) * 4u + texel.x % 4u];
    let slice = floor(15.0 * clamp(alpha, 0.0, 1.0));
    return (f32(rank) + 0.5) / 16.0 < slice / 15.0;
}

@fragment
fn fs_shadow_alpha(in: AlphaCasterOut) {
    let alpha = caster.alpha_cutoff.x * textureSample(caster_albedo, caster_sampler, in.uv).a;
    if (caster.alpha_cutoff.z > 0.5) {
        let modified = 1.0 - (1.0 - alpha) * (1.0 - caster.alpha_cutoff.w);
        if (!dither_keeps(vec2<u32>(in.clip.xy), modified)) {
            discard;
        }
    } else if (alpha < caster.alpha_cutoff.y) {
        discard;
    }
}
