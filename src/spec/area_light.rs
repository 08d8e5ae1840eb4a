//! Area lights in a scene: their keys' checks and their frame. HDRP draws a rectangle in real time
//! (Lit.hlsl EvaluateBSDF_Rect) and bakes a disc only (HDAdditionalLightData: Disc is Baked-only);
//! built-in and URP bake both (Unity manual, "Area Lights"). The plan says which are left out.

use glam::DVec3;

use super::scene::{Light, LightKind};
use crate::error::InputError;
use crate::input::validate::Checker;

/// HDAdditionalLightData's shapeWidth and shapeHeight defaults.
pub const HDRP_DEFAULT_RECT_SIZE: [f64; 2] = [0.5, 0.5];
/// A disc's radius where the scene gives none.
pub const DEFAULT_DISC_RADIUS: f64 = 0.5;

pub(super) fn validate(c: &Checker, i: usize, l: &Light) -> Result<(), InputError> {
    let k = |f: &str| format!("lights[{i}].{f}");
    if !matches!(l.kind, LightKind::Rect | LightKind::Disc) {
        return Ok(());
    }
    if l.shadows {
        return Err(c.err(
            &k("shadows"),
            "area lights cast no real-time shadows here (HDRP's rect-light shadow maps are not emulated); the truth traces their occlusion",
        ));
    }
    if let Some([w, h]) = l.size {
        c.range(&k("size[0]"), w, 1e-3, 100.0)?;
        c.range(&k("size[1]"), h, 1e-3, 100.0)?;
    }
    if l.kind == LightKind::Disc {
        if let Some(r) = l.shape_radius {
            c.range(&k("shape_radius"), r, 1e-3, 100.0)?;
        }
    }
    Ok(())
}

impl Light {
    pub fn is_area(&self) -> bool {
        matches!(self.kind, LightKind::Rect | LightKind::Disc)
    }

    /// An area light's (forward, right): it shines along `direction`; its width runs along the
    /// horizontal axis across it, forward × Y (X for a light facing straight up or down).
    pub fn area_frame(&self) -> (DVec3, DVec3) {
        let forward = DVec3::from(self.direction).normalize();
        let across = forward.cross(DVec3::Y);
        let right = if across.length_squared() > 1e-8 { across.normalize() } else { DVec3::X };
        (forward, right)
    }
}
