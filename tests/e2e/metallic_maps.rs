//! Metallic maps that vary within a preset (materials::metallic_from_mask): the blue paint's chips
//! show the steel under it, and the specular workflow carries the map over texel by texel (the
//! specular map an artist bakes from it: scene.wgsl `carried_specular`).

use crate::common::{cell_params, fixture, same_brdf_truth as truth};
use shadematrix::declarations::matrix::TruthBackend;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::uniforms::ROLE_SUBJECT;
use shadematrix::render::{CellParams, Renderer};
use shadematrix::shading::registry::{apply_workflow, workflow_source, Sliders};

/// `cell` in its specular workflow, carried over per texel (`carried`) or per cell as before.
fn in_specular_setup(mut cell: CellParams<'static>, sliders: &Sliders, carried: bool) -> CellParams<'static> {
    let model = cell.model;
    let mut s = model.surface(cell.pipeline, sliders);
    let slot = model.params.iter().find(|p| p.name == "specular_setup").expect("a specular setup").slot;
    s.params[slot] = 1.0;
    cell.settings.carried_workflow = workflow_source(model, &s, glam::DVec3::splat(0.04)).filter(|_| carried);
    apply_workflow(model, &mut s);
    cell.surface = s;
    cell
}

/// Under one directional light, a paint at metallic 0 with chips down to the steel (metallic 1).
/// Carried over per cell, as before, the specular setup's chips lose their metal (F0 0.04, the
/// steel a diffuse colour): the frames differ there by over 20 % from the metallic setup's, and
/// carried over per texel they keep it. Both tracers carry it over per texel too: the CPU truth
/// (same BRDF, direct light) brightens over the chips, and the GPU truth agrees with it. (The
/// frame's mips average the metallic before the BRDF, the tracers the BRDF over the texels, so
/// their changes differ in size: 1.38 against 1.14 on built-in.)
#[test]
fn the_specular_workflow_carries_a_varying_metallic_map_over_per_texel() {
    let _timer = crate::common::timed!();
    let plane = Scene::load_file(&fixture("textured_plane.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&plane).unwrap();
    let sliders = Sliders { base_color_linear: [0.040, 0.047, 0.305], metallic: 0.0, smoothness: 0.6 };
    for (pipeline, shader, path) in [
        (Pipeline::Builtin, "standard", RenderPath::Forward),
        (Pipeline::Builtin, "standard", RenderPath::Deferred),
        (Pipeline::Urp, "lit", RenderPath::Forward),
        (Pipeline::Hdrp, "lit", RenderPath::Deferred),
    ] {
        let mut metallic = cell_params(pipeline, shader, sliders, (1.0, 10.0), 64, path);
        metallic.settings.material_maps = Some("blue_paint");
        let reference = renderer.render(&prepared, &metallic, 1, 0).unwrap();
        let (per_texel, per_cell) =
            (in_specular_setup(metallic, &sliders, true), in_specular_setup(metallic, &sliders, false));
        let (a, b) = (
            renderer.render(&prepared, &per_texel, 1, 0).unwrap(),
            renderer.render(&prepared, &per_cell, 1, 0).unwrap(),
        );
        let lum = |hdr: &[f32], i: usize| (hdr[4 * i] + hdr[4 * i + 1] + hdr[4 * i + 2]) as f64;
        let subject = (0..reference.roles.len()).filter(|&i| reference.roles[i] == ROLE_SUBJECT);
        let apart = |f: &[f32], i: usize| (lum(f, i) - lum(&reference.hdr, i)).abs() / lum(&reference.hdr, i).max(1e-6);
        let chips: Vec<usize> = subject.clone().filter(|&i| apart(&b.hdr, i) > 0.2).collect();
        let kept = chips.iter().filter(|&&i| apart(&a.hdr, i) < 0.5 * apart(&b.hdr, i)).count();
        let sum = |f: &dyn Fn(usize) -> f64| chips.iter().map(|&i| f(i)).sum::<f64>();
        let frame_ratio = sum(&|i| lum(&a.hdr, i)) / sum(&|i| lum(&b.hdr, i));
        let (cpu_a, cpu_b) = (
            truth(&mut renderer, &prepared, &per_texel, TruthBackend::Cpu),
            truth(&mut renderer, &prepared, &per_cell, TruthBackend::Cpu),
        );
        let gpu_a = truth(&mut renderer, &prepared, &per_texel, TruthBackend::Gpu);
        let t = |tr: &shadematrix::render::truth::Truth, i: usize| tr.mean[i].iter().map(|&c| c as f64).sum::<f64>();
        let truth_ratio = sum(&|i| t(&cpu_a, i)) / sum(&|i| t(&cpu_b, i));
        let z = crate::common::subject_z(&cpu_a, &gpu_a);
        eprintln!(
            "{} {shader} {path:?}: {} of {} subject pixels are chips (per cell, over 20 % from the metallic setup); \
             per texel, {kept} of them within half that; over the chips per texel / per cell: frame {frame_ratio:.4}, \
             CPU truth {truth_ratio:.4}; CPU − GPU truth Z {z:.2}",
            pipeline.name(),
            chips.len(),
            subject.clone().count(),
        );
        assert!(chips.len() * 200 > subject.count(), "too few chips to tell: {}", chips.len());
        assert!(
            kept * 10 > chips.len() * 9,
            "the chips lose their metal per texel too: {kept} of {} kept",
            chips.len()
        );
        assert!(
            frame_ratio > 1.1 && truth_ratio > 1.05,
            "the chips' metal: frame ×{frame_ratio}, truth ×{truth_ratio}"
        );
        assert!(z.abs() < 4.0, "the tracers differ by {z:.2} standard errors");
    }
}
