//! HDRP's pre-integrated FGD table (models.md#hdrp), computed by the tool: for (√NV, pr) on a 64×64 grid,
//! x = mean(w·(1 − VH)⁵), y = mean(w) over 4096 GGX-distributed Hammersley samples with
//! w = 4·V_SmithJointGGX·NL·VH/NH, and z = mean(DisneyDiffuseNoPI) over cosine samples − 0.5.
//! Built once per process and shared by the GPU (a texture) and the f64 twin (the same f32 values,
//! interpolated the same way).

use glam::DVec3;
use std::f64::consts::TAU;
use std::sync::OnceLock;

pub const FGD_SIZE: usize = 64;
pub const FGD_SAMPLES: u32 = 4096;

pub struct FgdTable {
    /// Texels per side (FGD_SIZE for the renderer's table; other sizes for the convergence study).
    pub size: usize,
    /// RGBA f32 per texel, row j = perceptual roughness j/(size − 1), column i = √NV = i/(size − 1).
    pub texels: Vec<[f32; 4]>,
}

fn hammersley(i: u32, n: u32) -> (f64, f64) {
    (i as f64 / n as f64, i.reverse_bits() as f64 / 4_294_967_296.0)
}

/// 0.5/(λV + λL), height-correlated (HDRP V_SmithJointGGX)
pub fn v_smith_joint_ggx(nl: f64, nv: f64, a: f64) -> f64 {
    let a2 = a * a;
    let lambda_v = nl * ((-nv * a2 + nv) * nv + a2).sqrt();
    let lambda_l = nv * ((-nl * a2 + nl) * nl + a2).sqrt();
    0.5 / (lambda_v + lambda_l).max(f64::MIN_POSITIVE)
}

/// HDRP DisneyDiffuseNoPI, renormalised by 1/1.03571.
pub fn fd_disney_renormalized_no_pi(nl: f64, nv: f64, lv: f64, pr: f64) -> f64 {
    let fd90 = 0.5 + pr + pr * lv;
    let p5 = |x: f64| x.powi(5);
    (1.0 / 1.03571) * (1.0 + (fd90 - 1.0) * p5(1.0 - nl)) * (1.0 + (fd90 - 1.0) * p5(1.0 - nv))
}

/// (x, y, z) for one (NV, pr).
pub fn integrate(nv: f64, pr: f64, samples: u32) -> [f64; 3] {
    FgdSamples::new(samples).integrate(nv, pr)
}

/// What of each Hammersley sample does not depend on (NV, pr), computed once for a whole table:
/// u₁, the azimuth's cosine and sine, and the cosine-distributed L's polar cosine and sine.
pub struct FgdSamples {
    samples: Vec<[f64; 5]>,
}

impl FgdSamples {
    pub fn new(samples: u32) -> FgdSamples {
        let samples = (0..samples)
            .map(|i| {
                let (u1, u2) = hammersley(i, samples);
                let phi = TAU * u2;
                [u1, phi.cos(), phi.sin(), (1.0 - u1).sqrt(), u1.sqrt()]
            })
            .collect();
        FgdSamples { samples }
    }

    /// (x, y, z) for one (NV, pr).
    pub fn integrate(&self, nv: f64, pr: f64) -> [f64; 3] {
        let nv = nv.max(5.960_464_478e-8);
        let a = pr * pr;
        let v = DVec3::new((1.0 - nv * nv).max(0.0).sqrt(), 0.0, nv);
        let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
        for &[u1, cos_phi, sin_phi, cos_l, sin_l] in &self.samples {
            // GGX half-vector around N = +Z
            let cos_h = ((1.0 - u1) / (1.0 + (a * a - 1.0) * u1)).sqrt();
            let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
            let h = DVec3::new(sin_h * cos_phi, sin_h * sin_phi, cos_h);
            let vh = v.dot(h);
            let l = 2.0 * vh * h - v;
            let (nl, nh) = (l.z, h.z);
            if nl > 0.0 && vh > 0.0 {
                let w = 4.0 * v_smith_joint_ggx(nl, nv, a) * nl * vh / nh;
                x += w * (1.0 - vh).powi(5);
                y += w;
            }
            // Cosine-distributed L for the diffuse term
            let ld = DVec3::new(sin_l * cos_phi, sin_l * sin_phi, cos_l);
            z += fd_disney_renormalized_no_pi(cos_l, nv, ld.dot(v), pr);
        }
        let n = self.samples.len() as f64;
        [x / n, y / n, z / n - 0.5]
    }
}

impl FgdTable {
    /// The renderer's table: FGD_SIZE² texels of FGD_SAMPLES samples, built once per process.
    pub fn get() -> &'static FgdTable {
        static TABLE: OnceLock<FgdTable> = OnceLock::new();
        TABLE.get_or_init(|| FgdTable::build(FGD_SIZE, FGD_SAMPLES))
    }

    pub fn build(size: usize, samples: u32) -> FgdTable {
        use rayon::prelude::*;
        let shared = FgdSamples::new(samples);
        let texels = (0..size * size)
            .into_par_iter()
            .map(|k| {
                let (i, j) = (k % size, k / size);
                let sqrt_nv = i as f64 / (size - 1) as f64;
                let pr = j as f64 / (size - 1) as f64;
                let [x, y, z] = shared.integrate(sqrt_nv * sqrt_nv, pr);
                [x as f32, y as f32, z as f32, 0.0]
            })
            .collect();
        FgdTable { size, texels }
    }

    /// Bilinear lookup at (√NV, pr), texel centres at i/63 — the same arithmetic as WGSL `fgd_lookup`.
    pub fn lookup(&self, nv: f64, pr: f64) -> DVec3 {
        let max = (self.size - 1) as f64;
        let fx = (nv.clamp(0.0, 1.0).sqrt() * max).clamp(0.0, max);
        let fy = (pr.clamp(0.0, 1.0) * max).clamp(0.0, max);
        let (x0, y0) = (fx.floor().min(max - 1.0), fy.floor().min(max - 1.0));
        let (tx, ty) = (fx - x0, fy - y0);
        let t = |x: f64, y: f64| {
            let p = self.texels[y as usize * self.size + x as usize];
            DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
        };
        let a = t(x0, y0).lerp(t(x0 + 1.0, y0), tx);
        let b = t(x0, y0 + 1.0).lerp(t(x0 + 1.0, y0 + 1.0), tx);
        a.lerp(b, ty)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_normal_incidence_reflects_everything() {
        // α → 0: the GGX lobe is a mirror, y → 1 and x → (1 − NV)⁵·y.
        let [x, y, _] = integrate(1.0, 0.0, 256);
        assert!((y - 1.0).abs() < 1e-3, "{y}");
        assert!(x.abs() < 1e-6);
        // Rough surfaces lose energy to single scattering: y < 1.
        let [_, y_rough, _] = integrate(0.5, 1.0, FGD_SAMPLES);
        assert!(y_rough < 0.9 && y_rough > 0.3, "{y_rough}");
    }
}
