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

// A textured cutout subject's depth: its base alpha × its albedo map's alpha clipped at its
// cutoff, as the engines' ShadowCaster passes clip under _ALPHATEST_ON (clip(alpha − _Cutoff):
// UnityStandardShadow.cginc fragShadowCaster, URP ShadowCasterPass Alpha(), HDRP's shadow pass
// with alpha clipping). x: base alpha, y: cutoff.
struct CutoutMaterial {
    alpha_cutoff: vec4<f32>,
};

@group(2) @binding(0) var<uniform> cutout: CutoutMaterial;
@group(2) @binding(1) var cutout_albedo: texture_2d<f32>;
@group(2) @binding(2) var cutout_sampler: sampler;

struct CutoutOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_shadow_cutout(@location(0) position: vec3<f32>, @location(2) uv: vec2<f32>) -> CutoutOut {
    var out: CutoutOut;
    out.clip = layer.view_proj * object.model * vec4<f32>(position, 1.0);
    out.uv = uv;
    return out;
}

@fragment
fn fs_shadow_cutout(in: CutoutOut) {
    let alpha = cutout.alpha_cutoff.x * textureSample(cutout_albedo, cutout_sampler, in.uv).a;
    if (alpha < cutout.alpha_cutoff.y) {
        discard;
    }
}
