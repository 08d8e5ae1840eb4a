//! The audit's fixed, deterministic sample set: low-discrepancy directions and parameters, plus
//! hand-placed extreme cases (grazing angles, mirror and fully rough surfaces, retro-reflection).

use glam::DVec3;

use crate::shading::registry::Sliders;

/// Radical inverse in base `b`: the Halton sequence.
pub fn halton(mut i: u64, b: u64) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f /= b as f64;
        r += f * (i % b) as f64;
        i /= b;
    }
    r
}

/// Hammersley point i of n in [0, 1)².
pub fn hammersley(i: u32, n: u32) -> (f64, f64) {
    (i as f64 / n as f64, i.reverse_bits() as f64 / 4_294_967_296.0)
}

/// Direction in the hemisphere around +Y with cosθ = `cos_theta`, azimuth `phi`.
pub fn around_y(cos_theta: f64, phi: f64) -> DVec3 {
    let s = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    DVec3::new(s * phi.cos(), cos_theta, s * phi.sin())
}

#[derive(Debug, Clone, Copy)]
pub struct AuditSample {
    pub n: DVec3,
    pub v: DVec3,
    pub l: DVec3,
    pub sliders: Sliders,
    /// N·L ≥ 0.1, N·V ≥ 0.1 and smoothness ≤ `WELL_CONDITIONED_MAX_SMOOTHNESS`.
    pub well_conditioned: bool,
}

pub const N_LOW_DISCREPANCY: u64 = 2048;

/// GGX's d = NH²(α² − 1) + 1 cancels to α² at the peak, so f32 carries a relative error of about
/// 2ε/α² into D (ε = 6e-8): 1e-4 needs α ≳ 0.05. Smoothness ≤ 0.75 (α ≥ 1/16) keeps it near
/// 6e-5; smoother surfaces belong to the extreme domain, reported apart.
pub const WELL_CONDITIONED_MAX_SMOOTHNESS: f64 = 0.75;

pub fn audit_samples() -> Vec<AuditSample> {
    let mut out = Vec::new();
    let push = |out: &mut Vec<AuditSample>, v: DVec3, l: DVec3, sliders: Sliders| {
        let well = v.y >= 0.1 && l.y >= 0.1 && sliders.smoothness <= WELL_CONDITIONED_MAX_SMOOTHNESS;
        out.push(AuditSample { n: DVec3::Y, v, l, sliders, well_conditioned: well });
    };
    for i in 1..=N_LOW_DISCREPANCY {
        let v = around_y(halton(i, 2), std::f64::consts::TAU * halton(i, 3));
        let l = around_y(halton(i, 5), std::f64::consts::TAU * halton(i, 7));
        let sliders = Sliders {
            base_color_linear: [0.2 + 0.8 * halton(i, 13), 0.5, 0.1 + 0.9 * halton(i, 17)],
            metallic: [0.0, 0.5, 1.0][(i % 3) as usize],
            smoothness: halton(i, 11),
        };
        push(&mut out, v, l, sliders);
    }
    // Extremes: grazing view and light, mirror and fully rough, retro and mirror configurations.
    let cosines = [1e-4, 1e-3, 0.01, 0.05, 0.5, 1.0];
    let smooth = [0.0, 0.5, 0.95, 0.999, 1.0];
    for (a, &cv) in cosines.iter().enumerate() {
        for (b, &cl) in cosines.iter().enumerate() {
            for &s in &smooth {
                for &m in &[0.0, 1.0] {
                    let v = around_y(cv, 0.3 + a as f64);
                    let l = around_y(cl, 0.3 + a as f64 + std::f64::consts::PI * (b % 2) as f64);
                    push(&mut out, v, l, Sliders { base_color_linear: [0.9, 0.6, 0.3], metallic: m, smoothness: s });
                }
            }
        }
    }
    for &s in &smooth {
        let v = around_y(0.3, 1.0);
        let mirror = DVec3::new(-v.x, v.y, -v.z);
        push(&mut out, v, v, Sliders { base_color_linear: [1.0; 3], metallic: 1.0, smoothness: s });
        push(&mut out, v, mirror, Sliders { base_color_linear: [1.0; 3], metallic: 1.0, smoothness: s });
    }
    out
}
