//! URP's SSAO renderer feature (`render::passes::urp_ssao`) against its f64 twin
//! (`images::urp_ssao`), and what it does to a URP High Fidelity frame: the indirect light takes its
//! visibility whole, the direct light lerp(1, visibility, 0.25), custom shaders none, and the
//! default asset's renderer draws none.

use shadematrix::declarations::scene::{Camera, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::images::urp_ssao as twin;
use shadematrix::pipelines::settings::{UrpAssetPreset, UrpSsaoFeature};
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::Pass;
use shadematrix::render::passes::urp_ssao::{visibility_of, UrpSsaoFrame};

#[test]
fn gpu_urp_ssao_matches_its_twin_and_occludes_where_surfaces_meet() {
    let _timer = crate::common::timed!();
    let camera = Camera { position: [0.5, 2.2, 3.2], target: [0.0, 0.3, 0.0], fov_y_deg: 45.0, near: 0.1, far: 50.0 };
    let size = (128, 96);
    let (depth, normals) = super::ssao::synthetic_frame(&camera, size);
    let frame = UrpSsaoFrame::new(&camera, size.0, size.1, &UrpSsaoFeature::HIGH_FIDELITY);
    let expected = twin::visibility(size.0, size.1, &depth, &normals, &frame);
    let gpu = GpuContext::new().unwrap();
    let depth32: Vec<f32> = depth.iter().map(|&d| d as f32).collect();
    let normals32: Vec<[f32; 3]> = normals.iter().map(|n| n.as_vec3().to_array()).collect();
    let got = visibility_of(&gpu, size, &depth32, &normals32, &frame).unwrap();
    let n = got.len() as f64;
    let diffs: Vec<f64> = got.iter().zip(&expected).map(|(g, t)| (*g as f64 - t).abs()).collect();
    let mean = diffs.iter().sum::<f64>() / n;
    let worst = diffs.iter().cloned().fold(0.0, f64::max);
    let off = diffs.iter().filter(|d| **d > 1.5 / 255.0).count();
    eprintln!("urp ssao GPU vs twin: mean |Δ| {mean:.2e}, worst {worst:.3}, {off} of {n} pixels beyond 1.5/255");
    // Four 8-bit stores: an f32 value on the other side of a rounding step moves one level.
    assert!(mean < 2e-3, "mean |Δ| {mean}");
    assert!((off as f64) < 0.02 * n, "{off} pixels differ by more than a quantisation step");

    let raw = twin::obscurance(size.0, size.1, &depth, &normals, &frame);
    let min = expected.iter().cloned().fold(1.0, f64::min);
    let open = (0..size.0).map(|x| expected[((size.1 - 2) * size.0 + x) as usize]).fold(0.0, f64::max);
    let sky = expected[0];
    eprintln!("urp ssao twin: min visibility {min:.3}, open floor {open:.3}, sky {sky:.3}");
    assert!(min < 0.8, "the crease darkens: min visibility {min}");
    assert!(open > 0.97, "open floor stays lit: {open}");
    assert_eq!(sky, 1.0, "the sky is never occluded");
    // The blurs smooth the noisy estimator: fewer distinct levels after them than before.
    let spread = |v: &[f64]| v.windows(2).map(|w| (w[0] - w[1]).abs()).sum::<f64>();
    let before = spread(&raw.iter().map(|a| 1.0 - a).collect::<Vec<_>>());
    assert!(spread(&expected) < before, "the blur smooths: {} vs {before}", spread(&expected));
}

/// One URP frame of the default room (`edit` on the scene, the cell's URP asset `asset` with its
/// MSAA off, `light`: the lights' intensity) drawn with `shader`: linear RGB and roles per pixel,
/// and the plan's passes.
fn render_room(
    edit: impl Fn(&mut Scene),
    asset: shadematrix::pipelines::settings::UrpAsset,
    shader: &str,
    light: f64,
    path: RenderPath,
) -> (Vec<[f64; 3]>, Vec<u8>, Vec<Pass>) {
    let mut scene = Scene::load("default", None, "test", "composition").unwrap();
    edit(&mut scene);
    let mut renderer = shadematrix::render::renderer::Renderer::new(GpuContext::new().unwrap());
    let sliders =
        shadematrix::shading::registry::Sliders { base_color_linear: [0.8, 0.8, 0.8], metallic: 0.0, smoothness: 0.5 };
    let mut cell = crate::common::cell_params(Pipeline::Urp, shader, sliders, (light, 10.0), 128, path);
    cell.settings.engine.urp =
        shadematrix::pipelines::settings::UrpAsset { msaa: shadematrix::pipelines::Antialiasing::None, ..asset };
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
    let rgb = r.hdr.chunks(4).map(|p| [p[0] as f64, p[1] as f64, p[2] as f64]).collect();
    let passes = prepared.plan.passes_for(path, Pipeline::Urp, &cell.settings.engine, false);
    (rgb, r.roles, passes)
}

fn lum(c: &[f64; 3]) -> f64 {
    c[0] + c[1] + c[2]
}

#[test]
fn urp_ssao_takes_the_indirect_light_whole_and_a_quarter_of_the_direct() {
    let _timer = crate::common::timed!();
    let high = UrpAssetPreset::HighFidelity.asset();
    let without = shadematrix::pipelines::settings::UrpAsset { ssao: None, ..high };
    let no_ambient = |s: &mut Scene| {
        s.environment.ambient_intensity = 0.0;
        s.environment.reflections = shadematrix::declarations::scene::Reflections::Sky;
    };
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        // The ambient alone (lights at 0): the image darkens by the visibility v.
        let (on, roles, passes) = render_room(|_| {}, high, "lit", 0.0, path);
        let (off, _, passes_off) = render_room(|_| {}, without, "lit", 0.0, path);
        assert!(passes.contains(&Pass::UrpSsao) && passes.contains(&Pass::DepthPrepass), "{passes:?}");
        assert!(!passes_off.contains(&Pass::UrpSsao) && !passes.contains(&Pass::Ssao), "{passes_off:?}");
        // The lights alone: the image darkens by 1 − 0.25·(1 − v).
        let (lit_on, _, _) = render_room(no_ambient, high, "lit", 2.0, path);
        let (lit_off, _, _) = render_room(no_ambient, without, "lit", 2.0, path);
        let (mut checked, mut occluded, mut worst) = (0, 0, 0.0f64);
        for i in 0..on.len() {
            let (a, d) = (lum(&off[i]), lum(&lit_off[i]));
            if roles[i] == 0 || a < 1e-3 || d < 1e-3 {
                continue;
            }
            let v = lum(&on[i]) / a;
            let direct = lum(&lit_on[i]) / d;
            assert!(v <= 1.0 + 1e-3, "occlusion never brightens: {v} at {i}");
            worst = worst.max((direct - (1.0 - 0.25 * (1.0 - v))).abs());
            checked += 1;
            occluded += (v < 0.95) as usize;
        }
        eprintln!(
            "{path:?}: {occluded} of {checked} lit pixels occluded below 0.95; worst direct-share error {worst:.2e}"
        );
        assert!(occluded > checked / 50, "SSAO darkens creases and contacts: {occluded}");
        assert!(occluded < checked / 2, "open surfaces stay lit: {occluded} of {checked}");
        // Half floats and 8-bit visibility: the direct share follows the indirect one closely.
        assert!(worst < 2e-2, "direct light takes lerp(1, v, 0.25): worst error {worst}");
    }
}

#[test]
fn the_default_renderer_draws_none_and_custom_shaders_read_none() {
    let _timer = crate::common::timed!();
    let high = UrpAssetPreset::HighFidelity.asset();
    let without = shadematrix::pipelines::settings::UrpAsset { ssao: None, ..high };
    let (_, _, default_passes) = render_room(|_| {}, UrpAssetPreset::Default.asset(), "lit", 2.0, RenderPath::Forward);
    assert!(!default_passes.contains(&Pass::UrpSsao) && !default_passes.contains(&Pass::DepthPrepass));
    // Lambert is a custom shader under URP: its pixels are the same with the feature on and off,
    // while the fixed objects (URP Lit) darken.
    let (on, roles, _) = render_room(|_| {}, high, "lambert", 2.0, RenderPath::Forward);
    let (off, _, _) = render_room(|_| {}, without, "lambert", 2.0, RenderPath::Forward);
    // The role target: 2 marks the subject, 1 the fixed objects, 0 the background.
    let subject = 2u8;
    let fixed_changed = (0..on.len()).filter(|&i| roles[i] != subject && roles[i] != 0 && on[i] != off[i]).count();
    let subject_changed = (0..on.len()).filter(|&i| roles[i] == subject && on[i] != off[i]).count();
    assert!(fixed_changed > 0, "the fixed objects read it");
    assert_eq!(subject_changed, 0, "the custom shader reads none");
    // Unlit: its colour × lerp(1, v, 0.25) — never below three quarters of it.
    let (on, roles, _) = render_room(|_| {}, high, "unlit", 2.0, RenderPath::Forward);
    let (off, _, _) = render_room(|_| {}, without, "unlit", 2.0, RenderPath::Forward);
    let ratios: Vec<f64> =
        (0..on.len()).filter(|&i| roles[i] == subject).map(|i| lum(&on[i]) / lum(&off[i]).max(1e-9)).collect();
    let min = ratios.iter().cloned().fold(1.0, f64::min);
    eprintln!("unlit: min ratio {min:.4} over {} pixels", ratios.len());
    assert!((0.75 - 1e-3..1.0).contains(&min), "Unlit darkens by at most a quarter: {min}");
}
