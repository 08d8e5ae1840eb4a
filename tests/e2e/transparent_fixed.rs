//! Fixed objects in the Transparent queue (the window glass, `surface = "transparent"`): drawn
//! after the opaque objects, back to front, blended as each engine's Transparent surface blends,
//! forward on a deferred path; the CPU truth traces them as thin panes.

use crate::common::{cell_params, fixture, scene_from_text};
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::Pass;
use shadematrix::render::uniforms::ROLE_FIXED;
use shadematrix::render::Renderer;
use shadematrix::shading::registry::Sliders;

/// Behind the pane a pixel is the pane's own light plus the plane's × what the pane lets through,
/// 1 − alpha' (the blend One OneMinusSrcAlpha of a Transparent surface, specular preserved).
/// Rendering the plane at two colours cancels the pane's own light: the change behind the pane
/// over the change without it is the transmittance — built-in's alpha' = 1 − (1 − alpha)(1 −
/// reflectivity) (UnityStandardUtils.cginc PreMultiplyAlpha, reflectivity 0.04 for a dielectric),
/// URP's and HDRP's alpha (BRDF.hlsl InitializeBRDFData premultiplies the diffuse alone; Material.hlsl
/// ApplyBlendMode). Forward and deferred paths agree, the deferred one drawing the pane in its
/// Transparent pass; the pane writes no depth (the prepass leaves it out).
#[test]
fn a_transparent_pane_lets_through_what_each_engine_blends() {
    let _timer = crate::common::timed!();
    let text = std::fs::read_to_string(fixture("window_pane.toml")).unwrap();
    let with_pane = Scene::load_file(&fixture("window_pane.toml")).unwrap();
    let (start, end) = (text.find("# Black and rough").unwrap(), text.find("[environment]").unwrap());
    let without_pane = scene_from_text("window_pane_bare", &format!("{}{}", &text[..start], &text[end..]));
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let (glass, bare) = (renderer.prepare_scene(&with_pane).unwrap(), renderer.prepare_scene(&without_pane).unwrap());
    let alpha = 0.3;
    for (pipeline, shader, transmittance) in [
        (Pipeline::Builtin, "standard", (1.0 - alpha) * (1.0 - 0.04)),
        (Pipeline::Urp, "lit", 1.0 - alpha),
        (Pipeline::Hdrp, "lit", 1.0 - alpha),
    ] {
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let at = |grey: f64| {
                let sliders = Sliders { base_color_linear: [grey; 3], metallic: 0.0, smoothness: 0.5 };
                cell_params(pipeline, shader, sliders, (1.0, 10.0), 64, path)
            };
            let plan = renderer.plan(&glass, &at(0.8)).unwrap();
            assert_eq!(plan.has(Pass::Transparent), path == RenderPath::Deferred, "{:?}", plan.passes);
            let mut render = |prepared, grey| renderer.render(prepared, &at(grey), 1, 0).unwrap();
            let (g_hi, g_lo, b_hi, b_lo) =
                (render(&glass, 0.8), render(&glass, 0.4), render(&bare, 0.8), render(&bare, 0.4));
            let behind: Vec<usize> = (0..g_hi.roles.len()).filter(|&i| g_hi.roles[i] == ROLE_FIXED).collect();
            let change = |a: &[f32], b: &[f32], i: usize| (a[4 * i + 1] - b[4 * i + 1]) as f64;
            let ratios: Vec<f64> =
                behind.iter().map(|&i| change(&g_hi.hdr, &g_lo.hdr, i) / change(&b_hi.hdr, &b_lo.hdr, i)).collect();
            let worst = ratios.iter().map(|r| (r - transmittance).abs()).fold(0.0, f64::max);
            let outside = (0..g_hi.roles.len())
                .filter(|&i| g_hi.roles[i] != ROLE_FIXED)
                .map(|i| (g_hi.hdr[4 * i + 1] - b_hi.hdr[4 * i + 1]).abs() as f64)
                .fold(0.0, f64::max);
            eprintln!(
                "{} {path:?}: {} pixels behind the pane let through {:.4} (expected {transmittance:.4}, worst \
                 |Δ| {worst:.2e}); outside it the frame moves by at most {outside:.2e}",
                pipeline.name(),
                behind.len(),
                ratios.iter().sum::<f64>() / ratios.len() as f64,
            );
            assert!(behind.len() > 200, "the pane covers {} pixels", behind.len());
            assert!(worst < 2e-3, "transmittance off by {worst}");
            assert!(outside < 1e-5, "the pane changed the frame outside it by {outside}");
        }
    }
}

/// The truth's pane (render::truth::cpu::glass) lets through T = (1 − alpha)(1 − F(μ)) of what
/// is behind it, F Schlick's from F0 = 0.04 at the camera ray's cosine to the pane: the change
/// of the truth behind the pane between two plane colours over the change without the pane,
/// on the pane's inner pixels (the light turned so that the pane's shadow falls off the plane,
/// since the truth's pane shadows by the same T). The GPU tracer, which lets no ray through,
/// refuses the frame by the pane's name; `auto` traces it on the CPU.
#[test]
fn the_truth_sees_through_a_pane_by_what_it_neither_reflects_nor_covers() {
    use shadematrix::declarations::matrix::TruthBackend;
    let _timer = crate::common::timed!();
    let text = std::fs::read_to_string(fixture("window_pane.toml"))
        .unwrap()
        .replace("direction = [0.0, -1.0, -0.2]", "direction = [0.0, -1.0, 1.5]");
    let with_pane = scene_from_text("window_pane_lit_aside", &text);
    let (start, end) = (text.find("# Black and rough").unwrap(), text.find("[environment]").unwrap());
    let without_pane = scene_from_text("window_pane_bare", &format!("{}{}", &text[..start], &text[end..]));
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let (glass, bare) = (renderer.prepare_scene(&with_pane).unwrap(), renderer.prepare_scene(&without_pane).unwrap());
    let size = 48;
    let at = |grey: f64| {
        let sliders = Sliders { base_color_linear: [grey; 3], metallic: 0.0, smoothness: 0.5 };
        cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), size, RenderPath::Forward)
    };
    let frame = renderer.render(&glass, &at(0.8), 1, 0).unwrap();
    let fixed = |x: usize, y: usize| frame.roles[y * size as usize + x] == ROLE_FIXED;
    let n = size as usize;
    let inner: Vec<usize> = (1..n - 1)
        .flat_map(|y| (1..n - 1).map(move |x| (x, y)))
        .filter(|&(x, y)| fixed(x, y) && fixed(x - 1, y) && fixed(x + 1, y) && fixed(x, y - 1) && fixed(x, y + 1))
        .map(|(x, y)| y * n + x)
        .collect();
    assert!(inner.len() > 100, "{} inner pane pixels", inner.len());
    let mut truth =
        |prepared, grey| crate::common::same_brdf_truth(&mut renderer, prepared, &at(grey), TruthBackend::Auto);
    let (g_hi, g_lo, b_hi, b_lo) = (truth(&glass, 0.8), truth(&glass, 0.4), truth(&bare, 0.8), truth(&bare, 0.4));
    let sum = |a: &shadematrix::render::truth::Truth, b: &shadematrix::render::truth::Truth| {
        inner.iter().map(|&i| (a.mean[i][1] - b.mean[i][1]) as f64).sum::<f64>()
    };
    let through = sum(&g_hi, &g_lo) / sum(&b_hi, &b_lo);
    // The camera ray's cosine to the pane over its inner pixels is above 0.97: F(μ) ≈ F0.
    let expected = (1.0 - 0.3) * (1.0 - 0.04);
    eprintln!("the truth's pane lets through {through:.4} over {} pixels (expected {expected:.4})", inner.len());
    assert!((through - expected).abs() < 0.01, "the pane lets through {through}, expected {expected}");

    let gpu = shadematrix::render::truth::TruthSettings { backend: TruthBackend::Gpu, ..Default::default() };
    let Err(err) = renderer.render_truth(&glass, &at(0.8), &gpu) else { panic!("the GPU tracer traced a pane") };
    let err = err.to_string();
    assert!(err.contains("gpu") && err.contains("transparent fixed object `pane`"), "{err}");
}

/// The study's ray-traced visibility stands for the shadow maps, so it sees the casters they see:
/// a pane that casts no shadow (`cast_shadows = false`) stops no shadow ray, and the plane under
/// it is lit alike with the exact visibility and with the shadow map.
#[test]
fn the_exact_visibility_passes_what_casts_no_shadow() {
    let _timer = crate::common::timed!();
    let text = std::fs::read_to_string(fixture("window_pane.toml"))
        .unwrap()
        .replace("shadows = false\nkey = true", "shadows = true\nkey = true")
        .replace("direction = [0.0, -1.0, -0.2]", "direction = [0.0, -1.0, -0.8]");
    let scene = scene_from_text("window_pane_shadowed", &text);
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8; 3], metallic: 0.0, smoothness: 0.5 };
    let mut cell = cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), 64, RenderPath::Forward);
    let mapped = renderer.render(&prepared, &cell, 1, 0).unwrap();
    cell.settings.exact.visibility = true;
    let traced = renderer.render(&prepared, &cell, 1, 0).unwrap();
    // The plane and the pane over it: the plane shows through the pane.
    let plane: Vec<usize> = (0..mapped.roles.len()).filter(|&i| mapped.roles[i] != 0).collect();
    assert!(plane.len() > 1000, "{} plane pixels", plane.len());
    let worst = plane
        .iter()
        .map(|&i| ((traced.hdr[4 * i + 1] - mapped.hdr[4 * i + 1]) / mapped.hdr[4 * i + 1].max(1e-6)).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-3, "the exact visibility darkens the plane by up to {worst} where the pane casts nothing");
}
