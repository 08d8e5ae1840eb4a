//! Sky radiance in linear RGB for the three environment kinds.

use glam::DVec3;

use crate::color::srgb_to_linear;
use crate::declarations::scene::Sky;

fn lin(c: [f64; 3]) -> DVec3 {
    DVec3::from(c.map(srgb_to_linear))
}

/// Radiance arriving from direction `d` (unit, pointing away from the scene).
pub fn radiance(sky: &Sky, d: DVec3) -> DVec3 {
    match sky {
        Sky::Constant { color } => lin(*color),
        // Unity's trilight: sky above, equator at the horizon, ground below, blended by height.
        Sky::Gradient { sky, equator, ground } => {
            let (s, e, g) = (lin(*sky), lin(*equator), lin(*ground));
            if d.y >= 0.0 {
                e.lerp(s, d.y)
            } else {
                e.lerp(g, -d.y)
            }
        }
        Sky::Image { intensity, rotation_deg, image, units, .. } => match image {
            Some(image) => image_radiance(image, *rotation_deg, d) * (*intensity * units.scale()),
            None => DVec3::ZERO,
        },
        Sky::Cubemap { intensity, rotation_deg, images, units, .. } => match images {
            Some(faces) => cube_radiance(faces, *rotation_deg, d) * (*intensity * units.scale()),
            None => DVec3::ZERO,
        },
        Sky::Procedural { sun_direction, sun_size, atmosphere_thickness, sky_tint, ground, exposure } => procedural(
            DVec3::from(*sun_direction).normalize(),
            *sun_size,
            *atmosphere_thickness,
            lin(*sky_tint),
            lin(*ground),
            *exposure,
            d,
        ),
    }
}

/// d turned −rotation about +Y (so that the sky turns +rotation).
fn unrotated(rotation_deg: f64, d: DVec3) -> DVec3 {
    let (s, c) = (-rotation_deg.to_radians()).sin_cos();
    DVec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
}

/// An equirect image sky along d: its texel coordinates (`super::dir_to_uv`), bilinear between
/// texel centres, wrapping in u and clamped in v.
fn image_radiance(image: &crate::input::sky_image::SkyImage, rotation_deg: f64, d: DVec3) -> DVec3 {
    let [u, v] = super::dir_to_uv(unrotated(rotation_deg, d));
    DVec3::from(image.bilinear(u, v, true))
}

/// A cube-map sky along d: the face of d's major axis and its (s, t) as a Vulkan or OpenGL
/// `samplerCube` reads six images (+X −X +Y −Y +Z −Z; t down each image), bilinear within the face.
fn cube_radiance(faces: &[crate::input::sky_image::SkyImage], rotation_deg: f64, d: DVec3) -> DVec3 {
    let d = unrotated(rotation_deg, d);
    let a = d.abs();
    let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 {
            (0, -d.z, -d.y, a.x)
        } else {
            (1, d.z, -d.y, a.x)
        }
    } else if a.y >= a.z {
        if d.y > 0.0 {
            (2, d.x, d.z, a.y)
        } else {
            (3, d.x, -d.z, a.y)
        }
    } else if d.z > 0.0 {
        (4, d.x, -d.y, a.z)
    } else {
        (5, -d.x, -d.y, a.z)
    };
    let (u, v) = (0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0));
    DVec3::from(faces[face].bilinear(u, v, false))
}

/// APPROXIMATION of Unity's procedural sky (not its scattering integral): a zenith-to-horizon
/// gradient whose blue deepens with atmosphere thickness, tinted by sky_tint (0.5 grey = neutral),
/// a Mie-like glow and a sun disc of angular radius sun_size/2 rad, a ground colour lit by the
/// sun's elevation, all times exposure.
fn procedural(sun: DVec3, sun_size: f64, thickness: f64, tint: DVec3, ground: DVec3, exposure: f64, d: DVec3) -> DVec3 {
    let tint = tint / srgb_to_linear(0.5);
    let zenith = DVec3::new(0.10, 0.22, 0.55) * (0.5 + 0.5 * thickness) * tint;
    let horizon = DVec3::new(0.55, 0.62, 0.72) * tint;
    let sun_light = DVec3::new(1.0, 0.93, 0.82) * sun.y.max(0.05).sqrt();
    let sky = |y: f64| {
        let y = y.max(0.0);
        let base = horizon.lerp(zenith, y.sqrt());
        let cos = d.dot(sun);
        let glow = sun_light * 0.25 * (-(1.0 - cos) / 0.03).exp();
        let disc_radius = (sun_size * 0.5).max(1e-4);
        let disc = if cos > disc_radius.cos() { sun_light * 40.0 } else { DVec3::ZERO };
        base + glow + disc
    };
    let ground_lit = ground * (0.2 + 0.8 * sun.y.max(0.0));
    let c = if d.y >= 0.0 {
        sky(d.y)
    } else {
        // Blend across a thin band below the horizon so the horizon has no hard seam.
        ground_lit.lerp(horizon * tint.min_element().max(0.0), (1.0 + d.y / 0.02).clamp(0.0, 1.0))
    };
    c * exposure
}
