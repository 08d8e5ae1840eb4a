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
