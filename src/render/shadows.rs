//! Shadow maps: one depth layer per directional or spot light that casts shadows, six (a cube's
//! faces) per point light, in one depth texture array, re-rendered every frame as an engine does.
//! The forward pass samples them with a comparison sampler: one bilinear tap (hard) or 3×3
//! bilinear taps (soft), the receiver offset along its normal and towards the light by the light's
//! biases in shadow-map texels. APPROXIMATIONS, stated: one map per directional light fitted to the
//! whole scene (no cascades yet); Unity's soft-shadow tent filters are stood in for by the 3×3 PCF.

use glam::{DMat4, DVec3};

use super::uniforms::ShadowLayer;
use crate::spec::scene::{Light, LightKind};

pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Near plane of spot and point shadow frusta, metres.
const SHADOW_NEAR: f64 = 0.02;

/// The layers of one light: view-projection matrices and the texel size they imply.
pub fn light_layers(light: &Light, resolution: u32, scene_bounds: (DVec3, DVec3)) -> Vec<ShadowLayer> {
    let up_for = |dir: DVec3| if dir.cross(DVec3::Y).length() < 1e-6 { DVec3::Z } else { DVec3::Y };
    let res = resolution as f64;
    let perspective = |eye: DVec3, dir: DVec3, fov: f64, up: DVec3, far: f64| {
        let view = DMat4::look_at_rh(eye, eye + dir, up);
        let proj = DMat4::perspective_rh(fov, 1.0, SHADOW_NEAR, far.max(SHADOW_NEAR * 2.0));
        // World size of a texel per unit of view depth: 2·tan(fov/2)/resolution.
        layer(proj * view, [(2.0 * (fov * 0.5).tan() / res) as f32, 1.0, 0.0, 0.0])
    };
    match light.kind {
        LightKind::Directional => {
            let dir = DVec3::from(light.direction).normalize();
            let (lo, hi) = scene_bounds;
            let centre = (lo + hi) * 0.5;
            let radius = ((hi - lo).length() * 0.5).max(1e-3);
            let eye = centre - dir * radius * 2.0;
            let view = DMat4::look_at_rh(eye, centre, up_for(dir));
            let proj = DMat4::orthographic_rh(-radius, radius, -radius, radius, radius, radius * 3.0);
            vec![layer(proj * view, [(2.0 * radius / res) as f32, 0.0, 0.0, 0.0])]
        }
        LightKind::Spot => {
            let dir = DVec3::from(light.direction).normalize();
            // A texel of margin around the cone.
            let fov = (light.spot_angle_deg.to_radians() * (1.0 + 2.0 / res)).min(std::f64::consts::PI * 0.99);
            vec![perspective(DVec3::from(light.position), dir, fov, up_for(dir), light.range)]
        }
        LightKind::Point => {
            let eye = DVec3::from(light.position);
            // +X, −X, +Y, −Y, +Z, −Z: the face the forward pass picks by the major axis.
            let faces = [
                (DVec3::X, -DVec3::Y),
                (-DVec3::X, -DVec3::Y),
                (DVec3::Y, DVec3::Z),
                (-DVec3::Y, -DVec3::Z),
                (DVec3::Z, -DVec3::Y),
                (-DVec3::Z, -DVec3::Y),
            ];
            faces
                .iter()
                .map(|(dir, up)| {
                    perspective(eye, *dir, std::f64::consts::FRAC_PI_2 * (1.0 + 2.0 / res), *up, light.range)
                })
                .collect()
        }
    }
}

fn layer(view_proj: DMat4, params: [f32; 4]) -> ShadowLayer {
    ShadowLayer { view_proj: view_proj.as_mat4().to_cols_array_2d(), params }
}

/// The shader's GpuLight.shadow: (first layer or −1, layer count, strength, soft).
pub fn shadow_slot(light: &Light, first_layer: Option<usize>, layers: usize) -> ([f32; 4], [f32; 4]) {
    match first_layer {
        Some(first) => (
            [first as f32, layers as f32, light.shadow.strength as f32, if light.shadow.soft { 1.0 } else { 0.0 }],
            [light.shadow.bias as f32, light.shadow.normal_bias as f32, 0.0, 0.0],
        ),
        None => ([-1.0, 0.0, 0.0, 0.0], [0.0; 4]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_light_has_six_faces_each_seeing_its_axis() {
        let scene = crate::spec::scene::Scene::load("default", None, "t", "k").unwrap();
        let light = &scene.lights[scene.key_light().unwrap()];
        let layers = light_layers(light, 512, (DVec3::splat(-5.0), DVec3::splat(5.0)));
        assert_eq!(layers.len(), 6);
        let eye = DVec3::from(light.position);
        for (face, dir) in [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z].iter().enumerate() {
            let m = glam::Mat4::from_cols_array_2d(&layers[face].view_proj).as_dmat4();
            let clip = m * (eye + *dir * 2.0).extend(1.0);
            let ndc = clip.truncate() / clip.w;
            assert!(ndc.x.abs() < 1e-6 && ndc.y.abs() < 1e-6 && (0.0..1.0).contains(&ndc.z), "face {face}: {ndc}");
        }
    }
}
