// URP's SSAO renderer feature as the High Fidelity renderer configures it (render::passes::urp_ssao;
// twin: images::urp_ssao): Interleaved Gradient method, depth-normals source, full resolution,
// bilateral blur (com.unity.render-pipelines.universal ShaderLibrary/SSAO.hlsl). Four steps, each
// writing an 8-bit RGBA target as URP's ARGB32 ones: the occlusion packed with the normal
// (SSAO), the horizontal and vertical geometry-aware blurs (HorizontalBlur, VerticalBlur), and
// the final 5-tap blur whose complement is the visibility the lit shaders read (FinalBlur, R8).
//
// Coordinates follow SSAO.hlsl's: uv from the bottom-left corner (ReconstructViewPos flips y
// against the top-left frustum corner), so pixel (x, row) of these top-down textures is uv
// ((x + ½)/W, 1 − (row + ½)/H). Depth is wgpu's 0 (near) .. 1 (far): Unity's reversed-Z raw depth
// is 1 − it, so its sky test `raw < 0.00001` reads `1 − raw < 0.00001` here.

struct UrpSsaoStep {
    // x: mode (0 occlusion, 1 horizontal blur, 2 vertical blur, 3 final blur)
    mode: vec4<u32>,
};

struct UrpSsaoFrame {
    // _SourceSize: width, height, 1/width, 1/height
    source_size: vec4<f32>,
    // _SSAOParams: intensity, radius, downsample (1: full resolution), falloff distance
    params: vec4<f32>,
    // _CameraViewTopLeftCorner, _CameraViewXExtent, _CameraViewYExtent: the near plane's top-left
    // corner and its edges, world-aligned and camera-relative
    top_left: vec4<f32>,
    x_extent: vec4<f32>,
    y_extent: vec4<f32>,
    // x: _ProjectionParams2.x (1/near); y: near; z: far; w: SAMPLE_COUNT
    camera: vec4<f32>,
    // _CameraViewProjections rows 0 and 1 (xyz; the translation is not used), UNITY_MATRIX_V row 2
    view_proj0: vec4<f32>,
    view_proj1: vec4<f32>,
    view_z: vec4<f32>,
};

@group(0) @binding(0) var<uniform> step: UrpSsaoStep;
// The blurs' source (bilinear, clamped: URP's SAMPLE_BASEMAP with sampler_BlitTexture)
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var linear_clamp: sampler;
@group(0) @binding(3) var destination: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(4) var<uniform> frame: UrpSsaoFrame;
// The DepthNormals prepass's depth (its depth view read as unfilterable float) and world normals
// (n·0.5 + 0.5)
@group(0) @binding(5) var scene_depth: texture_2d<f32>;
@group(0) @binding(6) var scene_normals: texture_2d<f32>;

const SSAO_OCCLUSION: u32 = 0u;
const SSAO_BLUR_HORIZONTAL: u32 = 1u;
const SSAO_BLUR_VERTICAL: u32 = 2u;

// kContrast, kGeometryCoeff, kBeta, kEpsilon, SKY_DEPTH_VALUE (SSAO.hlsl)
const K_CONTRAST: f32 = 0.6;
const K_GEOMETRY_COEFF: f32 = 0.8;
const K_BETA: f32 = 0.004;
const K_EPSILON: f32 = 0.0001;
const SKY_DEPTH_VALUE: f32 = 0.00001;

// SSAORandomUV: frac(43758.5453·sin(dot((12.9898, 78.233), uv))) tabulated, 0–19 for u = 0 and
// 20–39 for u = 1 (a private copy: a const array indexed at run time is copied at every read)
var<private> ssao_random_uv: array<f32, 40> = array<f32, 40>(
    0.00000000, 0.33984375, 0.75390625, 0.56640625, 0.98437500, 0.07421875, 0.23828125, 0.64062500,
    0.35937500, 0.50781250, 0.38281250, 0.98437500, 0.17578125, 0.53906250, 0.28515625, 0.23137260,
    0.45882360, 0.54117650, 0.12941180, 0.64313730,
    0.92968750, 0.76171875, 0.13333330, 0.01562500, 0.00000000, 0.10546875, 0.64062500, 0.74609375,
    0.67968750, 0.35156250, 0.49218750, 0.12500000, 0.26562500, 0.62500000, 0.44531250, 0.17647060,
    0.44705890, 0.93333340, 0.87058830, 0.56862750,
);

// GetRandomVal: SSAORandomUV[u·20 + sampleIndex]
fn get_random_val(u: u32, sample_index: u32) -> f32 {
    return ssao_random_uv[u * 20u + sample_index];
}

// InterleavedGradientNoise (core Random.hlsl): frac(52.9829189·frac(dot(p + frame·(2.083, 4.867),
// (0.06711056, 0.00583715))))
fn interleaved_gradient_noise(pixel: vec2<f32>, frame_count: u32) -> f32 {
    let p = pixel + f32(frame_count) * vec2<f32>(2.083, 4.867);
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}

// LinearEyeDepth: the view depth of a raw depth
fn linear_eye_depth(raw: f32) -> f32 {
    let n = frame.camera.y;
    let f = frame.camera.z;
    return n * f / (f - raw * (f - n));
}

// SampleDepth: the point-sampled, clamped depth at uv
fn sample_depth(uv: vec2<f32>) -> f32 {
    let size = vec2<i32>(textureDimensions(scene_depth));
    let texel = clamp(vec2<i32>(floor(vec2<f32>(uv.x, 1.0 - uv.y) * vec2<f32>(size))), vec2<i32>(0), size - 1);
    return textureLoad(scene_depth, texel, 0).r;
}

// SampleSceneNormals: the prepass normal at uv, as URP's R8G8B8A8_SNorm normals texture holds it
fn sample_normal(uv: vec2<f32>) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(scene_normals));
    let texel = clamp(vec2<i32>(floor(vec2<f32>(uv.x, 1.0 - uv.y) * vec2<f32>(size))), vec2<i32>(0), size - 1);
    let n = textureLoad(scene_normals, texel, 0).xyz * 2.0 - 1.0;
    return round(clamp(n, vec3<f32>(-1.0), vec3<f32>(1.0)) * 127.0) / 127.0;
}

// ReconstructViewPos: (top-left + X·u + Y·(1 − v))·depth/near, camera-relative and world-aligned
fn reconstruct_view_pos(uv: vec2<f32>, linear_depth: f32) -> vec3<f32> {
    let p = frame.top_left.xyz + frame.x_extent.xyz * uv.x + frame.y_extent.xyz * (1.0 - uv.y);
    return p * (linear_depth * frame.camera.x);
}

// PickSamplePoint (Interleaved Gradient): a point on the unit sphere from the table and the
// pixel's noise, scaled by √((s + 1)/N) and the radius, turned into the normal's hemisphere
fn pick_sample_point(uv: vec2<f32>, sample_index: u32, rcp_sample_count: f32, normal: vec3<f32>) -> vec3<f32> {
    let position_ss = uv * frame.source_size.xy * frame.params.z;
    let noise = interleaved_gradient_noise(position_ss, sample_index);
    let u = fract(get_random_val(0u, sample_index) + noise) * 2.0 - 1.0;
    let theta = (get_random_val(1u, sample_index) + noise) * 2.0 * PI;
    let u2 = sqrt(1.0 - u * u);
    var v = vec3<f32>(u2 * cos(theta), u2 * sin(theta), u);
    v *= sqrt((f32(sample_index) + 1.0) * rcp_sample_count);
    // faceforward(v, −n, v) = −v·sign(dot(−n, v))
    v = -v * sign(dot(-normal, v));
    return v * frame.params.y;
}

// SSAO: the Alchemy obscurance Σ max(v·n − β·z, 0)/(v·v + ε) over the samples inside the radius,
// × radius × intensity × falloff² / N, raised to the contrast; packed with the normal
fn alchemy_obscurance(uv: vec2<f32>) -> vec4<f32> {
    let raw_o = sample_depth(uv);
    if (1.0 - raw_o < SKY_DEPTH_VALUE) {
        return pack_ao_normal(0.0, vec3<f32>(0.0));
    }
    let depth_o = linear_eye_depth(raw_o);
    let falloff_distance = frame.params.w;
    if (depth_o > falloff_distance) {
        return pack_ao_normal(0.0, vec3<f32>(0.0));
    }
    let normal_o = sample_normal(uv);
    let vpos_o = reconstruct_view_pos(uv, depth_o);
    let sample_count = u32(frame.camera.w);
    let rcp_sample_count = 1.0 / f32(sample_count);
    let radius = frame.params.y;
    var ao = 0.0;
    for (var s = 0u; s < sample_count; s++) {
        let vpos_s1 = vpos_o + pick_sample_point(uv, s, rcp_sample_count, normal_o);
        let spos_s1 = vec2<f32>(dot(frame.view_proj0.xyz, vpos_s1), dot(frame.view_proj1.xyz, vpos_s1));
        let z_dist = -dot(frame.view_z.xyz, vpos_s1);
        let uv_s1 = clamp((spos_s1 / z_dist + 1.0) * 0.5, vec2<f32>(0.0), vec2<f32>(1.0));
        let raw_s = sample_depth(uv_s1);
        let depth_s = linear_eye_depth(raw_s);
        var inside = select(0.0, 1.0, abs(z_dist - depth_s) < radius);
        inside *= select(0.0, 1.0, 1.0 - raw_s > SKY_DEPTH_VALUE);
        let v_s2 = reconstruct_view_pos(uv_s1, depth_s) - vpos_o;
        let a1 = max(dot(v_s2, normal_o) - K_BETA * depth_o, 0.0);
        let a2 = dot(v_s2, v_s2) + K_EPSILON;
        ao += a1 / a2 * inside;
    }
    ao *= radius;
    var falloff = 1.0 - depth_o / falloff_distance;
    falloff = falloff * falloff;
    ao = pow(sat(ao * frame.params.x * falloff * rcp_sample_count), K_CONTRAST);
    return pack_ao_normal(ao, normal_o);
}

// PackAONormal: (ao, n·½ + ½)
fn pack_ao_normal(ao: f32, n: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(ao, n * 0.5 + 0.5);
}

// GetPackedNormal: gba·2 − 1
fn get_packed_normal(p: vec4<f32>) -> vec3<f32> {
    return p.gba * 2.0 - 1.0;
}

// CompareNormal: smoothstep(kGeometryCoeff, 1, n₁·n₂)
fn compare_normal(d1: vec3<f32>, d2: vec3<f32>) -> f32 {
    return smoothstep(K_GEOMETRY_COEFF, 1.0, dot(d1, d2));
}

// SAMPLE_BASEMAP at Unity's uv (bottom-up)
fn sample_basemap(uv: vec2<f32>) -> vec4<f32> {
    return textureSampleLevel(source, linear_clamp, vec2<f32>(uv.x, 1.0 - uv.y), 0.0);
}

// Blur: the geometry-aware separable bilateral filter, 5 taps at 0, ±1.3846, ±3.2308 texels
// (bilinear), Gaussian weights 0.2270, 0.3162, 0.0703 × CompareNormal
fn bilateral_blur(uv: vec2<f32>, delta: vec2<f32>) -> vec4<f32> {
    let p0 = sample_basemap(uv);
    let p1a = sample_basemap(uv - delta * 1.3846153846);
    let p1b = sample_basemap(uv + delta * 1.3846153846);
    let p2a = sample_basemap(uv - delta * 3.2307692308);
    let p2b = sample_basemap(uv + delta * 3.2307692308);
    let n0 = get_packed_normal(p0);
    let w0 = 0.2270270270;
    let w1a = compare_normal(n0, get_packed_normal(p1a)) * 0.3162162162;
    let w1b = compare_normal(n0, get_packed_normal(p1b)) * 0.3162162162;
    let w2a = compare_normal(n0, get_packed_normal(p2a)) * 0.0702702703;
    let w2b = compare_normal(n0, get_packed_normal(p2b)) * 0.0702702703;
    var s = p0.r * w0 + p1a.r * w1a + p1b.r * w1b + p2a.r * w2a + p2b.r * w2b;
    s /= w0 + w1a + w1b + w2a + w2b;
    return pack_ao_normal(s, n0);
}

// BlurSmall: the centre and its four diagonal neighbours, weights 1 and CompareNormal
fn blur_small(uv: vec2<f32>, delta: vec2<f32>) -> f32 {
    let p0 = sample_basemap(uv);
    let p1 = sample_basemap(uv + vec2<f32>(-delta.x, -delta.y));
    let p2 = sample_basemap(uv + vec2<f32>(delta.x, -delta.y));
    let p3 = sample_basemap(uv + vec2<f32>(-delta.x, delta.y));
    let p4 = sample_basemap(uv + vec2<f32>(delta.x, delta.y));
    let n0 = get_packed_normal(p0);
    let w1 = compare_normal(n0, get_packed_normal(p1));
    let w2 = compare_normal(n0, get_packed_normal(p2));
    let w3 = compare_normal(n0, get_packed_normal(p3));
    let w4 = compare_normal(n0, get_packed_normal(p4));
    let s = p0.r + p1.r * w1 + p2.r * w2 + p3.r * w3 + p4.r * w4;
    return s / (1.0 + w1 + w2 + w3 + w4);
}

@compute @workgroup_size(8, 8)
fn cs_urp_ssao(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(destination);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let uv = vec2<f32>((f32(id.x) + 0.5) / f32(size.x), 1.0 - (f32(id.y) + 0.5) / f32(size.y));
    let texel = frame.source_size.zw / frame.params.z;
    var out: vec4<f32>;
    switch (step.mode.x) {
        case SSAO_OCCLUSION: { out = alchemy_obscurance(uv); }
        case SSAO_BLUR_HORIZONTAL: { out = bilateral_blur(uv, vec2<f32>(texel.x, 0.0)); }
        case SSAO_BLUR_VERTICAL: { out = bilateral_blur(uv, vec2<f32>(0.0, texel.y)); }
        // FinalBlur: 1 − BlurSmall, the visibility (R8)
        default: { out = vec4<f32>(1.0 - blur_small(uv, texel), 0.0, 0.0, 1.0); }
    }
    textureStore(destination, id.xy, out);
}
