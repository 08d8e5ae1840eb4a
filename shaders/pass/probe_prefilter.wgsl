// Reflection-probe prefilter on the GPU (render::passes::probes); twin: environment::filtered
// (probe, integrate), the same steps in the same order. A captured cube (six 90° faces) is
// resampled into an equirectangular source, halved into a mip chain, and each of Unity's seven
// levels (mip = pr'·6, pr' = pr(1.7 − 0.7pr)) is the GGX lobe of its α by filtered importance
// sampling of that chain, as HDRP's IntegrateLD (ImageBasedLighting.hlsl) does.

// Composed after shaders/common/math.wgsl (PI, cube_face).
const TAU: f32 = 6.28318530717959;

struct PrefilterParams {
    // x: output width, y: output height, z: unused, w: mode (0 faces → equirect, 1 halve, 2 filtered, 3 copy)
    dims: vec4<u32>,
    // faces: y = 1 / sub-samples per side; filtered: x = GGX α of the level, y = sample count,
    // w = the lobe's weight (0 N·L, 1 Smith masking)
    level: vec4<f32>,
    // the six faces' view-projections from the probe's position (render::passes::probes::face_view_proj)
    faces: array<mat4x4<f32>, 6>,
    probe_position: vec4<f32>,
};

@group(0) @binding(0) var<uniform> params: PrefilterParams;
@group(0) @binding(1) var cube_faces: texture_2d_array<f32>;
// One mip of the chain (halve, copy) or the whole chain (filtered)
@group(0) @binding(2) var source: texture_2d<f32>;
// Nearest: the faces are 32-bit float, which need not be filterable
@group(0) @binding(3) var face_sampler: sampler;
@group(0) @binding(4) var output: texture_storage_2d<rgba16float, write>;
// Trilinear, wrapping in u, clamped in v
@group(0) @binding(5) var chain_sampler: sampler;

// Equirectangular texel centre → direction (u: azimuth from −Z towards +X, v: polar angle from +Y);
// twin: environment::uv_to_dir
fn uv_to_dir(u: f32, v: f32) -> vec3<f32> {
    let phi = (u - 0.5) * TAU;
    let theta = v * PI;
    return vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// The captured radiance along d: the face of d's major axis, at d's projection into it.
fn cube_radiance(d: vec3<f32>) -> vec3<f32> {
    let face = cube_face(d);
    let clip = params.faces[face] * vec4<f32>(params.probe_position.xyz + d, 1.0);
    let ndc = clip.xy / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    return textureSampleLevel(cube_faces, face_sampler, uv, face, 0.0).rgb;
}

@compute @workgroup_size(8, 8)
fn cs_prefilter(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = params.dims.x;
    let h = params.dims.y;
    if (id.x >= w || id.y >= h) {
        return;
    }
    var c = vec3<f32>(0.0);
    switch params.dims.w {
        // Cube → equirect: sub-samples weighted by sin θ (twin: EquirectImage::sample)
        case 0u: {
            let step = params.level.y;
            var wsum = 0.0;
            for (var sy = step * 0.5; sy < 1.0; sy += step) {
                for (var sx = step * 0.5; sx < 1.0; sx += step) {
                    let u = (f32(id.x) + sx) / f32(w);
                    let v = (f32(id.y) + sy) / f32(h);
                    let wt = sin(v * PI);
                    c += cube_radiance(uv_to_dir(u, v)) * wt;
                    wsum += wt;
                }
            }
            c /= max(wsum, 1e-12);
        }
        // 2×2 halving weighted by solid angle ∝ sin θ (twin: EquirectImage::half)
        case 1u: {
            let sh = f32(h * 2u);
            var wsum = 0.0;
            for (var dy = 0u; dy < 2u; dy++) {
                let y = id.y * 2u + dy;
                let wt = sin((f32(y) + 0.5) / sh * PI);
                for (var dx = 0u; dx < 2u; dx++) {
                    c += textureLoad(source, vec2<u32>(id.x * 2u + dx, y), 0).rgb * wt;
                    wsum += wt;
                }
            }
            c /= max(wsum, 1e-12);
        }
        // Filtered importance sampling of the lobe around R = N = V (twin: filtered::integrate)
        case 2u: {
            let r = uv_to_dir((f32(id.x) + 0.5) / f32(w), (f32(id.y) + 0.5) / f32(h));
            c = integrate_ld(r, params.level.x, u32(params.level.y), u32(params.level.w));
        }
        // Copy (the mirror levels)
        default: {
            c = textureLoad(source, id.xy, 0).rgb;
        }
    }
    textureStore(output, id.xy, vec4<f32>(c, 1.0));
}

// Fibonacci2dSeq (Fibonacci.hlsl): ((i + ½)/n, frac(i·F₋₁/n)), n a Fibonacci number, F₋₁ the one before
fn fibonacci2d(i: u32, n: u32) -> vec2<f32> {
    var a = 1u;
    var b = 1u;
    while (b < n) {
        let next = a + b;
        a = b;
        b = next;
    }
    return vec2<f32>((f32(i) + 0.5) / f32(n), fract(f32(i) * f32(a) / f32(n)));
}

// The mip a sample reads: ½·log2(Ω_s/Ω_p) + α, Ω_s = 1/(n·D/4), Ω_p the finest texel's solid angle
// at l (IntegrateLD, its mipBias = α); twin: filtered::sample_mip
fn sample_mip(alpha: f32, nh: f32, n: u32, l: vec3<f32>) -> f32 {
    let size = vec2<f32>(textureDimensions(source, 0));
    let a2 = alpha * alpha;
    let t = nh * nh * (a2 - 1.0) + 1.0;
    let d = a2 / (PI * t * t);
    let omega_s = 1.0 / (f32(n) * 0.25 * d);
    let sin_theta = max(sqrt(max(1.0 - l.y * l.y, 0.0)), sin(0.5 * PI / size.y));
    let omega_p = (TAU / size.x) * (PI / size.y) * sin_theta;
    return 0.5 * log2(omega_s / omega_p) + alpha;
}

// IntegrateLD with N = V = R: GGX half-vectors by SampleGGXDir, L = reflect(−V, H), each read from
// its mip; weighed by N·L (weight 0) or by V_SmithJointGGX·N·L (weight 1); twin: filtered::integrate
fn integrate_ld(r: vec3<f32>, alpha: f32, n: u32, weight: u32) -> vec3<f32> {
    let frame = local_frame(r);
    let a2 = alpha * alpha;
    let last = f32(textureNumLevels(source) - 1u);
    var light = vec3<f32>(0.0);
    var total = 0.0;
    for (var i = 0u; i < n; i++) {
        let u = fibonacci2d(i, n);
        let cos_h = sqrt(max((1.0 - u.x) / (1.0 + (a2 - 1.0) * u.x), 0.0));
        let sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
        let phi = TAU * u.y;
        let local_h = vec3<f32>(sin_h * cos(phi), sin_h * sin(phi), cos_h);
        let local_l = 2.0 * cos_h * local_h - vec3<f32>(0.0, 0.0, 1.0);
        let nl = local_l.z;
        if (nl <= 0.0) {
            continue;
        }
        let l = frame * local_l;
        var wt = nl;
        if (weight == 1u) {
            wt = 0.5 / (nl + sqrt(nl * nl * (1.0 - a2) + a2)) * nl;
        }
        let mip = clamp(sample_mip(alpha, cos_h, n, l), 0.0, last);
        let uv = vec2<f32>(atan2(l.x, -l.z) / TAU + 0.5, acos(clamp(l.y, -1.0, 1.0)) / PI);
        light += textureSampleLevel(source, chain_sampler, uv, mip).rgb * wt;
        total += wt;
    }
    return light / max(total, 1e-30);
}
