//! A fixed object in the Transparent queue (the window glass, `surface = "transparent"`) as the
//! CPU truth traces it: a thin pane, one interface with parallel faces, so that what passes it
//! goes on straight. Its material reflects by the model's specular lobe whole and its diffuse lobe
//! × alpha (the real-time frame's premultiplied diffuse, `Surface::diffuse_weight`), and it lets
//! through T = (1 − alpha)·(1 − F(μ)) of what is behind it, F Schlick's Fresnel at the ray's
//! cosine to the pane from the metallic workflow's F0 (the mean of lerp(0.04, base colour,
//! metallic): a fixed material has no specular colour) — the light its interface does not
//! reflect and its coverage does not scatter. The real-time blends let through 1 − alpha (URP,
//! HDRP) or (1 − alpha)(1 − reflectivity) (built-in) at every angle, so their reflection and
//! transmission together pass 1 towards grazing angles, which this pane does not.
//!
//! A ray passes the pane with probability T (a camera ray, a continuation, a shadow ray); where
//! it stops there, the pane's own light is weighed by 1/(1 − T), so that the estimate is the
//! pane's light plus T × what is behind it.

use glam::DVec3;

use crate::render::uniforms::GpuMaterial;

/// The pane's share of light let through along a ray of direction `d` meeting a face of
/// geometric normal `ng` (either side).
pub(super) fn transmittance(m: &GpuMaterial, ng: DVec3, d: DVec3) -> f64 {
    let alpha = alpha(m);
    let metallic = m.params[0] as f64;
    let f0 = (0..3).map(|c| 0.04 * (1.0 - metallic) + m.base_color[c] as f64 * metallic).sum::<f64>() / 3.0;
    let mu = ng.normalize().dot(d.normalize()).abs();
    (1.0 - alpha) * (1.0 - f_schlick(f0, mu))
}

/// The pane's coverage: the material's alpha (`GpuMaterial::base_color.w`).
pub(super) fn alpha(m: &GpuMaterial) -> f64 {
    (m.base_color[3] as f64).clamp(0.0, 1.0)
}

/// The weight of the pane's own light where a ray that could pass stops at it: 1/(1 − T).
pub(super) fn stop_weight(transmittance: f64) -> f64 {
    1.0 / (1.0 - transmittance).max(1e-6)
}

/// F = F0 + (1 − F0)(1 − μ)⁵ (Schlick 1994), scalar.
fn f_schlick(f0: f64, mu: f64) -> f64 {
    f0 + (1.0 - f0) * (1.0 - mu.clamp(0.0, 1.0)).powi(5)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pane(alpha: f32, metallic: f32) -> GpuMaterial {
        GpuMaterial {
            base_color: [0.5, 0.5, 0.5, alpha],
            params: [metallic, 0.5, 0.0, 0.0],
            ..bytemuck::Zeroable::zeroed()
        }
    }

    #[test]
    fn a_pane_lets_through_what_it_neither_reflects_nor_covers() {
        let up = DVec3::Y;
        // Head on: (1 − alpha)(1 − 0.04) for a dielectric, from either side.
        for d in [-up, up] {
            assert!((transmittance(&pane(0.3, 0.0), up, d) - 0.7 * 0.96).abs() < 1e-6);
        }
        // All there: nothing passes; a metal pane's F0 is its colour.
        assert_eq!(transmittance(&pane(1.0, 0.0), up, -up), 0.0);
        assert!((transmittance(&pane(0.0, 1.0), up, -up) - 0.5).abs() < 1e-6);
        // Towards grazing, the interface reflects all: nothing passes.
        let grazing = DVec3::new(1.0, -1e-9, 0.0);
        assert!(transmittance(&pane(0.0, 0.0), up, grazing) < 1e-6);
        // Between, less than head on.
        let slant = DVec3::new(1.0, -1.0, 0.0);
        let t = transmittance(&pane(0.3, 0.0), up, slant);
        assert!(t < 0.7 * 0.96 && t > 0.6, "{t}");
        assert!((stop_weight(0.75) - 4.0).abs() < 1e-6);
    }
}
