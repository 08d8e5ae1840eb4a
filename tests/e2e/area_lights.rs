//! Area lights: HDRP's LTC rect light against its f64 twin, a Lambert plane under a rectangle
//! against the numerical integral of it, and the lights the frame leaves out where the engines
//! only bake them.

use crate::common::{cell_params, find_model, fixture, models};
use glam::{DVec2, DVec3};
use shadematrix::declarations::scene::{LightKind, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::lights::LightMode;
use shadematrix::render::{CellRender, Renderer};
use shadematrix::shading::ltc::{integrate_rect, RectLight};
use shadematrix::shading::registry::Sliders;

const SIZE: u32 = 49;

fn scene() -> Scene {
    let mut s = Scene::load_file(&fixture("rect_light.toml")).unwrap();
    // One pixel's value: HDRP's bloom would mix its neighbourhood in, SSAO darken it.
    s.hdrp.bloom = false;
    s.hdrp.ssao = false;
    s
}

fn centre(r: &CellRender) -> DVec3 {
    let i = ((SIZE / 2) * SIZE + SIZE / 2) as usize * 4;
    DVec3::new(r.hdr[i] as f64, r.hdr[i + 1] as f64, r.hdr[i + 2] as f64)
}

fn rect_of(scene: &Scene) -> RectLight {
    let l = &scene.lights[0];
    let (forward, right) = l.area_frame();
    let [w, h] = l.size.unwrap();
    RectLight { center: DVec3::from(l.position), forward, right, half_size: DVec2::new(w, h) * 0.5, range: l.range }
}

fn render(
    renderer: &mut Renderer,
    scene: &Scene,
    p: Pipeline,
    shader: &str,
    sliders: Sliders,
    path: RenderPath,
) -> (shadematrix::render::CellPlan, CellRender) {
    let prepared = renderer.prepare_scene(scene).unwrap();
    renderer.render_planned(&prepared, &cell_params(p, shader, sliders, (1.0, 8.0), SIZE, path), 1, 0).unwrap()
}

#[test]
fn hdrp_rect_lights_match_the_twin_forward_and_deferred() {
    let _timer = crate::common::timed!();
    // The image centre is the plane's origin (N = +Y, V towards the camera): the GPU's LTC
    // evaluation against the f64 twin's, × the light's luminance and HDRP's box attenuation.
    let scene = scene();
    let rect = rect_of(&scene);
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let v = DVec3::new(0.0, 3.0, 3.0).normalize();
    let l = &scene.lights[0];
    let color = DVec3::from(l.radiance(Pipeline::Hdrp, 1.0, &Default::default()));
    // The translucent case: the light behind the surface's horizon at the edge of the rect reaches
    // through as HDRP's flipped polygon.
    let cases =
        [("lit", 0.3, 0.0, false), ("lit", 0.9, 1.0, false), ("lambert", 0.5, 0.0, false), ("lit", 0.3, 0.0, true)];
    for (shader, smoothness, metallic, translucent) in cases {
        let model = find_model(Pipeline::Hdrp, shader).unwrap();
        let sliders = Sliders { base_color_linear: [0.7, 0.6, 0.5], metallic, smoothness };
        let mut s = model.surface(Pipeline::Hdrp, &sliders);
        if translucent {
            s.params[shadematrix::shading::twin::TRANSMISSION_SLOT] = 1.0;
            s.params[shadematrix::shading::twin::THICKNESS_SLOT] = 0.2;
        }
        let lobes =
            model.twin.unwrap().rect_lobes(Pipeline::Hdrp, &s, DVec3::Y, v, &rect.vertices(DVec3::ZERO)).unwrap();
        let want = lobes.sum() * color * rect.attenuation(DVec3::ZERO);
        // Deferred where the lobe is broad: the G-buffer's 10-bit normal moves a sharp lobe's tail
        // (6% at smoothness 0.9 here), which is the G-buffer's doing, not the light's.
        let paths: &[RenderPath] =
            if smoothness < 0.8 { &[RenderPath::Forward, RenderPath::Deferred] } else { &[RenderPath::Forward] };
        for &path in paths {
            let prepared = renderer.prepare_scene(&scene).unwrap();
            let mut cell = cell_params(Pipeline::Hdrp, shader, sliders, (1.0, 8.0), SIZE, path);
            cell.surface.params = s.params;
            let (plan, r) = renderer.render_planned(&prepared, &cell, 1, 0).unwrap();
            assert_eq!(plan.assignment[0].lights[0].mode, LightMode::PerPixel, "{:?}", plan.assignment);
            let got = centre(&r);
            let rel = ((got - want).abs() / want.max(DVec3::splat(1e-9))).max_element();
            // The G-buffer keeps albedo and smoothness in 8 bits (measured 7.1e-3 here).
            let tolerance = if path == RenderPath::Deferred { 1e-2 } else { 2e-3 };
            assert!(rel < tolerance, "{shader} s{smoothness} {path:?}: GPU {got} vs twin {want} (rel {rel:e})");
        }
    }
}

#[test]
fn a_lambert_plane_under_a_rect_is_the_numerical_integral_of_it() {
    let _timer = crate::common::timed!();
    // ρ/π·E with E = L·∫cos θ·cos θ'/d² dA over the rectangle, by a 400² midpoint rule: the
    // frame's value within 1e-3.
    let scene = scene();
    let rect = rect_of(&scene);
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let albedo = [0.7, 0.6, 0.5];
    let sliders = Sliders { base_color_linear: albedo, metallic: 0.0, smoothness: 0.5 };
    let got = centre(&render(&mut renderer, &scene, Pipeline::Hdrp, "lambert", sliders, RenderPath::Forward).1);
    let l = &scene.lights[0];
    let luminance = DVec3::from(l.radiance(Pipeline::Hdrp, 1.0, &Default::default()));
    let irradiance_per_luminance = integrate_rect(&rect, DVec3::ZERO, 400, |d| d.y.max(0.0));
    let want = DVec3::from(albedo) / std::f64::consts::PI
        * luminance
        * irradiance_per_luminance
        * rect.attenuation(DVec3::ZERO);
    let rel = ((got - want).abs() / want).max_element();
    assert!(rel <= 1e-3, "GPU {got} vs numerical {want} (rel {rel:e})");
}

#[test]
fn area_lights_the_engines_only_bake_are_left_out_with_the_reason() {
    let _timer = crate::common::timed!();
    let mut scene = scene();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let sliders = Sliders { base_color_linear: [0.7, 0.6, 0.5], metallic: 0.0, smoothness: 0.5 };
    let mut dark = |scene: &Scene, p: Pipeline, shader: &str, why: &str| {
        let (plan, r) = render(&mut renderer, scene, p, shader, sliders, RenderPath::Forward);
        let u = &plan.assignment[0].lights[0];
        assert_eq!(u.mode, LightMode::LeftOut, "{} {shader}: {u:?}", p.name());
        assert!(u.reason.contains(why), "{} {shader}: {}", p.name(), u.reason);
        assert!(r.hdr.iter().all(|&x| x == 0.0 || x == 1.0), "{} {shader}: the left-out light lit the frame", p.name());
    };
    dark(&scene, Pipeline::Builtin, "standard", "bakes area lights only");
    dark(&scene, Pipeline::Urp, "lit", "bakes area lights only");
    dark(&scene, Pipeline::Hdrp, "blinn_phong", "no area-light BSDF");
    scene.lights[0].kind = LightKind::Disc;
    scene.lights[0].size = None;
    dark(&scene, Pipeline::Hdrp, "lit", "bakes disc lights only");
}

#[test]
fn a_model_draws_rect_lights_exactly_when_its_twin_has_them() {
    let _timer = crate::common::timed!();
    let n = DVec3::Y;
    let v = DVec3::new(0.0, 0.6, 0.8);
    let corners = rect_of(&scene()).vertices(DVec3::ZERO);
    for m in models().models() {
        let Some(twin) = m.twin else { continue };
        for &p in &m.pipelines {
            let s = m.surface(p, &Sliders { base_color_linear: [0.5; 3], metallic: 0.0, smoothness: 0.5 });
            assert_eq!(m.area_lights(), twin.rect_lobes(p, &s, n, v, &corners).is_some(), "{} in {}", m.name, p.name());
        }
    }
}

#[test]
fn the_truth_samples_a_rect_light_and_agrees_with_the_exact_lambert_frame() {
    let _timer = crate::common::timed!();
    // A same-BRDF truth draws points on the rectangle (cos θ'·A/d² each, HDRP's box window at the
    // shaded point); the Lambert frame integrates it exactly: their subject means agree within the
    // truth's noise, on the CPU and on the GPU.
    use shadematrix::declarations::matrix::{TruthBackend, TruthSettings};
    use shadematrix::render::truth::TruthKind;
    let scene = scene();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.7, 0.6, 0.5], metallic: 0.0, smoothness: 0.5 };
    let cell = cell_params(Pipeline::Hdrp, "lambert", sliders, (1.0, 8.0), 32, RenderPath::Forward);
    let frame = renderer.render(&prepared, &cell, 1, 0).unwrap();
    for backend in [TruthBackend::Cpu, TruthBackend::Gpu] {
        let settings = TruthSettings {
            kind: TruthKind::SameBrdf,
            spp: 256,
            noise: 0.0,
            bounces: 0,
            batch: 64,
            backend,
            ..Default::default()
        };
        let truth = renderer.render_truth(&prepared, &cell, &settings).unwrap();
        let (mut t, mut f, mut var, mut n) = (0.0, 0.0, 0.0, 0usize);
        for i in 0..truth.mean.len() {
            if truth.roles[i] == 2 && frame.roles[i] == 2 {
                t += truth.mean[i][1] as f64;
                f += frame.hdr[4 * i + 1] as f64;
                var += (truth.std_error[i] as f64).powi(2);
                n += 1;
            }
        }
        let z = (f - t) / var.sqrt();
        eprintln!("{backend:?}: truth {:.4}, frame {:.4} over {n} pixels, Z {z:.2}", t / n as f64, f / n as f64);
        assert!(n > 500 && t > 0.0, "{n} pixels, truth {t}");
        assert!(z.abs() < 4.0, "{backend:?}: frame {f} vs truth {t}: {z:.2} standard errors");
    }
}
