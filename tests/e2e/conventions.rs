//! The engines' conventions as a run records and renders them: HDRP's ACES and exposure, the
//! metallic slider per pipeline, the built-in light colour, and sweeps over model parameters,
//! colour and the view.

use crate::common::{cell_params, find_model, fixture, shadematrix, write_matrix};
use glam::DVec3;
use shadematrix::color::linear_to_srgb;
use shadematrix::compare::images::LoadedImage;
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::images::aces::aces_display;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::record::CellRecord;
use shadematrix::render::Renderer;
use shadematrix::report::run_data::RunData;
use shadematrix::shading::registry::Sliders;
use std::path::Path;

fn run(dir: &Path, body: &str) -> RunData {
    let m = write_matrix(dir, "m.toml", body);
    let out = dir.join("out");
    let (code, _, err) = shadematrix(dir, &["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()], &[]);
    assert_eq!(code, 0, "{err}");
    RunData::load(&out).unwrap()
}

fn cell<'a>(run: &'a RunData, prefix: &str) -> &'a CellRecord {
    run.cells.iter().find(|c| c.id.0.starts_with(prefix)).unwrap_or_else(|| panic!("no cell {prefix}"))
}

/// HDRP's center-weighted automatic exposure computed here, apart from the library: every pixel's
/// EV100 = log2(max(L, 1e-4)·100/12.5) with Unity's Rec.709 luminance, weight
/// 1 − sat(|centre − pixel|/(0.5·(w + h))), the weighted mean over all pixels.
fn center_weighted_ev(rgba: &[f32], w: u32, h: u32) -> f64 {
    let (mut sum, mut weight) = (0.0, 0.0);
    for (i, px) in rgba.chunks_exact(4).enumerate() {
        let (x, y) = ((i as u32 % w) as f64, (i as u32 / w) as f64);
        let l = 0.2126729 * px[0] as f64 + 0.7151522 * px[1] as f64 + 0.0721750 * px[2] as f64;
        let d = ((w as f64 / 2.0 - x).powi(2) + (h as f64 / 2.0 - y).powi(2)).sqrt();
        let k = 1.0 - (d / (0.5 * (w + h) as f64)).clamp(0.0, 1.0);
        sum += k * (l.max(1e-4) * 100.0 / 12.5).log2();
        weight += k;
    }
    sum / weight
}

#[test]
fn hdrp_png_is_unity_aces_of_the_exposed_exr_and_metallic_follows_each_pipeline() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let run = run(
        tmp.path(),
        "name = \"conv\"\ncompositions = [\"medusa\"]\npipelines = [\"builtin\", \"urp\", \"hdrp\"]\n\
         shaders = [\"standard\", \"lit\"]\npresets = [\"plastic\"]\n[sweep]\nmetallic = [0.5]\n\
         [image]\nwidth = 48\nheight = 40\n",
    );
    assert_eq!(run.cells.len(), 3);
    let hdrp = cell(&run, "medusa__hdrp-forward__lit");
    let exposure = hdrp.display.exposure.expect("HDRP records its exposure");
    let dir = run.cell_dir(&hdrp.id.0);
    let LoadedImage::Hdr { width, height, rgba } = LoadedImage::load(&dir.join("image.exr")).unwrap() else {
        panic!("EXR")
    };
    let ev = center_weighted_ev(&rgba, width, height);
    assert!((exposure.metered_ev100 - ev).abs() < 1e-6, "recorded {} vs {ev}", exposure.metered_ev100);
    assert!(!exposure.clamped, "the scene's limits contain it: {exposure:?}");
    assert!((exposure.exposure - 1.0 / (1.2 * exposure.ev100.exp2())).abs() < 1e-12);
    let LoadedImage::Ldr { rgba8, .. } = LoadedImage::load(&dir.join("image.png")).unwrap() else { panic!("PNG") };
    let mut within = 0;
    for (hdr, png) in rgba.chunks_exact(4).zip(rgba8.chunks_exact(4)) {
        let x = [0, 1, 2].map(|k| (hdr[k] as f64 * exposure.exposure).max(0.0));
        let want = aces_display(x).map(|c| (linear_to_srgb(c.clamp(0.0, 1.0)) * 255.0).round());
        within += (0..3).all(|k| (want[k] - png[k] as f64).abs() <= 1.0) as usize;
    }
    let share = within as f64 / (width * height) as f64;
    eprintln!(
        "HDRP PNG within 1/255 of ACES(EXR × exposure): {:.2} % of pixels; EV {:.4} (independent {ev:.4})",
        100.0 * share,
        exposure.metered_ev100
    );
    assert!(share >= 0.99, "PNG within 1/255 of ACES(EXR × exposure) on {:.2} % of pixels", 100.0 * share);

    // The metallic slider 0.5: built-in Standard gamma-decodes it, URP and HDRP take it as is.
    let builtin = cell(&run, "medusa__builtin-forward__standard").shader_inputs.metallic;
    assert!((builtin - 0.214).abs() < 1e-3, "{builtin}");
    assert_eq!(cell(&run, "medusa__urp-forward__lit").shader_inputs.metallic, 0.5);
    assert_eq!(hdrp.shader_inputs.metallic, 0.5);
    assert!(hdrp.key_light.unit.starts_with("lumen"), "{}", hdrp.key_light.unit);
}

#[test]
fn builtin_white_light_of_intensity_two_delivers_two_to_the_2_2() {
    let _timer = crate::common::timed!();
    // GammaToLinearSpaceExact: (1·2)^2.2 = 4.595, not the sRGB curve's 4.95, on a Lambert plane.
    let mut scene = Scene::load_file(&fixture("plane_probe.toml")).unwrap();
    scene.lights[0].color = [1.0; 3];
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.5; 3], metallic: 0.0, smoothness: 0.5 };
    let mut centre = |intensity: f64| {
        let cell = cell_params(Pipeline::Builtin, "lambert", sliders, (intensity, 6.0), 33, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let i = (16 * 33 + 16) * 4;
        DVec3::new(r.hdr[i] as f64, r.hdr[i + 1] as f64, r.hdr[i + 2] as f64)
    };
    let (ambient, one, two) = (centre(0.0), centre(1.0), centre(2.0));
    let ratio = (two.y - ambient.y) / (one.y - ambient.y);
    eprintln!("built-in white light, intensity 2 over intensity 1 on a Lambert plane: {ratio:.5}");
    assert!((ratio - 2f64.powf(2.2)).abs() < 2e-3, "irradiance ratio {ratio}, want 4.595");
}

#[test]
fn sweeps_over_model_parameters_colour_and_view_render_and_sheet_every_cell() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let run = run(
        tmp.path(),
        "name = \"sweep\"\ncompositions = [\"medusa\"]\npipelines = [\"builtin\"]\n\
         shaders = [\"cook_torrance\", \"lambert\"]\npresets = [\"plastic\"]\n\
         sheets = [{ rows = \"color\", cols = \"params\" }, { rows = \"shader\", cols = \"color\" }]\n\
         [sweep]\ncolor = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]\nlight_angle = [30.0, 70.0]\n\
         [sweep.params]\nior = [1.3, 2.0]\n[image]\nwidth = 24\nheight = 24\n",
    );
    // cook_torrance: 2 colours × 2 angles × 2 IORs; lambert has no IOR: 2 colours × 2 angles.
    assert_eq!(run.cells.len(), 8 + 4, "{:?}", run.cells.iter().map(|c| &c.id.0).collect::<Vec<_>>());
    let ior13 = cell(&run, "medusa__builtin-forward__cook_torrance__plastic__m0.00_s0.75_cff0000_i1_r10_a30_ior1.3");
    assert_eq!(ior13.shader_inputs.params["ior"], 1.3);
    let ior20 = cell(&run, "medusa__builtin-forward__cook_torrance__plastic__m0.00_s0.75_cff0000_i1_r10_a30_ior2");
    assert_ne!(ior13.stats.subject_mean_luminance, ior20.stats.subject_mean_luminance, "the IOR reaches the shader");
    let wide = cell(&run, "medusa__builtin-forward__lambert__plastic__m0.00_s0.75_cff0000_i1_r10_a70");
    let narrow = cell(&run, "medusa__builtin-forward__lambert__plastic__m0.00_s0.75_cff0000_i1_r10_a30");
    assert_ne!(wide.stats.subject_mean_luminance, narrow.stats.subject_mean_luminance, "the light moved");
    for c in &run.cells {
        assert!(run.cell_dir(&c.id.0).join("image.png").is_file(), "{}", c.id);
    }
    for spec in &run.run.matrix.sheets {
        let mut placed: Vec<String> = shadematrix::report::sheets::layout(&run, spec)
            .into_iter()
            .flat_map(|s| {
                assert!(run.dir.join(&s.name).is_file(), "{}", s.name);
                s.tiles.into_iter().flatten().flatten().map(|t| t.id)
            })
            .collect();
        placed.sort();
        let all: Vec<String> = run.cells.iter().map(|c| c.id.0.clone()).collect();
        assert_eq!(placed, all, "{spec:?}: every cell in exactly one tile");
    }
}

#[test]
fn the_sky_lit_knob_meters_inside_its_scene_limits_in_hdrp() {
    let _timer = crate::common::timed!();
    // Under the default volume's limit of 10 EV100 the knob (metering ≈ 13) would be over-exposed
    // by three stops; the scene's own volume contains it, so the EV used is the metered one.
    let tmp = tempfile::tempdir().unwrap();
    let run = run(
        tmp.path(),
        "name = \"knob\"\ncompositions = [\"mitsuba\"]\npipelines = [\"hdrp\"]\nshaders = [\"lit\"]\n\
         presets = [\"plastic\"]\n[image]\nwidth = 64\nheight = 64\n",
    );
    let e = run.cells[0].display.exposure.unwrap();
    assert!(e.metered_ev100 > 10.0, "the knob meters above the default limit: {e:?}");
    assert!(!e.clamped && e.ev100 == e.metered_ev100 && e.limits[1] > e.metered_ev100, "{e:?}");
}

#[test]
fn the_custom_shader_as_written_sees_the_sun_alone_and_scales_ambient_by_it() {
    let _timer = crate::common::timed!();
    let scene = Scene::load_file(&fixture("sun_and_point.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8, 0.5, 0.3], metallic: 0.3, smoothness: 0.6 };
    let mut centre = |shader: &str, intensity: f64| {
        let cell = cell_params(Pipeline::Builtin, shader, sliders, (intensity, 6.0), 33, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let i = (16 * 33 + 16) * 4;
        DVec3::new(r.hdr[i] as f64, r.hdr[i + 1] as f64, r.hdr[i + 2] as f64)
    };
    let (dim, bright) = (centre("torrance_sparrow", 0.5), centre("torrance_sparrow", 3.0));
    assert_eq!(dim, bright, "the point light does not reach a ForwardBase-only shader");
    assert_ne!(centre("torrance_sparrow_corrected", 0.5), centre("torrance_sparrow_corrected", 3.0));

    // The pixel against the twin: the sun's direct term plus ambient scaled by the sun's colour.
    let model = find_model(Pipeline::Builtin, "torrance_sparrow").unwrap();
    let s = model.surface(Pipeline::Builtin, &sliders);
    let sun = &scene.lights[0];
    let sun_color = DVec3::from(Pipeline::Builtin.light_radiance(sun.color, sun.intensity, sun.emitter()));
    let (n, v) = (DVec3::Y, DVec3::from(scene.camera.position).normalize());
    let l = -DVec3::from(sun.direction).normalize();
    let env = prepared.env.intensity * Pipeline::Builtin.environment_scale();
    let gi_d = prepared.env.ambient_diffuse(n) * env;
    let gi_s = prepared.env.probe.levels[0].texels[0] * env;
    let twin = model.twin.unwrap();
    let want = twin.direct(Pipeline::Builtin, &s, n, v, l) * sun_color
        + twin.indirect(Pipeline::Builtin, &s, n, v, gi_d * sun_color, gi_s);
    let rel = ((dim - want).abs() / want.abs().max(DVec3::splat(1e-6))).max_element();
    assert!(rel < 2e-3, "GPU {dim} vs twin {want} (rel {rel:e})");
}
