// BRDF terms shared by several models (spec §1, §4).

// F = F0 + (1 − F0)(1 − c)⁵ (§1 FresnelTerm, §4 Schlick)
fn f_schlick(f0: vec3<f32>, c: f32) -> vec3<f32> {
    return f0 + (vec3<f32>(1.0) - f0) * pow5(1.0 - c);
}

// lerp(F0, F90, (1 − c)⁵) (§1 FresnelLerp)
fn f_schlick_lerp(f0: vec3<f32>, f90: vec3<f32>, c: f32) -> vec3<f32> {
    return mix(f0, f90, pow5(1.0 - c));
}
