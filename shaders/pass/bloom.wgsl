// HDRP's bloom (render::passes::bloom; twin: images::bloom), its steps as HDRP's compute shaders run them:
// a half-resolution prefilter (BloomPrefilter.compute LOW_QUALITY: five rotated bilinear taps
// [Lorach07] one full-resolution texel apart, each through QuadraticThreshold and weighted by
// 1/(1 + luminance) [Karis13]; HIGH_QUALITY at the High level: 13 taps in five Karis-weighted
// blocks [Jimenez14]), a pyramid whose levels are each a 2×2 bilinear downsample of the
// last then a 9-tap binomial blur across and down (BloomBlur.compute), an upsample from the
// coarsest level, lerp(level, filter(coarser), scatter) (BloomUpsample.compute KMainHighQ bicubic
// or KMainLowQ bilinear), and the composite lerp(colour, filter(bloom), weight) (UberPost.compute).
// Textures are read with loads and filtered here: 32-bit float textures need not be filterable.

struct BloomParams {
    // x, y: destination size; z: mode (0 prefilter, 1 downsample, 2 blur across, 3 blur down,
    // 4 upsample or composite); w: unused
    dims: vec4<u32>,
    // x: scatter (upsample) or weight (composite); y: 1 bicubic, 0 bilinear filtering of the coarse input
    factor: vec4<f32>,
};

@group(0) @binding(0) var<uniform> params: BloomParams;
@group(0) @binding(1) var source: texture_2d<f32>;
// The upsample's and the composite's second input (the coarser level, the bloom)
@group(0) @binding(2) var coarse: texture_2d<f32>;
@group(0) @binding(3) var destination: texture_storage_2d<rgba32float, write>;

fn load_clamped(t: texture_2d<f32>, p: vec2<i32>) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t));
    return textureLoad(t, clamp(p, vec2<i32>(0), size - 1), 0).rgb;
}

// Bilinear at uv with clamped edges (s_linear_clamp_sampler)
fn bilinear(t: texture_2d<f32>, uv: vec2<f32>) -> vec3<f32> {
    let x = uv * vec2<f32>(textureDimensions(t)) - 0.5;
    let p = vec2<i32>(floor(x));
    let f = x - floor(x);
    let a = mix(load_clamped(t, p), load_clamped(t, p + vec2<i32>(1, 0)), f.x);
    let b = mix(load_clamped(t, p + vec2<i32>(0, 1)), load_clamped(t, p + vec2<i32>(1, 1)), f.x);
    return mix(a, b, f.y);
}

// Cubic B-spline weights of the four texels around x's fraction f (core Filtering.hlsl BSpline3)
fn bspline(f: f32) -> vec4<f32> {
    let g = 1.0 - f;
    return vec4<f32>(g * g * g, 4.0 - 6.0 * f * f + 3.0 * f * f * f, 4.0 - 6.0 * g * g + 3.0 * g * g * g, f * f * f) / 6.0;
}

// SampleTexture2DBicubic: the B-spline bicubic at uv, edges clamped
fn bicubic(t: texture_2d<f32>, uv: vec2<f32>) -> vec3<f32> {
    let x = uv * vec2<f32>(textureDimensions(t)) - 0.5;
    let p = vec2<i32>(floor(x));
    let wx = bspline(x.x - floor(x.x));
    let wy = bspline(x.y - floor(x.y));
    var c = vec3<f32>(0.0);
    for (var j = 0; j < 4; j++) {
        var row = vec3<f32>(0.0);
        for (var i = 0; i < 4; i++) {
            row += load_clamped(t, p + vec2<i32>(i - 1, j - 1)) * wx[i];
        }
        c += row * wy[j];
    }
    return c;
}

// BloomCommon.hlsl QuadraticThreshold at the default threshold 0 (knee 1e-5, curve
// (−1e-5, 2e-5, 0.25/1e-5)): keeps colours brighter than 1e-4, fades the darker ones
fn quadratic_threshold(c: vec3<f32>) -> vec3<f32> {
    let br = max(c.r, max(c.g, c.b));
    var rq = clamp(br + 1e-5, 0.0, 2e-5);
    rq = 25000.0 * rq * rq;
    return c * (max(rq, br) / max(br, 1e-4));
}

// Core Color.hlsl Luminance (Rec. 709 weights)
fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126729, 0.7151522, 0.0721750));
}

// BilinearSample: the source at uv offset by `offset` full-resolution texels, through the
// threshold; its Karis weight 1/(1 + luminance) in w
fn prefilter_tap(uv: vec2<f32>, offset: vec2<f32>) -> vec4<f32> {
    let c = quadratic_threshold(bilinear(source, uv + offset / vec2<f32>(textureDimensions(source))));
    return vec4<f32>(c, 1.0 / (luminance(c) + 1.0));
}

// PartialAverage: four taps' Karis-weighted mean
fn partial_average(a: vec4<f32>, b: vec4<f32>, c: vec4<f32>, d: vec4<f32>) -> vec3<f32> {
    return (a.rgb * a.w + b.rgb * b.w + c.rgb * c.w + d.rgb * d.w) / (a.w + b.w + c.w + d.w);
}

// HIGH_QUALITY prefilter [Jimenez14]: the inner 2×2 block half a texel out weighs 1/2, the four
// corner blocks one texel out 1/8 each, every block a Karis-weighted mean
fn prefilter_high(uv: vec2<f32>) -> vec3<f32> {
    let a = prefilter_tap(uv, vec2<f32>(-1.0, -1.0));
    let b = prefilter_tap(uv, vec2<f32>(0.0, -1.0));
    let c = prefilter_tap(uv, vec2<f32>(1.0, -1.0));
    let d = prefilter_tap(uv, vec2<f32>(-0.5, -0.5));
    let e = prefilter_tap(uv, vec2<f32>(0.5, -0.5));
    let f = prefilter_tap(uv, vec2<f32>(-1.0, 0.0));
    let g = prefilter_tap(uv, vec2<f32>(0.0, 0.0));
    let h = prefilter_tap(uv, vec2<f32>(1.0, 0.0));
    let i = prefilter_tap(uv, vec2<f32>(-0.5, 0.5));
    let j = prefilter_tap(uv, vec2<f32>(0.5, 0.5));
    let k = prefilter_tap(uv, vec2<f32>(-1.0, 1.0));
    let l = prefilter_tap(uv, vec2<f32>(0.0, 1.0));
    let m = prefilter_tap(uv, vec2<f32>(1.0, 1.0));
    return partial_average(d, e, i, j) * 0.5
        + (partial_average(a, b, f, g) + partial_average(b, c, g, h) + partial_average(f, g, k, l)
            + partial_average(g, h, l, m)) * 0.125;
}

// The 9-tap binomial blur (C(8, k)/256) along `step`
fn blur(t: texture_2d<f32>, p: vec2<i32>, step: vec2<i32>) -> vec3<f32> {
    let w = array<f32, 5>(0.2734375, 0.21875, 0.109375, 0.03125, 0.00390625);
    var c = load_clamped(t, p) * w[0];
    for (var k = 1; k < 5; k++) {
        c += (load_clamped(t, p + step * k) + load_clamped(t, p - step * k)) * w[k];
    }
    return c;
}

@compute @workgroup_size(8, 8)
fn cs_bloom(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = params.dims.xy;
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    var c = vec3<f32>(0.0);
    switch params.dims.z {
        case 0u: {
            let taps = array<vec2<f32>, 5>(
                vec2<f32>(0.0, 0.0), vec2<f32>(0.9, -0.4), vec2<f32>(-0.9, 0.4), vec2<f32>(0.4, 0.9), vec2<f32>(-0.4, -0.9)
            );
            // The taps step in the source's (full-resolution) texels: _PostProcessScreenSize.zw
            let source_texel = 1.0 / vec2<f32>(textureDimensions(source));
            var weights = 0.0;
            for (var k = 0; k < 5; k++) {
                let tap = quadratic_threshold(bilinear(source, uv + taps[k] * source_texel));
                let w = 1.0 / (luminance(tap) + 1.0);
                c += tap * w;
                weights += w;
            }
            c /= weights;
        }
        case 1u: {
            c = bilinear(source, uv);
        }
        case 2u: {
            c = blur(source, vec2<i32>(id.xy), vec2<i32>(1, 0));
        }
        case 3u: {
            c = blur(source, vec2<i32>(id.xy), vec2<i32>(0, 1));
        }
        // 4: upsample and composite alike, lerp(source, filter(coarse), factor)
        default: {
            var up = bilinear(coarse, uv);
            if (params.factor.y > 0.5) {
                up = bicubic(coarse, uv);
            }
            c = mix(load_clamped(source, vec2<i32>(id.xy)), up, params.factor.x);
        }
    }
    textureStore(destination, id.xy, vec4<f32>(c, 1.0));
}

// BloomPrefilter.compute HIGH_QUALITY as its own entry point, so its 13 taps stay out of the
// kernel every other step runs
@compute @workgroup_size(8, 8)
fn cs_bloom_prefilter_high(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = params.dims.xy;
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    textureStore(destination, id.xy, vec4<f32>(prefilter_high(uv), 1.0));
}
