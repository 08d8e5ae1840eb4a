//! The fit of HDRP's two area-light lobes by linearly transformed cosines (Heitz, Dupuy, Hill and
//! Neubelt 2016, "Real-Time Polygonal-Light Shading with Linearly Transformed Cosines", §4 and its
//! fitting code): per texel, the matrix M = [X Y Z]·[[m00, 0, m02], [0, m11, 0], [0, 0, 1]] whose
//! distribution D(ω) = D₀(M⁻¹ω/|M⁻¹ω|)·|det M⁻¹|/|M⁻¹ω|³, D₀ = max(0, z)/π, best matches the
//! cosine-weighted lobe divided by its magnitude. Z is the lobe's mean direction, the error is
//! Heitz's: |ρ − D|³ over ρ's and D's samples, weighed by 1/(pdf_ρ + pdf_D), minimised by
//! Nelder–Mead from the neighbouring texel's solution.
//!
//! Written by hand because no crate fits LTCs, and the simplex for three parameters is shorter
//! than an optimisation framework's setup. Run by `shadematrix fit-ltc`, which writes the tables
//! `ltc::LtcTables::get` embeds (shaders/data/ltc.bin): Unity's own table data is not copied.

use glam::{DMat3, DVec3};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

use super::fgd::{fd_disney_renormalized_no_pi, v_smith_joint_ggx};
use super::ltc::{LtcLobe, LtcTables, LtcTexel, LTC_SIZE};

/// Samples per side of each error's grid (Heitz's Nsample).
const GRID: usize = 32;
/// The smallest GGX α fitted: the mirror limit, where the lobe is a δ.
const MIN_ALPHA: f64 = 1e-4;
/// The grazing limit of NV (HDRP's ClampNdotV).
const MIN_NV: f64 = 1e-4;

/// A cosine-weighted lobe: its value f·NL at l for view v (N = +Z), and a sampling of it.
trait Lobe: Sync {
    fn eval(&self, v: DVec3, l: DVec3) -> (f64, f64);
    fn sample(&self, v: DVec3, u1: f64, u2: f64) -> DVec3;
}

/// GGX with HDRP's height-correlated visibility and no Fresnel (its magnitude is specularFGD).
struct Ggx {
    alpha: f64,
}

impl Lobe for Ggx {
    /// (D·V·NL, pdf of the half-vector sampling D·NH/(4·VH))
    fn eval(&self, v: DVec3, l: DVec3) -> (f64, f64) {
        if l.z <= 0.0 {
            return (0.0, 0.0);
        }
        let h = (v + l).normalize();
        let a2 = self.alpha * self.alpha;
        let s = (h.z * a2 - h.z) * h.z + 1.0;
        let d = a2 / (PI * s * s);
        let value = d * v_smith_joint_ggx(l.z, v.z, self.alpha) * l.z;
        (value, d * h.z / (4.0 * v.dot(h)))
    }

    fn sample(&self, v: DVec3, u1: f64, u2: f64) -> DVec3 {
        let a2 = self.alpha * self.alpha;
        let cos_h = ((1.0 - u1) / (1.0 + (a2 - 1.0) * u1)).sqrt();
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        let phi = TAU * u2;
        let h = DVec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
        2.0 * v.dot(h) * h - v
    }
}

/// HDRP's renormalised Disney diffuse (DisneyDiffuseNoPI/π; its magnitude is diffuseFGD).
struct DisneyDiffuse {
    perceptual_roughness: f64,
}

impl Lobe for DisneyDiffuse {
    fn eval(&self, v: DVec3, l: DVec3) -> (f64, f64) {
        if l.z <= 0.0 {
            return (0.0, 0.0);
        }
        let fd = fd_disney_renormalized_no_pi(l.z, v.z, l.dot(v), self.perceptual_roughness);
        (fd / PI * l.z, l.z / PI)
    }

    fn sample(&self, _v: DVec3, u1: f64, u2: f64) -> DVec3 {
        let phi = TAU * u2;
        let r = u1.sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
    }
}

/// One candidate: the frame's Z and the parameters (m00, m11, m02).
#[derive(Clone, Copy, Debug)]
struct Ltc {
    z: DVec3,
    m: [f64; 3],
}

impl Ltc {
    fn matrix(&self) -> DMat3 {
        let y = DVec3::Y;
        let x = y.cross(self.z).normalize();
        let frame = DMat3::from_cols(x, y, self.z);
        let [m00, m11, m02] = self.m;
        frame * DMat3::from_cols(DVec3::new(m00, 0.0, 0.0), DVec3::new(0.0, m11, 0.0), DVec3::new(m02, 0.0, 1.0))
    }
}

/// D(l) of a transform, from its inverse and determinant; 0 where the cosine is below the horizon.
fn ltc_eval(inv: &DMat3, det: f64, l: DVec3) -> f64 {
    let lo = *inv * l;
    let len = lo.length();
    let lo = lo / len;
    if lo.z <= 0.0 {
        return 0.0;
    }
    // |det M⁻¹|/|M⁻¹l|³ = 1/(|det M|·|M⁻¹l|³) with l unit
    lo.z / PI / (det * len * len * len)
}

fn ltc_sample(m: &DMat3, u1: f64, u2: f64) -> DVec3 {
    let phi = TAU * u2;
    let r = u1.sqrt();
    (*m * DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())).normalize()
}

/// Heitz's error of `ltc` against the lobe normalised by `norm`.
fn error(lobe: &dyn Lobe, v: DVec3, norm: f64, ltc: &Ltc) -> f64 {
    let m = ltc.matrix();
    let det = m.determinant();
    if det.is_nan() || det <= 0.0 || !det.is_finite() {
        return f64::INFINITY;
    }
    let inv = m.inverse();
    let mut sum = 0.0;
    for i in 0..GRID {
        for j in 0..GRID {
            let u1 = (i as f64 + 0.5) / GRID as f64;
            let u2 = (j as f64 + 0.5) / GRID as f64;
            for l in [ltc_sample(&m, u1, u2), lobe.sample(v, u1, u2)] {
                let (value, pdf_lobe) = lobe.eval(v, l);
                let d = ltc_eval(&inv, det, l);
                let e = (value / norm - d).abs();
                let pdfs = d + pdf_lobe;
                if pdfs > 0.0 {
                    sum += e * e * e / pdfs;
                }
            }
        }
    }
    sum / (GRID * GRID) as f64
}

/// The lobe's magnitude ∫ρ and mean direction, by its own sampling.
fn moments(lobe: &dyn Lobe, v: DVec3) -> (f64, DVec3) {
    let n = 64;
    let (mut norm, mut dir) = (0.0, DVec3::ZERO);
    for i in 0..n {
        for j in 0..n {
            let l = lobe.sample(v, (i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            let (value, pdf) = lobe.eval(v, l);
            if pdf > 0.0 {
                norm += value / pdf;
                dir += l * (value / pdf);
            }
        }
    }
    let count = (n * n) as f64;
    (norm / count, (dir / count).normalize())
}

/// Nelder–Mead over `k` of the three parameters (the rest follow `tie`), from `start`.
fn nelder_mead(f: &dyn Fn([f64; 3]) -> f64, start: [f64; 3], k: usize, tie: fn([f64; 3]) -> [f64; 3]) -> [f64; 3] {
    let eval = |p: &[f64; 3]| f(tie(*p));
    let mut simplex: Vec<([f64; 3], f64)> = (0..=k)
        .map(|i| {
            let mut p = start;
            if i > 0 {
                p[i - 1] += 0.05 * p[i - 1].abs().max(1e-3);
            }
            (p, eval(&p))
        })
        .collect();
    for _ in 0..200 {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (simplex[0].1, simplex[k].1);
        if (worst - best).abs() <= 1e-7 * best.abs().max(1e-12) {
            break;
        }
        let mut centroid = [0.0; 3];
        for (p, _) in &simplex[..k] {
            for d in 0..3 {
                centroid[d] += p[d] / k as f64;
            }
        }
        let along = |t: f64| -> [f64; 3] {
            let mut q = centroid;
            for (d, q) in q.iter_mut().enumerate().take(k) {
                *q = centroid[d] + t * (simplex[k].0[d] - centroid[d]);
            }
            for (d, q) in q.iter_mut().enumerate().skip(k) {
                *q = start[d];
            }
            q
        };
        let r = along(-1.0);
        let fr = eval(&r);
        if fr < simplex[0].1 {
            let e = along(-2.0);
            let fe = eval(&e);
            simplex[k] = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < simplex[k - 1].1 {
            simplex[k] = (r, fr);
        } else {
            let c = if fr < simplex[k].1 { along(-0.5) } else { along(0.5) };
            let fc = eval(&c);
            if fc < fr.min(simplex[k].1) {
                simplex[k] = (c, fc);
            } else {
                let best = simplex[0].0;
                for s in simplex.iter_mut().skip(1) {
                    for (d, x) in s.0.iter_mut().enumerate().take(k) {
                        *x = best[d] + 0.5 * (*x - best[d]);
                    }
                    s.1 = eval(&s.0);
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    tie(simplex[0].0)
}

/// The view of texel row `j`: √(1 − NV) = j/63 (HDRP's cosThetaParam).
fn view(j: usize) -> DVec3 {
    let s = j as f64 / (LTC_SIZE - 1) as f64;
    let nv = (1.0 - s * s).max(MIN_NV);
    DVec3::new((1.0 - nv * nv).max(0.0).sqrt(), 0.0, nv)
}

fn lobe_at(kind: LtcLobe, i: usize) -> Box<dyn Lobe> {
    let pr = i as f64 / (LTC_SIZE - 1) as f64;
    match kind {
        LtcLobe::Ggx => Box::new(Ggx { alpha: (pr * pr).max(MIN_ALPHA) }),
        LtcLobe::DisneyDiffuse => Box::new(DisneyDiffuse { perceptual_roughness: pr }),
    }
}

/// Fit one texel from a starting guess; returns the parameters and the stored inverse.
fn fit_texel(kind: LtcLobe, i: usize, j: usize, start: [f64; 3]) -> ([f64; 3], LtcTexel) {
    let lobe = lobe_at(kind, i);
    let v = view(j);
    let (norm, z) = moments(lobe.as_ref(), v);
    let f = |m: [f64; 3]| error(lobe.as_ref(), v, norm, &Ltc { z, m });
    // At normal incidence the lobe is isotropic: one parameter, m00 = m11, no skew.
    let m = if j == 0 { nelder_mead(&f, start, 1, |p| [p[0], p[0], 0.0]) } else { nelder_mead(&f, start, 3, |p| p) };
    let inv = Ltc { z, m }.matrix().inverse();
    let s = inv.z_axis.z;
    assert!(s > 0.0, "LTC fit ({i}, {j}): M⁻¹ m22 = {s}");
    let t = |x: f64| (x / s) as f32;
    // [m00, m02, m11, m20] of M⁻¹/m22 (glam is column-major: x_axis.z is row 2, column 0)
    (m, [t(inv.x_axis.x), t(inv.z_axis.x), t(inv.y_axis.y), t(inv.x_axis.z)])
}

/// One lobe's table: the normal-incidence column first (roughest to smoothest, each from the
/// last), then every roughness's row of views in parallel, each view from the one before.
fn fit_lobe(kind: LtcLobe) -> Vec<LtcTexel> {
    let mut starts = vec![[1.0, 1.0, 0.0]; LTC_SIZE];
    let mut first = vec![[0f32; 4]; LTC_SIZE];
    let mut guess = [1.0, 1.0, 0.0];
    for i in (0..LTC_SIZE).rev() {
        let (m, texel) = fit_texel(kind, i, 0, guess);
        guess = m;
        starts[i] = m;
        first[i] = texel;
    }
    let columns: Vec<Vec<LtcTexel>> = (0..LTC_SIZE)
        .into_par_iter()
        .map(|i| {
            let mut out = vec![first[i]];
            let mut guess = starts[i];
            for j in 1..LTC_SIZE {
                let (m, texel) = fit_texel(kind, i, j, guess);
                guess = m;
                out.push(texel);
            }
            out
        })
        .collect();
    // Stored as HDRP's uv: column = perceptual roughness, row = √(1 − NV).
    let mut texels = vec![[0f32; 4]; LTC_SIZE * LTC_SIZE];
    for (i, column) in columns.iter().enumerate() {
        for (j, t) in column.iter().enumerate() {
            texels[j * LTC_SIZE + i] = *t;
        }
    }
    texels
}

/// Both tables, fitted afresh.
pub fn fit() -> LtcTables {
    LtcTables { ggx: fit_lobe(LtcLobe::Ggx), disney: fit_lobe(LtcLobe::DisneyDiffuse) }
}

/// One texel fitted along the same path as `fit` would take to it, for the check that the
/// embedded tables are this fitter's: the normal-incidence column from the roughest, then the
/// views up to `j`.
pub fn fit_one(kind: LtcLobe, i: usize, j: usize) -> LtcTexel {
    let mut guess = [1.0, 1.0, 0.0];
    let mut texel = [0f32; 4];
    for r in (i..LTC_SIZE).rev() {
        let (m, t) = fit_texel(kind, r, 0, guess);
        guess = m;
        texel = t;
    }
    for v in 1..=j {
        let (m, t) = fit_texel(kind, i, v, guess);
        guess = m;
        texel = t;
    }
    texel
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_tables_are_this_fitter_s() {
        let t = LtcTables::get();
        for (lobe, i, j) in [(LtcLobe::Ggx, 63, 6), (LtcLobe::DisneyDiffuse, 60, 3)] {
            let fresh = fit_one(lobe, i, j);
            let stored = t.table(lobe)[j * LTC_SIZE + i];
            for k in 0..4 {
                assert!(
                    (fresh[k] - stored[k]).abs() <= 1e-4 * stored[k].abs().max(1.0),
                    "{lobe:?} ({i}, {j}): {fresh:?} vs {stored:?}"
                );
            }
        }
    }
}
