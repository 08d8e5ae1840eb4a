//! The bake's f64 twin (truth.wgsl `cs_bake`): the same sums at the same points, traced by the CPU
//! tracer's own paths (`Tracer::incoming`), so a GPU bake can be checked against an independent
//! estimate of the light it gathers; a probe's by quadrature over a grid of directions. Baked shadow radii and angles are the GPU's alone: the twin
//! refuses them.

use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::PI;

use super::{
    power_heuristic, sample_surface, surface_pdf, CpuScene, CpuTruthInputs, EnvironmentSample, Rng, Surface, Tracer,
    RAY_EPSILON,
};
use crate::error::Error;
use crate::render::truth::bake::{BakeLight, BakePoint, BakeSums, BAKE_STRIDE};
use crate::shading::twin::irradiance_per_intensity;

/// Gather `samples` samples at every point with paths of `bounces` bounces, as the GPU does.
pub fn gather(
    scene: &CpuScene,
    inputs: &CpuTruthInputs,
    points: &[BakePoint],
    lights: &[BakeLight],
    (samples, bounces): (u32, u32),
) -> Result<BakeSums, Error> {
    if lights.iter().any(|l| l.shape[0] > 0.0 || l.shape[1] > 0.0) {
        return Err(Error::Other(
            "the CPU bake traces hard baked shadows only (no baked shadow radius or angle)".into(),
        ));
    }
    let mut tracer = Tracer::new(scene, inputs, bounces, false);
    tracer.baking = true;
    let weights: Vec<[f64; 4]> = lights.iter().map(|l| l.weights.map(f64::from)).collect();
    let sums = points
        .par_iter()
        .enumerate()
        .map(|(index, point)| {
            let mut sums = [[0f64; 4]; BAKE_STRIDE];
            for k in 0..samples.max(1) {
                let mut rng = Rng::new(index as u32, k);
                let p = DVec3::new(point.position[0] as f64, point.position[1] as f64, point.position[2] as f64);
                if point.position[3] < 0.5 {
                    let n =
                        DVec3::new(point.normal[0] as f64, point.normal[1] as f64, point.normal[2] as f64).normalize();
                    texel_sample(&tracer, &weights, p, n, &mut rng, &mut sums);
                } else if k == 0 {
                    probe_projection(&tracer, &weights, p, samples.max(1), index as u32, &mut sums);
                }
            }
            sums.map(|s| s.map(|v| v as f32))
        })
        .collect();
    Ok(sums)
}

fn lum(c: DVec3) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// Light i's visibility from p (a hard shadow ray).
fn visible(tracer: &Tracer, i: usize, p: DVec3, rng: &mut Rng) -> (DVec3, f64, bool) {
    let light = &tracer.lights[i];
    let (l, atten) = light.incidence(p, tracer.falloff());
    let distance = if light.kind != 0 { (light.position - p).length() * (1.0 - 1e-4) } else { f64::INFINITY };
    (l, atten, !tracer.blocked(p, l, distance, rng))
}

/// One texel sample (truth.wgsl `texel_sample`): the direct light at a white Lambertian point,
/// then one cosine-sampled continuation.
fn texel_sample(
    tracer: &Tracer,
    w: &[[f64; 4]],
    p: DVec3,
    n: DVec3,
    rng: &mut Rng,
    sums: &mut [[f64; 4]; BAKE_STRIDE],
) {
    let pipeline = tracer.inputs.pipeline;
    let origin = p + n * RAY_EPSILON;
    let (mut c, mut dominant, mut dominant_w) = (DVec3::ZERO, DVec3::ZERO, 0.0);
    for (i, light) in tracer.lights.iter().enumerate() {
        if w[i][0] <= 0.0 {
            continue;
        }
        let (l, atten, distance) = if light.kind >= super::LIGHT_RECT {
            let (l, atten, d) = light.area_incidence(p, tracer.inputs.kind, rng);
            (l, atten, d * (1.0 - 1e-4))
        } else {
            let (l, atten) = light.incidence(p, tracer.falloff());
            let d = if light.kind != 0 { (light.position - p).length() * (1.0 - 1e-4) } else { f64::INFINITY };
            (l, atten, d)
        };
        let f = n.dot(l).max(0.0) / PI;
        if atten > 0.0 && f > 0.0 && !tracer.blocked(origin, l, distance, rng) {
            let e = f * irradiance_per_intensity(pipeline) * light.color * atten * w[i][0];
            c += e;
            dominant += l * lum(e);
            dominant_w += lum(e);
        }
    }
    let white = Surface::basic(DVec3::ONE, 0.0, 0.0);
    if tracer.env_scale > 0.0 {
        let EnvironmentSample { direction: l, pdf, radiance } = tracer.scene.environment.sample(rng);
        let f = n.dot(l).max(0.0) / PI;
        if pdf > 0.0 && f > 0.0 && !tracer.blocked(origin, l, f64::INFINITY, rng) {
            let e = f * radiance * tracer.env_scale / pdf * power_heuristic(pdf, f);
            c += e;
            dominant += l * lum(e);
            dominant_w += lum(e);
        }
    }
    let l = sample_surface(&white, 0.0, n, n, rng);
    let pdf = surface_pdf(&white, 0.0, n, n, l);
    if pdf > 0.0 && n.dot(l) > 0.0 {
        let (indirect, _) = tracer.incoming(origin, l, (1, Some(pdf)), rng, &|_, i| w[i][2]);
        c += indirect;
        dominant += l * lum(indirect);
        dominant_w += lum(indirect);
    }
    if !c.is_finite() {
        return;
    }
    add(&mut sums[0], c, 1.0);
    add(&mut sums[1], c * c, 0.0);
    add(&mut sums[2], dominant, dominant_w);
    for (i, wi) in w.iter().enumerate() {
        if wi[3] >= 0.0 {
            sums[3][wi[3] as usize] += visible(tracer, i, origin, rng).2 as u32 as f64;
        }
    }
}

/// Directions of the probe twin's quadrature: an n × 2n (θ, φ) grid (environment::sh::project).
const PROBE_GRID: usize = 16;

/// A probe's projection (truth.wgsl `cs_bake` draws directions at random; the twin integrates
/// over a midpoint grid of directions, each cell weighted by its exact solid angle, with
/// `samples`/(2n²) traced paths per direction): ∫ L·Y_i dω, and each light's direct light as a
/// delta at its direction (E·Y_i). Stored with a count of 1, as the GPU's sums over their count.
fn probe_projection(
    tracer: &Tracer,
    w: &[[f64; 4]],
    p: DVec3,
    samples: u32,
    index: u32,
    sums: &mut [[f64; 4]; BAKE_STRIDE],
) {
    let n = PROBE_GRID;
    let per_direction = (samples as usize / (2 * n * n)).max(1);
    let mut path = 0u32;
    for i in 0..n {
        let theta = (i as f64 + 0.5) / n as f64 * PI;
        let band = (i as f64 / n as f64 * PI).cos() - ((i + 1) as f64 / n as f64 * PI).cos();
        let d_omega = band * (2.0 * PI / (2 * n) as f64);
        for j in 0..2 * n {
            let phi = (j as f64 + 0.5) / (2 * n) as f64 * 2.0 * PI;
            let d = DVec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            let mut radiance = DVec3::ZERO;
            for _ in 0..per_direction {
                let mut rng = Rng::new(index, path);
                path += 1;
                let (c, _) = tracer.incoming(p, d, (1, None), &mut rng, &|_, i| w[i][2]);
                if c.is_finite() {
                    radiance += c;
                }
            }
            radiance /= per_direction as f64;
            for (s, y) in sums.iter_mut().zip(crate::environment::sh::basis(d)) {
                add(s, radiance * y * d_omega, 0.0);
            }
        }
    }
    let pipeline = tracer.inputs.pipeline;
    let mut rng = Rng::new(index, path);
    for (i, light) in tracer.lights.iter().enumerate() {
        let (l, atten, seen) = visible(tracer, i, p, &mut rng);
        if w[i][3] >= 0.0 {
            sums[10][w[i][3] as usize] += seen as u32 as f64;
        }
        if w[i][1] <= 0.0 || atten <= 0.0 || !seen || light.kind >= super::LIGHT_RECT {
            continue;
        }
        let e = irradiance_per_intensity(pipeline) * light.color * atten * w[i][1];
        for (s, y) in sums.iter_mut().zip(crate::environment::sh::basis(l)) {
            add(s, e * y, 0.0);
        }
    }
    sums[9][3] = 1.0;
}

fn add(s: &mut [f64; 4], c: DVec3, w: f64) {
    s[0] += c.x;
    s[1] += c.y;
    s[2] += c.z;
    s[3] += w;
}
