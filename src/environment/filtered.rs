//! Filtered importance sampling of the GGX lobe from a source's mip chain (Křivánek & Colbert,
//! "Real-time Shading with Filtered Importance Sampling", 2008): the f64 twin of the captured
//! probes' prefilter (shaders/pass/probe_prefilter.wgsl, render::passes::probes). It follows HDRP's
//! runtime convolution, IntegrateLD in the core ShaderLibrary's ImageBasedLighting.hlsl, step by
//! step: N = V = R; sample i of n at Fibonacci2d(i, n) (Fibonacci.hlsl); the GGX half-vector by
//! SampleGGXDir with V = N; L = reflect(−V, H); each sample read from the mip whose texel matches
//! its solid angle, mip = ½·log2(Ω_s / Ω_p) + α with Ω_s = 1/(n·pdf), pdf = D(N·H)/4; the sample
//! counts per level of GetIBLRuntimeFilterSampleCount (21, 34, 55, 89, 89, 89 for levels 1–6).
//! Ω_p is the solid angle of the source's finest texel at the sample's direction (the equirectangular
//! texel shrinks with sin θ, as IntegrateLDCharlie corrects a cube texel's by its distance from the
//! face centre).
//!
//! The weight is the pipeline's: HDRP's IntegrateLD weighs each sample by G = V_SmithJointGGX·N·L
//! (its default); built-in and URP, whose probes the Unity editor convolves with unpublished code,
//! keep the lobe this tool used before, D·(N·L), which the same samples reach with the weight N·L
//! (IntegrateLD's USE_KARIS_APPROXIMATION). `audit::convergence` measures both against the
//! brute-force integral of their lobe.
//!
//! Written here rather than taken from a crate: it must be the step-by-step twin of the shader.

use glam::DVec3;
use std::f64::consts::{PI, TAU};

use rayon::prelude::*;

use super::dir_to_uv;
use super::prefilter::{EquirectImage, Probe, PROBE_WIDTH};
use crate::pipelines::Pipeline;

/// The weight each sample takes (see the module comment).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LobeWeight {
    /// D·(N·L): built-in and URP (IntegrateLD's USE_KARIS_APPROXIMATION weight, N·L).
    CosineWeighted,
    /// D·G₂ with N = V: HDRP (IntegrateLD's default weight, V_SmithJointGGX·N·L·N·V).
    SmithMasked,
}

impl LobeWeight {
    /// How `pipeline`'s captured probes weigh the lobe: HDRP's IntegrateLD by Smith masking,
    /// built-in and URP (whose probes the editor convolves with unpublished code) by N·L.
    pub fn of_pipeline(pipeline: Pipeline) -> LobeWeight {
        match pipeline {
            Pipeline::Hdrp => LobeWeight::SmithMasked,
            Pipeline::Builtin | Pipeline::Urp => LobeWeight::CosineWeighted,
        }
    }

    /// The shader's code for it (PrefilterParams.level.w).
    pub fn code(self) -> u32 {
        match self {
            LobeWeight::CosineWeighted => 0,
            LobeWeight::SmithMasked => 1,
        }
    }

    /// The weight of a sample at N·L (N = V).
    pub fn of(self, alpha: f64, nl: f64) -> f64 {
        match self {
            LobeWeight::CosineWeighted => nl,
            // V_SmithJointGGX(N·L, N·V = 1, α)·N·L·N·V (BSDF.hlsl; the 4 cancels in the ratio).
            LobeWeight::SmithMasked => {
                let a2 = alpha * alpha;
                let v = 0.5 / (nl + (nl * nl * (1.0 - a2) + a2).sqrt());
                v * nl
            }
        }
    }
}

/// GetIBLRuntimeFilterSampleCount (ImageBasedLighting.hlsl, desktop): samples for probe level 1–6.
pub fn sample_count(level: usize) -> u32 {
    match level {
        1 => 21,
        2 => 34,
        3 => 55,
        _ => 89,
    }
}

/// The Fibonacci number before `n` in the sequence (`n` is one of the sample counts).
fn fibonacci_before(n: u32) -> u32 {
    let (mut a, mut b) = (1u32, 1u32);
    while b < n {
        (a, b) = (b, a + b);
    }
    a
}

/// Fibonacci2d(i, n) = ((i + ½)/n, frac(i·F₋₁/n)) (Fibonacci.hlsl Fibonacci2dSeq with n a Fibonacci
/// number and F₋₁ the one before it).
pub fn fibonacci2d(i: u32, n: u32) -> [f64; 2] {
    let f = fibonacci_before(n) as f64;
    let n = n as f64;
    let y = i as f64 * f / n;
    [(i as f64 + 0.5) / n, y - y.floor()]
}

/// The coarsest mip of the chain. An equirectangular texel of a coarser one spans a quarter of the
/// sphere or more and no longer stands for the lobe's footprint: stopping at 16×8 halves the error
/// of the roughest level against the exact lobe (8.99e-2 → 5.29e-2 RMS on the test's sun-lit sky).
pub const MIP_CHAIN_MIN_WIDTH: usize = 16;

/// The source and its 2×2 halvings down to `MIP_CHAIN_MIN_WIDTH`: the mip chain samples read from.
pub fn mip_chain(source: &EquirectImage) -> Vec<EquirectImage> {
    let mut chain = vec![source.clone()];
    while chain.last().is_some_and(|m| m.width > MIP_CHAIN_MIN_WIDTH) {
        let next = chain.last().map(EquirectImage::half).expect("non-empty");
        chain.push(next);
    }
    chain
}

/// A trilinear read of the chain along `d` at fractional mip `mip` (clamped to the chain), as the
/// GPU's linear sampler reads it: bilinear in the two nearest mips, wrapping in u, clamped in v.
pub fn sample_chain(chain: &[EquirectImage], d: DVec3, mip: f64) -> DVec3 {
    let mip = mip.clamp(0.0, (chain.len() - 1) as f64);
    let m0 = mip.floor() as usize;
    let m1 = (m0 + 1).min(chain.len() - 1);
    let f = mip - m0 as f64;
    chain[m0].lookup(d).lerp(chain[m1].lookup(d), f)
}

/// The mip a sample of GGX α at N·H reads, for a source `width`×`height` (finest) at direction l.
pub fn sample_mip(alpha: f64, nh: f64, n: u32, l: DVec3, (width, height): (usize, usize)) -> f64 {
    let a2 = alpha * alpha;
    let t = nh * nh * (a2 - 1.0) + 1.0;
    let d = a2 / (PI * t * t);
    // pdf = D·(N·H)/(4·(L·H)) = D/4 when N = V.
    let omega_s = 1.0 / (n as f64 * 0.25 * d);
    let [_, v] = dir_to_uv(l);
    // The pole rows' texels are the smallest there are: no read finer than theirs.
    let sin_theta = (v * PI).sin().max((0.5 * PI / height as f64).sin());
    let omega_p = (TAU / width as f64) * (PI / height as f64) * sin_theta;
    0.5 * (omega_s / omega_p).log2() + alpha
}

/// One prefiltered texel: the lobe of GGX α around `r` from `n` samples of the chain.
pub fn integrate(chain: &[EquirectImage], r: DVec3, alpha: f64, n: u32, weight: LobeWeight) -> DVec3 {
    let frame = crate::shading::twin::local_frame(r);
    let size = (chain[0].width, chain[0].height);
    let mut light = DVec3::ZERO;
    let mut total = 0.0;
    for i in 0..n {
        let [u0, u1] = fibonacci2d(i, n);
        // SampleGGXDir with V = N.
        let cos_h = ((1.0 - u0) / (1.0 + (alpha * alpha - 1.0) * u0)).max(0.0).sqrt();
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        let phi = TAU * u1;
        let local_h = DVec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
        let local_l = 2.0 * cos_h * local_h - DVec3::Z;
        let nl = local_l.z;
        if nl <= 0.0 {
            continue;
        }
        let l = frame[0] * local_l.x + frame[1] * local_l.y + frame[2] * local_l.z;
        let w = weight.of(alpha, nl);
        light += sample_chain(chain, l, sample_mip(alpha, cos_h, n, l, size)) * w;
        total += w;
    }
    light / total.max(1e-300)
}

/// The levels as the captured probes' GPU prefilter makes them: the mirror level the source
/// halved to `PROBE_WIDTH`, each lobe narrower than a texel a copy of it, the others filtered
/// importance sampling of the source's mip chain.
pub fn probe(source: &EquirectImage, weight: LobeWeight) -> Probe {
    let chain = mip_chain(source);
    let level0 = chain.iter().find(|m| m.width <= PROBE_WIDTH).unwrap_or(&chain[0]).clone();
    Probe::from_mirror(level0, |level, alpha, output| {
        let n = sample_count(level);
        output.direction.par_iter().map(|d| integrate(&chain, *d, alpha, n, weight)).collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibonacci_points_follow_the_sequence() {
        assert_eq!(fibonacci_before(21), 13);
        assert_eq!(fibonacci_before(89), 55);
        let p = fibonacci2d(3, 21);
        assert!((p[0] - 3.5 / 21.0).abs() < 1e-15 && (p[1] - (39.0f64 / 21.0).fract()).abs() < 1e-15);
    }

    #[test]
    fn the_local_frame_is_orthonormal() {
        for z in [DVec3::Z, DVec3::NEG_Z, DVec3::new(0.3, -0.8, 0.2).normalize(), DVec3::X] {
            let [x, y, zz] = crate::shading::twin::local_frame(z);
            for (a, b) in [(x, y), (y, zz), (x, zz)] {
                assert!(a.dot(b).abs() < 1e-12);
            }
            assert!((x.length() - 1.0).abs() < 1e-12 && (y.length() - 1.0).abs() < 1e-12);
            assert!((x.cross(y) - zz).length() < 1e-12, "right-handed around {z}");
        }
    }

    #[test]
    fn a_constant_source_stays_constant() {
        let src = EquirectImage::sample(&|_| DVec3::splat(0.7), 64, 32, 1);
        let chain = mip_chain(&src);
        for weight in [LobeWeight::CosineWeighted, LobeWeight::SmithMasked] {
            let c = integrate(&chain, DVec3::new(0.2, 0.9, -0.3).normalize(), 0.4, 89, weight);
            assert!((c - DVec3::splat(0.7)).abs().max_element() < 1e-9, "{c}");
        }
    }
}

#[cfg(test)]
mod against_brute_force {
    use super::*;
    use crate::environment::prefilter::SOURCE_WIDTH;

    /// How far the sampled levels are from the brute-force integral of the same lobe on a sky with
    /// a sun, a gradient and an edge: printed for the note, held under a bound.
    #[test]
    fn filtered_levels_stay_near_the_exact_lobe() {
        let sun = DVec3::new(0.3, 0.6, -0.5).normalize();
        let radiance = |d: DVec3| {
            let disc = if d.dot(sun) > 0.995 { DVec3::new(40.0, 36.0, 30.0) } else { DVec3::ZERO };
            let edge = if d.x > 0.2 { DVec3::new(0.0, 0.3, 0.0) } else { DVec3::ZERO };
            DVec3::new(0.2, 0.3, 0.5) * (0.5 + 0.5 * d.y) + disc + edge
        };
        let source = EquirectImage::sample(&radiance, SOURCE_WIDTH, SOURCE_WIDTH / 2, 2);
        let exact = Probe::from_source(&source);
        let sampled = probe(&source, LobeWeight::CosineWeighted);
        for (level, (e, s)) in exact.levels.iter().zip(&sampled.levels).enumerate() {
            let mean = |img: &EquirectImage| img.texels.iter().map(|t| t.element_sum()).sum::<f64>();
            let (me, ms) = (mean(e), mean(s));
            let peak = e.texels.iter().map(|t| t.max_element()).fold(0.0, f64::max);
            let rms = (e.texels.iter().zip(&s.texels).map(|(a, b)| (*a - *b).length_squared()).sum::<f64>()
                / e.texels.len() as f64)
                .sqrt();
            eprintln!("level {level}: mean ratio {:.4}, RMS difference {:.3e} of peak {peak:.3}", ms / me, rms);
            assert!((ms / me - 1.0).abs() < 0.03, "level {level}: the sampled lobe's mean is off: {}", ms / me);
            assert!(rms < 0.1 * peak, "level {level}: RMS difference {rms} of peak {peak}");
        }
    }
}
