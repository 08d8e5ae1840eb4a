//! HDRP's light features beyond the three engines' common light (HDAdditionalLightData, Fig 3.13
//! of the thesis): spot shapes, Affect Diffuse / Affect Specular, Range Attenuation, the light's
//! and its shadow's Fade Distance and Dimmer, Shadow Tint and Penumbra Tint. The f64 twins of
//! what shaders/pass/scene.wgsl evaluates per pixel, and what HDRP's GetLightData computes once
//! per light on the CPU (LightLoop.cs; HDGpuLightsBuilder.Jobs.cs ConvertLightToGPUFormat).

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// HDRP's spot light shapes (SpotLightShape). A pyramid is a perspective projector whose smaller
/// side spans the spot angle; a box an orthographic one (GPULightType.ProjectorPyramid / Box).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "shape")]
pub enum SpotShape {
    #[default]
    Cone,
    /// `aspect_ratio`: width over height of the frustum (HDRP's aspectRatio, default 1).
    Pyramid { aspect_ratio: f64 },
    /// The box's width and height in metres (HDRP's shapeWidth and shapeHeight, default 0.5).
    Box { width: f64, height: f64 },
}

impl SpotShape {
    pub fn is_cone(&self) -> bool {
        *self == SpotShape::Cone
    }

    pub fn name(&self) -> &'static str {
        match self {
            SpotShape::Cone => "cone",
            SpotShape::Pyramid { .. } => "pyramid",
            SpotShape::Box { .. } => "box",
        }
    }
}

/// The pyramid's frustum width and height at unit distance (GetLightData): the smaller side spans
/// the spot angle, 2·tan(θ/2), the other that times the aspect ratio.
pub fn frustum_size(spot_angle_deg: f64, aspect_ratio: f64) -> (f64, f64) {
    let side = 2.0 * (spot_angle_deg * 0.5).to_radians().tan();
    if aspect_ratio >= 1.0 {
        (side * aspect_ratio, side)
    } else {
        (side, side / aspect_ratio)
    }
}

/// The solid angle of a pyramid of apex angles a and b, 4·asin(sin(a/2)·sin(b/2)): HDRP's
/// reflector divides a pyramid's lumen by it (LightUtils.ConvertFrustrumLightLumenToCandela, the
/// angles from CalculateAnglesForPyramid).
pub fn pyramid_solid_angle(spot_angle_deg: f64, aspect_ratio: f64) -> f64 {
    let (w, h) = frustum_size(spot_angle_deg, aspect_ratio);
    let (a, b) = (2.0 * (w * 0.5).atan(), 2.0 * (h * 0.5).atan());
    4.0 * ((a * 0.5).sin() * (b * 0.5).sin()).asin()
}

/// DistanceWindowing (core CommonLighting.hlsl): sat(bias − (d²·scale)²).
pub fn distance_windowing(dist_sq: f64, scale: f64, bias: f64) -> f64 {
    (bias - (dist_sq * scale).powi(2)).clamp(0.0, 1.0)
}

/// rangeAttenuationScale and Bias (GetLightData): 1/r² and 1 with Range Attenuation on; off, a
/// step at the range, 2¹²/r² and 2²⁴ (f(x) = b − (a·x)², f(0) huge, f(1) = 0).
pub fn range_attenuation(range: f64, on: bool) -> (f64, f64) {
    if on {
        (1.0 / (range * range), 1.0)
    } else {
        (4096.0 / (range * range), 16_777_216.0)
    }
}

/// PunctualLightAttenuation with HDRP's range windowing: [min(1/d, 100)·window(d²)]² (a box light:
/// d is the distance along its axis and 1/d is 1, GetPunctualLightVectors).
pub fn punctual_attenuation(dist: f64, range: f64, range_attenuation_on: bool, box_light: bool) -> f64 {
    let (scale, bias) = range_attenuation(range, range_attenuation_on);
    let inv_d = if box_light { 1.0 } else { (1.0 / dist).min(100.0) };
    (inv_d * distance_windowing(dist * dist, scale, bias)).powi(2)
}

/// Whether a point at light-space (x, y, z) is inside a projector's window (EvaluateCookie_Punctual
/// with boxLightSafeExtent 1): |x_cs|, |y_cs| ≤ 1 with x_cs = x/(z·tan) for a pyramid and x/half
/// for a box, and 0 ≤ z ≤ range. `extents`: the pyramid's half-size at unit distance, the box's
/// half width and height.
pub fn projector_window(shape: SpotShape, local: DVec3, extents: (f64, f64), range: f64) -> f64 {
    let perspective_z = if matches!(shape, SpotShape::Box { .. }) { 1.0 } else { local.z };
    let (x, y) = (local.x / (perspective_z * extents.0), local.y / (perspective_z * extents.1));
    let depth = (local.z - 0.5 * range).abs() - 0.5 * range + 1.0;
    if x.abs().max(y.abs()).max(depth) > 1.0 {
        0.0
    } else {
        1.0
    }
}

/// The projector's half-size the shaders read: (w/2, h/2) at unit distance for a pyramid, the
/// box's half width and height; none for a cone.
pub fn projector_extents(shape: SpotShape, spot_angle_deg: f64) -> Option<(f64, f64)> {
    match shape {
        SpotShape::Cone => None,
        SpotShape::Pyramid { aspect_ratio } => {
            let (w, h) = frustum_size(spot_angle_deg, aspect_ratio);
            Some((w * 0.5, h * 0.5))
        }
        SpotShape::Box { width, height } => Some((width.max(0.001) * 0.5, height.max(0.001) * 0.5)),
    }
}

/// ComputeLinearDistanceFade (HDUtils): 1 − sat((d − 0.9·f)/(0.1·f)), a linear fade over the last
/// tenth of the fade distance f.
pub fn linear_distance_fade(distance_to_camera: f64, fade_distance: f64) -> f64 {
    let near = 0.9 * fade_distance;
    1.0 - ((distance_to_camera - near) / (fade_distance - near)).clamp(0.0, 1.0)
}

/// ComputeShadowColor (core CommonLighting.hlsl): the light's colour factor at
/// shadow value s, lerp(1 − (1 − s)(1 − tint), s³(1 − tint) + s·tint, penumbra).
pub fn compute_shadow_color(shadow: f64, tint: DVec3, penumbra: bool) -> DVec3 {
    let inv_tint = DVec3::ONE - tint;
    if penumbra {
        inv_tint * shadow.powi(3) + tint * shadow
    } else {
        DVec3::ONE - inv_tint * (1.0 - shadow)
    }
}

/// The shadow tint as the shaders receive it, and whether the penumbra is tinted: Penumbra Tint
/// holds only for a coloured tint, which it then takes as pow(tint, 2.2) (ConvertLightToGPUFormat).
pub fn shadow_tint(tint_srgb: [f64; 3], penumbra: bool) -> (DVec3, bool) {
    let t = DVec3::from(tint_srgb);
    let coloured = t.x != t.y || t.y != t.z;
    if penumbra && coloured {
        (t.powf(2.2), true)
    } else {
        (t, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_attenuation_off_is_a_step_at_the_range() {
        let on = |d: f64| punctual_attenuation(d, 8.0, true, false);
        let off = |d: f64| punctual_attenuation(d, 8.0, false, false);
        // Off: the inverse square up to the range, then nothing.
        for d in [0.5, 2.0, 6.0, 7.9] {
            assert!((off(d) - 1.0 / (d * d)).abs() < 1e-12 / (d * d), "d = {d}: {}", off(d));
        }
        assert_eq!(off(8.01), 0.0);
        // On: the smooth window, below the inverse square inside the range.
        assert!(on(6.0) < 0.5 / 36.0 && on(6.0) > 0.0);
        // A box light has no 1/d: its value is the window alone.
        assert_eq!(punctual_attenuation(5.0, 8.0, false, true), 1.0);
    }

    #[test]
    fn a_pyramid_spans_the_spot_angle_on_its_smaller_side() {
        let (w, h) = frustum_size(60.0, 2.0);
        assert!((h - 2.0 * 30f64.to_radians().tan()).abs() < 1e-12 && (w - 2.0 * h).abs() < 1e-12);
        let (w, h) = frustum_size(60.0, 0.5);
        assert!((w - 2.0 * 30f64.to_radians().tan()).abs() < 1e-12 && (h - 2.0 * w).abs() < 1e-12);
        // A square pyramid of 90° spans a sixth of the sphere (a cube face): 4π/6.
        assert!((pyramid_solid_angle(90.0, 1.0) - 4.0 * std::f64::consts::PI / 6.0).abs() < 1e-12);
    }

    #[test]
    fn the_window_clips_the_frustum_and_the_range() {
        let pyramid = SpotShape::Pyramid { aspect_ratio: 1.0 };
        let e = projector_extents(pyramid, 90.0).unwrap();
        assert_eq!(projector_window(pyramid, DVec3::new(0.9, 0.0, 1.0), e, 5.0), 1.0);
        assert_eq!(projector_window(pyramid, DVec3::new(1.1, 0.0, 1.0), e, 5.0), 0.0);
        assert_eq!(projector_window(pyramid, DVec3::new(0.0, 0.0, 5.1), e, 5.0), 0.0);
        let b = SpotShape::Box { width: 2.0, height: 1.0 };
        let e = projector_extents(b, 30.0).unwrap();
        assert_eq!(projector_window(b, DVec3::new(0.9, 0.4, 3.0), e, 5.0), 1.0);
        assert_eq!(projector_window(b, DVec3::new(0.9, 0.6, 3.0), e, 5.0), 0.0);
        assert_eq!(projector_window(b, DVec3::new(0.0, 0.0, -0.1), e, 5.0), 0.0);
    }

    #[test]
    fn shadow_colour_is_the_shadow_without_a_tint_and_the_tint_in_the_umbra() {
        let tint = DVec3::new(0.2, 0.4, 0.8);
        for s in [0.0, 0.3, 1.0] {
            assert!((compute_shadow_color(s, DVec3::ZERO, false) - DVec3::splat(s)).abs().max_element() < 1e-15);
        }
        assert!((compute_shadow_color(0.0, tint, false) - tint).abs().max_element() < 1e-15);
        // The penumbra form leaves the umbra black and full light white, tinting between.
        assert_eq!(compute_shadow_color(0.0, tint, true), DVec3::ZERO);
        assert!((compute_shadow_color(1.0, tint, true) - DVec3::ONE).abs().max_element() < 1e-15);
        assert_eq!(shadow_tint([0.5, 0.5, 0.5], true), (DVec3::splat(0.5), false), "grey: no penumbra tint");
        assert!(shadow_tint([0.5, 0.2, 0.2], true).1);
    }

    #[test]
    fn the_fade_runs_over_the_last_tenth() {
        assert_eq!(linear_distance_fade(80.0, 100.0), 1.0);
        assert!((linear_distance_fade(95.0, 100.0) - 0.5).abs() < 1e-12);
        assert_eq!(linear_distance_fade(100.0, 100.0), 0.0);
    }
}
