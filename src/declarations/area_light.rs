//! Area lights in a scene: their keys' checks and their frame. HDRP draws a rectangle in real time
//! (Lit.hlsl EvaluateBSDF_Rect) and bakes a disc only (HDAdditionalLightData: Disc is Baked-only);
//! built-in and URP bake both (Unity manual, "Area Lights"). The plan says which are left out.

use glam::DVec3;

use crate::error::InputError;
use crate::input::validate::Checker;

/// HDAdditionalLightData's shapeWidth and shapeHeight defaults.
pub const HDRP_DEFAULT_RECT_SIZE: [f64; 2] = [0.5, 0.5];
/// A disc's radius where the scene gives none.
pub const DEFAULT_DISC_RADIUS: f64 = 0.5;

/// An area light's keys as the scene gives them.
pub(super) struct AreaKeys {
    pub disc: bool,
    pub shadows: bool,
    pub size: Option<[f64; 2]>,
    pub radius: Option<f64>,
}

/// The checks of lights[i], an area light.
pub(super) fn validate(c: &Checker, i: usize, keys: AreaKeys) -> Result<(), InputError> {
    let k = |f: &str| format!("lights[{i}].{f}");
    if keys.shadows {
        return Err(c.err(
            &k("shadows"),
            "area lights cast no real-time shadows here (HDRP's rect-light shadow maps are not emulated); the truth traces their occlusion",
        ));
    }
    if let Some([w, h]) = keys.size {
        c.range(&k("size[0]"), w, 1e-3, 100.0)?;
        c.range(&k("size[1]"), h, 1e-3, 100.0)?;
    }
    if let (true, Some(r)) = (keys.disc, keys.radius) {
        c.range(&k("shape_radius"), r, 1e-3, 100.0)?;
    }
    Ok(())
}

/// An area light's (forward, right) from the direction it shines along: its width runs along the
/// horizontal axis across it, forward × Y (X for a light facing straight up or down).
pub fn area_frame(direction: [f64; 3]) -> (DVec3, DVec3) {
    let forward = DVec3::from(direction).normalize();
    let across = forward.cross(DVec3::Y);
    let right = if across.length_squared() > 1e-8 { across.normalize() } else { DVec3::X };
    (forward, right)
}
