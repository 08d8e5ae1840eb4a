use glam::DVec3;
use std::f64::consts::FRAC_1_PI;

use super::{irradiance_per_intensity, Lobes, Surface, SurfaceTwin};
use crate::pipelines::Pipeline;

/// ρ/π (models.md#classic Lambert).
pub fn fd_lambert(albedo: DVec3) -> DVec3 {
    albedo * FRAC_1_PI
}

/// Lambert, models.md#lambert: ρ/π·E·max(0, NL).
pub struct Lambert;

impl SurfaceTwin for Lambert {
    fn diffuse_only(&self) -> bool {
        true
    }

    fn direct_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, _v: DVec3, l: DVec3) -> Lobes {
        Lobes::diffuse(fd_lambert(s.base_color) * irradiance_per_intensity(p) * n.dot(l).max(0.0))
    }

    /// ρ/π·π·L·(1/π)∫max(0, NL)dω: the exact horizon-clipped integral of the rectangle.
    fn rect_lobes(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, corners: &[DVec3; 4]) -> Option<Lobes> {
        use crate::shading::ltc::{ortho_basis_view_normal, polygon_irradiance_clipped};
        let basis = ortho_basis_view_normal(v, n, n.dot(v));
        let local: Vec<DVec3> = corners.iter().map(|c| basis * *c).collect();
        let form_factor = polygon_irradiance_clipped(&local);
        Some(Lobes::diffuse(
            fd_lambert(s.base_color) * irradiance_per_intensity(p) * std::f64::consts::PI * form_factor,
        ))
    }

    fn indirect_lobes(
        &self,
        _p: Pipeline,
        s: &Surface,
        _n: DVec3,
        _v: DVec3,
        gi_diffuse: DVec3,
        _gi_specular: DVec3,
    ) -> Lobes {
        Lobes::diffuse(s.base_color * gi_diffuse)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unity_convention_is_albedo_times_nl() {
        let s = Surface::basic(DVec3::splat(0.5), 0.0, 0.0);
        let n = DVec3::Y;
        let l = DVec3::new(0.0, 0.5, 0.75f64.sqrt());
        let c = Lambert.direct(Pipeline::Builtin, &s, n, DVec3::Y, l);
        assert!((c.x - 0.25).abs() < 1e-12, "built-in: ρ·I·NL, got {c}");
        let h = Lambert.direct(Pipeline::Hdrp, &s, n, DVec3::Y, l);
        assert!((h.x - 0.25 / std::f64::consts::PI).abs() < 1e-12, "HDRP: ρ/π·E·NL");
    }
}
