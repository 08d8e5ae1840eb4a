//! HDRP's bloom (`render::passes::bloom`) against its f64 twin (`images::bloom`), and the switch that
//! turns it off.

use glam::DVec3;
use shadematrix::gpu::GpuContext;
use shadematrix::images::bloom::{bloom, Image};
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::renderer::Renderer;
use shadematrix::spec::scene::Scene;

#[test]
fn gpu_bloom_matches_its_twin_and_the_switch_turns_it_off() {
    let with = Scene::load("mitsuba", None, "test", "composition").unwrap();
    assert!(with.hdrp.bloom, "on by default, as HDRP's default volume");
    let mut without = with.clone();
    without.hdrp.bloom = false;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let gold = shadematrix::shading::registry::Sliders {
        base_color_linear: [1.0, 0.766, 0.336],
        metallic: 1.0,
        smoothness: 0.9,
    };
    let cell = crate::common::cell_params(Pipeline::Hdrp, "lit", gold, (2.0, 10.0), 96, RenderPath::Forward);
    let mut render = |scene: &Scene| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let passes: Vec<String> = r.gpu_passes.map(|p| p.into_iter().map(|(n, _)| n).collect()).unwrap_or_default();
        let texels = r.hdr.chunks(4).map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)).collect();
        (Image { width: 96, height: 96, texels }, passes, prepared.plan.passes_for(RenderPath::Forward, Pipeline::Hdrp))
    };
    let (bloomed, timed, plan) = render(&with);
    let (plain, _, plan_off) = render(&without);
    assert!(plan.contains(&"bloom") && !plan_off.contains(&"bloom"), "{plan:?} / {plan_off:?}");
    if !timed.is_empty() {
        assert!(timed.iter().any(|n| n == "bloom"), "{timed:?}");
    }
    let twin = bloom(&plain, 0.2, 0.7);
    let peak = plain.texels.iter().map(|t| t.max_element()).fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    let mut changed = 0;
    for ((g, c), p) in bloomed.texels.iter().zip(&twin.texels).zip(&plain.texels) {
        worst = worst.max(((*g - *c).abs() / (c.abs() + DVec3::splat(1e-4 * peak))).max_element());
        if ((*g - *p).abs() / (p.abs() + DVec3::splat(1e-4 * peak))).max_element() > 0.01 {
            changed += 1;
        }
    }
    eprintln!(
        "GPU bloom vs f64 twin: worst relative difference {worst:.2e}; {changed} of 9216 pixels changed by > 1 %"
    );
    assert!(worst < 1e-3, "{worst}");
    assert!(changed > 500, "bloom changes {changed} pixels");
}
