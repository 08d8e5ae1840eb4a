//! MSAA on the forward paths: it brings geometry edges closer to a supersampled render, deferred
//! paths render one sample and say why, and the cell record says what was rendered.

use crate::common::cell_params;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Antialiasing, Pipeline, RenderPath};
use shadematrix::render::{CellParams, Renderer};
use shadematrix::shading::registry::Sliders;

#[test]
fn msaa_brings_edges_closer_to_a_supersampled_render() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    for comp in ["default", "mitsuba", "medusa", "spikes"] {
        let scene = Scene::load(comp, None, "test", "composition").unwrap();
        let prepared = renderer.prepare_scene(&scene).unwrap();
        let sliders = Sliders { base_color_linear: [0.6, 0.6, 0.6], metallic: 0.0, smoothness: 0.3 };
        let size = 64u32;
        let base = cell_params(Pipeline::Urp, "lit", sliders, (2.0, 10.0), size, RenderPath::Forward);
        let with = |aa: Antialiasing, side: u32| CellParams {
            width: side,
            height: side,
            settings: shadematrix::render::CellSettings { antialiasing: aa, ..base.settings },
            ..base
        };
        let k = 8;
        let reference = renderer.render(&prepared, &with(Antialiasing::None, size * k), 1, 0).unwrap();
        let mut errors = Vec::new();
        for aa in [Antialiasing::None, Antialiasing::Msaa4] {
            let (plan, r) = renderer.render_planned(&prepared, &with(aa, size), 1, 0).unwrap();
            assert_eq!(plan.multisampling.samples, aa.samples(), "{:?}", plan.multisampling.note);
            let (err, pixels) = edge_error(&r.hdr, &reference.hdr, &reference.roles, size as usize, k as usize);
            eprintln!(
            "URP lit, {comp} {size}²: {} relative L1 error on {pixels} edge pixels against {k}×{k} supersampled {err:.4}",
            aa.name()
        );
            errors.push(err);
        }
        assert!(errors[1] < 0.7 * errors[0], "MSAA ×4 {} vs none {}", errors[1], errors[0]);
    }
}

/// Relative L1 difference over RGB, on geometry-edge pixels, between a linear image and `big`
/// box-filtered down by `k`: Σ|small − reference| / Σ|reference| over the pixels whose k×k block in
/// `big` covers more than one object role (what MSAA addresses; shading aliasing, such as a
/// checkerboard, it leaves as it is). Linear, not clamped: MSAA resolves linear HDR.
fn edge_error(small: &[f32], big: &[f32], big_roles: &[u8], size: usize, k: usize) -> (f64, usize) {
    let (mut diff, mut total, mut pixels) = (0.0, 0.0, 0);
    for y in 0..size {
        for x in 0..size {
            let at = |dx: usize, dy: usize| (y * k + dy) * size * k + x * k + dx;
            let first = big_roles[at(0, 0)];
            if (0..k * k).all(|i| big_roles[at(i % k, i / k)] == first) {
                continue;
            }
            pixels += 1;
            for c in 0..3 {
                let reference = (0..k * k).map(|i| big[at(i % k, i / k) * 4 + c] as f64).sum::<f64>() / (k * k) as f64;
                diff += (small[(y * size + x) * 4 + c] as f64 - reference).abs();
                total += reference.abs();
            }
        }
    }
    (diff / total, pixels)
}

#[test]
fn deferred_paths_render_one_sample_and_say_why() {
    let _timer = crate::common::timed!();
    let scene = Scene::load("default", None, "test", "composition").unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.6, 0.6, 0.6], metallic: 0.0, smoothness: 0.3 };
    let mut cell = cell_params(Pipeline::Builtin, "standard", sliders, (2.0, 10.0), 32, RenderPath::Deferred);
    cell.settings.antialiasing = Antialiasing::Msaa4;
    let m = renderer.plan(&prepared, &cell).unwrap().multisampling;
    assert_eq!(m.samples, 1);
    assert!(m.note.as_deref().is_some_and(|n| n.contains("forward paths only")), "{m:?}");
}
