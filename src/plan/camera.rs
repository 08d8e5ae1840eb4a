use glam::{DMat4, DVec3};

use crate::declarations::scene::{Camera, Light, LightKind, Scene};

/// Right-handed view and wgpu (0..1 depth) projection.
pub fn view_projection(c: &Camera, aspect: f64) -> DMat4 {
    let proj = DMat4::perspective_rh(c.fov_y_deg.to_radians(), aspect, c.near, c.far);
    proj * view_matrix(c)
}

/// The right-handed world-to-view matrix (looking down −z, as Unity's view space).
pub fn view_matrix(c: &Camera) -> DMat4 {
    let eye = DVec3::from(c.position);
    let target = DVec3::from(c.target);
    let dir = (target - eye).normalize();
    // Looking straight up or down leaves Y undefined as "up"; use Z then.
    let up = if dir.cross(DVec3::Y).length() < 1e-6 { DVec3::Z } else { DVec3::Y };
    DMat4::look_at_rh(eye, target, up)
}

/// The view axes of a cell; None keeps the scene's own value.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ViewAxes {
    /// Metres from the camera target along the scene's view direction.
    pub camera_distance: Option<f64>,
    /// Degrees between the directions from the camera target to the camera and to the key light.
    pub light_angle: Option<f64>,
}

/// The scene's camera moved along its view direction to `camera_distance` from its target.
pub fn posed_camera(c: &Camera, view: &ViewAxes) -> Camera {
    let mut c = c.clone();
    if let Some(d) = view.camera_distance {
        let target = DVec3::from(c.target);
        let back = (DVec3::from(c.position) - target).normalize();
        c.position = (target + back * d).to_array();
    }
    c
}

/// The key light turned about the camera target, in the plane of the view and the light's own
/// direction, so the two make `light_angle`; its distance from the target is kept. A directional
/// light turns its travel direction instead.
pub fn posed_key_light(light: &Light, camera: &Camera, view: &ViewAxes) -> Light {
    let mut l = light.clone();
    let Some(angle) = view.light_angle else { return l };
    let target = DVec3::from(camera.target);
    let to_camera = (DVec3::from(camera.position) - target).normalize();
    let (to_light, distance) = match l.kind {
        LightKind::Directional => (-DVec3::from(l.direction).normalize(), 0.0),
        _ => {
            let d = DVec3::from(l.position) - target;
            (d.normalize_or_zero(), d.length())
        }
    };
    let mut side = to_light - to_camera * to_light.dot(to_camera);
    if side.length() < 1e-9 {
        side = to_camera.cross(DVec3::Y);
        if side.length() < 1e-9 {
            side = to_camera.cross(DVec3::X);
        }
    }
    let side = side.normalize();
    let a = angle.to_radians();
    let dir = to_camera * a.cos() + side * a.sin();
    match l.kind {
        LightKind::Directional => l.direction = (-dir).to_array(),
        _ => l.position = (target + dir * distance).to_array(),
    }
    l
}

/// A cell's lights: the scene's, with the key light at the cell's intensity and range and turned
/// to the cell's light angle (or the scene's own `light_angle_deg`).
pub fn cell_lights(scene: &Scene, intensity: f64, range: f64, camera: &Camera, view: &ViewAxes) -> Vec<Light> {
    let mut lights = super::lights::cell_lights(scene, intensity, range);
    if let Some(k) = scene.key_light() {
        let view = ViewAxes { light_angle: view.light_angle.or(scene.light_angle_deg), ..*view };
        lights[k] = posed_key_light(&lights[k], camera, &view);
    }
    lights
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_angle_and_distance_are_what_was_asked() {
        let cam = Camera { position: [0.0, 1.0, 2.0], target: [0.0, 0.0, 0.0], fov_y_deg: 30.0, near: 0.01, far: 10.0 };
        let view = ViewAxes { camera_distance: Some(0.5), light_angle: Some(70.0) };
        let c = posed_camera(&cam, &view);
        assert!((DVec3::from(c.position).length() - 0.5).abs() < 1e-12);
        let scene: crate::declarations::scene::Scene =
            crate::declarations::scene::Scene::load("medusa", None, "t", "k").unwrap();
        let l = posed_key_light(&scene.lights[0], &c, &view);
        let angle = DVec3::from(l.position).normalize().angle_between(DVec3::from(c.position).normalize());
        assert!((angle.to_degrees() - 70.0).abs() < 1e-9, "{}", angle.to_degrees());
        let keep = DVec3::from(scene.lights[0].position).length();
        assert!((DVec3::from(l.position).length() - keep).abs() < 1e-12);
    }
}
