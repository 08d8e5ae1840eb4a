//! Every light kept or accounted for: each pipeline's light budget, vertex and SH lights against
//! their formulas, and superposition where every light is per-pixel.

use crate::common::{cell_params, find_model, fixture, shadematrix, write_matrix};
use glam::DVec3;
use shadematrix::declarations::scene::{LightKind, RenderMode, Scene};
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::lights::{sh_of_light, LightMode};
use shadematrix::render::{CellRender, PreparedScene, Renderer};
use shadematrix::shading::registry::Sliders;

const SIZE: u32 = 49;

const ALBEDO: Sliders = Sliders { base_color_linear: [0.7, 0.6, 0.5], metallic: 0.0, smoothness: 0.5 };

fn render_on(
    renderer: &mut Renderer,
    prepared: &PreparedScene,
    pipeline: Pipeline,
    intensity: f64,
    path: RenderPath,
) -> CellRender {
    renderer.render(prepared, &cell_params(pipeline, "lambert", ALBEDO, (intensity, 8.0), SIZE, path), 1, 0).unwrap()
}

/// How each light reaches each object in a lambert cell (its plan).
fn lights_of(
    renderer: &Renderer,
    prepared: &PreparedScene,
    pipeline: Pipeline,
    intensity: f64,
    path: RenderPath,
) -> Vec<shadematrix::plan::lights::ObjectLights> {
    let cell = cell_params(pipeline, "lambert", ALBEDO, (intensity, 8.0), SIZE, path);
    renderer.plan(prepared, &cell).unwrap().assignment
}

fn render(renderer: &mut Renderer, prepared: &PreparedScene, pipeline: Pipeline, intensity: f64) -> CellRender {
    render_on(renderer, prepared, pipeline, intensity, RenderPath::Forward)
}

fn centre(r: &CellRender) -> DVec3 {
    let i = ((SIZE / 2) * SIZE + SIZE / 2) as usize * 4;
    DVec3::new(r.hdr[i] as f64, r.hdr[i + 1] as f64, r.hdr[i + 2] as f64)
}

#[test]
fn list_shows_which_of_twelve_lights_are_per_pixel_per_vertex_and_sh() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let scene = fixture("twelve_points.toml");
    let body = format!(
        "name = \"l\"\ncompositions = [\"{}\"]\npipelines = [\"builtin\", \"urp\", \"hdrp\"]\nshaders = [\"lambert\"]\npresets = [\"plastic\"]\n",
        scene.display()
    );
    let m = write_matrix(tmp.path(), "m.toml", &body);
    let (code, out, err) = shadematrix(tmp.path(), &["list", m.to_str().unwrap()], &[]);
    assert_eq!(code, 0, "{err}");
    let line = |label: &str| -> String {
        let at = out.find(label).unwrap_or_else(|| panic!("no `{label}` in {out}"));
        out[at..].lines().nth(1).unwrap().to_string()
    };
    let builtin = line("lights in builtin-forward:");
    assert!(
        builtin.contains("per-pixel [") && builtin.contains("per-vertex [") && builtin.contains("SH ["),
        "{builtin}"
    );
    let count = |s: &str, mode: &str| {
        s.split(&format!("{mode} [")).nth(1).unwrap().split(']').next().unwrap().split(", ").count()
    };
    assert_eq!(
        (count(&builtin, "per-pixel"), count(&builtin, "per-vertex"), count(&builtin, "SH")),
        (4, 4, 4),
        "{builtin}"
    );
    let urp = line("lights in urp-forward:");
    assert!(urp.contains("per-pixel [") && urp.contains("dropped ["), "{urp}");
    assert!(out.contains("dropped: beyond URP's per-object limit of 4 additional lights"), "{out}");
    assert!(out.contains("lights in hdrp-forward: all 12 per-pixel on every object"), "{out}");
}

#[test]
fn all_twelve_lights_add_up_where_every_light_is_per_pixel() {
    let _timer = crate::common::timed!();
    // HDRP renders every light per pixel: the image of all twelve is the sum of the twelve images
    // of one light each (no ambient), within f32 rounding.
    let base = Scene::load_file(&fixture("twelve_points.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let worst = crate::common::superposition_error(&base, |scene, intensity| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        render(&mut renderer, &prepared, Pipeline::Hdrp, intensity).hdr
    });
    eprintln!("superposition of 12 lights, HDRP forward: worst relative difference {worst:.2e}");
    assert!(worst < 1e-3, "{worst}");
}

#[test]
fn a_vertex_light_is_shade4pointlights_and_an_sh_light_is_its_clamped_cosine() {
    let _timer = crate::common::timed!();
    let base = Scene::load_file(&fixture("twelve_points.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let albedo = DVec3::new(0.7, 0.6, 0.5);

    // One Not Important point light over the plane's centre: built-in makes it a vertex light.
    let mut scene = base.clone();
    scene.lights.truncate(1);
    scene.lights[0].render_mode = RenderMode::NotImportant;
    scene.lights[0].position = [0.4, 1.2, -0.3];
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let r = render(&mut renderer, &prepared, Pipeline::Builtin, 1.5);
    let lights = lights_of(&renderer, &prepared, Pipeline::Builtin, 1.5, RenderPath::Forward);
    assert_eq!(lights[0].lights[0].mode, LightMode::PerVertex, "{lights:?}");
    let l = &scene.lights[0];
    let c = DVec3::from(Pipeline::Builtin.light_radiance(l.color, 1.5, l.emitter()));
    let to = DVec3::from(l.position);
    let atten = 1.0 / (1.0 + to.length_squared() * 25.0 / (8.0 * 8.0));
    let want = albedo * c * (to.normalize().y * atten);
    let got = centre(&r);
    let rel = ((got - want).abs() / want).max_element();
    assert!(rel < 1e-2, "vertex light: GPU {got} vs Shade4PointLights {want} (rel {rel:e})");

    // One Not Important directional light: not the main light, not a point: SH.
    let mut scene = base.clone();
    scene.lights.truncate(1);
    scene.lights[0].kind = LightKind::Directional;
    scene.lights[0].direction = [-0.3, -1.0, 0.5];
    scene.lights[0].render_mode = RenderMode::NotImportant;
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let r = render(&mut renderer, &prepared, Pipeline::Builtin, 1.5);
    let lights = lights_of(&renderer, &prepared, Pipeline::Builtin, 1.5, RenderPath::Forward);
    assert_eq!(lights[0].lights[0].mode, LightMode::Sh, "{lights:?}");
    // Without a point light there is no key light: the sun keeps its own intensity.
    assert_eq!(scene.key_light(), None);
    let l = &scene.lights[0];
    let c = DVec3::from(Pipeline::Builtin.light_radiance(l.color, l.intensity, l.emitter()));
    let sh = sh_of_light(-DVec3::from(l.direction), c);
    // At n = +Y the basis is (0.282095, 0.488603, 0, 0, 0, 0, 0.315392·(−1), 0, 0.546274·(−1)).
    let at_up = sh[0] * 0.282095 + sh[1] * 0.488603 - sh[6] * 0.315392 - sh[8] * 0.546274;
    let want = albedo * at_up;
    let got = centre(&r);
    let rel = ((got - want).abs() / want).max_element();
    assert!(rel < 1e-3, "SH light: GPU {got} vs {want} (rel {rel:e})");
    // And the clamped cosine it stands for is close: order-2 SH of max(0, n·l).
    let exact = albedo * c * (-DVec3::from(l.direction)).normalize().y;
    assert!(((got - exact).abs() / exact).max_element() < 0.15, "{got} vs exact {exact}");
}

#[test]
fn each_pipeline_falls_off_as_its_source_says() {
    let _timer = crate::common::timed!();
    // A point light straight above the plane's centre at height d (N·L = 1), range 8: the centre
    // pixel over its value at d = 1 is the pipeline's falloff ratio, written here from the sources.
    let range: f64 = 8.0;
    let sat = |x: f64| x.clamp(0.0, 1.0);
    let window = |d: f64| sat(1.0 - (d * d / (range * range)).powi(2));
    let falloff = |p: Pipeline, d: f64| -> f64 {
        match p {
            // Built-in: _LightTextureB0's curve, core LightFalloffLUT.cs LegacyUnityFalloff:
            // 1/(1 + 25x²), faded linearly in x² from 0.64 to 1.
            Pipeline::Builtin => {
                let x2 = sat(d / range).powi(2);
                let fade = if x2 >= 0.64 { 1.0 - (x2 - 0.64) / 0.36 } else { 1.0 };
                fade / (1.0 + 25.0 * x2)
            }
            // URP DistanceAttenuation: (1/max(d², HALF_MIN))·sat(1 − (d²/r²)²)².
            Pipeline::Urp => window(d).powi(2) / (d * d).max(6.103515625e-5),
            // HDRP PunctualLightAttenuation: [min(1/d, 100)·sat(1 − (d²/r²)²)]².
            Pipeline::Hdrp => ((1.0 / d).min(100.0) * window(d)).powi(2),
        }
    };
    let mut base = Scene::load_file(&fixture("twelve_points.toml")).unwrap();
    // The falloff at one pixel: HDRP's bloom would mix its neighbourhood in.
    base.hdrp.bloom = false;
    base.hdrp.ssao = false;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    for p in Pipeline::ALL {
        let mut at = |d: f64| {
            let mut scene = base.clone();
            scene.lights.truncate(1);
            scene.lights[0].position = [0.0, d, 0.0];
            scene.lights[0].color = [1.0; 3];
            let prepared = renderer.prepare_scene(&scene).unwrap();
            centre(&render(&mut renderer, &prepared, p, 1.0)).y
        };
        let reference = at(1.0);
        for d in [0.3, 2.0, 4.0, 7.0] {
            let got = at(d) / reference;
            let want = falloff(p, d) / falloff(p, 1.0);
            assert!((got - want).abs() <= 2e-3 * want.max(1e-3), "{}: d = {d}: {got} vs {want}", p.name());
        }
    }
}

#[test]
fn the_vertex_lit_path_lights_eight_lights_at_the_vertices_and_drops_the_rest() {
    let _timer = crate::common::timed!();
    let base = Scene::load_file(&fixture("twelve_points.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let model = find_model(Pipeline::Builtin, "lambert").unwrap();
    let sliders = ALBEDO;
    let prepared = renderer.prepare_scene(&base).unwrap();
    let all = lights_of(&renderer, &prepared, Pipeline::Builtin, base.lights[0].intensity, RenderPath::VertexLit);
    let mut render = |scene: &Scene, intensity: f64| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        render_on(&mut renderer, &prepared, Pipeline::Builtin, intensity, RenderPath::VertexLit)
    };
    let count = |m: LightMode| all[0].lights.iter().filter(|u| u.mode == m).count();
    assert_eq!((count(LightMode::PerVertex), count(LightMode::Dropped)), (8, 4), "{all:?}");
    // One light: the model's own Lambert term at the vertex under the image centre.
    let mut one = base.clone();
    one.lights.truncate(1);
    one.lights[0].position = [0.3, 1.1, -0.2];
    let r = render(&one, 1.5);
    let l = &one.lights[0];
    let c = DVec3::from(Pipeline::Builtin.light_radiance(l.color, 1.5, l.emitter()));
    let to = DVec3::from(l.position);
    let atten = Pipeline::Builtin.attenuation().eval(to.length(), 8.0);
    let want = model.twin.unwrap().direct(
        Pipeline::Builtin,
        &model.surface(Pipeline::Builtin, &sliders),
        DVec3::Y,
        DVec3::Y,
        to.normalize(),
    ) * c
        * atten;
    let got = centre(&r);
    let rel = ((got - want).abs() / want).max_element();
    assert!(rel < 1e-2, "vertex-lit: GPU {got} vs twin {want} (rel {rel:e})");
}
