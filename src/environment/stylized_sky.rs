//! The stylized sky the project ships (scenes/skies/stylized.exr), baked here so that it is made,
//! not downloaded: toon bands from a deep zenith through a pale middle to a warm horizon, flat
//! cloud shapes with darker undersides, a sun disc with a halo, and a plain ground — the hard-edged
//! look of a game's painted skybox, in linear radiance (sky ≈ 0.1–1, sun 40). `examples/
//! bake_stylized_sky.rs` writes it; a test holds the shipped file to this bake.

use glam::DVec3;

/// Where the sun is: azimuth from −Z towards +X and elevation, degrees.
pub const SUN_AZIMUTH_DEG: f64 = 40.0;
pub const SUN_ELEVATION_DEG: f64 = 25.0;
/// The shipped size.
pub const WIDTH: usize = 512;
pub const HEIGHT: usize = 256;

fn direction(azimuth_deg: f64, elevation_deg: f64) -> DVec3 {
    let (a, e) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
    DVec3::new(e.cos() * a.sin(), e.sin(), -e.cos() * a.cos())
}

/// Cloud shapes: (azimuth, elevation, half-width, half-height), degrees.
const CLOUDS: [(f64, f64, f64, f64); 6] = [
    (-60.0, 18.0, 22.0, 5.0),
    (-35.0, 24.0, 12.0, 4.0),
    (100.0, 14.0, 26.0, 4.5),
    (150.0, 30.0, 16.0, 5.5),
    (-140.0, 10.0, 30.0, 3.5),
    (10.0, 45.0, 14.0, 4.0),
];

/// The sky's radiance along d (unit).
pub fn radiance(d: DVec3) -> DVec3 {
    let elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
    if elevation < 0.0 {
        // Ground: two flat tones, darker away from the horizon.
        return if elevation > -8.0 { DVec3::new(0.16, 0.13, 0.10) } else { DVec3::new(0.09, 0.08, 0.07) };
    }
    let bands = [
        (6.0, DVec3::new(1.00, 0.70, 0.42)),
        (18.0, DVec3::new(0.85, 0.78, 0.70)),
        (40.0, DVec3::new(0.40, 0.58, 0.95)),
        (90.1, DVec3::new(0.12, 0.24, 0.62)),
    ];
    let mut c = bands.iter().find(|(top, _)| elevation < *top).map_or(bands[3].1, |b| b.1);
    let azimuth = d.x.atan2(-d.z).to_degrees();
    for (a, e, w, h) in CLOUDS {
        let da = ((azimuth - a + 540.0) % 360.0) - 180.0;
        let r = (da / w).powi(2) + ((elevation - e) / h).powi(2);
        if r < 1.0 {
            // A flat top, a darker underside below the cloud's middle.
            c = if elevation < e - 0.3 * h { DVec3::new(0.62, 0.62, 0.72) } else { DVec3::new(0.95, 0.95, 0.98) };
        }
    }
    let sun = direction(SUN_AZIMUTH_DEG, SUN_ELEVATION_DEG);
    let angle = d.dot(sun).clamp(-1.0, 1.0).acos().to_degrees();
    if angle < 2.5 {
        c = DVec3::new(40.0, 36.0, 30.0);
    } else if angle < 5.0 {
        c += DVec3::new(1.2, 1.0, 0.7);
    }
    c
}

/// The sky at `width` × `height` (equirect, `super::uv_to_dir`), each texel the mean of 4 × 4
/// directions over it.
pub fn bake(width: usize, height: usize) -> Vec<[f32; 3]> {
    let ss = 4;
    (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let mut acc = DVec3::ZERO;
            for sy in 0..ss {
                for sx in 0..ss {
                    let u = (x as f64 + (sx as f64 + 0.5) / ss as f64) / width as f64;
                    let v = (y as f64 + (sy as f64 + 0.5) / ss as f64) / height as f64;
                    acc += radiance(super::uv_to_dir(u, v));
                }
            }
            let c = acc / (ss * ss) as f64;
            [c.x as f32, c.y as f32, c.z as f32]
        })
        .collect()
}
