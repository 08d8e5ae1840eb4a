// Shared math and constants (spec/shading.md notation). Prepended to every model and pass.
const PI: f32 = 3.14159265358979;
const INV_PI: f32 = 0.318309886183791;
const LOG2_E: f32 = 1.442695041;
const HALF_PI: f32 = 1.57079632679490;

// sat(x) = clamp(x, 0, 1) (spec notation)
fn sat(x: f32) -> f32 {
    return clamp(x, 0.0, 1.0);
}

// sat per channel
fn sat3(x: vec3<f32>) -> vec3<f32> {
    return clamp(x, vec3<f32>(0.0), vec3<f32>(1.0));
}

// GetLocalFrame (core CommonLighting.hlsl, 'ortho_basis_pixar_r2', Duff et al. 2017): an
// orthonormal frame around a unit z, columns x, y, z; twin: shading::twin::local_frame
fn local_frame(z: vec3<f32>) -> mat3x3<f32> {
    let sz = select(-1.0, 1.0, z.z >= 0.0);
    let a = 1.0 / (sz + z.z);
    let ya = z.y * a;
    let b = z.x * ya;
    let c = z.x * sz;
    return mat3x3<f32>(vec3<f32>(c * z.x * a - 1.0, sz * b, c), vec3<f32>(b, z.y * ya - sz, z.y), z);
}

// x⁵ by multiplies: pow() is undefined for x = 0 in WGSL (models.md#stability)
fn pow5(x: f32) -> f32 {
    let x2 = x * x;
    return x2 * x2 * x;
}

// v·rsqrt(max(eps, |v|²)): normalize(0) is NaN in WGSL (models.md#stability, Unity_SafeNormalize)
fn safe_normalize(v: vec3<f32>, eps: f32) -> vec3<f32> {
    return v * inverseSqrt(max(eps, dot(v, v)));
}

// The cube face of d's major axis, in the order +X, −X, +Y, −Y, +Z, −Z (point-light shadow maps
// and reflection-probe captures lay their faces out so)
fn cube_face(d: vec3<f32>) -> u32 {
    let a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        return select(1u, 0u, d.x > 0.0);
    }
    if (a.y >= a.z) {
        return 2u + select(1u, 0u, d.y > 0.0);
    }
    return 4u + select(1u, 0u, d.z > 0.0);
}

// The sRGB encode: 12.92·c below 0.0031308, else 1.055·c^(1/2.4) − 0.055 (twin: color::linear_to_srgb)
fn linear_to_srgb(c: f32) -> f32 {
    if (c <= 0.0031308) {
        return 12.92 * c;
    }
    return 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

// Core Random.hlsl JenkinsHash
fn jenkins_hash(x_in: u32) -> u32 {
    var x = x_in;
    x += x << 10u;
    x ^= x >> 6u;
    x += x << 3u;
    x ^= x >> 11u;
    x += x << 15u;
    return x;
}
