// The approximation study's exact alternatives (plan::exact), in place of approximations.wgsl:
// each replaces one real-time approximation of the subject's forward pass by the term it
// approximates, computed as the truth computes it (rays.wgsl), so that the change in error against
// the truth and in GPU time measures what the approximation costs and saves. Overrides pick which.

// 1: every light's visibility by a shadow ray through the cell's BVH (hard, as the truth's),
// traced per pixel by traced_shadows.wgsl; lights past the 32nd keep their shadow maps
override TRACED_VISIBILITY: u32 = 0u;
// 1: the ambient term from the exact irradiance map instead of order-2 SH
override EXACT_AMBIENT: u32 = 0u;
// 1: the environment integrated over the model's whole BRDF (no SH, no split-sum probe)
override EXACT_ENVIRONMENT: u32 = 0u;
// Sample pairs per pixel of that integral: one from the environment's table, one from the
// surface, weighted by the power heuristic
override EXACT_ENVIRONMENT_SAMPLES: u32 = 64u;

fn light_visibility(light: Light, index: u32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, receives: bool) -> f32 {
    if (TRACED_VISIBILITY == 0u || index >= 32u) {
        return shadow_visibility(light, p, n, l, receives);
    }
    let width = traced_mask[0];
    let mask = traced_mask[1u + u32(shading_pixel.y) * width + u32(shading_pixel.x)];
    return select(1.0, 0.0, (mask & (1u << index)) != 0u);
}

// E(n)/π from the irradiance grid (environment::irradiance::IrradianceMap::lookup, its twin):
// column x at u = x/w wrapping, row y at v = y/(h − 1), bilinear
fn irradiance_lookup(n: vec3<f32>) -> vec3<f32> {
    let w = rays.env_size.z;
    let h = rays.env_size.w;
    let uv = equirect_uv(n);
    let fx = uv.x * f32(w);
    let fy = uv.y * f32(h - 1u);
    let x0 = floor(fx);
    let y0 = min(floor(fy), f32(h - 2u));
    let t = vec2<f32>(fx - x0, fy - y0);
    let xa = u32(i32(x0) - i32(w) * i32(floor(x0 / f32(w))));
    let xb = (xa + 1u) % w;
    let ya = u32(y0);
    let a = mix(irradiance_texels[ya * w + xa].rgb, irradiance_texels[ya * w + xb].rgb, t.x);
    let b = mix(irradiance_texels[(ya + 1u) * w + xa].rgb, irradiance_texels[(ya + 1u) * w + xb].rgb, t.x);
    return mix(a, b, t.y);
}

fn environment_ambient(n: vec3<f32>) -> vec3<f32> {
    if (EXACT_ENVIRONMENT == 1u) {
        return vec3<f32>(0.0);
    }
    if (EXACT_AMBIENT == 1u) {
        return irradiance_lookup(n) * frame.env.y;
    }
    return ambient_diffuse(n);
}

fn environment_replaced() -> bool {
    return EXACT_ENVIRONMENT == 1u;
}

// The subject's BRDF × cosine as the truth's `response` takes it: model_direct without the
// pipeline's irradiance per intensity
fn exact_response(s: Surface, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    if (dot(n, l) <= 0.0) {
        return vec3<f32>(0.0);
    }
    return max(model_direct(s, n, v, l), vec3<f32>(0.0)) / irradiance_per_intensity();
}

// ∫ L_env(l) f(v, l) (n·l) dl, unshadowed (what SH and the split-sum probe approximate), by
// multiple importance sampling with a per-pixel seed: the same inputs give the same image
fn environment_exact(s: Surface, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    if (EXACT_ENVIRONMENT == 0u || frame.env.y <= 0.0) {
        return vec3<f32>(0.0);
    }
    rng_seed(u32(shading_pixel.x) + 65536u * u32(shading_pixel.y), 0u);
    let saved = light_min_roughness;
    light_min_roughness = 4.617e-5;
    var c = vec3<f32>(0.0);
    for (var k = 0u; k < EXACT_ENVIRONMENT_SAMPLES; k++) {
        let e = sample_env();
        if (e.w > 0.0) {
            let f = exact_response(s, n, v, e.xyz);
            c += f * env_radiance(e.xyz) / e.w * power_heuristic(e.w, surface_pdf(s, specular_share(s), n, v, e.xyz));
        }
        let l = sample_surface(s, specular_share(s), n, v);
        let pdf = surface_pdf(s, specular_share(s), n, v, l);
        if (pdf > 0.0) {
            let f = exact_response(s, n, v, l);
            c += f * env_radiance(l) / pdf * power_heuristic(pdf, env_pdf(l));
        }
    }
    light_min_roughness = saved;
    return c / f32(EXACT_ENVIRONMENT_SAMPLES);
}
