//! f64 twin of HDRP's tent shadow filters (shaders/pass/shadow_filters.wgsl, same names): the
//! tent's area over each texel of the map, and the visibility it weights them into.

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
}
