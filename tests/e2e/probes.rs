//! Reflection probes (`render::reflection_probes`): the GPU prefilter is the twin of the CPU one
//! (filtered importance sampling, environment::filtered),
//! and a probe in the default room puts the walls into a metal sphere's reflection.

use crate::common::fixture;
use glam::DVec3;
use shadematrix::environment::filtered::LobeWeight;
use shadematrix::environment::prefilter::{EquirectImage, SOURCE_WIDTH};
use shadematrix::gpu::GpuContext;
use shadematrix::plan::Pass;
use shadematrix::render::reflection_probes::Prefilter;

#[test]
fn gpu_prefilter_matches_its_cpu_twin() {
    let _timer = crate::common::timed!();
    // A sky with structure at every scale: a gradient, a bright disc and a sharp edge.
    let sun = DVec3::new(0.3, 0.6, -0.5).normalize();
    let radiance = |d: DVec3| {
        let disc = if d.dot(sun) > 0.995 { DVec3::new(40.0, 36.0, 30.0) } else { DVec3::ZERO };
        let edge = if d.x > 0.2 { DVec3::new(0.0, 0.3, 0.0) } else { DVec3::ZERO };
        DVec3::new(0.2, 0.3, 0.5) * (0.5 + 0.5 * d.y) + disc + edge
    };
    let source = EquirectImage::sample(&radiance, SOURCE_WIDTH, SOURCE_WIDTH / 2, 2);
    let gpu_context = GpuContext::new().unwrap();
    let prefilter = Prefilter::new(&gpu_context).unwrap();
    for weight in [LobeWeight::CosineWeighted, LobeWeight::SmithMasked] {
        let cpu = shadematrix::environment::filtered::probe(&source, weight);
        let gpu = prefilter.prefilter_source(&gpu_context, &source, weight).unwrap();
        assert_eq!(gpu.len(), cpu.levels.len());
        for (level, (g, c)) in gpu.iter().zip(&cpu.levels).enumerate() {
            let peak = c.texels.iter().map(|t| t.max_element()).fold(0.0, f64::max);
            let mut worst: f64 = 0.0;
            for (gt, ct) in g.iter().zip(&c.texels) {
                for k in 0..3 {
                    // Half-float storage of the chain and the levels (2⁻¹¹ relative each), f32
                    // directions and the sampler's filter weights.
                    let err = (gt[k] as f64 - ct[k]).abs() / (ct[k].abs() + 1e-3 * peak);
                    worst = worst.max(err);
                }
            }
            eprintln!("{weight:?} level {level}: worst relative difference {worst:.2e}");
            assert!(worst < 5e-3, "{weight:?} level {level}: GPU and CPU prefilter differ by {worst}");
        }
    }
}

#[test]
fn a_probe_puts_the_room_into_a_metal_sphere() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::scene::{Reflections, Scene};
    use shadematrix::pipelines::{Pipeline, RenderPath};
    use shadematrix::render::renderer::Renderer;
    let with_probe = Scene::load_file(&fixture("probe_room.toml")).unwrap();
    assert_eq!(with_probe.environment.reflections, Reflections::Probe);
    let mut sky_only = with_probe.clone();
    sky_only.environment.reflections = Reflections::Sky;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let silver = shadematrix::shading::registry::Sliders {
        base_color_linear: shadematrix::declarations::presets::find_preset("silver").unwrap().base_color,
        metallic: 1.0,
        smoothness: 1.0,
    };
    let cell = crate::common::cell_params(Pipeline::Urp, "lit", silver, (2.0, 10.0), 96, RenderPath::Forward);
    let mut render = |scene: &Scene| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let lum: Vec<f64> =
            r.hdr.chunks(4).map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64).collect();
        (lum, r.roles, r.gpu_passes)
    };
    let (probe, roles, passes) = render(&with_probe);
    let (sky, _, _) = render(&sky_only);
    if let Some(passes) = passes {
        let names: Vec<Pass> = passes.iter().map(|(n, _)| *n).collect();
        assert!(names.contains(&Pass::ProbeCapture) && names.contains(&Pass::ProbePrefilter), "{names:?}");
    }
    let subject: Vec<usize> = (0..probe.len()).filter(|&i| roles[i] == 2).collect();
    let others: Vec<usize> = (0..probe.len()).filter(|&i| roles[i] != 2).collect();
    assert!(subject.len() > 500, "the sphere and box cover {} pixels", subject.len());
    let rel = |i: usize| (probe[i] - sky[i]).abs() / sky[i].max(probe[i]).max(1e-6);
    let changed = subject.iter().filter(|&&i| rel(i) > 0.25).count() as f64 / subject.len() as f64;
    // Elsewhere only the walls' and floor's own faint reflections (rough dielectrics) change.
    let others_mean = others.iter().map(|&i| rel(i)).sum::<f64>() / others.len() as f64;
    eprintln!(
        "subject pixels changed by > 25 %: {:.1} %; mean relative change elsewhere {others_mean:.4}",
        changed * 100.0
    );
    assert!(changed > 0.3, "the probe changes too little of the metal subject: {changed}");
    assert!(others_mean < 0.02, "the probe changes the rest of the image: {others_mean}");
    // The sphere reflects the lit walls and floor, brighter than the dim sky they hide.
    let mean = |img: &[f64]| subject.iter().map(|&i| img[i]).sum::<f64>() / subject.len() as f64;
    assert!(mean(&probe) > 1.5 * mean(&sky), "probe {} vs sky {}", mean(&probe), mean(&sky));
}

#[test]
fn a_reused_capture_renders_the_same_image() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::scene::Scene;
    use shadematrix::pipelines::{Pipeline, RenderPath};
    use shadematrix::render::renderer::Renderer;
    let scene = Scene::load_file(&fixture("probe_room.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let timestamps = renderer.gpu.record.timestamp_queries;
    let silver = shadematrix::shading::registry::Sliders {
        base_color_linear: [0.972, 0.960, 0.915],
        metallic: 1.0,
        smoothness: 1.0,
    };
    let urp = crate::common::cell_params(Pipeline::Urp, "lit", silver, (2.0, 10.0), 48, RenderPath::Forward);
    let hdrp = crate::common::cell_params(Pipeline::Hdrp, "lit", silver, (2.0, 10.0), 48, RenderPath::Forward);
    let mut render = |cell| {
        let r = renderer.render(&prepared, cell, 1, 0).unwrap();
        // A cell reports the GPU time of the capture it reads: the same figure when it is reused.
        let capture = r.gpu_passes.and_then(|p| p.into_iter().find(|(n, _)| *n == Pass::ProbeCapture));
        (r.hdr, capture.map(|(_, ms)| ms))
    };
    let (first, first_capture) = render(&urp);
    let (_, hdrp_capture) = render(&hdrp);
    let (again, capture_again) = render(&urp);
    assert!(first == again, "URP's capture, kept in its slot while HDRP captured its own, gives the same image");
    if timestamps {
        assert!(hdrp_capture.is_some() && first_capture.is_some(), "every probe cell reports its capture");
        assert_eq!(capture_again, first_capture, "URP's second cell reads (and reports) its first capture");
    }
}

#[test]
fn urps_default_asset_reads_a_box_projected_probe_along_the_ray() {
    let _timer = crate::common::timed!();
    // URP's default asset has reflectionProbeBoxProjection off: its frame is the one the probe
    // would give without box projection; High Fidelity's asset box-projects it (plan::probes).
    use shadematrix::declarations::scene::Scene;
    use shadematrix::pipelines::settings::UrpAssetPreset;
    use shadematrix::pipelines::{Pipeline, RenderPath};
    use shadematrix::render::renderer::Renderer;
    let mut projected = Scene::load_file(&fixture("probe_room.toml")).unwrap();
    projected.probes[0].box_projection = true;
    let mut along_ray = projected.clone();
    along_ray.probes[0].box_projection = false;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let silver = shadematrix::shading::registry::Sliders {
        base_color_linear: [0.972, 0.960, 0.915],
        metallic: 1.0,
        smoothness: 1.0,
    };
    let mut render = |scene: &Scene, asset: UrpAssetPreset| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        let mut cell = crate::common::cell_params(Pipeline::Urp, "lit", silver, (2.0, 10.0), 48, RenderPath::Forward);
        cell.settings.engine.urp = asset.asset();
        renderer.render(&prepared, &cell, 1, 0).unwrap().hdr
    };
    assert!(render(&projected, UrpAssetPreset::Default) == render(&along_ray, UrpAssetPreset::Default));
    let high = (render(&projected, UrpAssetPreset::HighFidelity), render(&along_ray, UrpAssetPreset::HighFidelity));
    assert!(high.0 != high.1, "High Fidelity box-projects the probe");
}

#[test]
fn urps_default_asset_takes_the_renderers_probe_at_full_weight() {
    let _timer = crate::common::timed!();
    // Without reflectionProbeBlending each renderer samples its unity_SpecCube0 at full weight:
    // the frame does not depend on the probe's blend distance (a per-pixel fade would darken the
    // subject where it stands within a metre of the box's floor). High Fidelity blends: it does.
    use shadematrix::declarations::scene::Scene;
    use shadematrix::pipelines::settings::UrpAssetPreset;
    use shadematrix::pipelines::{Pipeline, RenderPath};
    use shadematrix::render::renderer::Renderer;
    let near = Scene::load("default", None, "test", "composition").unwrap();
    let (mut sharp, mut wide) = (near.clone(), near.clone());
    sharp.probes[0].blend_distance = Some(0.01);
    wide.probes[0].blend_distance = Some(1.5);
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let silver = shadematrix::shading::registry::Sliders {
        base_color_linear: [0.972, 0.960, 0.915],
        metallic: 1.0,
        smoothness: 0.9,
    };
    let mut render = |scene: &Scene, asset: UrpAssetPreset| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        let mut cell = crate::common::cell_params(Pipeline::Urp, "lit", silver, (2.0, 10.0), 48, RenderPath::Forward);
        cell.settings.engine.urp = asset.asset();
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let subject: Vec<f32> =
            r.hdr.chunks(4).zip(&r.roles).filter(|(_, role)| **role == 2).flat_map(|(p, _)| p[..3].to_vec()).collect();
        assert!(!subject.is_empty(), "the subject is in view");
        subject
    };
    assert!(render(&sharp, UrpAssetPreset::Default) == render(&wide, UrpAssetPreset::Default));
    assert!(render(&sharp, UrpAssetPreset::HighFidelity) != render(&wide, UrpAssetPreset::HighFidelity));
}
