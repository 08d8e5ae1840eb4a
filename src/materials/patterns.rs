//! The twelve presets' surface patterns on the unit tile (u, v ∈ [0, 1), tileable): wood grain,
//! brick courses with mortar, marble veins, fabric weave, concrete noise, cracked withered wood,
//! brushed aluminium, scratched gold and silver, plastic with fine noise, rubber with tread, painted
//! steel with chips down to the metal. Each gives an albedo multiplier, a height, occlusion, a
//! smoothness offset and where bare metal shows; `super::generate` normalises the means.

use std::f64::consts::TAU;

use super::Texel;

pub struct Pattern {
    pub texel: fn(f64, f64) -> Texel,
    /// Height units per unit of UV for the normal map's slopes.
    pub bump: f64,
}

fn hash(x: i64, y: i64, seed: u64) -> f64 {
    let mut h = (x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F) ^ seed;
    h ^= h >> 33;
    h = h.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
    h ^= h >> 33;
    (h >> 11) as f64 / (1u64 << 53) as f64
}

/// Value noise on a `period`-cell lattice that wraps (so the tile repeats), smoothstep-interpolated.
pub fn noise(u: f64, v: f64, period: i64, seed: u64) -> f64 {
    let (x, y) = (u * period as f64, v * period as f64);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sy) = (s(fx), s(fy));
    let (ix, iy) = (x0 as i64, y0 as i64);
    let h = |dx: i64, dy: i64| hash((ix + dx).rem_euclid(period), (iy + dy).rem_euclid(period), seed);
    let a = h(0, 0) + (h(1, 0) - h(0, 0)) * sx;
    let b = h(0, 1) + (h(1, 1) - h(0, 1)) * sx;
    a + (b - a) * sy
}

/// Four octaves of `noise`, in [0, 1).
pub fn fbm(u: f64, v: f64, period: i64, seed: u64) -> f64 {
    let (mut sum, mut amp, mut total, mut p) = (0.0, 0.5, 0.0, period);
    for o in 0..4 {
        sum += amp * noise(u, v, p, seed + o);
        total += amp;
        amp *= 0.5;
        p *= 2;
    }
    sum / total
}

fn grey(a: f64) -> [f64; 3] {
    [a, a, a]
}

fn texel(albedo: [f64; 3], height: f64, occlusion: f64, smoothness: f64) -> Texel {
    Texel { albedo, height, occlusion, smoothness, bare_metal: 0.0 }
}

fn wood(u: f64, v: f64) -> Texel {
    // Growth rings across v, bent by low-frequency noise; late wood darker and a little raised.
    let t = v * 6.0 + 0.35 * fbm(u, v, 4, 11) + 0.05 * fbm(u, v, 32, 12);
    let ring = (0.5 + 0.5 * (TAU * t).sin()).powi(3);
    let fibre = noise(u, v * 0.25, 64, 13);
    texel(grey(1.0 - 0.45 * ring - 0.1 * fibre), 0.3 * ring + 0.1 * fibre, 1.0, -0.1 * ring)
}

fn withered_wood(u: f64, v: f64) -> Texel {
    let w = wood(u, v);
    // Cracks along the grain: where a stretched noise crosses its median.
    let c = (noise(u * 0.5, v, 16, 21) - 0.5).abs();
    let crack = (1.0 - c / 0.03).clamp(0.0, 1.0);
    let grain = 0.9 + 0.2 * fbm(u, v, 8, 22);
    texel(
        grey(grain * (w.albedo[0] * 0.6 + 0.4) * (1.0 - 0.7 * crack)),
        w.height - 0.8 * crack,
        1.0 - 0.6 * crack,
        -0.05 * crack,
    )
}

fn brick(u: f64, v: f64) -> Texel {
    // Four courses of two bricks, every other course offset by half a brick; mortar 8 % of the pitch.
    let (rows, cols) = (4.0, 2.0);
    let row = (v * rows).floor();
    let x = u * cols + if (row as i64) % 2 == 1 { 0.5 } else { 0.0 };
    let (fx, fy) = (x.fract(), (v * rows).fract());
    let edge = fx.min(1.0 - fx).min((fy.min(1.0 - fy)) * cols / rows * 2.0);
    let mortar = (1.0 - edge / 0.04).clamp(0.0, 1.0);
    let brick_id = hash(x.floor() as i64, row as i64, 31);
    let tone = 0.85 + 0.3 * brick_id + 0.15 * fbm(u, v, 16, 32);
    // Mortar is grey against red brick: relatively much more green and blue.
    let mortar_colour = [1.6, 3.5, 4.5];
    let albedo = [0, 1, 2].map(|c| tone * (1.0 - mortar) + mortar_colour[c] * mortar);
    texel(albedo, 1.0 - mortar + 0.1 * fbm(u, v, 32, 33), 1.0 - 0.25 * mortar, -0.05 * mortar)
}

fn marble(u: f64, v: f64) -> Texel {
    let t = u * 3.0 + v * 2.0 + 2.5 * fbm(u, v, 4, 41);
    let vein = (TAU * t).sin().abs().powf(0.25);
    let cloud = fbm(u, v, 8, 42);
    texel(grey(0.55 + 0.45 * vein + 0.1 * cloud), 0.02 * cloud, 1.0, 0.0)
}

fn fabric(u: f64, v: f64) -> Texel {
    // Plain weave: warp and weft threads alternate over and under, 48 per tile.
    let n = 48.0;
    let (a, b) = ((u * n * TAU).sin(), (v * n * TAU).sin());
    let over = if ((u * n).floor() as i64 + (v * n).floor() as i64) % 2 == 0 { a.abs() } else { b.abs() };
    let slub = noise(u, v, 24, 51);
    texel(grey(0.85 + 0.2 * over + 0.1 * slub), 0.6 * over, 0.96 + 0.04 * over, 0.05 * over)
}

fn concrete(u: f64, v: f64) -> Texel {
    let base = fbm(u, v, 8, 61);
    let grain = noise(u, v, 128, 62);
    let pit = ((noise(u, v, 64, 63) - 0.85) / 0.15).clamp(0.0, 1.0);
    texel(
        grey(0.85 + 0.25 * base + 0.1 * grain - 0.3 * pit),
        0.3 * base + 0.2 * grain - pit,
        1.0 - 0.4 * pit,
        -0.05 * pit,
    )
}

fn brushed(u: f64, v: f64) -> Texel {
    // Brushing along u: noise stretched 64:1.
    let streak = fbm(u, v * 64.0, 4, 71);
    let fine = noise(u, v, 256, 72);
    texel(grey(0.9 + 0.2 * streak), 0.3 * streak + 0.02 * fine, 1.0, 0.15 * (streak - 0.5))
}

fn scratched(u: f64, v: f64) -> Texel {
    // Scratches: thin lines where noise stretched along a few directions crosses its median.
    let mut s: f64 = 0.0;
    for (i, (du, dv)) in [(1.0, 0.3), (0.4, 1.0), (1.0, -0.7)].into_iter().enumerate() {
        let along = noise(u * du + v * dv, (v * du - u * dv) * 0.05, 32, 81 + i as u64);
        let line = (1.0 - (along - 0.5).abs() / 0.015).clamp(0.0, 1.0);
        let patchy = ((noise(u, v, 8, 91 + i as u64) - 0.4) / 0.3).clamp(0.0, 1.0);
        s = s.max(line * patchy);
    }
    texel(grey(1.0 - 0.25 * s), -0.4 * s, 1.0 - 0.2 * s, -0.35 * s)
}

fn plastic(u: f64, v: f64) -> Texel {
    let fine = fbm(u, v, 64, 101);
    texel(grey(0.92 + 0.16 * fine), 0.1 * fine, 1.0, -0.05 * fine)
}

fn rubber(u: f64, v: f64) -> Texel {
    // Tread: grooves across v (8 per tile) and a zigzag rib along u.
    let zig = ((u * 8.0).fract() - 0.5).abs() * 0.25;
    let g = ((v * 8.0 + zig).fract() - 0.5).abs();
    let groove = (1.0 - ((g - 0.35) / 0.05).max(0.0)).clamp(0.0, 1.0) * ((g - 0.3) / 0.05).clamp(0.0, 1.0);
    let wear = fbm(u, v, 16, 111);
    texel(grey(0.9 + 0.2 * wear - 0.3 * groove), -groove + 0.05 * wear, 1.0 - 0.25 * groove, 0.1 * wear)
}

fn painted_chips(u: f64, v: f64) -> Texel {
    // Chips: where the paint came off, the steel under it shows (metal, rougher, recessed).
    let chip = ((fbm(u, v, 8, 121) - 0.70) / 0.03).clamp(0.0, 1.0);
    let orange_peel = noise(u, v, 96, 122);
    // Steel's F0 (0.56, 0.57, 0.58, the metal reflectance charts' iron) against the blue paint's
    // (0.040, 0.047, 0.305): relatively much more red and green.
    let steel = [0.56 / 0.040, 0.57 / 0.047, 0.58 / 0.305];
    let albedo = [0, 1, 2].map(|c| (1.0 - chip) * (0.97 + 0.06 * orange_peel) + chip * steel[c]);
    Texel { bare_metal: chip, ..texel(albedo, -0.5 * chip + 0.03 * orange_peel, 1.0 - 0.1 * chip, -0.25 * chip) }
}

/// The pattern of a preset (the presets' names, spec presets.md); an unknown name gets plastic's.
pub fn pattern(preset: &str) -> Pattern {
    let (texel, bump): (fn(f64, f64) -> Texel, f64) = match preset {
        "wood" => (wood, 0.004),
        "withered_wood" => (withered_wood, 0.006),
        "brick" => (brick, 0.01),
        "marble" => (marble, 0.002),
        "fabric" => (fabric, 0.002),
        "concrete" => (concrete, 0.006),
        "aluminium" => (brushed, 0.004),
        "gold" | "silver" => (scratched, 0.003),
        "rubber" => (rubber, 0.008),
        "blue_paint" => (painted_chips, 0.005),
        _ => (plastic, 0.002),
    };
    Pattern { texel, bump }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_tiles() {
        for (u, v) in [(0.1, 0.7), (0.93, 0.02)] {
            assert!((noise(u, v, 8, 1) - noise(u + 1.0, v, 8, 1)).abs() < 1e-12);
            assert!((fbm(u, v, 4, 2) - fbm(u, v + 1.0, 4, 2)).abs() < 1e-12);
        }
    }
}
