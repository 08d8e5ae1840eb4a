//! Writes the composite scene's two framed photos, scenes/textures/landscape.png (a lake under
//! mountains at dusk, 3:2) and scenes/textures/tree.png (a tree on a hill, 3:4): painted here from
//! gradients, a small value noise and shapes, not downloaded. 8-bit sRGB PNGs.
//! `cargo run --release --example bake_composite_photos`; the shipped files are this output.

use std::path::Path;

/// Value noise on a lattice of `cell` pixels, smoothstep-interpolated, in 0..1.
fn noise(x: f64, y: f64, seed: u32) -> f64 {
    let hash = |i: i64, j: i64| {
        let mut h = (i as u32).wrapping_mul(374_761_393) ^ (j as u32).wrapping_mul(668_265_263) ^ seed;
        h = (h ^ (h >> 13)).wrapping_mul(1_274_126_177);
        ((h ^ (h >> 16)) & 0xffff) as f64 / 65535.0
    };
    let (i, j) = (x.floor(), y.floor());
    let (fx, fy) = (x - i, y - j);
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (i, j) = (i as i64, j as i64);
    let top = hash(i, j) + (hash(i + 1, j) - hash(i, j)) * s(fx);
    let bottom = hash(i, j + 1) + (hash(i + 1, j + 1) - hash(i, j + 1)) * s(fx);
    top + (bottom - top) * s(fy)
}

/// Three octaves of `noise`.
fn fbm(x: f64, y: f64, seed: u32) -> f64 {
    (noise(x, y, seed) * 4.0 + noise(2.0 * x, 2.0 * y, seed + 1) * 2.0 + noise(4.0 * x, 4.0 * y, seed + 2)) / 7.0
}

fn mix(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    let t = t.clamp(0.0, 1.0);
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t)
}

/// Sky, sun, two mountain ridges, a lake mirroring them.
fn landscape(u: f64, v: f64) -> [f64; 3] {
    let horizon = 0.62;
    let sky = |v: f64| mix([0.16, 0.22, 0.45], [0.98, 0.62, 0.35], v / horizon);
    let ridge = |u: f64, k: u32, base: f64, amp: f64| base - amp * fbm(u * 5.0, 0.5, k);
    let scene = |u: f64, v: f64| {
        let sun = ((u - 0.68).powi(2) + (v - 0.45).powi(2)).sqrt();
        let mut c = sky(v);
        if sun < 0.06 {
            c = [1.0, 0.93, 0.7];
        }
        if v > ridge(u, 7, horizon, 0.28) {
            c = mix([0.36, 0.27, 0.38], [0.28, 0.22, 0.3], fbm(u * 20.0, v * 20.0, 3));
        }
        if v > ridge(u, 11, horizon, 0.14) {
            c = mix([0.14, 0.2, 0.16], [0.09, 0.14, 0.1], fbm(u * 30.0, v * 30.0, 5));
        }
        c
    };
    if v <= horizon {
        return scene(u, v);
    }
    // The lake: the scene mirrored about the horizon, darkened, rippled.
    let ripple = (fbm(u * 40.0, v * 160.0, 9) - 0.5) * 0.02;
    let c = scene(u + ripple, 2.0 * horizon - v);
    mix(c.map(|x| x * 0.7), [0.08, 0.12, 0.2], (v - horizon) / (1.0 - horizon) * 0.8)
}

/// A tree with a round crown on a green hill under a pale sky.
fn tree(u: f64, v: f64) -> [f64; 3] {
    let mut c = mix([0.55, 0.72, 0.9], [0.9, 0.92, 0.85], v / 0.7);
    let hill = 0.72 - 0.08 * (1.0 - ((u - 0.45) * 2.2).powi(2)).max(0.0);
    if v > hill {
        c = mix([0.32, 0.55, 0.2], [0.2, 0.38, 0.12], fbm(u * 25.0, v * 25.0, 13));
    }
    let trunk = (u - 0.48).abs() < 0.035 && v > 0.42 && v < hill + 0.02;
    if trunk {
        c = [0.3, 0.2, 0.12];
    }
    let r = fbm(u * 9.0, v * 9.0, 17) * 0.08 + 0.2;
    let d = ((u - 0.48).powi(2) + ((v - 0.34) * 1.1).powi(2)).sqrt();
    if d < r {
        c = mix([0.14, 0.42, 0.14], [0.36, 0.6, 0.18], fbm(u * 30.0, v * 30.0, 19) + (0.34 - v));
    }
    c
}

fn write(name: &str, (w, h): (u32, u32), paint: fn(f64, f64) -> [f64; 3]) {
    // Four samples per pixel, averaged in linear light, then sRGB-encoded.
    let image = image::RgbImage::from_fn(w, h, |x, y| {
        let mut acc = [0.0; 3];
        for (dx, dy) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
            let c = paint((x as f64 + dx) / w as f64, (y as f64 + dy) / h as f64);
            for k in 0..3 {
                acc[k] += c[k] / 4.0;
            }
        }
        image::Rgb(acc.map(|c| (shadematrix::color::linear_to_srgb(c).clamp(0.0, 1.0) * 255.0).round() as u8))
    });
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/textures").join(name);
    image.save(&path).expect("writing the photo");
    println!("wrote {}", path.display());
}

fn main() {
    write("landscape.png", (192, 128), landscape);
    write("tree.png", (96, 128), tree);
}
