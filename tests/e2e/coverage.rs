//! scenes.md: medusa and spikes must cover many half-vector angles in one image. The histogram of
//! θh = ∠(N, H) over the visible subject pixels should spread over roughly 0–60°.

use crate::common::find_model;
use glam::DVec3;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::Pipeline;
use shadematrix::render::{CellParams, Renderer};
use shadematrix::shading::twin::Surface;

/// θh per visible subject pixel: the rendered role mask says which pixels see the subject; the
/// mesh vertex nearest the camera in each pixel gives its position and analytic normal, from which
/// N, L, V and so θh are known exactly.
fn theta_h_histogram(name: &str) -> [f64; 9] {
    let scene = Scene::load(name, None, "test", "composition").unwrap();
    let meshes = shadematrix::geometry::procedural::build_scene(&scene).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let size = 96;
    let prepared = renderer.upload_scene(&scene, meshes.clone()).unwrap();
    let cell = CellParams {
        pipeline: Pipeline::Builtin,
        model: find_model(Pipeline::Builtin, "lambert").unwrap(),
        surface: Surface::basic(DVec3::ONE, 0.0, 0.5),
        light_intensity: 1.0,
        light_range: 10.0,
        width: size,
        height: size,
        view: Default::default(),
        settings: Default::default(),
    };
    let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
    // Visible subject surface: the rendered mask tells which pixels see the disc; the mesh vertices
    // nearest to those pixels' rays give N and the position.
    let vp = shadematrix::plan::camera::view_projection(&scene.camera, 1.0);
    let cam = DVec3::from(scene.camera.position);
    let light = DVec3::from(scene.lights[0].position);
    let mut grid: Vec<Option<(f64, DVec3, DVec3)>> = vec![None; (size * size) as usize];
    for v in &meshes[0].vertices {
        let p = DVec3::from(v.position.map(f64::from));
        let clip = vp * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        let (x, y) = (((ndc.x + 1.0) * 0.5 * size as f64) as i64, ((1.0 - ndc.y) * 0.5 * size as f64) as i64);
        if x < 0 || y < 0 || x >= size as i64 || y >= size as i64 {
            continue;
        }
        let i = (y * size as i64 + x) as usize;
        if grid[i].is_none_or(|(d, _, _)| ndc.z < d) {
            grid[i] = Some((ndc.z, p, DVec3::from(v.normal.map(f64::from))));
        }
    }
    let mut hist = [0.0; 9];
    let mut total = 0.0;
    for (i, g) in grid.iter().enumerate() {
        let (Some((_, p, n)), 2) = (g, r.roles[i]) else { continue };
        let h = ((light - *p).normalize() + (cam - *p).normalize()).normalize();
        let theta = n.dot(h).clamp(-1.0, 1.0).acos().to_degrees();
        hist[((theta / 10.0) as usize).min(8)] += 1.0;
        total += 1.0;
    }
    assert!(total > 1000.0, "{name}: only {total} subject pixels sampled");
    hist.map(|c| c / total)
}

fn assert_spread(name: &str) {
    let h = theta_h_histogram(name);
    eprintln!("{name}: θh fractions per 10° bin: {:?}", h.map(|f| (f * 1000.0).round() / 1000.0));
    let bins_used = h[..6].iter().filter(|f| **f >= 0.02).count();
    let beyond_30: f64 = h[3..].iter().sum();
    assert!(bins_used >= 5, "{name}: θh histogram (10° bins) too narrow: {h:?}");
    assert!(beyond_30 > 0.1, "{name}: too few pixels with θh > 30°: {h:?}");
}

#[test]
fn medusa_covers_half_vector_angles() {
    let _timer = crate::common::timed!();
    assert_spread("medusa");
}

#[test]
fn spikes_covers_half_vector_angles() {
    let _timer = crate::common::timed!();
    assert_spread("spikes");
}
