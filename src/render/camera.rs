use glam::{DMat4, DVec3};

use crate::spec::scene::Camera;

/// Right-handed view and wgpu (0..1 depth) projection.
pub fn view_projection(c: &Camera, aspect: f64) -> DMat4 {
    let eye = DVec3::from(c.position);
    let target = DVec3::from(c.target);
    let dir = (target - eye).normalize();
    // Looking straight up or down leaves Y undefined as "up"; use Z then.
    let up = if dir.cross(DVec3::Y).length() < 1e-6 { DVec3::Z } else { DVec3::Y };
    let view = DMat4::look_at_rh(eye, target, up);
    let proj = DMat4::perspective_rh(c.fov_y_deg.to_radians(), aspect, c.near, c.far);
    proj * view
}
