// HDRP's shadow filters (HDShadowAlgorithms.hlsl: PUNCTUAL_ / DIRECTIONAL_FILTER_ALGORITHM per
// Filtering Quality), read by forward.wgsl's shadow_visibility. f64 twin: src/shading/shadow_filter.rs.

// The share of a tent of half-width h (its base 2h texels, centred at 0) below t: its CDF. The
// tent's area over a texel is a difference of two (SampleShadow_GetTexelAreas_Tent_NxN)
fn tent_cdf(t: f32, h: f32) -> f32 {
    let x = clamp(t, -h, h);
    if (x <= 0.0) {
        return (x + h) * (x + h) / (2.0 * h * h);
    }
    return 1.0 - (h - x) * (h - x) / (2.0 * h * h);
}

// Weight of the texel covering [i, i + 1) under the tent of half-width h centred at s (texel space)
fn tent_texel_weight(i: f32, s: f32, h: f32) -> f32 {
    return tent_cdf(i + 1.0 - s, h) - tent_cdf(i - s, h);
}

// Visibility under an n×n tent PCF (SampleShadow_PCF_Tent_3x3 / 5x5 / 7x7): each texel's depth
// comparison (lit where depth ≤ the map's: the comparison sampler's LessEqual) weighted by the
// tent's area over it. The n + 1 texels a side are read in 2×2 gathers, each at the corner its
// four texels share; past the layer's edge its edge texel repeats (the sampler clamps)
fn shadow_tent(layer: u32, uv: vec2<f32>, depth: f32, n: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
    let s = uv * size;
    let h = 0.5 * n;
    let first = floor(s - h);
    let blocks = i32(n + 1.0) / 2;
    var vis = 0.0;
    for (var by = 0; by < blocks; by++) {
        let y0 = first.y + 2.0 * f32(by);
        let wy = vec2<f32>(tent_texel_weight(y0, s.y, h), tent_texel_weight(y0 + 1.0, s.y, h));
        for (var bx = 0; bx < blocks; bx++) {
            let x0 = first.x + 2.0 * f32(bx);
            let wx = vec2<f32>(tent_texel_weight(x0, s.x, h), tent_texel_weight(x0 + 1.0, s.x, h));
            // x: (x0, y0 + 1), y: (x0 + 1, y0 + 1), z: (x0 + 1, y0), w: (x0, y0)
            let lit = textureGatherCompare(shadow_maps, shadow_sampler, vec2<f32>(x0 + 1.0, y0 + 1.0) / size, layer, depth);
            vis += dot(lit, vec4<f32>(wx.x * wy.y, wx.y * wy.y, wx.y * wy.x, wx.x * wy.x));
        }
    }
    return vis;
}

// HDRP's PCSS, Filtering Quality High (HDShadowSampling.hlsl SampleShadow_PCSS, HDPCSS.hlsl): a
// blocker search over a Fibonacci disc, the penumbra it implies, then comparison taps over a
// Fibonacci disc that wide, both discs turned per pixel by interleaved gradient noise. Depths are
// HDRP's reversed-Z ones, 1 − this tool's (exact for the same near and far planes).

// HDAdditionalLightData's m_BlockerSampleCount and m_FilterSampleCount
const PCSS_BLOCKER_SAMPLES: u32 = 24u;
const PCSS_FILTER_SAMPLES: u32 = 16u;
// The golden angle's share of a turn, (3 − √5)/2: fibonacciSpiralDirection[i] turns i of them
const GOLDEN_TURN: f32 = 0.381966011250105;

// ComputeFibonacciSpiralDiskSample: sample i of n on a disc of `radius`, its direction i golden
// turns round, at radius·√(i/n + 1/(2n))
fn fibonacci_spiral_disk_sample(i: u32, n: u32, radius: f32) -> vec2<f32> {
    let theta = fract(f32(i) * GOLDEN_TURN) * 2.0 * PI;
    let inv = 1.0 / f32(n);
    return vec2<f32>(cos(theta), sin(theta)) * radius * sqrt(f32(i) * inv + 0.5 * inv);
}

// The per-pixel turn of a disc sample: (o.x·j.y + o.y·j.x, −o.x·j.x + o.y·j.y), j = (sin, cos)
fn pcss_turn(o: vec2<f32>, j: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(o.x * j.y + o.y * j.x, -o.x * j.x + o.y * j.y);
}

// PenumbraSizePunctual: |(receiver − blocker)/blocker| in reversed-Z depth
fn penumbra_size_punctual(receiver: f32, blocker: f32) -> f32 {
    return abs((receiver - blocker) / blocker);
}

// PenumbraSizeDirectional: |receiver − blocker|·range scale
fn penumbra_size_directional(receiver: f32, blocker: f32, range_scale: f32) -> f32 {
    return abs(receiver - blocker) * range_scale;
}

// SampleShadow_PCSS's softness scale for a punctual light's blocker at distance d (clamped to
// 7.5): a quartic "fitted to match ray trace reference as good as possible"
fn pcss_distance_scale(d: f32) -> f32 {
    let d2 = d * d;
    return 3.298300241 - 2.001364639 * d + 0.4967311427 * d2 - 0.05464058455 * d * d2 + 0.0021974 * d2 * d2;
}

// BlockerSearch: the mean reversed depth of the disc's texels closer than z (point-sampled) and
// their count
fn pcss_blocker_search(layer: u32, uv: vec2<f32>, z: f32, radius: f32, jitter: vec2<f32>) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(shadow_maps));
    var sum = 0.0;
    var count = 0.0;
    for (var i = 0u; i < PCSS_BLOCKER_SAMPLES; i++) {
        let o = pcss_turn(fibonacci_spiral_disk_sample(i, PCSS_BLOCKER_SAMPLES, radius), jitter);
        let texel = clamp(vec2<i32>(floor((uv + o) * vec2<f32>(size))), vec2<i32>(0), size - 1);
        let map_z = 1.0 - textureLoad(shadow_maps, texel, layer, 0);
        if (map_z > z) {
            sum += map_z;
            count += 1.0;
        }
    }
    return vec2<f32>(select(0.0, sum / max(count, 1.0), count > 0.0), count);
}

// PCSS: the mean of the disc's comparison taps; a tap off the light's map (the top-left `scale`
// of the layer) reads the centre instead
fn pcss_filter(layer: u32, uv: vec2<f32>, depth: f32, radius: f32, scale: f32, jitter: vec2<f32>) -> f32 {
    var sum = 0.0;
    for (var i = 0u; i < PCSS_FILTER_SAMPLES; i++) {
        let o = pcss_turn(fibonacci_spiral_disk_sample(i, PCSS_FILTER_SAMPLES, radius), jitter);
        let p = uv + o;
        let outside = p.x <= 0.0 || p.x >= scale || p.y <= 0.0 || p.y >= scale;
        sum += textureSampleCompareLevel(shadow_maps, shadow_sampler, select(p, uv, outside), layer, depth);
    }
    return sum / f32(PCSS_FILTER_SAMPLES);
}

// SampleShadow_PCSS at the layer's uv and this tool's depth. The "atlas" is the layer: offsets
// scale by 4096 / its side as HDRP's by its atlas's ("the softness fitting has been done using a
// reference 4096x4096"), the softness is capped at 0.04 per 512 texels of the map, and the noise
// is frame 0's (no TAA here)
fn shadow_pcss(layer: u32, info: ShadowLayer, uv: vec2<f32>, depth: f32) -> f32 {
    let atlas = f32(textureDimensions(shadow_maps).x);
    let scale = info.params.w;
    let perspective = info.params.y > 0.5;
    let z = 1.0 - depth;
    let angle = interleaved_gradient_noise(shading_pixel) * 2.0 * PI;
    let jitter = vec2<f32>(sin(angle), cos(angle));
    let atlas_res_factor = 4096.0 / atlas;
    let max_softness = 0.04 * (scale * atlas / 512.0);
    var softness = info.pcss.x;
    let search = min(softness + 0.000001, max_softness) * atlas_res_factor;
    let blocker = pcss_blocker_search(layer, uv, z, search, jitter);
    var penumbra = 0.0;
    if (perspective) {
        let d = min(1.0 / (info.pcss.z * blocker.x + info.pcss.w), 7.5);
        softness = min(softness * pcss_distance_scale(d), max_softness);
        penumbra = penumbra_size_punctual(z, blocker.x);
    } else {
        penumbra = penumbra_size_directional(z, blocker.x, info.pcss.z);
    }
    var radius = info.pcss.y;
    if (blocker.y >= 1.0) {
        radius = max(softness * penumbra, info.pcss.y);
    }
    return pcss_filter(layer, uv, depth, radius * atlas_res_factor, scale, jitter);
}
