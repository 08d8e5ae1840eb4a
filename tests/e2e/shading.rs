//! Shading on the GPU against the f64 twins, and the visible behaviour the foundation must show.

use crate::common::find_model;
use glam::DVec3;
use shadematrix::color::luminance;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::Pipeline;
use shadematrix::render::probe::{evaluate, ProbeInput};
use shadematrix::render::{CellParams, CellRender, Renderer};
use shadematrix::shading::registry::Sliders;

fn renderer() -> Renderer {
    Renderer::new(GpuContext::new().expect("a GPU adapter (lavapipe in CI)"))
}

fn params(
    pipeline: Pipeline,
    shader: &str,
    color: [f64; 3],
    metallic: f64,
    smoothness: f64,
    size: u32,
) -> CellParams<'static> {
    let model = find_model(pipeline, shader).unwrap();
    let sliders = Sliders { base_color_linear: color, metallic, smoothness };
    CellParams {
        pipeline,
        model,
        surface: model.surface(pipeline, &sliders),
        light_intensity: 1.0,
        light_range: 10.0,
        width: size,
        height: size,
        view: Default::default(),
        settings: Default::default(),
    }
}

/// A scene for per-pixel shading checks: HDRP's bloom (which mixes a fifth of the neighbourhood
/// into every pixel) is turned off, as these tests measure the shading itself.
fn scene(name_or_fixture: &str) -> Scene {
    let mut scene = if name_or_fixture.ends_with(".toml") {
        Scene::load_file(&crate::common::fixture(name_or_fixture)).unwrap()
    } else {
        Scene::load(name_or_fixture, None, "test", "composition").unwrap()
    };
    scene.hdrp.bloom = false;
    scene.hdrp.ssao = false;
    scene
}

/// A deterministic low-discrepancy set of unit vectors in the hemisphere around +Y.
fn hemisphere(i: usize, n: usize, salt: f64) -> DVec3 {
    let u = (i as f64 + 0.5) / n as f64;
    let v = ((i as f64 * 0.618_033_988_75 + salt) % 1.0).abs();
    let cos_t = 1.0 - u;
    let sin_t = (1.0 - cos_t * cos_t).sqrt();
    let phi = v * std::f64::consts::TAU;
    DVec3::new(sin_t * phi.cos(), cos_t, sin_t * phi.sin())
}

/// Parity of every model in every pipeline, GPU f32 against the f64 twin, on the well-conditioned
/// domain (N·L and N·V ≥ 0.1, smoothness ≤ 0.95 — grazing and mirror-like cases belong to the audit).
#[test]
fn gpu_models_match_their_f64_twins() {
    let _timer = crate::common::timed!();
    let gpu = GpuContext::new().unwrap();
    let n = 512;
    let mut report = Vec::new();
    for model in crate::common::models().models() {
        for &pipeline in &model.pipelines {
            let mut inputs = Vec::new();
            let mut cases = Vec::new();
            for i in 0..n {
                let v = hemisphere(i, n, 0.11);
                let l = hemisphere((i * 7 + 3) % n, n, 0.37);
                if v.y < 0.1 || l.y < 0.1 {
                    continue;
                }
                let sliders = Sliders {
                    base_color_linear: [0.9, 0.5, 0.1 + 0.8 * (i % 5) as f64 / 5.0],
                    metallic: (i % 3) as f64 / 2.0,
                    smoothness: 0.95 * ((i * 13) % 17) as f64 / 16.0,
                };
                let mut s = model.surface(pipeline, &sliders);
                // Every other sample takes each parameter at its largest value (Simple Lit's
                // highlights on, Standard's and URP Lit's off, the largest IOR and Fresnel
                // power, the specular workflow, ...),
                // every fourth at its smallest (HDRP's energy compensation off).
                if i % 2 == 1 {
                    for spec in &model.params {
                        s.params[spec.slot] = if i % 4 == 1 { spec.max } else { spec.min };
                    }
                    // The specular workflow where a model has it: its specular colour from the sliders.
                    shadematrix::shading::registry::apply_workflow(model, &mut s);
                }
                let gi_d = DVec3::new(0.2, 0.3, 0.4);
                let gi_s = DVec3::new(0.5, 0.4, 0.3);
                // HDRP's per-light roughness floor: radius 0, the default radius, the default sun, a large light.
                let min_roughness = [2.4e-7, 4.617e-5, 1.25e-4, 0.01][i % 4];
                let input = ProbeInput::new(&s, DVec3::Y, v, l, gi_d, gi_s).with_min_roughness(min_roughness);
                inputs.push(input);
                cases.push((s.rounded_f32(), v, l, gi_d, gi_s, min_roughness as f32 as f64));
            }
            let gpu_out = evaluate(&gpu, pipeline, model, &inputs).unwrap();
            let mut worst: f64 = 0.0;
            for ((s32, v, l, gd, gs, min_r), (d_gpu, i_gpu)) in cases.iter().zip(&gpu_out) {
                // The twin sees the f32-rounded inputs the GPU saw.
                let r = |x: DVec3| x.as_vec3().as_dvec3();
                let d_cpu = model.twin.unwrap().direct_for_light(pipeline, s32, DVec3::Y, r(*v), r(*l), *min_r);
                let i_cpu = model.twin.unwrap().indirect(pipeline, s32, DVec3::Y, r(*v), r(*gd), r(*gs));
                for (cpu, g) in [(d_cpu, d_gpu), (i_cpu, i_gpu)] {
                    for k in 0..3 {
                        let rel = (g[k] as f64 - cpu[k]).abs() / cpu[k].abs().max(1e-3);
                        worst = worst.max(rel);
                    }
                }
            }
            report.push((format!("{}/{}", pipeline.name(), model.name), worst, model.parity_tolerance));
        }
    }
    for (name, worst, tol) in &report {
        eprintln!("parity {name:32} worst relative error {worst:.2e} (allowed {tol:.0e})");
    }
    let failed: Vec<_> = report.iter().filter(|(_, w, tol)| w.is_nan() || w > tol).collect();
    assert!(failed.is_empty(), "over tolerance: {failed:?}");
}

fn centre(r: &CellRender) -> DVec3 {
    let i = ((r.height / 2) * r.width + r.width / 2) as usize * 4;
    DVec3::new(r.hdr[i] as f64, r.hdr[i + 1] as f64, r.hdr[i + 2] as f64)
}

/// The whole forward path (light colour and units, attenuation, SH ambient, probe) at one pixel,
/// against the f64 twin of each stage.
#[test]
fn rendered_pixel_matches_cpu_evaluation_in_every_pipeline() {
    let _timer = crate::common::timed!();
    let mut renderer = renderer();
    let sc = scene("plane_probe.toml");
    let prepared = renderer.prepare_scene(&sc).unwrap();
    let cam = DVec3::from(sc.camera.position);
    let light = &sc.lights[0];
    let (n, p) = (DVec3::Y, DVec3::ZERO);
    let v = (cam - p).normalize();
    let l = (DVec3::from(light.position) - p).normalize();
    let dist = (DVec3::from(light.position) - p).length();
    for model in crate::common::models().models() {
        for &pipeline in &model.pipelines {
            let mut cell = params(pipeline, &model.name, [0.6, 0.4, 0.2], 0.5, 0.6, 65);
            cell.light_intensity = 1.5;
            cell.light_range = 6.0;
            let got = centre(&renderer.render(&prepared, &cell, 1, 0).unwrap());
            let s = cell.surface;
            let emitter = light.emitter();
            let radiance = DVec3::from(pipeline.light_radiance(light.color, 1.5, emitter));
            let atten = pipeline.attenuation().eval(dist, 6.0);
            let env_scale = prepared.env.intensity * pipeline.environment_scale();
            let gi_d = prepared.env.ambient_diffuse(n) * env_scale;
            let gi_s = prepared.env.probe.levels[0].texels[0] * env_scale;
            let twin = model.twin.unwrap();
            let min_roughness = emitter.hdrp_min_roughness() as f32 as f64;
            let want = if model.main_light_only {
                // A ForwardBase shader: the point light does not light it, and its ambient is
                // scaled by the main directional light's colour, of which this scene has none.
                twin.indirect(pipeline, &s, n, v, gi_d * 0.0, gi_s)
            } else {
                twin.direct_for_light(pipeline, &s, n, v, l, min_roughness) * radiance * atten
                    + twin.indirect(pipeline, &s, n, v, gi_d, gi_s)
            };
            let rel = ((got - want).abs() / want.abs().max(DVec3::splat(1e-6))).max_element();
            // f16 storage of the probe colour bounds the agreement at ~5e-4.
            assert!(rel < 2e-3, "{}/{}: GPU {got} vs CPU {want} (rel {rel:e})", pipeline.name(), model.name);
        }
    }
}

fn subject_stats(r: &CellRender) -> (usize, DVec3, DVec3, f64) {
    let (mut n_subj, mut n_other) = (0usize, 0usize);
    let (mut subj, mut other) = (DVec3::ZERO, DVec3::ZERO);
    let mut max_l: f64 = 0.0;
    for (px, role) in r.hdr.chunks_exact(4).zip(&r.roles) {
        let c = DVec3::new(px[0] as f64, px[1] as f64, px[2] as f64);
        if *role == 2 {
            n_subj += 1;
            subj += c;
            max_l = max_l.max(luminance(c.to_array()));
        } else {
            n_other += 1;
            other += c;
        }
    }
    (n_subj, subj / n_subj.max(1) as f64, other / n_other.max(1) as f64, max_l)
}

#[test]
fn subject_is_lit_and_visible_in_every_composition() {
    let _timer = crate::common::timed!();
    let mut renderer = renderer();
    for name in ["default", "mitsuba", "medusa", "spikes"] {
        let prepared = renderer.prepare_scene(&scene(name)).unwrap();
        let r = renderer
            .render(&prepared, &params(Pipeline::Builtin, "standard", [0.8, 0.2, 0.1], 0.0, 0.5, 96), 1, 0)
            .unwrap();
        let (n, subj, rest, _) = subject_stats(&r);
        assert!(n > 96 * 96 / 50, "{name}: only {n} subject pixels");
        assert!((subj - rest).length() > 0.02, "{name}: subject {subj} indistinguishable from the rest {rest}");
        assert!(subj.x > subj.z * 1.5, "{name}: a red subject must render red, got {subj}");
    }
}

#[test]
fn raising_smoothness_sharpens_the_standard_highlight() {
    let _timer = crate::common::timed!();
    let mut renderer = renderer();
    let prepared = renderer.prepare_scene(&scene("default")).unwrap();
    let rough =
        renderer.render(&prepared, &params(Pipeline::Builtin, "standard", [0.3; 3], 0.0, 0.2, 128), 1, 0).unwrap();
    // 0.75, not ~1: a near-mirror point highlight is smaller than a pixel at this size.
    let smooth =
        renderer.render(&prepared, &params(Pipeline::Builtin, "standard", [0.3; 3], 0.0, 0.75, 128), 1, 0).unwrap();
    let (_, _, _, peak_rough) = subject_stats(&rough);
    let (_, _, _, peak_smooth) = subject_stats(&smooth);
    assert!(peak_smooth > 3.0 * peak_rough, "peak luminance: smooth {peak_smooth}, rough {peak_rough}");
    // Lambert ignores smoothness: the same two values give the same image.
    let a = renderer.render(&prepared, &params(Pipeline::Builtin, "lambert", [0.3; 3], 0.0, 0.2, 64), 1, 0).unwrap();
    let b = renderer.render(&prepared, &params(Pipeline::Builtin, "lambert", [0.3; 3], 0.0, 0.95, 64), 1, 0).unwrap();
    assert_eq!(a.hdr, b.hdr);
}

#[test]
fn black_metal_under_a_point_light_and_black_environment_is_black() {
    let _timer = crate::common::timed!();
    let mut renderer = renderer();
    let prepared = renderer.prepare_scene(&scene("black_room.toml")).unwrap();
    let r = renderer.render(&prepared, &params(Pipeline::Builtin, "standard", [0.0; 3], 1.0, 0.8, 96), 1, 0).unwrap();
    let (n, subj, rest, max_l) = subject_stats(&r);
    assert!(n > 500, "sphere visible: {n} pixels");
    assert_eq!(max_l, 0.0, "no diffuse, no specular colour: mean {subj}");
    assert!(rest.length() > 0.01, "the floor is lit, so the black is the sphere's own");
    // The same sphere in white plastic is not black: the test can fail.
    let lit = renderer.render(&prepared, &params(Pipeline::Builtin, "standard", [0.8; 3], 0.0, 0.8, 96), 1, 0).unwrap();
    assert!(subject_stats(&lit).3 > 0.1);
}

#[test]
fn gpu_resources_are_reused_across_cells() {
    let _timer = crate::common::timed!();
    let mut renderer = renderer();
    let prepared = renderer.prepare_scene(&scene("medusa")).unwrap();
    let mut compiled = Vec::new();
    for s in [0.1, 0.5, 0.9] {
        for p in [Pipeline::Builtin, Pipeline::Urp] {
            renderer.render(&prepared, &params(p, "lambert", [0.5; 3], 0.0, s, 32), 1, 0).unwrap();
        }
        compiled.push(renderer.compiled_pipelines());
    }
    // The first smoothness compiles each pipeline's (ForwardBase and ForwardAdd for built-in's
    // point key light, one forward for URP, the background; medusa has no fixed object, so no
    // pipeline of the fixed objects' model); the others reuse them.
    assert!(compiled[0] >= 4 && compiled.iter().all(|&n| n == compiled[0]), "{compiled:?}");
}

/// The specular workflow of Standard, URP Lit and HDRP Lit with the specular colour set to the F0
/// the metallic workflow gives (albedo colour·(1 − metallic)) renders the metallic cell exactly
/// where the engines' energy rules agree, and differs by the diffuse alone elsewhere: the
/// specular setups scale the diffuse by 1 − max(F0), built-in's and URP's metallic ones by
/// 0.96(1 − metallic) — equal for a dielectric (F0 0.04) and a metal (albedo black) — and HDRP's
/// by 1 − metallic, equal for a metal only: its dielectric's diffuse is 0.96× in the specular
/// type (Energy Conserving Specular Color).
#[test]
fn the_specular_workflow_matches_the_metallic_one_where_the_sources_say_it_must() {
    let _timer = crate::common::timed!();
    let mut renderer = renderer();
    let prepared = renderer.prepare_scene(&scene("default")).unwrap();
    let colour = [0.8, 0.5, 0.2];
    for (pipeline, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Urp, "lit"), (Pipeline::Hdrp, "lit")] {
        let mut frame = |metallic: f64, specular: bool| {
            let mut cell = params(pipeline, shader, colour, metallic, 0.7, 48);
            if specular {
                let slot = cell.model.params.iter().find(|p| p.name == "specular_setup").expect("the param").slot;
                cell.surface.params[slot] = 1.0;
                shadematrix::shading::registry::apply_workflow(cell.model, &mut cell.surface);
            }
            let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
            let subject: Vec<usize> = (0..r.roles.len()).filter(|&i| r.roles[i] == 2).collect();
            let mean = |c: usize| subject.iter().map(|&i| r.hdr[4 * i + c] as f64).sum::<f64>() / subject.len() as f64;
            let means = [mean(0), mean(1), mean(2)];
            (r.hdr, means)
        };
        let equal_at: &[f64] = if pipeline == Pipeline::Hdrp { &[1.0] } else { &[0.0, 1.0] };
        for &metallic in equal_at {
            let ((a, _), (b, _)) = (frame(metallic, false), frame(metallic, true));
            let peak = a.iter().fold(0.0f32, |m, v| m.max(v.abs()));
            let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
            eprintln!(
                "{}/{shader} metallic {metallic}: specular against metallic worst {worst:.2e} of {peak:.3}",
                pipeline.name()
            );
            assert!(worst <= 1e-5 * peak.max(1.0), "{pipeline:?} at metallic {metallic}: {worst}");
        }
        if pipeline == Pipeline::Hdrp {
            // A dielectric: the specular type's diffuse is 0.96× the metallic one's, the specular
            // term the same, so the image is darker by less than 4 %.
            let ((a, metal), (b, spec)) = (frame(0.0, false), frame(0.0, true));
            assert!(a.iter().zip(&b).all(|(x, y)| *y <= *x + 1e-6 * x.abs()), "the specular type is never brighter");
            let ratio = spec[0] / metal[0];
            eprintln!("hdrp/lit metallic 0: specular type over metallic {ratio:.4}");
            assert!(ratio > 0.96 - 1e-4 && ratio < 1.0 - 1e-4, "{ratio}");
        }
        // Between them the two workflows differ.
        let ((_, metal), (_, spec)) = (frame(0.5, false), frame(0.5, true));
        eprintln!("{}/{shader} metallic 0.5: subject mean {metal:.4?} metallic, {spec:.4?} specular", pipeline.name());
        assert!((metal[0] - spec[0]).abs() > 1e-3 * metal[0], "{pipeline:?}: the workflows agree at 0.5");
    }
}

/// Standard's and URP Lit's Specular Highlights toggle: off removes the lights' highlight from a
/// smooth subject in forward, and in URP's deferred lighting (its G-buffer carries the flag), but
/// not in built-in's deferred lighting, which Internal-DeferredShading does without the
/// material's keywords.
#[test]
fn the_specular_highlights_toggle_reaches_the_passes_the_engines_read_it_in() {
    let _timer = crate::common::timed!();
    use shadematrix::pipelines::RenderPath;
    let mut renderer = renderer();
    let prepared = renderer.prepare_scene(&scene("default")).unwrap();
    for (pipeline, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Urp, "lit")] {
        for path in [RenderPath::Forward, RenderPath::Deferred] {
            let mut frame = |highlights_off: f64| {
                let mut cell = params(pipeline, shader, [0.5, 0.5, 0.5], 0.0, 0.9, 48);
                cell.settings.path = path;
                let slot = cell.model.params.iter().find(|p| p.name == "specular_highlights_off").unwrap().slot;
                cell.surface.params[slot] = highlights_off;
                renderer.render(&prepared, &cell, 1, 0).unwrap().hdr
            };
            let (on, off) = (frame(0.0), frame(1.0));
            let worst = on.iter().zip(&off).map(|(a, b)| a - b).fold(0.0f32, f32::max);
            let brighter = off.iter().zip(&on).all(|(b, a)| *b <= *a + 1e-6);
            eprintln!("{}/{shader} {path:?}: highlights take off up to {worst:.4}", pipeline.name());
            assert!(brighter, "{pipeline:?} {path:?}: highlights off is never brighter");
            match (pipeline, path) {
                (Pipeline::Builtin, RenderPath::Deferred) => assert_eq!(worst, 0.0, "built-in deferred ignores it"),
                _ => assert!(worst > 0.01, "{pipeline:?} {path:?}: the highlight stays ({worst})"),
            }
        }
    }
}

/// URP Lit's Environment Reflections toggle: off, a surface reflects the constant
/// _GlossyEnvironmentColor (the ambient probe's L0: the environment's mean radiance). Under a
/// constant sky, which is its own mean, the frame does not change; in the default room, whose
/// probe holds the walls and floor, the smooth metal sphere's reflections do.
#[test]
fn urp_environment_reflections_off_reflect_the_mean_of_the_environment() {
    let _timer = crate::common::timed!();
    let mut renderer = renderer();
    let mut constant = scene("default");
    constant.environment.sky = shadematrix::declarations::scene::Sky::Constant { color: [0.4, 0.5, 0.6] };
    constant.environment.reflections = shadematrix::declarations::scene::Reflections::Sky;
    let room = scene("default");
    for (what, sc, changes) in [("constant sky", constant, false), ("the default room", room, true)] {
        let prepared = renderer.prepare_scene(&sc).unwrap();
        let mut frame = |off: f64| {
            let mut cell = params(Pipeline::Urp, "lit", [0.9, 0.9, 0.9], 1.0, 0.9, 48);
            let slot = cell.model.params.iter().find(|p| p.name == "environment_reflections_off").unwrap().slot;
            cell.surface.params[slot] = off;
            let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
            (0..r.roles.len())
                .filter(|&i| r.roles[i] == 2)
                .flat_map(|i| r.hdr[4 * i..4 * i + 3].to_vec())
                .collect::<Vec<f32>>()
        };
        let (on, off) = (frame(0.0), frame(1.0));
        let peak = on.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let worst = on.iter().zip(&off).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
        eprintln!("urp/lit reflections off under {what}: worst change {worst:.4} of {peak:.4}");
        if changes {
            assert!(worst > 0.05 * peak, "{what}: the probe's room should leave the reflections");
        } else {
            assert!(worst < 2e-3 * peak.max(1e-3), "{what}: a constant sky is its own mean ({worst})");
        }
    }
}
