//! f64 twin of built-in's vertex-lit fallback (shaders/pass/forward.wgsl `vertex_lit_ffp`): the
//! fixed-function lighting Unity generates for Legacy Shaders/VertexLit (Lighting On,
//! SeparateSpecular On, `Combine texture * primary DOUBLE`), which the vertex-lit path draws for a
//! shader without a Vertex pass (Standard).

use glam::DVec3;

/// VertexLit's _Shininess default 0.7, × 128 in the generated code.
pub const FFP_SHININESS: f64 = 89.6;

/// One light as the fixed-function loop sees it at a vertex: the unit direction to it, its colour
/// (unity_LightColor) and its attenuation (1 directional; 1/(1 + 25·d²/range²), 0 beyond the range,
/// for points and spots; spots × sat((ρ − cos outer)/(cos inner − cos outer))).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FfpLight {
    pub to_light: DVec3,
    pub color: DVec3,
    pub attenuation: f64,
}

/// The fixed-function point attenuation of a light `d` metres away with `range`.
pub fn ffp_attenuation(d: f64, range: f64) -> f64 {
    let (d2, r2) = (d * d, range * range);
    if d2 > r2 {
        0.0
    } else {
        1.0 / (1.0 + d2 * 25.0 / r2)
    }
}

/// The vertex's (primary, specular) colours: sat(C·A/2 + Σ min(att/2·NL·C·L, 1)) and
/// sat(Σ att/2·sat((N·H)^89.6)·L) over the lights with NL > 0; `ambient` A is the flat ambient.
pub fn vertex_lit_ffp(c: DVec3, ambient: DVec3, n: DVec3, v: DVec3, lights: &[FfpLight]) -> (DVec3, DVec3) {
    let mut diffuse = c * ambient * 0.5;
    let mut specular = DVec3::ZERO;
    for l in lights {
        let att = l.attenuation * 0.5;
        let nl = n.dot(l.to_light).max(0.0);
        diffuse += (c * l.color * (nl * att)).min(DVec3::ONE);
        if nl > 0.0 {
            let nh = n.dot((l.to_light + v).normalize()).max(0.0);
            specular += l.color * (att * nh.powf(FFP_SHININESS).clamp(0.0, 1.0));
        }
    }
    (diffuse.clamp(DVec3::ZERO, DVec3::ONE), specular.clamp(DVec3::ZERO, DVec3::ONE))
}

/// The pixel: texture × primary × 2 (DOUBLE) + the separate specular.
pub fn vertex_lit_pixel(texture: DVec3, (primary, specular): (DVec3, DVec3)) -> DVec3 {
    texture * primary * 2.0 + specular
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_light_head_on_doubles_back_to_its_colour_and_saturates_at_two() {
        let n = DVec3::Y;
        let light = FfpLight { to_light: DVec3::Y, color: DVec3::splat(0.5), attenuation: 1.0 };
        let c = DVec3::new(0.8, 0.4, 0.2);
        // Diffuse: 2·(0.5·1·C·0.5) = C·0.5 — the fixed-function path's halving and DOUBLE cancel.
        let v = DVec3::new(1.0, 0.0, 0.0);
        let (p, s) = vertex_lit_ffp(c, DVec3::ZERO, n, v, &[light]);
        assert!((vertex_lit_pixel(DVec3::ONE, (p, DVec3::ZERO)) - c * 0.5).length() < 1e-12);
        assert!(s.max_element() < 1e-6, "N·H = cos 45° raised to 89.6 is ≈ 0: {s}");
        // A bright light saturates the primary at 1 before DOUBLE: the pixel stops at 2.
        let bright = FfpLight { color: DVec3::splat(100.0), ..light };
        let (p, _) = vertex_lit_ffp(DVec3::ONE, DVec3::ZERO, n, v, &[bright]);
        assert_eq!(vertex_lit_pixel(DVec3::ONE, (p, DVec3::ZERO)), DVec3::splat(2.0));
        // The ambient is flat: C·A whatever the normal.
        let (p, _) = vertex_lit_ffp(c, DVec3::splat(0.3), DVec3::X, v, &[]);
        assert!((vertex_lit_pixel(DVec3::ONE, (p, DVec3::ZERO)) - c * 0.3).length() < 1e-12);
        assert_eq!(ffp_attenuation(11.0, 10.0), 0.0);
        assert!((ffp_attenuation(10.0, 10.0) - 1.0 / 26.0).abs() < 1e-12);
    }
}
