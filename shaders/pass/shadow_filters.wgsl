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
// comparison (lit where depth ≤ the map's, the comparison sampler's LessEqual) weighted by the
// tent's area over it; `extent`: the share of the layer's side the light's map fills, whose last
// texel edge reads repeat
fn shadow_tent(layer: u32, uv: vec2<f32>, depth: f32, n: f32, extent: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
    let s = uv * size;
    let h = 0.5 * n;
    let first = floor(s - h);
    let last = vec2<i32>(ceil(extent * size)) - vec2<i32>(1);
    let count = i32(n);
    var vis = 0.0;
    for (var j = 0; j <= count; j++) {
        let y = first.y + f32(j);
        let wy = tent_texel_weight(y, s.y, h);
        for (var i = 0; i <= count; i++) {
            let x = first.x + f32(i);
            let w = tent_texel_weight(x, s.x, h) * wy;
            let texel = clamp(vec2<i32>(i32(x), i32(y)), vec2<i32>(0), last);
            let stored = textureLoad(shadow_maps, texel, layer, 0);
            vis += w * select(0.0, 1.0, depth <= stored);
        }
    }
    return vis;
}
