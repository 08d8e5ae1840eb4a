//! f64 twin of HDRP's shadow filters (shaders/pass/shadow_filters.wgsl, same names): the tent's
//! area over each texel of the map and the visibility it weights them into (Low, Medium), and
//! PCSS (High): the Fibonacci discs, the blocker search, the penumbra and the filter.

/// The share of a tent of half-width `h` (base 2h texels, centred at 0) below `t`.
pub fn tent_cdf(t: f64, h: f64) -> f64 {
    let x = t.clamp(-h, h);
    if x <= 0.0 {
        (x + h) * (x + h) / (2.0 * h * h)
    } else {
        1.0 - (h - x) * (h - x) / (2.0 * h * h)
    }
}

/// The weight of the texel covering [i, i + 1) under the tent of half-width `h` centred at `s`.
pub fn tent_texel_weight(i: f64, s: f64, h: f64) -> f64 {
    tent_cdf(i + 1.0 - s, h) - tent_cdf(i - s, h)
}

/// Visibility under an n×n tent PCF at texel-space position `s` of a layer whose texel (x, y) is
/// lit where `lit(x, y)` (its depth comparison), texels past the layer's edge `last` reading the
/// edge's (the GPU reads them in 2×2 gathers; the sum is the same).
pub fn shadow_tent(s: [f64; 2], n: u32, last: [i64; 2], lit: impl Fn(i64, i64) -> bool) -> f64 {
    let h = 0.5 * n as f64;
    let first = [(s[0] - h).floor(), (s[1] - h).floor()];
    let mut vis = 0.0;
    for j in 0..=n {
        let y = first[1] + j as f64;
        let wy = tent_texel_weight(y, s[1], h);
        for i in 0..=n {
            let x = first[0] + i as f64;
            let w = tent_texel_weight(x, s[0], h) * wy;
            let (tx, ty) = ((x as i64).clamp(0, last[0]), (y as i64).clamp(0, last[1]));
            vis += if lit(tx, ty) { w } else { 0.0 };
        }
    }
    vis
}

/// A shadow map as the PCSS twin reads it: its side in texels (the layer's), the share of it the
/// light's map covers from the top-left, and each texel's depth (this tool's, 0 near, 1 far).
pub struct DepthMap<'a> {
    pub side: usize,
    pub scale: f64,
    pub depth: &'a dyn Fn(i64, i64) -> f64,
}

impl DepthMap<'_> {
    fn texel(&self, x: i64, y: i64) -> f64 {
        let last = self.side as i64 - 1;
        (self.depth)(x.clamp(0, last), y.clamp(0, last))
    }

    /// A bilinear comparison tap (LessEqual, edges clamped): the lit share of the four texels.
    fn compare(&self, uv: [f64; 2], depth: f64) -> f64 {
        let (x, y) = (uv[0] * self.side as f64 - 0.5, uv[1] * self.side as f64 - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let lit = |i: i64, j: i64| if depth <= self.texel(x0 as i64 + i, y0 as i64 + j) { 1.0 } else { 0.0 };
        (lit(0, 0) * (1.0 - fx) + lit(1, 0) * fx) * (1.0 - fy) + (lit(0, 1) * (1.0 - fx) + lit(1, 1) * fx) * fy
    }
}

/// HDAdditionalLightData's m_BlockerSampleCount and m_FilterSampleCount.
pub const PCSS_BLOCKER_SAMPLES: u32 = 24;
pub const PCSS_FILTER_SAMPLES: u32 = 16;

/// The golden angle's share of a turn, (3 − √5)/2.
fn golden_turn() -> f64 {
    (3.0 - 5f64.sqrt()) / 2.0
}

/// ComputeFibonacciSpiralDiskSample: sample i of n on a disc of `radius`.
pub fn fibonacci_spiral_disk_sample(i: u32, n: u32, radius: f64) -> [f64; 2] {
    let c = i as f64 * golden_turn();
    let theta = (c - c.floor()) * std::f64::consts::TAU;
    let r = radius * (i as f64 / n as f64 + 0.5 / n as f64).sqrt();
    [theta.cos() * r, theta.sin() * r]
}

/// The per-pixel turn of a disc sample by j = (sin, cos) of the noise's angle.
pub fn pcss_turn(o: [f64; 2], j: [f64; 2]) -> [f64; 2] {
    [o[0] * j[1] + o[1] * j[0], -o[0] * j[0] + o[1] * j[1]]
}

/// PenumbraSizePunctual in reversed-Z depth.
pub fn penumbra_size_punctual(receiver: f64, blocker: f64) -> f64 {
    ((receiver - blocker) / blocker).abs()
}

/// PenumbraSizeDirectional.
pub fn penumbra_size_directional(receiver: f64, blocker: f64, range_scale: f64) -> f64 {
    (receiver - blocker).abs() * range_scale
}

/// HDRP's fit of a punctual light's PCSS softness to its shape radius x (× softness scale), / 100
/// (HDAdditionalLightData: "fitted with quartic regression checking against raytracing reference
/// and with a resolution of 512").
pub fn pcss_softness_punctual(x: f64) -> f64 {
    let x2 = x * x;
    (0.02403461 + 3.452916 * x - 1.362672 * x2 + 0.6700115 * x2 * x + 0.2159474 * x2 * x2) / 100.0
}

/// SampleShadow_PCSS's fitted softness scale for a punctual blocker at distance d (≤ 7.5).
pub fn pcss_distance_scale(d: f64) -> f64 {
    let d2 = d * d;
    3.298300241 - 2.001364639 * d + 0.4967311427 * d2 - 0.05464058455 * d * d2 + 0.0021974 * d2 * d2
}

/// Interleaved gradient noise at a pixel's centre, frame 0 (core Random.hlsl).
pub fn interleaved_gradient_noise(pixel: [f64; 2]) -> f64 {
    let f = |x: f64| x - x.floor();
    f(52.9829189 * f(0.06711056 * pixel[0] + 0.00583715 * pixel[1]))
}

/// BlockerSearch: the mean reversed depth of the disc's texels closer than z and their count.
pub fn pcss_blocker_search(map: &DepthMap, uv: [f64; 2], z: f64, radius: f64, jitter: [f64; 2]) -> (f64, u32) {
    let (mut sum, mut count) = (0.0, 0);
    for i in 0..PCSS_BLOCKER_SAMPLES {
        let o = pcss_turn(fibonacci_spiral_disk_sample(i, PCSS_BLOCKER_SAMPLES, radius), jitter);
        let s = map.side as f64;
        let map_z = 1.0 - map.texel(((uv[0] + o[0]) * s).floor() as i64, ((uv[1] + o[1]) * s).floor() as i64);
        if map_z > z {
            sum += map_z;
            count += 1;
        }
    }
    (if count > 0 { sum / count as f64 } else { 0.0 }, count)
}

/// PCSS: the mean of the disc's comparison taps, a tap off the light's map reading the centre.
pub fn pcss_filter(map: &DepthMap, uv: [f64; 2], depth: f64, radius: f64, jitter: [f64; 2]) -> f64 {
    let mut sum = 0.0;
    for i in 0..PCSS_FILTER_SAMPLES {
        let o = pcss_turn(fibonacci_spiral_disk_sample(i, PCSS_FILTER_SAMPLES, radius), jitter);
        let p = [uv[0] + o[0], uv[1] + o[1]];
        let outside = p[0] <= 0.0 || p[0] >= map.scale || p[1] <= 0.0 || p[1] >= map.scale;
        sum += map.compare(if outside { uv } else { p }, depth);
    }
    sum / PCSS_FILTER_SAMPLES as f64
}

/// SampleShadow_PCSS at the layer's `uv`, this tool's `depth`, the pixel `pixel` (its noise), with
/// the layer's PCSS terms `pcss` (plan::shadows::hdrp_pcss) and whether its map is perspective.
pub fn shadow_pcss(
    map: &DepthMap,
    uv: [f64; 2],
    depth: f64,
    pixel: [f64; 2],
    pcss: [f64; 4],
    perspective: bool,
) -> f64 {
    let z = 1.0 - depth;
    let angle = interleaved_gradient_noise(pixel) * std::f64::consts::TAU;
    let jitter = [angle.sin(), angle.cos()];
    let atlas_res_factor = 4096.0 / map.side as f64;
    let max_softness = 0.04 * (map.scale * map.side as f64 / 512.0);
    let mut softness = pcss[0];
    let search = (softness + 0.000001).min(max_softness) * atlas_res_factor;
    let (blocker, count) = pcss_blocker_search(map, uv, z, search, jitter);
    let penumbra = if perspective {
        let d = (1.0 / (pcss[2] * blocker + pcss[3])).min(7.5);
        softness = (softness * pcss_distance_scale(d)).min(max_softness);
        penumbra_size_punctual(z, blocker)
    } else {
        penumbra_size_directional(z, blocker, pcss[2])
    };
    let radius = if count >= 1 { (softness * penumbra).max(pcss[1]) } else { pcss[1] };
    pcss_filter(map, uv, depth, radius * atlas_res_factor, jitter)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tents_weights_are_hdrps_texel_areas() {
        // HDRP's 3×3 tent (1.5 high, 3 wide) centred between two texels lies on four: the outer
        // ones under 0.125 of its 2.25, the inner ones 1 each (SampleShadow_GetTexelAreas_Tent_3x3).
        let w: Vec<f64> = (-2..2).map(|i| tent_texel_weight(i as f64, 0.0, 1.5)).collect();
        for (got, want) in w.iter().zip([0.125, 1.0, 1.0, 0.125]) {
            assert!((got - want / 2.25).abs() < 1e-12, "{w:?}");
        }
        // Every tent's weights sum to 1 wherever it is centred.
        for n in [3u32, 5, 7] {
            for s in [0.0, 0.3, 0.5, 0.77] {
                let h = n as f64 / 2.0;
                let sum: f64 = (-5..6).map(|i| tent_texel_weight(i as f64, s, h)).sum();
                assert!((sum - 1.0).abs() < 1e-12, "{n} at {s}: {sum}");
            }
        }
    }

    #[test]
    fn a_wider_tent_spreads_an_edge_further() {
        // An edge at x = 10 (lit to its left): the tent's visibility falls from 1 to 0 over n texels.
        let lit = |x: i64, _y: i64| x < 10;
        let vis = |x: f64, n: u32| shadow_tent([x, 5.0], n, [63, 63], lit);
        assert!((vis(10.0, 5) - 0.5).abs() < 1e-12, "half at the edge");
        for n in [3u32, 5, 7] {
            let h = n as f64 / 2.0;
            assert!((vis(10.0 - h, n) - 1.0).abs() < 1e-12 && vis(10.0 + h, n).abs() < 1e-12);
            assert!(vis(10.0 - h + 0.25, n) < 1.0 && vis(10.0 + h - 0.25, n) > 0.0);
        }
    }

    #[test]
    fn the_fibonacci_disc_is_hdrps_table() {
        // HDPCSS.hlsl's fibonacciSpiralDirection[1], [2], [63], and the radius √(i/n + 1/2n).
        for (i, want) in [
            (1u32, [-0.7373688780783197, 0.6754902942615238]),
            (2, [0.08742572471695988, -0.9961710408648278]),
            (63, [0.9205789302157817, 0.3905565685566777]),
        ] {
            let s = fibonacci_spiral_disk_sample(i, 64, 1.0);
            let r = ((i as f64 + 0.5) / 64.0).sqrt();
            assert!((s[0] / r - want[0]).abs() < 1e-9 && (s[1] / r - want[1]).abs() < 1e-9, "{i}: {s:?}");
        }
        // The fitted terms at known points: the distance scale's constant, the punctual softness
        // of HDRP's default 0.025 m shape radius.
        assert!((pcss_distance_scale(0.0) - 3.298300241).abs() < 1e-12);
        let soft = pcss_softness_punctual(0.025);
        assert!((soft - 0.0010949).abs() < 1e-6, "{soft}");
    }

    #[test]
    fn pcss_hardens_at_contact_and_softens_with_distance() {
        // A blocker over the left half of a 256² orthographic map at reversed depth 0.9; the
        // receiver behind it at 0.9 − gap. The penumbra (visibility strictly between 0.02 and
        // 0.98, across x) widens with the gap, as a physical penumbra does.
        let gap_width = |gap: f64| {
            let depth = |x: i64, _y: i64| if x < 128 { 0.1 } else { 1.0 };
            let map = DepthMap { side: 256, scale: 1.0, depth: &depth };
            let receiver = 0.1 + gap;
            let pcss = [0.02, 0.0001, 2.0 * 20.0 / 100.0, 0.0];
            (0..256)
                .map(|x| {
                    let uv = [(x as f64 + 0.5) / 256.0, 0.5];
                    shadow_pcss(&map, uv, receiver, [x as f64 + 0.5, 10.5], pcss, false)
                })
                .filter(|v| *v > 0.02 && *v < 0.98)
                .count()
        };
        let (near, far) = (gap_width(0.01), gap_width(0.2));
        assert!(near < far, "penumbra {near} texels at a small gap, {far} at a large one");
        // Lit where nothing is closer: no blocker, the minimum filter, fully lit.
        let depth = |_x: i64, _y: i64| 1.0;
        let map = DepthMap { side: 64, scale: 1.0, depth: &depth };
        assert_eq!(shadow_pcss(&map, [0.5, 0.5], 0.5, [3.5, 3.5], [0.02, 0.0001, 0.4, 0.0], false), 1.0);
    }
}
