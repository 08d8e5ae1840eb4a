//! Rendering paths: deferred renders what forward renders (within the G-buffer's quantisation),
//! lights add up on the deferred path, and `list` shows each path's passes.

use crate::common::{cell_params, fixture, shadematrix, write_matrix};
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::Renderer;
use shadematrix::report::run_data::RunData;
use shadematrix::shading::registry::Sliders;

/// Without MSAA on either side: built-in forward's default 4× MSAA would add its edge blending to
/// the difference (worst FLIP 0.0199 instead of 0.0094, measured).
#[test]
fn deferred_renders_like_forward_within_the_gbuffer_quantisation() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"paths\"\ncompositions = [\"default\", \"mitsuba\"]\npipelines = [\"builtin\", \"urp\", \"hdrp\"]\n\
         paths = [\"forward\", \"deferred\"]\nshaders = [\"standard\", \"lit\", \"torrance_sparrow\"]\npresets = [\"gold\", \"plastic\"]\n\
         reference = { path = \"forward\" }\nantialiasing = \"none\"\n[image]\nwidth = 96\nheight = 96\n",
    );
    let out = tmp.path().join("out");
    let (code, _, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()], &[]);
    assert_eq!(code, 0, "{err}");
    let run = RunData::load(&out).unwrap();
    let deferred: Vec<_> = run.cells.iter().filter(|c| c.path == RenderPath::Deferred).collect();
    assert_eq!(
        deferred.len(),
        2 * 4 * 2,
        "2 compositions × (standard, torrance_sparrow, urp lit, hdrp lit) × 2 presets"
    );
    let mut worst: f64 = 0.0;
    let mut own_rule = 0;
    for c in deferred {
        let flip = c.metrics.ldr_flip().unwrap_or_else(|| panic!("{}: no FLIP against forward", c.id));
        eprintln!("{}: mean FLIP against forward {flip:.4}", c.id);
        // Built-in weighs a reflection probe differently on its two paths (plan::probes: the
        // deferred reflections pass gives full weight inside the box): there the frames differ by
        // the engine's own rule, which the record names.
        let forward_id = c.id.0.replace("-deferred__", "-forward__");
        let forward = run.cells.iter().find(|f| f.id.0 == forward_id).expect("the forward reference");
        if c.rules.reflection_probes != forward.rules.reflection_probes {
            assert_eq!(c.pipeline, Pipeline::Builtin, "{}: only built-in's paths weigh probes apart", c.id);
            own_rule += 1;
            continue;
        }
        worst = worst.max(flip);
    }
    assert!(worst <= 0.02, "worst mean FLIP {worst}");
    assert_eq!(own_rule, 4, "built-in's cells of the probe room: standard and torrance_sparrow × 2 presets");
}

#[test]
fn twelve_lights_add_up_on_the_deferred_path() {
    let _timer = crate::common::timed!();
    let base = Scene::load_file(&fixture("twelve_points.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    // Each pipeline's own G-buffer shader: a model without a G-buffer pass is drawn forward.
    for (pipeline, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Hdrp, "lit")] {
        let sliders = Sliders { base_color_linear: [0.7, 0.6, 0.5], metallic: 0.0, smoothness: 0.5 };
        let prepared = renderer.prepare_scene(&base).unwrap();
        let cell = cell_params(pipeline, shader, sliders, (base.lights[0].intensity, 8.0), 49, RenderPath::Deferred);
        let plan = renderer.plan(&prepared, &cell).unwrap().assignment;
        let mut render = |scene: &Scene, intensity: f64| {
            let prepared = renderer.prepare_scene(scene).unwrap();
            let cell = cell_params(pipeline, shader, sliders, (intensity, 8.0), 49, RenderPath::Deferred);
            renderer.render(&prepared, &cell, 1, 0).unwrap()
        };
        assert!(plan[0].lights.iter().all(|u| u.reason.contains("deferred")), "{plan:?}");
        let worst = crate::common::superposition_error(&base, |scene, intensity| render(scene, intensity).hdr);
        eprintln!("superposition of 12 lights, {} deferred: worst relative difference {worst:.2e}", pipeline.name());
        assert!(worst < 1e-3, "{}: {worst}", pipeline.name());
    }
}

#[test]
fn list_shows_each_paths_passes() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"p\"\ncompositions = [\"default\"]\npipelines = [\"urp\", \"hdrp\"]\npaths = [\"forward\", \"deferred\"]\nshaders = [\"lit\"]\npresets = [\"gold\"]\n",
    );
    let (code, out, err) = shadematrix(tmp.path(), &["list", m.to_str().unwrap()], &[]);
    assert_eq!(code, 0, "{err}");
    // The default room's reflection probe is captured and prefiltered before the frame's passes.
    assert!(
        out.contains("composition default (urp-forward): passes probe capture → probe prefilter → shadow → forward;"),
        "{out}"
    );
    assert!(
        out.contains("composition default (urp-deferred): passes probe capture → probe prefilter → shadow → gbuffer → deferred lighting → forward-only;"),
        "{out}"
    );
    // HDRP's SSAO reads a depth-normal prepass before the lighting, and its bloom follows the frame.
    assert!(out.contains("(hdrp-deferred): passes probe capture → probe prefilter → shadow → depth prepass → ssao → gbuffer → light tiles → deferred lighting"), "{out}");
    assert!(
        out.contains(
            "(hdrp-forward): passes probe capture → probe prefilter → shadow → depth prepass → ssao → forward → bloom;"
        ),
        "{out}"
    );
}

#[test]
fn forward_time_grows_faster_with_the_light_count_than_deferred() {
    let _timer = crate::common::timed!();
    // Six spheres drawn back to front: forward evaluates every light for every overdrawn fragment,
    // deferred once per pixel. Ordering only: the slope of time against lights.
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let sliders = Sliders { base_color_linear: [0.5; 3], metallic: 0.0, smoothness: 0.5 };
    let mut time = |lights: u32, path: RenderPath| -> f64 {
        let scene =
            Scene::load_file(&crate::common::repo().join(format!("scenes/light_count/lights_{lights}.toml"))).unwrap();
        let prepared = renderer.prepare_scene(&scene).unwrap();
        let cell = cell_params(Pipeline::Hdrp, "lit", sliders, (scene.lights[0].intensity, 6.0), 96, path);
        let r = renderer.render(&prepared, &cell, 3, 1).unwrap();
        let mut ms = r.gpu_pass_ms.unwrap_or(r.frame_ms);
        ms.sort_by(|a, b| a.total_cmp(b));
        ms[ms.len() / 2]
    };
    let forward = time(32, RenderPath::Forward) - time(1, RenderPath::Forward);
    let deferred = time(32, RenderPath::Deferred) - time(1, RenderPath::Deferred);
    eprintln!("31 more lights cost {forward:.2} ms forward, {deferred:.2} ms deferred");
    assert!(forward > deferred, "forward {forward} ms vs deferred {deferred} ms");
}

#[test]
fn hdrp_tiled_light_loop_keeps_every_light_where_it_reaches() {
    let _timer = crate::common::timed!();
    // Short ranges make most lights miss most tiles: the tiled deferred image must still match
    // forward (every light per pixel) everywhere, within the G-buffer's 8-bit quantisation.
    let mut scene = Scene::load_file(&fixture("twelve_points.toml")).unwrap();
    for l in &mut scene.lights {
        l.range = 1.6;
        l.position[1] = 0.3;
    }
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.7, 0.6, 0.5], metallic: 0.0, smoothness: 0.5 };
    let mut render = |path: RenderPath| {
        let cell = cell_params(Pipeline::Hdrp, "lambert", sliders, (scene.lights[0].intensity, 1.6), 128, path);
        renderer.render(&prepared, &cell, 1, 0).unwrap()
    };
    let deferred = render(RenderPath::Deferred);
    assert!(
        deferred.gpu_passes.as_ref().is_none_or(|p| p.iter().any(|(n, _)| *n == shadematrix::plan::Pass::LightTiles)),
        "{:?}",
        deferred.gpu_passes
    );
    let forward = render(RenderPath::Forward);
    let peak = forward.hdr.iter().copied().fold(0.0f32, f32::max) as f64;
    let mut worst: f64 = 0.0;
    let mut lit = 0;
    for (k, (d, f)) in deferred.hdr.iter().zip(&forward.hdr).enumerate() {
        if k % 4 != 3 && (*f as f64) > 0.05 * peak {
            lit += 1;
            worst = worst.max((*d as f64 - *f as f64).abs() / *f as f64);
        }
    }
    eprintln!("tiled HDRP deferred vs forward: worst relative difference {worst:.2e} over {lit} lit channels");
    assert!(lit > 1000, "the lights reach the plane: {lit}");
    assert!(worst < 0.03, "{worst}");
}

/// Built-in's Lambert and Blinn-Phong surface shaders have Deferred passes (Lighting.cginc
/// LightingLambert_Deferred / LightingBlinnPhong_Deferred) writing UnityStandardData, which
/// Internal-DeferredShading lights with BRDF1: a deferred Lambert is the G-buffer of a Standard
/// in its specular setup with specular colour 0 and smoothness 0 — Disney diffuse at perceptual
/// roughness 1, no specular — not the forward Lambert.
#[test]
fn builtins_deferred_lambert_is_lit_as_standard_data_by_brdf1() {
    let _timer = crate::common::timed!();
    let scene = Scene::load("default", None, "test", "composition").unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.6, 0.4, 0.3], metallic: 0.0, smoothness: 0.0 };
    let mut subject = |shader: &str, path: RenderPath, specular_setup: bool| {
        let mut cell = cell_params(Pipeline::Builtin, shader, sliders, (2.0, 10.0), 96, path);
        if specular_setup {
            cell.surface.params[0] = 1.0;
            cell.surface.specular = glam::DVec3::ZERO;
        }
        let plan = renderer.plan(&prepared, &cell).unwrap();
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let role = shadematrix::render::uniforms::ROLE_SUBJECT;
        let px: Vec<[f32; 3]> = (0..r.roles.len())
            .filter(|&i| r.roles[i] == role)
            .map(|i| [r.hdr[4 * i], r.hdr[4 * i + 1], r.hdr[4 * i + 2]])
            .collect();
        (plan.draws.counts.get("gbuffer").copied().unwrap_or(0), px)
    };
    let (gbuffer, deferred) = subject("lambert", RenderPath::Deferred, false);
    let (_, forward) = subject("lambert", RenderPath::Forward, false);
    let (_, standard) = subject("standard", RenderPath::Deferred, true);
    assert_eq!(gbuffer, scene.objects.len() as u32, "every object into the G-buffer, the Lambert subject too");
    assert_eq!((deferred.len(), forward.len()), (standard.len(), standard.len()));
    let rel = |a: &[[f32; 3]], b: &[[f32; 3]]| {
        let (mut d, mut t) = (0.0f64, 0.0f64);
        for (x, y) in a.iter().zip(b) {
            for k in 0..3 {
                d += (x[k] - y[k]).abs() as f64;
                t += y[k].abs() as f64;
            }
        }
        d / t
    };
    let (as_standard, as_forward) = (rel(&deferred, &standard), rel(&deferred, &forward));
    eprintln!(
        "deferred Lambert against deferred Standard data: {as_standard:.5}; against forward Lambert: {as_forward:.5}"
    );
    assert!(as_standard < 0.01, "BRDF1 on UnityStandardData: {as_standard}");
    assert!(as_forward > 2.0 * as_standard, "not the forward Lambert: {as_forward}");
}

/// LightingBlinnPhong_Deferred writes specularColor = _SpecColor·Gloss/π and smoothness =
/// Specular (n/128): a deferred built-in Blinn-Phong of shininess 64 and specular grey 0.5 is a
/// deferred Standard in its specular setup with specular 0.5/π and smoothness 0.5, whose albedo
/// carries the 1 − max(specular) the setup takes off (the legacy pass stores Albedo as is).
#[test]
fn builtins_deferred_blinn_phong_is_lit_as_its_standard_data_by_brdf1() {
    let _timer = crate::common::timed!();
    let scene = Scene::load("default", None, "test", "composition").unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let colour = [0.6, 0.4, 0.3];
    // Blinn-Phong's smoothness 0.5 is shininess 2^(10·0.5 + 1) = 64; metallic 0 keeps ks 0.5 grey.
    let sliders = Sliders { base_color_linear: colour, metallic: 0.0, smoothness: 0.5 };
    let spec = 0.5 / std::f64::consts::PI;
    let mut subject = |shader: &str, standard: bool| {
        let mut cell = cell_params(Pipeline::Builtin, shader, sliders, (2.0, 10.0), 96, RenderPath::Deferred);
        if standard {
            cell.surface.params[0] = 1.0;
            cell.surface.specular = glam::DVec3::splat(spec);
            cell.surface.smoothness = 0.5;
            cell.surface.base_color = glam::DVec3::from(colour) / (1.0 - spec);
        }
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let role = shadematrix::render::uniforms::ROLE_SUBJECT;
        (0..r.roles.len())
            .filter(|&i| r.roles[i] == role)
            .flat_map(|i| [r.hdr[4 * i], r.hdr[4 * i + 1], r.hdr[4 * i + 2]])
            .collect::<Vec<f32>>()
    };
    let (legacy, standard) = (subject("blinn_phong", false), subject("standard", true));
    assert_eq!(legacy.len(), standard.len());
    let d: f64 = legacy.iter().zip(&standard).map(|(a, b)| (a - b).abs() as f64).sum();
    let t: f64 = standard.iter().map(|b| b.abs() as f64).sum();
    eprintln!("deferred Blinn-Phong against its Standard data: relative L1 {:.5}", d / t);
    // The Standard cell's albedo passes the G-buffer's 8 bits at 1/(1 − 0.159) of the legacy one's.
    assert!(d / t < 0.01, "BRDF1 on LightingBlinnPhong_Deferred's data: {}", d / t);
}
