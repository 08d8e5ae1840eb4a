// The Schlick term of models.md#fresnel shown as colour: F = F0 + (1 − F0)(1 − NV)^p — N·V, not V·H.
// F0 = ((1 − IOR)/(1 + IOR))² lerped to the base colour by metallic; params0.x IOR, params0.y p.
// A visualisation, not a BRDF: no light is involved.

fn model_direct(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn model_indirect(s: Surface, n: vec3<f32>, v: vec3<f32>, gi_diffuse: vec3<f32>) -> vec3<f32> {
    let f = (1.0 - s.params0.x) / (1.0 + s.params0.x);
    let f0 = mix(vec3<f32>(f * f), s.base_color, s.metallic);
    return indirect_specular(f0 + (vec3<f32>(1.0) - f0) * pow(1.0 - sat(dot(n, v)), s.params0.y));
}
