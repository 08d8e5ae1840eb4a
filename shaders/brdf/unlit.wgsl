// Unlit: the base colour as emitted radiance; no light, no environment.

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    // The colour is all the surface gives: premultiplied surfaces multiply it by alpha (URP's
    // Unlit _ALPHAPREMULTIPLY_ON, HDRP's ApplyBlendMode on its diffuse lighting)
    return emitted(s.base_color * diffuse_weight);
}
