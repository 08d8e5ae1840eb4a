//! HDRP's light settings (`[lights.hdrp]`) in rendered frames, against the formulas of its source
//! (LightLoop.cs GetLightData, LightEvaluation.hlsl, PunctualLightCommon.hlsl, SurfaceShading.hlsl,
//! core CommonLighting.hlsl) through their f64 twins (pipelines::hdrp_light).

use crate::common::{cell_params, fixture};
use glam::{DVec3, DVec4};
use shadematrix::declarations::hdrp_light::{HdrpLightKeys, SpotShapeName};
use shadematrix::declarations::scene::{LightKind, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::hdrp_light::{compute_shadow_color, punctual_attenuation};
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::{CellParams, Renderer};
use shadematrix::shading::registry::Sliders;

const SIZE: u32 = 65;
const MATTE: Sliders = Sliders { base_color_linear: [0.7, 0.6, 0.5], metallic: 0.0, smoothness: 0.5 };

/// The scene with bloom and SSAO off, so that a pixel is its own light alone.
fn scene(name: &str) -> Scene {
    let mut s = Scene::load_file(&fixture(name)).unwrap();
    s.hdrp.bloom = false;
    s.hdrp.ssao = false;
    s
}

fn cell(p: Pipeline, model: &str, sliders: Sliders) -> CellParams<'static> {
    cell_params(p, model, sliders, (1.0, 8.0), SIZE, RenderPath::Forward)
}

/// The pixel world point `w` lands in.
fn pixel_of(scene: &Scene, w: DVec3) -> (usize, usize) {
    let vp = shadematrix::plan::camera::view_projection(&scene.camera, 1.0);
    let c = vp * DVec4::new(w.x, w.y, w.z, 1.0);
    let (x, y) = (c.x / c.w, c.y / c.w);
    let px = (((x * 0.5 + 0.5) * SIZE as f64) as usize).min(SIZE as usize - 1);
    let py = (((0.5 - y * 0.5) * SIZE as f64) as usize).min(SIZE as usize - 1);
    (px, py)
}

/// The point of the plane y = 0 a pixel's centre sees.
fn ground_at(scene: &Scene, (px, py): (usize, usize)) -> DVec3 {
    let inv = shadematrix::plan::camera::view_projection(&scene.camera, 1.0).inverse();
    let ndc = ((px as f64 + 0.5) / SIZE as f64 * 2.0 - 1.0, 1.0 - (py as f64 + 0.5) / SIZE as f64 * 2.0);
    let point = |z: f64| {
        let h = inv * DVec4::new(ndc.0, ndc.1, z, 1.0);
        h.truncate() / h.w
    };
    let (a, b) = (point(0.0), point(1.0));
    a + (b - a) * (a.y / (a.y - b.y))
}

fn texel(hdr: &[f32], (px, py): (usize, usize)) -> DVec3 {
    let i = (py * SIZE as usize + px) * 4;
    DVec3::new(hdr[i] as f64, hdr[i + 1] as f64, hdr[i + 2] as f64)
}

/// The linear colour where world point `w` lands in the frame.
fn at(hdr: &[f32], scene: &Scene, w: DVec3) -> DVec3 {
    texel(hdr, pixel_of(scene, w))
}

/// One light straight down over the plane of `twelve_points` at height `h`, with HDRP's keys.
fn one_light(kind: LightKind, h: f64, keys: HdrpLightKeys) -> Scene {
    let mut s = scene("twelve_points.toml");
    s.lights.truncate(1);
    let l = &mut s.lights[0];
    l.kind = kind;
    l.position = [0.0, h, 0.0];
    l.direction = [0.0, -1.0, 0.0];
    l.color = [1.0; 3];
    l.spot_angle_deg = 60.0;
    l.hdrp = keys;
    s
}

fn render(renderer: &mut Renderer, s: &Scene, c: &CellParams) -> Vec<f32> {
    let prepared = renderer.prepare_scene(s).unwrap();
    renderer.render(&prepared, c, 1, 0).unwrap().hdr
}

fn close(got: f64, want: f64, rel: f64) -> bool {
    (got - want).abs() <= rel * want.abs().max(1e-6)
}

#[test]
fn range_attenuation_off_keeps_the_inverse_square_up_to_the_range() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let keys = HdrpLightKeys { range_attenuation: false, ..HdrpLightKeys::default() };
    let c = cell(Pipeline::Hdrp, "lambert", MATTE);
    let mut centre = |h: f64, keys: &HdrpLightKeys| {
        let s = one_light(LightKind::Point, h, keys.clone());
        at(&render(&mut renderer, &s, &c), &s, DVec3::ZERO).y
    };
    let reference = centre(1.0, &keys);
    for h in [2.0, 4.0, 7.0] {
        let (got, want) = (centre(h, &keys) / reference, punctual_attenuation(h, 8.0, false, false));
        assert!(close(got, want / punctual_attenuation(1.0, 8.0, false, false), 2e-3), "h = {h}: {got} vs {want}");
        assert!(close(want, 1.0 / (h * h), 1e-9), "the twin: the inverse square inside the range");
    }
    // Past the range: nothing; with the attenuation on, the smooth window dims it well before.
    assert_eq!(centre(8.5, &keys), 0.0);
    let on = centre(7.0, &HdrpLightKeys::default()) / centre(1.0, &HdrpLightKeys::default());
    assert!(close(on, punctual_attenuation(7.0, 8.0, true, false) / punctual_attenuation(1.0, 8.0, true, false), 2e-3));
}

#[test]
fn a_box_light_has_no_falloff_and_lights_its_box_alone() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let keys = HdrpLightKeys { spot_shape: SpotShapeName::Box, box_size: Some([1.2, 0.6]), ..HdrpLightKeys::default() };
    let c = cell(Pipeline::Hdrp, "lambert", MATTE);
    let mut frame = |h: f64| {
        let s = one_light(LightKind::Spot, h, keys.clone());
        (render(&mut renderer, &s, &c), s)
    };
    let (near, s) = frame(1.5);
    let (far, _) = frame(6.0);
    let lit = at(&near, &s, DVec3::ZERO).y;
    assert!(lit > 0.0);
    // A collimated beam: the same light at any height inside the range, and across the box.
    assert!(close(at(&far, &s, DVec3::ZERO).y, lit, 1e-4), "{} vs {lit}", at(&far, &s, DVec3::ZERO).y);
    assert!(close(at(&near, &s, DVec3::new(0.5, 0.0, 0.2)).y, lit, 1e-4));
    // Outside its 1.2 × 0.6 window (right = X for a light straight down): dark.
    assert_eq!(at(&near, &s, DVec3::new(0.7, 0.0, 0.0)).y, 0.0);
    assert_eq!(at(&near, &s, DVec3::new(0.0, 0.0, 0.4)).y, 0.0);
}

#[test]
fn a_pyramid_light_falls_off_as_a_point_inside_its_frustum() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let keys =
        HdrpLightKeys { spot_shape: SpotShapeName::Pyramid, aspect_ratio: Some(2.0), ..HdrpLightKeys::default() };
    let c = cell(Pipeline::Hdrp, "lambert", MATTE);
    let h = 1.0;
    let s = one_light(LightKind::Spot, h, keys);
    let hdr = render(&mut renderer, &s, &c);
    // 60° spans the smaller side (depth, z: half-size tan 30° = 0.577 at unit distance), the width
    // twice that (x: 1.155). Inside, no cone falloff: E ∝ cos θ/d² × the window, = h/d³.
    // Each pixel at the point its centre sees.
    let lit = |w: DVec3| {
        let px = pixel_of(&s, w);
        let g = ground_at(&s, px);
        let d = (h * h + g.x * g.x + g.z * g.z).sqrt();
        (texel(&hdr, px).y, (h / d) * punctual_attenuation(d, 8.0, true, false))
    };
    let (centre, centre_want) = lit(DVec3::ZERO);
    for x in [0.5, 1.0] {
        let (got, want) = lit(DVec3::new(x, 0.0, 0.0));
        assert!(close(got / centre, want / centre_want, 2e-3), "x = {x}: {} vs {}", got / centre, want / centre_want);
    }
    assert_eq!(at(&hdr, &s, DVec3::new(1.3, 0.0, 0.0)).y, 0.0, "past the width");
    assert_eq!(at(&hdr, &s, DVec3::new(0.0, 0.0, 0.7)).y, 0.0, "past the depth");
    assert!(at(&hdr, &s, DVec3::new(0.0, 0.0, 0.45)).y > 0.0);
}

#[test]
fn affect_diffuse_and_affect_specular_split_the_light_between_the_lobes() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let shiny = Sliders { base_color_linear: [0.7, 0.6, 0.5], metallic: 0.3, smoothness: 0.8 };
    let c = cell(Pipeline::Hdrp, "lit", shiny);
    let mut frame = |diffuse: bool, specular: bool| {
        let keys = HdrpLightKeys { affect_diffuse: diffuse, affect_specular: specular, ..HdrpLightKeys::default() };
        render(&mut renderer, &one_light(LightKind::Point, 1.5, keys), &c)
    };
    let (both, diffuse, specular, neither) =
        (frame(true, true), frame(true, false), frame(false, true), frame(false, false));
    let peak = both.iter().fold(0f32, |m, v| m.max(*v)) as f64;
    let mut worst = 0f64;
    let (mut d_total, mut s_total) = (0.0, 0.0);
    for i in 0..both.len() {
        let (a, d, s, n) = (both[i] as f64, diffuse[i] as f64, specular[i] as f64, neither[i] as f64);
        worst = worst.max((d + s - n - a).abs());
        d_total += d - n;
        s_total += s - n;
    }
    // Superposition: the two lobes lit apart add up to both lit together.
    assert!(worst <= 1e-4 * peak, "{worst} of {peak}");
    assert!(d_total > 0.0 && s_total > 0.0, "each lobe carries light: {d_total}, {s_total}");
}

#[test]
fn dimmers_fade_and_shadow_tint_scale_the_light_as_getlightdata_says() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let base = scene("shadow_box.toml");
    let c = cell(Pipeline::Hdrp, "lambert", MATTE);
    let mut centre = |edit: &dyn Fn(&mut Scene)| {
        let mut s = base.clone();
        edit(&mut s);
        at(&render(&mut renderer, &s, &c), &s, DVec3::ZERO)
    };
    let unshadowed = centre(&|s| s.lights[0].shadows = false);
    assert!(unshadowed.y > 0.0);
    assert!(centre(&|_| {}).max_element() <= 1e-3 * unshadowed.max_element(), "the centre is in the box's umbra");
    // Intensity Multiplier 2, and a fade distance that puts the light (4.47 m from the camera)
    // at 95 % of it: half faded (ComputeLinearDistanceFade).
    let dimmed = centre(&|s| {
        s.lights[0].shadows = false;
        s.lights[0].hdrp.dimmer = 2.0;
        s.lights[0].hdrp.fade_distance = 20f64.sqrt() / 0.95;
    });
    assert!((dimmed - unshadowed).abs().max_element() <= 2e-3 * unshadowed.max_element(), "{dimmed} vs {unshadowed}");
    // Shadow Dimmer 0.3: lerp(1, 0, 0.3) of the light reaches the umbra.
    let leaked = centre(&|s| s.lights[0].hdrp.shadow_dimmer = Some(0.3));
    assert!((leaked - unshadowed * 0.7).abs().max_element() <= 2e-3 * unshadowed.max_element(), "{leaked}");
    // Shadow Tint: the umbra takes the tint (ComputeShadowColor at s = 0); Penumbra Tint leaves it black.
    let tint = [0.5, 0.25, 1.0];
    let tinted = centre(&|s| s.lights[0].hdrp.shadow_tint = tint);
    let want = unshadowed * compute_shadow_color(0.0, DVec3::from(tint), false);
    assert!((tinted - want).abs().max_element() <= 2e-3 * unshadowed.max_element(), "{tinted} vs {want}");
    let penumbra = centre(&|s| {
        s.lights[0].hdrp.shadow_tint = tint;
        s.lights[0].hdrp.penumbra_tint = true;
    });
    assert!(penumbra.max_element() <= 1e-3 * unshadowed.max_element(), "{penumbra}");
}

#[test]
fn built_in_and_urp_leave_hdrp_settings_out_and_the_truth_refuses_what_no_transport_does() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let keys = HdrpLightKeys { affect_specular: false, spot_shape: SpotShapeName::Box, ..HdrpLightKeys::default() };
    let s = one_light(LightKind::Spot, 2.0, keys);
    let prepared = renderer.prepare_scene(&s).unwrap();
    for p in [Pipeline::Builtin, Pipeline::Urp] {
        let plan = renderer.plan(&prepared, &cell(p, "lambert", MATTE)).unwrap();
        assert!(plan
            .left_out
            .iter()
            .any(|(what, _)| what.contains("HDRP settings of light 0 (spot_shape, affect_specular)")));
        assert!(plan.truth_unreachable().is_none() && plan.distinct_light_terms().is_empty());
    }
    let plan = renderer.plan(&prepared, &cell(Pipeline::Hdrp, "lambert", MATTE)).unwrap();
    assert!(plan.truth_unreachable().unwrap().contains("Affect Specular off"));
    assert_eq!(plan.distinct_light_terms().len(), 1);
}

#[test]
fn a_bad_hdrp_light_key_is_refused_naming_the_file_the_key_and_what_is_allowed() {
    let _timer = crate::common::timed!();
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(fixture("shadow_box.toml")).unwrap();
    let matrix = "name = \"m\"\ncompositions = [\"scene.toml\"]\npipelines = [\"hdrp\"]\nshaders = [\"lit\"]\npresets = [\"gold\"]\n";
    crate::common::write_matrix(dir.path(), "m.toml", matrix);
    let cases = [
        ("[lights.hdrp]\nspot_shape = \"box\"\n", ["lights[0].hdrp.spot_shape", "only spot lights"]),
        ("[lights.hdrp]\nshadow_dimmer = 1.5\n", ["lights[0].hdrp.shadow_dimmer", "1.5"]),
        ("[lights.hdrp]\nspot_shape = \"cube\"\n", ["scene.toml", "pyramid"]),
        ("[lights.hdrp]\naffect_difuse = false\n", ["scene.toml", "affect_diffuse"]),
    ];
    for (table, needles) in cases {
        // The table belongs to the scene's one light, before its objects.
        let scene = base.replacen("\n[[objects]]", &format!("\n{table}\n[[objects]]"), 1);
        std::fs::write(dir.path().join("scene.toml"), scene).unwrap();
        let (rc, out, err) = crate::common::shadematrix(dir.path(), &["list", "m.toml"], &[]);
        assert_eq!(rc, 2, "{table}: {out}{err}");
        assert!(!err.contains("panicked"));
        for n in needles {
            assert!(err.contains(n), "{table}: `{n}` not in {err}");
        }
    }
}

/// The CPU tracer's light (render::truth::cpu, the twin of scene.wgsl `hdrp_light_incidence`)
/// against the GPU tracer's: a box and a pyramid, Range Attenuation off, each truth kind.
#[test]
fn the_cpu_and_gpu_truths_agree_on_box_and_pyramid_lights() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::matrix::TruthBackend;
    use shadematrix::render::truth::{TruthKind, TruthSettings};
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let shapes = [
        HdrpLightKeys { spot_shape: SpotShapeName::Box, box_size: Some([1.5, 0.8]), ..HdrpLightKeys::default() },
        HdrpLightKeys {
            spot_shape: SpotShapeName::Pyramid,
            aspect_ratio: Some(0.5),
            range_attenuation: false,
            ..HdrpLightKeys::default()
        },
    ];
    let c = cell_params(Pipeline::Hdrp, "lit", MATTE, (1.0, 8.0), 24, RenderPath::Forward);
    for (keys, kind) in shapes.iter().zip([TruthKind::SameBrdf, TruthKind::Physical]) {
        let mut s = scene("shadow_box.toml");
        s.lights[0].kind = LightKind::Spot;
        s.lights[0].direction = [0.3, -1.0, 0.1];
        s.lights[0].hdrp = keys.clone();
        let prepared = renderer.prepare_scene(&s).unwrap();
        let mut truth = |backend| {
            let settings =
                TruthSettings { kind, spp: 64, noise: 0.0, bounces: 1, batch: 32, backend, ..Default::default() };
            renderer.render_truth(&prepared, &c, &settings).unwrap()
        };
        let (cpu, gpu) = (truth(TruthBackend::Cpu), truth(TruthBackend::Gpu));
        let lum = |c: [f32; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        let (mut diff, mut var, mut lit) = (0.0, 0.0, 0);
        for i in 0..cpu.mean.len() {
            let (a, b) = (lum(cpu.mean[i]), lum(gpu.mean[i]));
            let v = (cpu.std_error[i] as f64).powi(2) + (gpu.std_error[i] as f64).powi(2);
            if v <= 0.0 {
                assert!((a - b).abs() <= 1e-5 * a.abs().max(1.0), "{keys:?} pixel {i}: {a} vs {b} without noise");
                continue;
            }
            lit += (a > 0.0) as usize;
            diff += a - b;
            var += v;
        }
        let z = diff / var.sqrt();
        assert!(lit > 20, "{keys:?}: the light reaches the frame ({lit} pixels)");
        assert!(z.abs() < 4.0, "{keys:?} {kind:?}: the tracers' sums differ by {z:.2} standard errors");
    }
}
