//! Standard's and URP Lit's smoothness Source = Albedo Alpha (registry SMOOTHNESS_FROM_ALBEDO_ALPHA):
//! the smoothness is the albedo map's alpha × the slider, in the frame and in both tracers.

use crate::common::{cell_params, fixture, same_brdf_truth as truth, subject_mean};
use shadematrix::declarations::matrix::TruthBackend;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::uniforms::ROLE_SUBJECT;
use shadematrix::render::Renderer;
use shadematrix::shading::registry::Sliders;

/// Wood's maps vary its smoothness (its rings' offset in the mask) over an opaque albedo (alpha 1): read
/// from the albedo's alpha, the smoothness is the slider's everywhere. The frame changes where the
/// rings set another smoothness, both tracers follow it (they agree, and move as the frame does).
#[test]
fn smoothness_from_the_albedo_alpha_is_the_sliders_under_opaque_maps() {
    let _timer = crate::common::timed!();
    let plane = Scene::load_file(&fixture("textured_plane.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&plane).unwrap();
    for (pipeline, shader) in [(Pipeline::Builtin, "standard"), (Pipeline::Urp, "lit")] {
        let sliders = Sliders { base_color_linear: [0.83, 0.79, 0.75], metallic: 0.0, smoothness: 0.6 };
        let mut cell = cell_params(pipeline, shader, sliders, (1.0, 10.0), 48, RenderPath::Forward);
        cell.settings.material_maps = Some("wood");
        let before = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let truth_before = truth(&mut renderer, &prepared, &cell, TruthBackend::Cpu);
        let slot = cell.model.params.iter().find(|p| p.name == "smoothness_from_albedo_alpha").unwrap().slot;
        cell.surface.params[slot] = 1.0;
        let after = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let n = after.roles.len();
        let subject = (0..n).filter(|&i| after.roles[i] == ROLE_SUBJECT);
        let changed = subject
            .clone()
            .filter(|&i| (after.hdr[4 * i] - before.hdr[4 * i]).abs() > 0.01 * before.hdr[4 * i])
            .count();
        let count = subject.count();
        let (cpu, gpu) = (
            truth(&mut renderer, &prepared, &cell, TruthBackend::Cpu),
            truth(&mut renderer, &prepared, &cell, TruthBackend::Gpu),
        );
        let z = crate::common::subject_z(&cpu, &gpu);
        let frame_ratio = subject_mean(&after.roles, |i| after.hdr[4 * i] as f64)
            / subject_mean(&before.roles, |i| before.hdr[4 * i] as f64);
        let truth_ratio = subject_mean(&cpu.roles, |i| cpu.mean[i][0] as f64)
            / subject_mean(&truth_before.roles, |i| truth_before.mean[i][0] as f64);
        eprintln!(
            "{shader}: {changed} of {count} subject pixels change by over 1%; CPU − GPU truth Z {z:.2}; \
             subject mean after/before: frame {frame_ratio:.4}, truth {truth_ratio:.4}"
        );
        assert!(changed * 10 > count, "{changed} of {count} changed");
        assert!(z.abs() < 4.0, "the tracers' subjects differ by {z:.2} standard errors");
        assert!((frame_ratio - truth_ratio).abs() < 0.04, "frame {frame_ratio} vs truth {truth_ratio}");
    }
}
