//! LOD groups (`plan::lod`): in a cross-fade band the shipped three-level sphere draws both
//! levels dithered into complementary pixels. Which levels a distance draws is decided by the
//! cell's plan and tested there (`plan::cell`).

use crate::common::{cell_params, repo};
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::camera::ViewAxes;
use shadematrix::render::renderer::{LodUse, Renderer};

fn render(renderer: &mut Renderer, scene: &Scene, distance: f64, shader: &str) -> (Vec<f64>, Vec<u8>, Vec<LodUse>) {
    let plastic =
        shadematrix::shading::registry::Sliders { base_color_linear: [0.284; 3], metallic: 0.0, smoothness: 0.75 };
    let mut cell = cell_params(Pipeline::Urp, shader, plastic, (2.0, 10.0), 128, RenderPath::Forward);
    cell.view = ViewAxes { camera_distance: Some(distance), light_angle: None };
    let prepared = renderer.prepare_scene(scene).unwrap();
    let (plan, r) = renderer.render_planned(&prepared, &cell, 1, 0).unwrap();
    let lum = r.hdr.chunks(4).map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64).collect();
    (lum, r.roles, plan.lod)
}

#[test]
fn a_cross_fade_band_dithers_the_two_levels_into_complementary_pixels() {
    let _timer = crate::common::timed!();
    let mut scene = Scene::load_file(&repo().join("scenes/default_lod.toml")).unwrap();
    // The sky's reflections: a probe would be captured anew for every render here.
    scene.environment.reflections = shadematrix::declarations::scene::Reflections::Sky;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    // Which levels each distance draws is the plan's (plan::cell's unit tests); here, the pixels.
    // In the band each pixel of the sphere is one level's or the other's, in the share the fade says.
    // (Without shadows: the shadow pass draws the level fading out whole, so the level fading in
    // is shadowed by the other's shape.)
    scene.lights[0].shadows = false;
    // URP's quality level has lodBias 2: at 12 m the sphere is in its level 0 → 1 band.
    let d = 12.0;
    // URP Lit dithers with the hashed view-direction seed (LODDitheringTransition), the SRP
    // tutorial's Lit with interleaved gradient noise (plan::lod::CrossFade).
    for shader in ["lit", "srp_lit"] {
        let (band, roles, lod) = render(&mut renderer, &scene, d, shader);
        let t = lod[0].drawn[0].fade;
        let mut only0 = scene.clone();
        only0.objects[0].lod.as_mut().unwrap().fade_width = 0.0;
        let mut only1 = only0.clone();
        only1.objects[0].lod.as_mut().unwrap().transitions[0] = 0.9;
        let (a, _, _) = render(&mut renderer, &only0, d, shader);
        let (b, _, _) = render(&mut renderer, &only1, d, shader);
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-4 * x.abs().max(y.abs()).max(1e-3);
        let differing: Vec<usize> = (0..band.len()).filter(|&i| roles[i] == 2 && !close(a[i], b[i])).collect();
        assert!(differing.len() > 200, "the levels differ on {} pixels", differing.len());
        let from_a = differing.iter().filter(|&&i| close(band[i], a[i])).count() as f64 / differing.len() as f64;
        let from_b = differing.iter().filter(|&&i| close(band[i], b[i])).count() as f64 / differing.len() as f64;
        eprintln!(
            "{shader}: band at fade {t:.3}: {:.1} % of differing pixels from level 0, {:.1} % from level 1",
            from_a * 100.0,
            from_b * 100.0
        );
        assert!(from_a + from_b > 0.9, "{shader}: pixels that are neither level: {}", 1.0 - from_a - from_b);
        assert!((from_a - t).abs() < 0.1, "{shader}: level 0 keeps {from_a} of the pixels at fade {t}");
    }
}

#[test]
fn list_shows_the_levels_each_distance_draws() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let m = repo().join("matrices/lod.toml");
    let (rc, out, err) = crate::common::shadematrix(tmp.path(), &["list", m.to_str().unwrap()], &[]);
    assert_eq!(rc, 0, "{err}");
    // The sphere (radius 1, 2 m across, centred at (−1.35, 1, 0)) seen from the camera moved along
    // its view direction to `d` from the target, under a 42° field of view.
    // Times the pipeline's QualitySettings.lodBias: 2 for built-in and URP, 1 for HDRP.
    let height = |d: f64, bias: f64| {
        let (target, eye) = (glam::DVec3::new(0.0, 0.9, 0.0), glam::DVec3::new(0.0, 1.7, 6.2));
        let camera = target + (eye - target).normalize() * d;
        let distance = (camera - glam::DVec3::new(-1.35, 1.0, 0.0)).length();
        2.0 / (2.0 * distance * 21f64.to_radians().tan()) * 100.0 * bias
    };
    let line = |d: f64, pipeline: &str, drawn: &str| {
        let bias = if pipeline == "hdrp" { 1.0 } else { 2.0 };
        format!("LOD at camera distance {d} ({pipeline}): sphere at {:.1} % of the screen: {drawn}", height(d, bias))
    };
    // 35 % and 20 % are the transitions; fade width 0.25 of each level's range.
    assert!(out.contains(&(line(4.0, "hdrp", "level 0") + "\n")), "{out}");
    assert!(out.contains(&line(6.5, "hdrp", "level 0 (fade")), "{out}");
    assert!(out.contains(&line(12.0, "hdrp", "level 1 (fade")), "{out}");
    assert!(out.contains(&(line(14.0, "hdrp", "level 2") + "\n")), "{out}");
    // The same distances one band nearer in URP; built-in's Standard draws a band's levels whole.
    assert!(out.contains(&(line(8.0, "urp", "level 0") + "\n")), "{out}");
    assert!(out.contains(&line(12.0, "urp", "level 0 (fade +0.50, dithered)")), "{out}");
    assert!(out.contains(&line(24.0, "builtin", "level 1 (fade +0.45, drawn whole)")), "{out}");
}
