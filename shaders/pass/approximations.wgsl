// The real-time approximations as the pipelines make them. The approximation study swaps this
// file for exact.wgsl in the subject's forward pipeline (plan::exact), which computes each term
// exactly instead; forward.wgsl calls these four and nothing else of either.

// The visibility at p of light `index`: the pipeline's shadow map
fn light_visibility(light: Light, index: u32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, receives: bool) -> f32 {
    return shadow_visibility(light, p, n, l, receives);
}

// The environment's ambient term E(n)/π: order-2 SH
fn environment_ambient(n: vec3<f32>) -> vec3<f32> {
    return ambient_diffuse(n);
}

// Whether environment_exact replaces the SH ambient and the split-sum probe
fn environment_replaced() -> bool {
    return false;
}

// The environment's light through the whole BRDF, where an exact alternative computes it
fn environment_exact(s: Surface, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}
