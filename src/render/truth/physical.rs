//! f64 twin of the `physical` truth's model (shaders/pass/truth_physical.wgsl), same names:
//! Lambert diffuse, height-correlated Smith GGX with Turquin's multiple-scattering compensation
//! (the FGD table's single-scattering albedo), Schlick's Fresnel from F0 = lerp(0.04, base, m);
//! D and F are the shared twins `d_ggx` and `f_schlick`.

use glam::DVec3;
use std::f64::consts::PI;

use crate::shading::fgd::FgdTable;
use crate::shading::twin::{d_ggx, f_schlick, sat, Surface};

/// V = 0.5/(NL·√(NV²(1 − α²) + α²) + NV·√(NL²(1 − α²) + α²)).
pub fn physical_v_smith_correlated(nv: f64, nl: f64, a: f64) -> f64 {
    let a2 = a * a;
    let gv = nl * (nv * nv * (1.0 - a2) + a2).sqrt();
    let gl = nv * (nl * nl * (1.0 - a2) + a2).sqrt();
    0.5 / (gv + gl).max(1e-12)
}

/// 1 + F0·(1/E(NV) − 1), E the FGD table's single-scattering albedo.
pub fn physical_energy_compensation(f0: DVec3, nv: f64, pr: f64) -> DVec3 {
    let e = FgdTable::get().lookup(nv, pr).y.max(1e-4);
    DVec3::ONE + f0 * (1.0 / e - 1.0)
}

/// f·NL of the physical model.
pub fn physical_response(s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> DVec3 {
    PhysicalLobe::new(s, n, v).response(l)
}

/// The physical model at one surface point seen from v: what `physical_response` computes from
/// the point and the view alone (F0, α, the energy compensation's table lookup), computed once
/// for every light direction the tracer asks about there, in the same order of operations.
#[derive(Debug, Clone, Copy)]
pub struct PhysicalLobe {
    n: DVec3,
    v: DVec3,
    nv: f64,
    a: f64,
    f0: DVec3,
    diffuse: DVec3,
    compensation: DVec3,
}

impl PhysicalLobe {
    pub fn new(s: &Surface, n: DVec3, v: DVec3) -> PhysicalLobe {
        let nv = n.dot(v);
        let pr = 1.0 - s.smoothness;
        let a = (pr * pr).max(1e-4);
        let f0 = DVec3::splat(0.04).lerp(s.base_color, s.metallic);
        // Seen from below the surface it reflects nothing: no table lookup for it.
        let compensation = if nv > 0.0 { physical_energy_compensation(f0, nv, pr) } else { DVec3::ZERO };
        // A premultiplied surface keeps `diffuse_weight` of its diffuse lobe (a pane: its alpha).
        let diffuse = s.base_color * (1.0 - s.metallic) * s.diffuse_weight / PI;
        PhysicalLobe { n, v, nv, a, f0, diffuse, compensation }
    }

    /// f·NL towards l.
    pub fn response(&self, l: DVec3) -> DVec3 {
        let (n, v) = (self.n, self.v);
        let (nl, nv) = (n.dot(l), self.nv);
        if nl <= 0.0 || nv <= 0.0 {
            return DVec3::ZERO;
        }
        let h = (v + l).normalize();
        let spec = f_schlick(self.f0, sat(v.dot(h)))
            * d_ggx(sat(n.dot(h)), self.a)
            * physical_v_smith_correlated(nv, nl, self.a)
            * self.compensation;
        (self.diffuse + spec) * nl
    }
}

/// The model's directional albedo seen from NV (quadrature over the hemisphere): what a white
/// furnace of radiance 1 reflects towards the viewer, for the tests of the tracer.
pub fn directional_albedo(s: &Surface, nv: f64) -> DVec3 {
    let n = DVec3::Z;
    let v = DVec3::new((1.0 - nv * nv).max(0.0).sqrt(), 0.0, nv);
    let (steps_t, steps_p) = (256, 512);
    let mut sum = DVec3::ZERO;
    for i in 0..steps_t {
        let theta = (i as f64 + 0.5) / steps_t as f64 * PI / 2.0;
        for j in 0..steps_p {
            let phi = (j as f64 + 0.5) / steps_p as f64 * 2.0 * PI;
            let l = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            let d_omega = theta.sin() * (PI / 2.0 / steps_t as f64) * (2.0 * PI / steps_p as f64);
            sum += physical_response(s, n, v, l) * d_omega;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_white_rough_metal_reflects_all_its_light() {
        // Multiple scattering puts back what single scattering loses on rough metal (Turquin).
        let metal = Surface {
            base_color: DVec3::ONE,
            metallic: 1.0,
            smoothness: 0.3,
            specular: DVec3::ZERO,
            params: [0.0; crate::shading::twin::PARAM_SLOTS],
            diffuse_weight: 1.0,
            tangent: DVec3::ZERO,
        };
        let a = directional_albedo(&metal, 0.7).x;
        assert!((a - 1.0).abs() < 0.03, "white rough metal albedo {a}");
        // Single scattering alone loses a visible share of it at this roughness.
        assert!(physical_energy_compensation(DVec3::ONE, 0.7, 0.7).x > 1.05);
    }
}
