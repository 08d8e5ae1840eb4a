//! Twin of HDRP Lit (models.md#hdrp-lit).

use glam::DVec3;
use std::f64::consts::FRAC_1_PI;

use super::{pow5, sat, Surface, SurfaceTwin};
use crate::pipelines::Pipeline;
use crate::shading::fgd::{fd_disney_renormalized_no_pi, FgdTable};

const FLT_EPS: f64 = 5.960_464_478e-8;

/// minRoughness of a punctual light of radius 0: (1 − clamp01(1.1725/(1.01 + 0.1²) − 0.15))².
pub fn min_roughness_punctual() -> f64 {
    let max_smoothness = (1.1725 / (1.01 + 0.1 * 0.1) - 0.15f64).clamp(0.0, 1.0);
    (1.0 - max_smoothness).powi(2)
}

pub fn dv_smith_joint_ggx(nh: f64, nl: f64, nv: f64, a: f64) -> f64 {
    let a2 = a * a;
    let s = (nh * a2 - nh) * nh + 1.0;
    let lambda_v = nl * ((-nv * a2 + nv) * nv + a2).sqrt();
    let lambda_l = nv * ((-nl * a2 + nl) * nl + a2).sqrt();
    FRAC_1_PI * 0.5 * a2 / (s * s * (lambda_v + lambda_l)).max(f32::MIN_POSITIVE as f64)
}

fn view_normal(n: DVec3, v: DVec3) -> (DVec3, f64) {
    let nv = n.dot(v);
    (n + 2.0 * sat(-nv) * v, nv.abs().max(1e-4))
}

fn f0(s: &Surface) -> DVec3 {
    DVec3::splat(0.04).lerp(s.base_color, s.metallic)
}

fn energy_compensation(s: &Surface, nv: f64) -> DVec3 {
    if s.params[0] < 0.5 {
        return DVec3::ONE;
    }
    let y = FgdTable::get().lookup(nv, 1.0 - s.smoothness).y;
    DVec3::ONE + f0(s) * (1.0 / y - 1.0)
}

pub struct HdrpLit;

impl SurfaceTwin for HdrpLit {
    fn direct(&self, _: Pipeline, s: &Surface, n_in: DVec3, v: DVec3, l: DVec3) -> DVec3 {
        let (n, nv) = view_normal(n_in, v);
        let nl = n.dot(l);
        if nl <= 0.0 {
            return DVec3::ZERO;
        }
        let lv = l.dot(v);
        let inv_len = 1.0 / (2.0 * lv + 2.0).max(FLT_EPS).sqrt();
        let nh = sat((nl + nv) * inv_len);
        let lh = sat(inv_len * lv + inv_len);
        let pr = 1.0 - s.smoothness;
        let a = (pr * pr).max(min_roughness_punctual() as f32 as f64);
        let x5 = pow5(1.0 - lh);
        let f = f0(s) * (1.0 - x5) + DVec3::splat(x5);
        let spec = f * dv_smith_joint_ggx(nh, nl.abs(), nv, a) * energy_compensation(s, nv);
        let diffuse =
            s.base_color * (1.0 - s.metallic) * FRAC_1_PI * fd_disney_renormalized_no_pi(nl.abs(), nv, lv, pr);
        (diffuse + spec) * sat(nl)
    }

    fn indirect(&self, _: Pipeline, s: &Surface, n_in: DVec3, v: DVec3, gi_d: DVec3, gi_s: DVec3) -> DVec3 {
        let (_, nv) = view_normal(n_in, v);
        let fgd = FgdTable::get().lookup(nv, 1.0 - s.smoothness);
        let f0 = f0(s);
        let specular_fgd = (DVec3::ONE - f0) * fgd.x + f0 * fgd.y;
        s.base_color * (1.0 - s.metallic) * gi_d * (fgd.z + 0.5) + specular_fgd * gi_s * energy_compensation(s, nv)
    }
}
