//! The passes each engine draws (plan::draws): built-in's ForwardBase + one additive ForwardAdd
//! draw per extra pixel light, adding up to the single-pass image; URP's asset turning
//! additional-light shadows off; models without a G-buffer pass drawn forward on deferred paths.

use crate::common::{cell_params, fixture};
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::renderer::Renderer;
use shadematrix::render::CellParams;
use shadematrix::shading::registry::Sliders;

const PLASTIC: Sliders = Sliders { base_color_linear: [0.4, 0.3, 0.2], metallic: 0.0, smoothness: 0.7 };

fn scene() -> Scene {
    Scene::load_file(&fixture("forward_add.toml")).unwrap()
}

/// Largest |a − b| over colour channels, relative to the largest |a|.
fn worst_relative(a: &[f32], b: &[f32]) -> f64 {
    let peak = a.iter().fold(0.0f32, |m, v| m.max(v.abs())) as f64;
    let worst = a
        .iter()
        .zip(b)
        .enumerate()
        .filter(|(k, _)| k % 4 != 3)
        .map(|(_, (x, y))| (*x as f64 - *y as f64).abs())
        .fold(0.0, f64::max);
    worst / peak
}

#[test]
fn builtin_forward_adds_one_pass_per_extra_pixel_light_and_they_sum_to_one_pass() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene()).unwrap();
    for shader in ["standard", "lambert"] {
        let cell = cell_params(Pipeline::Builtin, shader, PLASTIC, (1.5, 8.0), 96, RenderPath::Forward);
        let plan = renderer.plan(&prepared, &cell).unwrap();
        // Two lit objects, four pixel lights each: the sun in the base draw, three points added.
        assert_eq!(plan.draws.counts.get("forward_base"), Some(&2), "{shader}: {:?}", plan.draws.counts);
        assert_eq!(plan.draws.counts.get("forward_add"), Some(&6), "{shader}: {:?}", plan.draws.counts);
        assert_eq!(plan.draws.forward_add[0], vec![1, 2, 3], "{shader}");
        let passes = renderer.render(&prepared, &cell, 1, 0).unwrap().hdr;
        let mut single: CellParams = cell;
        single.settings.engine.builtin.forward_add = false;
        let plan = renderer.plan(&prepared, &single).unwrap();
        assert_eq!(plan.draws.counts.get("forward"), Some(&2), "{shader}: {:?}", plan.draws.counts);
        let one = renderer.render(&prepared, &single, 1, 0).unwrap().hdr;
        let worst = worst_relative(&one, &passes);
        eprintln!("{shader}: base + 3 adds vs one pass, worst difference {worst:.2e} of the peak");
        assert!(worst < 1e-4, "{shader}: the additive passes do not sum to the one-pass image: {worst:.2e}");
    }
}

#[test]
fn only_fullforwardshadows_shaders_are_shadowed_by_forward_add_lights() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let lit = scene();
    let mut unshadowed = lit.clone();
    unshadowed.lights[1].shadows = false;
    let (a, b) = (renderer.prepare_scene(&lit).unwrap(), renderer.prepare_scene(&unshadowed).unwrap());
    for (shader, shadowed) in [("standard", true), ("lambert", false)] {
        let cell = cell_params(Pipeline::Builtin, shader, PLASTIC, (1.5, 8.0), 96, RenderPath::Forward);
        let with = renderer.render(&a, &cell, 1, 0).unwrap().hdr;
        let without = renderer.render(&b, &cell, 1, 0).unwrap().hdr;
        let d = worst_relative(&with, &without);
        eprintln!("{shader}: the point light's shadow changes the image by {d:.2e} of the peak");
        assert_eq!(d > 1e-3, shadowed, "{shader}: a ForwardAdd light's shadow {d:.2e}");
    }
}

#[test]
fn urp_default_asset_draws_no_additional_light_shadows() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let lit = scene();
    let mut unshadowed = lit.clone();
    unshadowed.lights[1].shadows = false;
    let (a, b) = (renderer.prepare_scene(&lit).unwrap(), renderer.prepare_scene(&unshadowed).unwrap());
    let mut cell = cell_params(Pipeline::Urp, "lit", PLASTIC, (1.5, 8.0), 96, RenderPath::Forward);
    let plan = renderer.plan(&a, &cell).unwrap();
    assert!(plan.left_out.iter().any(|(_, why)| why.contains("additional-light shadows off")), "{:?}", plan.left_out);
    let with = renderer.render(&a, &cell, 1, 0).unwrap().hdr;
    let without = renderer.render(&b, &cell, 1, 0).unwrap().hdr;
    assert_eq!(with, without, "the code-default URP asset casts no point-light shadow");
    cell.settings.engine.urp.additional_light_shadows = true;
    let with = renderer.render(&a, &cell, 1, 0).unwrap().hdr;
    let without = renderer.render(&b, &cell, 1, 0).unwrap().hdr;
    let d = worst_relative(&with, &without);
    assert!(d > 1e-3, "with additional-light shadows on, the point light's shadow shows: {d:.2e}");
}

#[test]
fn a_model_without_a_gbuffer_pass_is_drawn_forward_on_deferred_paths() {
    let _timer = crate::common::timed!();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene()).unwrap();
    for (pipeline, shader) in
        [(Pipeline::Builtin, "phong"), (Pipeline::Urp, "lambert"), (Pipeline::Hdrp, "blinn_phong")]
    {
        let forward = cell_params(pipeline, shader, PLASTIC, (1.5, 8.0), 96, RenderPath::Forward);
        let deferred = cell_params(pipeline, shader, PLASTIC, (1.5, 8.0), 96, RenderPath::Deferred);
        let plan = renderer.plan(&prepared, &deferred).unwrap();
        let counts = &plan.draws.counts;
        // The floor (the subject) is forward; the box (the pipeline's lit shader) goes through the
        // G-buffer, lit by one full-screen draw.
        assert_eq!(counts.get("gbuffer"), Some(&1), "{pipeline:?}: {counts:?}");
        assert_eq!(counts.get("deferred_lighting"), Some(&1), "{pipeline:?}: {counts:?}");
        let forward_draws = match pipeline {
            Pipeline::Builtin => counts.get("forward_base"),
            _ => counts.get("forward_only"),
        };
        assert_eq!(forward_draws, Some(&1), "{pipeline:?}: {counts:?}");
        let f = renderer.render(&prepared, &forward, 1, 0).unwrap();
        let d = renderer.render(&prepared, &deferred, 1, 0).unwrap();
        assert_eq!(f.roles, d.roles, "{pipeline:?}: the same pixels are the subject's");
        let (mut worst, mut peak) = (0.0f64, 0.0f64);
        for k in (0..f.roles.len()).filter(|&k| f.roles[k] == 2) {
            for c in 0..3 {
                let (x, y) = (f.hdr[4 * k + c] as f64, d.hdr[4 * k + c] as f64);
                worst = worst.max((x - y).abs());
                peak = peak.max(x.abs());
            }
        }
        eprintln!("{pipeline:?}/{shader}: deferred vs forward on the subject, worst {:.2e} of the peak", worst / peak);
        // HDRP's frame is read after its bloom, which spreads the box's light onto the floor: the
        // box is G-buffer-lit (8-bit albedo) on one path and forward-lit on the other, a 3e-4
        // difference carried into the subject's pixels. Built-in and URP have no bloom: exact.
        let allowed = if pipeline == Pipeline::Hdrp { 1e-3 } else { 1e-6 };
        assert!(worst <= allowed * peak, "{pipeline:?}/{shader}: {worst} of {peak}");
    }
}

/// HDRP's key light read as URP's unitless intensity (`light_unit = "unity"`) keeps URP's balance
/// of sky to key light in the default room; read as the app's ×10⁴ lumen it is about 4π² off.
#[test]
fn hdrp_light_unit_unity_keeps_urps_sky_to_key_balance() {
    let _timer = crate::common::timed!();
    use shadematrix::pipelines::settings::HdrpLightUnit;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&Scene::load("default", None, "test", "composition").unwrap()).unwrap();
    let plastic = Sliders { base_color_linear: [0.284; 3], metallic: 0.0, smoothness: 0.75 };
    let mut subject_mean = |pipeline: Pipeline, unit: HdrpLightUnit, (key, ambient): (f64, f64)| {
        let mut cell = cell_params(pipeline, "lit", plastic, (key, 10.0), 64, RenderPath::Forward);
        cell.settings.ambient_intensity = Some(ambient);
        cell.settings.engine.hdrp.light_unit = unit;
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let (mut sum, mut n) = (0.0, 0usize);
        for k in (0..r.roles.len()).filter(|&k| r.roles[k] == 2) {
            sum += 0.2126 * r.hdr[4 * k] as f64 + 0.7152 * r.hdr[4 * k + 1] as f64 + 0.0722 * r.hdr[4 * k + 2] as f64;
            n += 1;
        }
        sum / n as f64
    };
    let balance = |f: &mut dyn FnMut(Pipeline, HdrpLightUnit, (f64, f64)) -> f64, p, unit| {
        f(p, unit, (0.0, 1.0)) / f(p, unit, (2.0, 0.0))
    };
    let urp = balance(&mut subject_mean, Pipeline::Urp, HdrpLightUnit::Lumen);
    let unity = balance(&mut subject_mean, Pipeline::Hdrp, HdrpLightUnit::Unity);
    let lumen = balance(&mut subject_mean, Pipeline::Hdrp, HdrpLightUnit::Lumen);
    eprintln!("sky ÷ key on the subject: URP {urp:.4}, HDRP unity {unity:.4}, HDRP lumen {lumen:.4}");
    assert!((unity / urp - 1.0).abs() < 0.1, "{unity} vs {urp}");
    assert!(lumen / urp > 30.0, "{lumen} vs {urp}");
}

/// Built-in's vertex-lit path draws Standard, which has no Vertex pass, with its fallback
/// Legacy Shaders/VertexLit: fixed-function lighting at the vertices (f64 twin
/// `shading::twin::vertex_lit`): a flat ambient C·A, and 2·sat(C·A/2 + min(NL·C·L/2, 1)) under a
/// directional light, with no reflection.
#[test]
fn standard_on_the_vertex_lit_path_falls_back_to_fixed_function_vertexlit() {
    let _timer = crate::common::timed!();
    use shadematrix::shading::twin::vertex_lit::{vertex_lit_ffp, vertex_lit_pixel, FfpLight};
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let scene = Scene::load_file(&fixture("sun_and_point.toml")).unwrap();
    let mut dark = scene.clone();
    dark.lights[0].intensity = 0.0;
    let c = glam::DVec3::new(0.6, 0.4, 0.2);
    let sliders = Sliders { base_color_linear: c.to_array(), metallic: 0.0, smoothness: 0.9 };
    // The key (point) light off: the sun alone, or nothing but the ambient.
    let cell = cell_params(Pipeline::Builtin, "standard", sliders, (0.0, 6.0), 64, RenderPath::VertexLit);
    let centre = |r: &shadematrix::render::renderer::CellRender| {
        let k = 4 * (32 * 64 + 32);
        glam::DVec3::new(r.hdr[k] as f64, r.hdr[k + 1] as f64, r.hdr[k + 2] as f64)
    };
    let (dark, lit_scene) = (renderer.prepare_scene(&dark).unwrap(), renderer.prepare_scene(&scene).unwrap());
    let ambient_only = centre(&renderer.render(&dark, &cell, 1, 0).unwrap());
    let lit = centre(&renderer.render(&lit_scene, &cell, 1, 0).unwrap());
    // Flat ambient: C·A, so A is the ambient-only pixel over C.
    let a = ambient_only / c;
    assert!((a.x - a.y).abs() < 1e-4 && (a.y - a.z).abs() < 1e-4, "a grey sky's flat ambient: {a}");
    let sun = &scene.lights[0];
    let to_light = -glam::DVec3::from(sun.direction).normalize();
    let color = glam::DVec3::from(Pipeline::Builtin.light_radiance(sun.color, sun.intensity, sun.emitter()));
    let eye = glam::DVec3::from(scene.camera.position);
    let v = eye.normalize();
    let want = vertex_lit_pixel(
        glam::DVec3::ONE,
        vertex_lit_ffp(c, a, glam::DVec3::Y, v, &[FfpLight { to_light, color, attenuation: 1.0 }]),
    );
    eprintln!("vertex-lit Standard at the centre: {lit} against the fixed-function twin {want}");
    assert!((lit - want).abs().max_element() < 1e-3 * want.max_element(), "{lit} vs {want}");
    // Not Standard's own BRDF at the vertices: that has a specular lobe and Fresnel.
    let own = cell_params(Pipeline::Builtin, "standard", sliders, (0.0, 6.0), 64, RenderPath::Forward);
    let forward = centre(&renderer.render(&lit_scene, &own, 1, 0).unwrap());
    assert!((forward - lit).abs().max_element() > 1e-3, "{forward} vs {lit}");
}

/// A cell's record names the passes its frame ran: `passes` (from the plan) is the list of passes
/// its timings name, in the same order (the plan is the frame's script). None: the adapter has
/// no timestamp queries.
pub fn timed_passes_match_the_record(record: &shadematrix::record::CellRecord) -> Option<()> {
    let timed: Vec<&str> = record.timing.gpu_passes.value()?.iter().map(|s| s.kind.as_str()).collect();
    assert_eq!(record.passes, timed, "{}: cell.json's passes against its timings", record.id.0);
    Some(())
}

#[test]
fn every_cell_json_names_the_passes_its_frame_timed_on_every_path_and_surface() {
    let _timer = crate::common::timed!();
    // surfaces.toml on every path (its surfaces, two alphas, the default room's probes and
    // shadows; the vertex-lit path in built-in), smaller: the passes do not depend on the size.
    let text = std::fs::read_to_string(crate::common::repo().join("matrices/surfaces.toml")).unwrap();
    let text = text
        .replace(
            "shaders = [\"standard\", \"lit\"]",
            "shaders = [\"standard\", \"lit\"]\npaths = [\"forward\", \"deferred\", \"vertex_lit\"]",
        )
        .replace("width = 160\nheight = 160", "width = 24\nheight = 24");
    assert!(text.contains("vertex_lit") && text.contains("width = 24"), "surfaces.toml changed shape");
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("surfaces.toml");
    std::fs::write(&path, text).unwrap();
    let matrix = crate::common::load_matrix(&path);
    let out = tmp.path().join("run");
    let options =
        shadematrix::run::RunOptions { results_root: tmp.path().into(), out: Some(out.clone()), ..Default::default() };
    shadematrix::run::run(&matrix, &options).unwrap();
    let mut checked = Vec::new();
    for dir in std::fs::read_dir(out.join("cells")).unwrap() {
        let record = shadematrix::record::CellRecord::load(&dir.unwrap().path().join("cell.json")).unwrap();
        if timed_passes_match_the_record(&record).is_none() {
            return; // no timestamp queries on this adapter: nothing timed to compare
        }
        checked.push((record.path, record.passes.clone()));
    }
    for path in [RenderPath::Forward, RenderPath::Deferred, RenderPath::VertexLit] {
        assert!(checked.iter().any(|(p, _)| *p == path), "no {path:?} cell among {}", checked.len());
    }
    assert!(checked.iter().any(|(_, passes)| passes.iter().any(|p| p == "transparent")), "a Transparent queue");
}

#[test]
fn a_pass_is_named_in_plan_pass_alone() {
    let _timer = crate::common::timed!();
    // Every pass name is `Pass::name`'s; a string literal with one elsewhere is a second list that
    // can drift from the plan. A path (`forward`) and a surface type (`transparent`) share words
    // with passes and are named where they are declared, as is the URP asset's `ssao` setting
    // (its renderer's feature, a sweep key).
    let allowed = [
        ("src/pipelines/mod.rs", "forward"),
        ("src/declarations/matrix.rs", "forward"),
        ("src/pipelines/surface.rs", "transparent"),
        ("src/pipelines/settings_axes.rs", "ssao"),
        ("src/pipelines/settings_axes.rs", "bloom"),
    ];
    let names: Vec<String> = shadematrix::plan::Pass::ALL.iter().map(|p| format!("\"{}\"", p.name())).collect();
    let mut found = Vec::new();
    for (rel, code) in crate::common::crate_code() {
        if rel == "src/plan/pass.rs" {
            continue;
        }
        for (i, line) in code.lines().enumerate() {
            let line = line.split("//").next().unwrap_or("");
            for name in names.iter().filter(|n| line.contains(n.as_str())) {
                if !allowed.contains(&(rel.as_str(), name.trim_matches('"'))) {
                    found.push(format!("{rel}:{}: {name}", i + 1));
                }
            }
        }
    }
    assert!(found.is_empty(), "pass names outside plan::Pass::name:\n{}", found.join("\n"));
}
