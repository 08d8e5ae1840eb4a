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
