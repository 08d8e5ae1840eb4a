//! Shadow maps: a caster darkens what lies under it when its light casts shadows, for every light
//! kind and pipeline; and the frame plan leaves the shadow pass out when nothing can cast.

use crate::common::{cell_params, fixture};
use shadematrix::color::luminance;
use shadematrix::declarations::scene::{LightKind, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::FramePlan;
use shadematrix::render::Renderer;
use shadematrix::shading::registry::Sliders;

const SIZE: u32 = 65;

/// Luminance at the image centre (under the box) and near the bottom edge (floor in the open).
fn centre_and_open_floor(renderer: &mut Renderer, scene: &Scene, pipeline: Pipeline) -> (f64, f64) {
    let prepared = renderer.prepare_scene(scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8; 3], metallic: 0.0, smoothness: 0.5 };
    // The pipeline's lit shader: built-in's Standard is compiled with fullforwardshadows, so its
    // ForwardAdd lights (the point and the spot) cast shadows; a classic model's would not.
    let shader = pipeline.fixed_object_shader();
    let cell = cell_params(pipeline, shader, sliders, (1.5, 10.0), SIZE, RenderPath::Forward);
    let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
    let at = |row: u32| {
        let i = (row * SIZE + SIZE / 2) as usize * 4;
        luminance([r.hdr[i] as f64, r.hdr[i + 1] as f64, r.hdr[i + 2] as f64])
    };
    (at(SIZE / 2), at(SIZE - 3))
}

#[test]
fn a_caster_darkens_the_receiver_under_it_only_with_shadows_on() {
    let _timer = crate::common::timed!();
    let mut base = Scene::load_file(&fixture("shadow_box.toml")).unwrap();
    // Shadowed and lit pixels side by side: HDRP's bloom would blur the edge between them.
    base.hdrp.bloom = false;
    base.hdrp.ssao = false;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    for kind in [LightKind::Point, LightKind::Spot, LightKind::Directional] {
        for pipeline in Pipeline::ALL {
            let mut on = base.clone();
            on.lights[0].kind = kind;
            let mut off = on.clone();
            off.lights[0].shadows = false;
            let (lit, open_off) = centre_and_open_floor(&mut renderer, &off, pipeline);
            let (shadowed, open_on) = centre_and_open_floor(&mut renderer, &on, pipeline);
            eprintln!("{kind:?} in {}: centre {shadowed:.4e} with shadows, {lit:.4e} without", pipeline.name());
            assert!(lit > 0.0, "{kind:?}/{}: the centre is lit without shadows", pipeline.name());
            if pipeline == Pipeline::Urp && kind != LightKind::Directional {
                // The code-default URP asset has additional-light shadows off (tests/e2e/passes.rs
                // turns them on): the point and the spot cast none.
                assert_eq!(shadowed, lit, "{kind:?}/urp");
                continue;
            }
            assert!(shadowed < 0.5 * lit, "{kind:?}/{}: {shadowed} vs {lit}", pipeline.name());
            // Floor in the open keeps its light: no acne, no map edge darkening it.
            assert!(
                (open_on - open_off).abs() <= 1e-3 * open_off,
                "{kind:?}/{}: open floor {open_on} vs {open_off}",
                pipeline.name()
            );
        }
    }
}

#[test]
fn no_shadow_pass_without_a_caster_a_receiver_or_a_shadowed_light() {
    let _timer = crate::common::timed!();
    let base = Scene::load_file(&fixture("shadow_box.toml")).unwrap();
    assert!(FramePlan::for_scene(&base).passes.contains(&shadematrix::plan::Pass::Shadow));
    let reason = |scene: &Scene| {
        let plan = FramePlan::for_scene(scene);
        assert!(!plan.passes.contains(&shadematrix::plan::Pass::Shadow));
        plan.left_out.iter().find(|(what, _)| what == "shadow pass").map(|(_, why)| why.clone()).unwrap()
    };
    let mut no_caster = base.clone();
    no_caster.objects.iter_mut().for_each(|o| o.cast_shadows = false);
    assert_eq!(reason(&no_caster), "no object casts shadows");
    let mut no_light = base.clone();
    no_light.lights[0].shadows = false;
    assert_eq!(reason(&no_light), "no light casts shadows");
    let mut no_receiver = base;
    no_receiver.objects.iter_mut().for_each(|o| o.receive_shadows = false);
    assert_eq!(reason(&no_receiver), "no object receives shadows");
}
