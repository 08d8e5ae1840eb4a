//! Surface types (pipelines::surface) as the GPU draws them, against the f64 twins: each
//! premultiplied surface keeps its reflection whole and multiplies its diffuse light by alpha,
//! Fade multiplies both, and a cutout's coverage is where its alpha reaches the cutoff.

use crate::common::{cell_params, find_model, fixture, shadematrix, write_matrix};
use glam::{DMat4, DVec3, DVec4};
use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::surface::{LitTerms, SurfaceOptions, SurfaceType};
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::plan::camera::view_projection;
use shadematrix::plan::roles::ROLE_SUBJECT;
use shadematrix::render::Renderer;
use shadematrix::shading::registry::Sliders;

const SIZE: u32 = 48;

/// The point of the plane y = 0 the ray through pixel (x, y)'s centre meets, where it is well
/// inside the fixture's 6 m plane.
fn plane_point(inverse: DMat4, camera: DVec3, x: u32, y: u32) -> Option<DVec3> {
    let ndc = ((x as f64 + 0.5) / SIZE as f64 * 2.0 - 1.0, 1.0 - (y as f64 + 0.5) / SIZE as f64 * 2.0);
    let far = inverse * DVec4::new(ndc.0, ndc.1, 1.0, 1.0);
    let dir = far.truncate() / far.w - camera;
    let p = camera + dir * (-camera.y / dir.y);
    (dir.y < 0.0 && p.x.abs() < 2.8 && p.z.abs() < 2.8).then_some(p)
}

#[test]
fn premultiplied_surfaces_keep_the_reflection_and_fade_fades_it() {
    let _timer = crate::common::timed!();
    let scene = Scene::load_file(&fixture("glass_plane.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8, 0.3, 0.2], metallic: 0.0, smoothness: 0.8 };
    let alpha = 0.35;
    let inverse = view_projection(&scene.camera, 1.0).inverse();
    let camera = DVec3::from(scene.camera.position);
    let sun = &scene.lights[0];
    let l = -DVec3::from(sun.direction).normalize();
    let cases: [(Pipeline, &str, &[SurfaceType]); 4] = [
        (Pipeline::Builtin, "standard", &[SurfaceType::Opaque, SurfaceType::Fade, SurfaceType::Transparent]),
        (Pipeline::Urp, "lit", &[SurfaceType::Transparent, SurfaceType::Premultiply, SurfaceType::Additive]),
        (Pipeline::Hdrp, "lit", &[SurfaceType::Transparent, SurfaceType::Premultiply, SurfaceType::Additive]),
        (Pipeline::Urp, "simple_lit", &[SurfaceType::Transparent]),
    ];
    for (pipeline, shader, kinds) in cases {
        let model = find_model(pipeline, shader).unwrap();
        let twin = model.twin.unwrap();
        let radiance = DVec3::from(pipeline.light_radiance(sun.color, sun.intensity, sun.emitter()));
        let mut images: Vec<(SurfaceType, Vec<f32>)> = Vec::new();
        for &kind in kinds {
            let mut cell = cell_params(pipeline, shader, sliders, (sun.intensity, 10.0), SIZE, RenderPath::Forward);
            cell.settings.surface = SurfaceOptions { kind, alpha, ..Default::default() };
            // Simple Lit's highlights on (`specular_highlights`), so that it has a reflection to keep.
            if shader == "simple_lit" {
                cell.surface.params[0] = 1.0;
            }
            let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
            let s = cell.surface;
            let (mut worst, mut peak_specular, mut pixels) = (0.0f64, 0.0f64, 0);
            for y in 0..SIZE {
                for x in 0..SIZE {
                    let Some(p) = plane_point(inverse, camera, x, y) else { continue };
                    let (n, v) = (DVec3::Y, (camera - p).normalize());
                    let floor = sun.emitter().hdrp_min_roughness();
                    let full = twin.direct_for_light(pipeline, &s, n, v, l, floor) * radiance;
                    let specular = twin.direct_for_light(
                        pipeline,
                        &shadematrix::shading::twin::Surface { diffuse_weight: 0.0, ..s },
                        n,
                        v,
                        l,
                        floor,
                    ) * radiance;
                    let diffuse = full - specular;
                    let weight = if kind.premultiplies_diffuse(pipeline) { alpha } else { 1.0 };
                    let lit = LitTerms {
                        diffuse: (diffuse * weight).to_array(),
                        specular: specular.to_array(),
                        emission: [0.0; 3],
                    };
                    let want = DVec3::from(kind.composite(pipeline, &lit, alpha, twin.reflectivity(&s), [0.0; 3]));
                    let i = ((y * SIZE + x) * 4) as usize;
                    let got = DVec3::new(r.hdr[i] as f64, r.hdr[i + 1] as f64, r.hdr[i + 2] as f64);
                    let scale = want.max_element().max(radiance.max_element() * 1e-3);
                    worst = worst.max((got - want).abs().max_element() / scale);
                    peak_specular = peak_specular.max(specular.max_element() / full.max_element().max(1e-12));
                    pixels += 1;
                }
            }
            eprintln!(
                "{}/{shader} {}: {pixels} plane pixels, worst relative difference from the twin {worst:.2e} (specular share up to {peak_specular:.2})",
                pipeline.name(),
                kind.name()
            );
            assert!(pixels > SIZE as usize * SIZE as usize / 3, "the plane fills the frame");
            assert!(peak_specular > 0.25, "the sun's highlight is in the frame");
            assert!(worst < 2e-3, "{}/{shader} {}: worst relative difference {worst:e}", pipeline.name(), kind.name());
            images.push((kind, r.hdr));
        }
        // Over black, built-in's Transparent less its Fade is exactly (1 − alpha) × the reflection.
        if pipeline == Pipeline::Builtin {
            let image = |k: SurfaceType| &images.iter().find(|(kind, _)| *kind == k).unwrap().1;
            let (opaque, fade, transparent) =
                (image(SurfaceType::Opaque), image(SurfaceType::Fade), image(SurfaceType::Transparent));
            let s = find_model(pipeline, shader).unwrap().surface(pipeline, &sliders);
            let mut worst = 0.0f64;
            for y in 0..SIZE {
                for x in 0..SIZE {
                    let Some(p) = plane_point(inverse, camera, x, y) else { continue };
                    let v = (camera - p).normalize();
                    let specular = twin.direct(
                        pipeline,
                        &shadematrix::shading::twin::Surface { diffuse_weight: 0.0, ..s },
                        DVec3::Y,
                        v,
                        l,
                    ) * radiance;
                    for c in 0..3 {
                        let i = ((y * SIZE + x) * 4) as usize + c;
                        let difference = (transparent[i] - fade[i]) as f64;
                        let want = (1.0 - alpha) * specular[c];
                        worst = worst.max((difference - want).abs() / (opaque[i] as f64).max(1e-6));
                        // Fade is alpha × the opaque colour, to float error.
                        assert!(
                            ((fade[i] - alpha as f32 * opaque[i]).abs() as f64) <= 1e-5 * opaque[i].abs() as f64 + 1e-7
                        );
                    }
                }
            }
            eprintln!("built-in Transparent − Fade against (1 − alpha) × the twin's reflection: worst {worst:.2e} of the opaque colour");
            assert!(worst < 2e-3, "{worst:e}");
        }
    }
}

/// A quad whose base colour texture's alpha rises from 0 to 1 across u, as a glTF with
/// `alphaMode` MASK at `cutoff`.
fn write_alpha_ramp_gltf(dir: &std::path::Path, cutoff: f64) {
    // Texel x holds alpha (x + 0.5)/256: bilinear sampling makes alpha(u) = u away from the edges.
    image::RgbaImage::from_fn(256, 4, |x, _| image::Rgba([255, 255, 255, x as u8])).save(dir.join("ramp.png")).unwrap();
    let material = format!(
        r#"{{"name": "ramp", "alphaMode": "MASK", "alphaCutoff": {cutoff},
      "pbrMetallicRoughness": {{"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 1, "baseColorTexture": {{"index": 0}}}}}}"#
    );
    crate::common::write_quad_gltf(dir, "quad", &material, &["ramp.png"]);
    let scene = std::fs::read_to_string(fixture("textured_plane.toml"))
        .unwrap()
        .replace("name = \"textured_plane\"", "name = \"ramp\"")
        .replace(
            "mesh = { kind = \"plane\", size = [2.0, 2.0], subdivisions = 1 }",
            "mesh = { kind = \"gltf\", path = \"quad.gltf\" }",
        );
    std::fs::write(dir.join("ramp.toml"), scene).unwrap();
}

/// The share of the frame's pixels the subject covers.
fn coverage(roles: &[u8]) -> f64 {
    roles.iter().filter(|r| **r == ROLE_SUBJECT).count() as f64 / roles.len() as f64
}

#[test]
fn a_cutout_quad_covers_what_its_alpha_leaves_above_the_cutoff() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    write_alpha_ramp_gltf(tmp.path(), 0.3);
    let scene = Scene::load_file(&tmp.path().join("ramp.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [1.0; 3], metallic: 0.0, smoothness: 0.0 };
    let size = 128;
    for (pipeline, shader, path) in [
        (Pipeline::Builtin, "standard", RenderPath::Forward),
        (Pipeline::Urp, "lit", RenderPath::Deferred),
        (Pipeline::Hdrp, "lit", RenderPath::Forward),
    ] {
        let mut cell = cell_params(pipeline, shader, sliders, (1.0, 10.0), size, path);
        cell.settings.material_maps = Some(shadematrix::declarations::presets::OWN.name);
        let whole = coverage(&renderer.render(&prepared, &cell, 1, 0).unwrap().roles);
        for cutoff in [0.25, 0.5, 0.75] {
            cell.settings.surface = SurfaceOptions { kind: SurfaceType::Cutout, alpha: 1.0, cutoff };
            let share = coverage(&renderer.render(&prepared, &cell, 1, 0).unwrap().roles) / whole;
            eprintln!("{}-{} cutoff {cutoff}: covers {share:.4} of the opaque quad", pipeline.name(), path.name());
            // One pixel column of the quad's ~80 is the resolution.
            assert!((share - (1.0 - cutoff)).abs() < 0.02, "cutoff {cutoff}: coverage {share}");
        }
    }
    // A run reads the file's alphaMode and alphaCutoff: the `own` cell is a cutout at 0.3.
    let m = write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"t\"\ncompositions = [\"ramp.toml\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"own\"]\n\
         [sweep]\ntextured = [true]\n[image]\nwidth = 128\nheight = 128\n",
    );
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let cells = tmp.path().join("r/cells");
    let dir = std::fs::read_dir(&cells).unwrap().next().unwrap().unwrap().path();
    let record = std::fs::read_to_string(dir.join("cell.json")).unwrap();
    assert!(record.contains("\"surface\": \"cutout\"") && record.contains("\"alpha_cutoff\": 0.3"), "{record}");
}

#[test]
fn render_faces_cull_as_the_engines_and_hdrp_alone_flips_a_back_faces_normal() {
    let _timer = crate::common::timed!();
    // The textured-plane fixture seen from below, lit from above, with nothing else in the frame.
    let tmp = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(fixture("textured_plane.toml"))
        .unwrap()
        .replace("position = [0.0, 2.6, 0.001]", "position = [0.0, -2.6, 0.001]");
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let sliders = Sliders { base_color_linear: [0.6; 3], metallic: 0.0, smoothness: 0.3 };
    let mut frame = |face: &str, pipeline: Pipeline| {
        let text = base.replace("role = \"subject\"", &format!("role = \"subject\"\nrender_face = \"{face}\""));
        let path = tmp.path().join(format!("{face}.toml"));
        std::fs::write(&path, text).unwrap();
        let scene = Scene::load_file(&path).unwrap();
        let prepared = renderer.prepare_scene(&scene).unwrap();
        let cell = cell_params(pipeline, "lit", sliders, (1.0, 10.0), 32, RenderPath::Forward);
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let centre = ((16 * 32 + 16) * 4) as usize;
        (coverage(&r.roles), r.hdr[centre])
    };
    let (front, _) = frame("front", Pipeline::Urp);
    let (both, urp_lit) = frame("both", Pipeline::Urp);
    let (back, _) = frame("back", Pipeline::Urp);
    let (hdrp_both, hdrp_lit) = frame("both", Pipeline::Hdrp);
    eprintln!("coverage from below: front {front}, back {back}, both {both} (HDRP {hdrp_both}); centre URP {urp_lit}, HDRP {hdrp_lit}");
    assert_eq!(front, 0.0, "a single-sided plane seen from behind is culled");
    assert!(both > 0.3 && back == both && hdrp_both == both);
    // URP shades the back face with the mesh's normal, which faces the light; HDRP flips it away.
    assert!(urp_lit > 0.01, "{urp_lit}");
    assert_eq!(hdrp_lit, 0.0);
}

#[test]
fn the_truth_traces_fade_as_coverage_and_a_clipped_cutout_as_absent() {
    let _timer = crate::common::timed!();
    use shadematrix::render::truth::TruthSettings;
    let scene = Scene::load_file(&fixture("glass_plane.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8, 0.3, 0.2], metallic: 0.0, smoothness: 0.4 };
    let settings = TruthSettings { spp: 256, noise: 0.0, bounces: 0, ..Default::default() };
    let mut truth = |kind: SurfaceType, alpha: f64| {
        let mut cell = cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), 24, RenderPath::Forward);
        cell.settings.surface = SurfaceOptions { kind, alpha, ..Default::default() };
        renderer.render_truth(&prepared, &cell, &settings)
    };
    let sum = |t: &shadematrix::render::truth::Truth| t.mean.iter().map(|p| p[0] as f64).sum::<f64>();
    let opaque = truth(SurfaceType::Opaque, 1.0).unwrap();
    let fade = truth(SurfaceType::Fade, 0.3).unwrap();
    // Over the black background, a screen door of 30 % returns 30 % of the light.
    let ratio = sum(&fade) / sum(&opaque);
    eprintln!("Fade 0.3 against opaque, red summed over the frame: {ratio:.4}");
    assert!((ratio - 0.3).abs() < 0.02, "{ratio}");
    let clipped = truth(SurfaceType::Cutout, 0.4).unwrap();
    assert_eq!(sum(&clipped), 0.0, "a cutout below its cutoff is not there");
    let kept = truth(SurfaceType::Cutout, 0.6).unwrap();
    assert_eq!(sum(&kept), sum(&opaque), "above its cutoff a cutout is the opaque surface, path for path");
    let refused = truth(SurfaceType::Transparent, 0.3).unwrap_err().to_string();
    assert!(refused.contains("no counterpart"), "{refused}");
}

#[test]
fn khr_materials_specular_draws_the_specular_workflow_with_its_dielectric_f0() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    crate::common::write_quad_gltf(
        tmp.path(),
        "spec",
        r#"{"name": "spec", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 0.4},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [2.0, 1.0, 10.0]}}}"#,
        &[],
    );
    let scene = std::fs::read_to_string(fixture("textured_plane.toml"))
        .unwrap()
        .replace("name = \"textured_plane\"", "name = \"spec\"")
        .replace(
            "mesh = { kind = \"plane\", size = [2.0, 2.0], subdivisions = 1 }",
            "mesh = { kind = \"gltf\", path = \"spec.gltf\" }",
        );
    std::fs::write(tmp.path().join("spec.toml"), scene).unwrap();
    let m = write_matrix(
        tmp.path(),
        "m.toml",
        "name = \"t\"\ncompositions = [\"spec.toml\"]\npipelines = [\"builtin\", \"urp\"]\nshaders = [\"standard\", \"lit\", \"lambert\"]\n\
         presets = [\"own\"]\n[image]\nwidth = 16\nheight = 16\n",
    );
    let (rc, out, err) = shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", "r"], &[]);
    assert_eq!(rc, 0, "{out}\n{err}");
    let run = shadematrix::report::run_data::RunData::load(&tmp.path().join("r")).unwrap();
    // min(0.04·(2, 1, 10), 1)·0.5: the dielectric F0 of the extension, the albedo as the file's.
    let want = [0.04, 0.02, 0.2];
    for c in &run.cells {
        let inputs = &c.shader_inputs;
        if c.id.0.contains("lambert") {
            assert!(!inputs.params.contains_key("specular_setup"), "{}", c.id);
            continue;
        }
        assert_eq!(inputs.params.get("specular_setup"), Some(&1.0), "{}", c.id);
        for (got, want) in inputs.specular.iter().zip(want) {
            assert!((got - want).abs() < 1e-12, "{}: {:?}", c.id, inputs.specular);
        }
    }
    assert_eq!(run.cells.len(), 4);
}

#[test]
fn a_flat_cutout_below_its_cutoff_is_left_out_shadow_and_all() {
    let _timer = crate::common::timed!();
    let text = std::fs::read_to_string(crate::common::repo().join("scenes/invariants/key_only.toml")).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let path = tmp.path().join(name);
        std::fs::write(&path, text).unwrap();
        Scene::load_file(&path).unwrap()
    };
    let scene = write("key_only.toml", &text);
    let unshadowed =
        write("no_cast.toml", &text.replace("role = \"subject\"", "role = \"subject\"\ncast_shadows = false"));
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let sliders = Sliders { base_color_linear: [0.6; 3], metallic: 0.0, smoothness: 0.5 };
    let mut frame = |scene: &Scene, kind: SurfaceType, alpha: f64| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        let mut cell = cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), 48, RenderPath::Forward);
        cell.settings.surface = SurfaceOptions { kind, alpha, ..Default::default() };
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        (r.hdr, r.roles)
    };
    let opaque = frame(&scene, SurfaceType::Opaque, 1.0);
    assert_eq!(frame(&scene, SurfaceType::Cutout, 0.6), opaque, "above its cutoff a cutout is the opaque surface");
    let (clipped, roles) = frame(&scene, SurfaceType::Cutout, 0.3);
    assert!(roles.iter().all(|r| *r != ROLE_SUBJECT), "no subject pixel");
    let (no_cast, no_cast_roles) = frame(&unshadowed, SurfaceType::Opaque, 1.0);
    // Where the floor is seen in both frames it is lit as if the sphere cast nothing.
    let mut compared = 0;
    for (i, (r, q)) in roles.iter().zip(&no_cast_roles).enumerate() {
        if *r == shadematrix::plan::roles::ROLE_FIXED && *q == shadematrix::plan::roles::ROLE_FIXED {
            assert_eq!(clipped[4 * i..4 * i + 3], no_cast[4 * i..4 * i + 3], "pixel {i}");
            compared += 1;
        }
    }
    assert!(compared > 500, "{compared}");
}

#[test]
fn a_deferred_path_draws_its_transparent_subject_in_a_pass_of_its_own() {
    let _timer = crate::common::timed!();
    let scene = Scene::load_file(&crate::common::repo().join("scenes/invariants/key_only.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.6; 3], metallic: 0.0, smoothness: 0.5 };
    for kind in [SurfaceType::Opaque, SurfaceType::Transparent] {
        let mut cell = cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), 32, RenderPath::Deferred);
        cell.settings.surface = SurfaceOptions { kind, alpha: 0.5, ..Default::default() };
        let plan = renderer.plan(&prepared, &cell).unwrap();
        let transparent = kind.is_transparent();
        assert_eq!(plan.passes.contains(&shadematrix::plan::Pass::Transparent), transparent, "{:?}", plan.passes);
        assert_eq!(plan.draws.counts.get("transparent").copied().unwrap_or(0), transparent as u32);
        assert_eq!(plan.draws.counts.get("gbuffer").copied(), Some(if transparent { 1 } else { 2 }));
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        if let Some(passes) = &r.gpu_passes {
            let timed = passes.iter().any(|(name, _)| *name == shadematrix::plan::Pass::Transparent);
            assert_eq!(timed, transparent, "{passes:?}");
        }
        assert!(r.roles.contains(&ROLE_SUBJECT), "the subject is drawn");
    }
}

/// A textured cutout casts the shadow of what its alpha keeps: the shadow pass clips by the
/// albedo map's alpha as the engines' ShadowCaster passes do (`_ALPHATEST_ON`: clip(alpha −
/// _Cutoff) in UnityStandardShadow.cginc, URP's ShadowCasterPass Alpha(), HDRP's shadow pass
/// with alpha clipping), so the ramp quad's shadow on the floor shrinks as its cutoff rises.
#[test]
fn a_textured_cutout_casts_the_shadow_of_what_its_alpha_keeps() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    write_alpha_ramp_gltf(tmp.path(), 0.5);
    // The ramp quad 1 m above a floor, a sun at 63° throwing its shadow 2 m aside, seen from above.
    let scene = r#"
name = "ramp_shadow"
[camera]
position = [1.0, 8.0, 0.001]
target = [1.0, 0.0, 0.0]
fov_y_deg = 40.0
[[lights]]
kind = "directional"
direction = [2.0, -1.0, 0.0]
intensity = 1.0
shadows = true
key = true
[[objects]]
name = "quad"
role = "subject"
mesh = { kind = "gltf", path = "quad.gltf" }
transform = { translate = [0.0, 1.0, 0.0] }
[[objects]]
name = "floor"
role = "fixed"
mesh = { kind = "plane", size = [10.0, 10.0], subdivisions = 1 }
material = { base_color_linear = [0.5, 0.5, 0.5] }
[environment]
sky = { kind = "constant", color = [0.0, 0.0, 0.0] }
ambient_intensity = 0.0
background = false
"#;
    std::fs::write(tmp.path().join("ramp_shadow.toml"), scene).unwrap();
    let scene = Scene::load_file(&tmp.path().join("ramp_shadow.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [1.0; 3], metallic: 0.0, smoothness: 0.0 };
    for (pipeline, shader, path) in [
        (Pipeline::Builtin, "standard", RenderPath::Forward),
        (Pipeline::Urp, "lit", RenderPath::Deferred),
        (Pipeline::Hdrp, "lit", RenderPath::Forward),
    ] {
        let mut cell = cell_params(pipeline, shader, sliders, (1.0, 10.0), 96, path);
        cell.settings.material_maps = Some(shadematrix::declarations::presets::OWN.name);
        // Floor pixels darker than half the lit floor's brightest: the shadow.
        let mut shadow = |cell: &shadematrix::render::CellParams| {
            let r = renderer.render(&prepared, cell, 1, 0).unwrap();
            let floor: Vec<f32> =
                r.roles.iter().zip(r.hdr.chunks_exact(4)).filter(|(role, _)| **role == 1).map(|(_, p)| p[1]).collect();
            let lit = floor.iter().cloned().fold(0.0f32, f32::max);
            floor.iter().filter(|g| **g < 0.5 * lit).count() as f64
        };
        let whole = shadow(&cell);
        assert!(whole > 100.0, "{}: the opaque quad's shadow ({whole} pixels)", pipeline.name());
        for cutoff in [0.5, 0.75] {
            cell.settings.surface = SurfaceOptions { kind: SurfaceType::Cutout, alpha: 1.0, cutoff };
            let share = shadow(&cell) / whole;
            eprintln!("{}-{} cutoff {cutoff}: shadow {share:.4} of the opaque quad's", pipeline.name(), path.name());
            assert!((share - (1.0 - cutoff)).abs() < 0.05, "{} cutoff {cutoff}: shadow share {share}", pipeline.name());
        }
    }
}

/// The CPU tracer reads the subject's maps: a textured cutout is there where its alpha map
/// reaches the cutoff (the ramp quad covers 1 − cutoff of itself, as the rasteriser's does), and
/// a textured opaque subject's truth agrees with the GPU tracer's within noise.
#[test]
fn the_cpu_truth_reads_the_subjects_maps_and_their_alpha() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::matrix::TruthBackend;
    use shadematrix::render::truth::TruthSettings;
    let tmp = tempfile::tempdir().unwrap();
    write_alpha_ramp_gltf(tmp.path(), 0.5);
    let ramp = Scene::load_file(&tmp.path().join("ramp.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&ramp).unwrap();
    let sliders = Sliders { base_color_linear: [1.0; 3], metallic: 0.0, smoothness: 0.3 };
    let settings = TruthSettings { spp: 16, noise: 0.0, bounces: 0, ..Default::default() };
    let mut cell = cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), 64, RenderPath::Forward);
    cell.settings.material_maps = Some(shadematrix::declarations::presets::OWN.name);
    let whole = coverage(&renderer.render_truth(&prepared, &cell, &settings).unwrap().roles);
    for cutoff in [0.25, 0.75] {
        cell.settings.surface = SurfaceOptions { kind: SurfaceType::Cutout, alpha: 1.0, cutoff };
        let traced = coverage(&renderer.render_truth(&prepared, &cell, &settings).unwrap().roles) / whole;
        let drawn = coverage(&renderer.render(&prepared, &cell, 1, 0).unwrap().roles) / whole;
        eprintln!("cutoff {cutoff}: the truth covers {traced:.4}, the frame {drawn:.4} of the opaque quad");
        assert!((traced - (1.0 - cutoff)).abs() < 0.03, "cutoff {cutoff}: traced coverage {traced}");
    }
    // Brick's maps on the textured plane: both tracers, the same subject within noise.
    let plane = Scene::load_file(&fixture("textured_plane.toml")).unwrap();
    let prepared = renderer.prepare_scene(&plane).unwrap();
    let sliders = Sliders { base_color_linear: [0.262, 0.095, 0.061], metallic: 0.0, smoothness: 0.6 };
    let mut cell = cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), 32, RenderPath::Forward);
    cell.settings.material_maps = Some("brick");
    let at = |backend, cell: &shadematrix::render::CellParams, renderer: &mut Renderer| {
        crate::common::same_brdf_truth(renderer, &prepared, cell, backend)
    };
    let (cpu, gpu) = (at(TruthBackend::Cpu, &cell, &mut renderer), at(TruthBackend::Gpu, &cell, &mut renderer));
    // A pixel's samples spread over the texture beneath it: its standard error holds the map's
    // variation, so pixels are compared in standard errors.
    let (mut diff, mut var, mut z2, mut n, mut outliers) = (0.0f64, 0.0f64, 0.0f64, 0usize, 0usize);
    for i in 0..cpu.mean.len() {
        if cpu.roles[i] != ROLE_SUBJECT || gpu.roles[i] != ROLE_SUBJECT {
            continue;
        }
        let v = (cpu.std_error[i] as f64).powi(2) + (gpu.std_error[i] as f64).powi(2);
        let d = cpu.mean[i][0] as f64 - gpu.mean[i][0] as f64;
        if v > 0.0 {
            z2 += d * d / v;
            outliers += (d.abs() / v.sqrt() > 4.5) as usize;
        }
        diff += d;
        var += v;
        n += 1;
    }
    let z = if var > 0.0 { diff / var.sqrt() } else { 0.0 };
    let rms = (z2 / n.max(1) as f64).sqrt();
    eprintln!("textured brick: CPU − GPU truth over the subject Z {z:.2}, per-pixel Z RMS {rms:.3} over {n}, |Z| > 4.5: {outliers}");
    assert!(n > 100 && z.abs() < 4.0, "subject means differ by {z:.2} standard errors");
    assert!(rms < 1.5 && outliers * 100 <= n, "per-pixel Z RMS {rms}, {outliers} outliers");
    // And the maps are read: without them the CPU truth is another image.
    cell.settings.material_maps = None;
    let flat = at(TruthBackend::Cpu, &cell, &mut renderer);
    let moved = cpu.mean.iter().zip(&flat.mean).filter(|(a, b)| (a[0] - b[0]).abs() > 0.1 * b[0].abs()).count();
    assert!(moved * 4 > n, "the brick maps change {moved} of {n} subject pixels");
}

/// Built-in's Fade and Transparent cast semitransparent shadows: UnityStandardShadow.cginc's
/// fragShadowCaster dithers by alpha (`_DitherMaskLOD`, slice ⌊15·alpha⌋ of a 4×4 block), taking
/// PreMultiplyAlpha's alpha under Transparent, so the floor under a sphere of alpha 0.35 keeps
/// about 1 − 5/16 of its light. URP's and HDRP's transparent Lit cast opaque shadows.
#[test]
fn builtins_fade_and_transparent_cast_a_shadow_that_lets_their_alpha_through() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let scene = r#"
name = "fade_shadow"
[camera]
position = [0.0, 7.0, 0.001]
target = [0.0, 0.0, 0.0]
fov_y_deg = 40.0
[[lights]]
kind = "directional"
direction = [1.0, -2.0, 0.0]
intensity = 1.0
shadows = true
key = true
[[objects]]
name = "sphere"
role = "subject"
mesh = { kind = "uv_sphere", radius = 0.5, rings = 24, segments = 48 }
transform = { translate = [-0.6, 1.2, 0.0] }
[[objects]]
name = "floor"
role = "fixed"
mesh = { kind = "plane", size = [10.0, 10.0], subdivisions = 1 }
material = { base_color_linear = [0.5, 0.5, 0.5] }
[environment]
sky = { kind = "constant", color = [0.0, 0.0, 0.0] }
ambient_intensity = 0.0
background = false
"#;
    let path = tmp.path().join("fade_shadow.toml");
    std::fs::write(&path, scene).unwrap();
    let no_cast = tmp.path().join("no_cast.toml");
    std::fs::write(&no_cast, scene.replace("role = \"subject\"", "role = \"subject\"\ncast_shadows = false")).unwrap();
    let (scene, no_cast) = (Scene::load_file(&path).unwrap(), Scene::load_file(&no_cast).unwrap());
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let mut frame = |scene: &Scene, pipeline: Pipeline, kind: SurfaceType, metallic: f64| {
        let prepared = renderer.prepare_scene(scene).unwrap();
        let shader = if pipeline == Pipeline::Builtin { "standard" } else { "lit" };
        let sliders = Sliders { base_color_linear: [0.6; 3], metallic, smoothness: 0.5 };
        let mut cell = cell_params(pipeline, shader, sliders, (1.0, 10.0), 96, RenderPath::Forward);
        cell.settings.surface = SurfaceOptions { kind, alpha: 0.35, ..Default::default() };
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        (r.hdr, r.roles)
    };
    // The share of the opaque shadow's darkening a caster leaves lit, over floor pixels in shadow.
    let mut light_through = |pipeline: Pipeline, kind: SurfaceType, metallic: f64| {
        let (shadowed, roles) = frame(&scene, pipeline, SurfaceType::Opaque, metallic);
        let (lit, lit_roles) = frame(&no_cast, pipeline, SurfaceType::Opaque, metallic);
        let (through, through_roles) = frame(&scene, pipeline, kind, metallic);
        let fixed = shadematrix::plan::roles::ROLE_FIXED;
        let (mut sum, mut n) = (0.0, 0);
        for i in 0..roles.len() {
            let (s, l, t) = (shadowed[4 * i + 1] as f64, lit[4 * i + 1] as f64, through[4 * i + 1] as f64);
            if roles[i] == fixed && lit_roles[i] == fixed && through_roles[i] == fixed && l - s > 0.5 * l {
                sum += (t - s) / (l - s);
                n += 1;
            }
        }
        assert!(n > 200, "{} {kind:?}: {n} shadowed floor pixels", pipeline.name());
        sum / n as f64
    };
    // Fade: alpha 0.35 → slice 5 keeps 5 of 16. Transparent at the metallic slider's 0.5, which
    // Standard reads as 0.214 ([Gamma] _Metallic): reflectivity 1 − 0.96·0.786 = 0.245, alpha' =
    // 1 − 0.65·0.755 = 0.510 → slice 7 keeps 7 of 16.
    for (kind, metallic, expected) in
        [(SurfaceType::Fade, 0.0, 1.0 - 5.0 / 16.0), (SurfaceType::Transparent, 0.5, 1.0 - 7.0 / 16.0)]
    {
        let through = light_through(Pipeline::Builtin, kind, metallic);
        eprintln!("built-in {kind:?}: {through:.3} of the light through its shadow (dither {expected:.3})");
        assert!((through - expected).abs() < 0.08, "built-in {kind:?}: {through} against {expected}");
    }
    for pipeline in [Pipeline::Urp, Pipeline::Hdrp] {
        let through = light_through(pipeline, SurfaceType::Transparent, 0.0);
        // (HDRP's SSAO no longer sees the transparent sphere, which moves the floor by a hair.)
        assert!(through.abs() < 0.02, "{}: a transparent Lit casts opaque ({through})", pipeline.name());
    }
}

/// URP resolves an alpha-clipped Lit by alpha-to-coverage under MSAA: Lit.shader's
/// `AlphaToMask[_AlphaToMask]`, on for alpha clipping, and AlphaClip (ShaderVariablesFunctions.hlsl)
/// exporting SharpenAlpha(alpha, cutoff) = sat((alpha − cutoff)/fwidth(alpha) + ½) where the
/// renderer has MSAA (IsAlphaToMaskAvailable). So the cut across the ramp quad is antialiased in
/// URP, as its silhouette is; built-in Standard's alpha test leaves it hard (no AlphaToMask).
#[test]
fn urps_alpha_clipped_lit_is_antialiased_by_alpha_to_coverage_under_msaa() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    write_alpha_ramp_gltf(tmp.path(), 0.45);
    let scene = Scene::load_file(&tmp.path().join("ramp.toml")).unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [1.0; 3], metallic: 0.0, smoothness: 0.0 };
    // Per row, pixels between the black background and the row's lit quad: the antialiased cut
    // (at u = 0.45 it falls inside a pixel column, which 4× MSAA covers in part).
    let mut partial = |pipeline: Pipeline, shader: &str, aa: shadematrix::pipelines::Antialiasing| {
        let mut cell = cell_params(pipeline, shader, sliders, (1.0, 10.0), 128, RenderPath::Forward);
        cell.settings.material_maps = Some(shadematrix::declarations::presets::OWN.name);
        cell.settings.antialiasing = aa;
        cell.settings.surface = SurfaceOptions { kind: SurfaceType::Cutout, alpha: 1.0, cutoff: 0.45 };
        let samples = renderer.plan(&prepared, &cell).unwrap().multisampling.samples;
        assert_eq!(samples, aa.samples(), "the adapter multisamples");
        let r = renderer.render(&prepared, &cell, 1, 0).unwrap();
        let lum: Vec<f64> = r.hdr.chunks_exact(4).map(|p| p[1] as f64).collect();
        lum.chunks_exact(128)
            .map(|row| {
                let lit = row.iter().cloned().fold(0.0, f64::max);
                row.iter().filter(|&&l| l > 0.1 * lit && l < 0.9 * lit).count()
            })
            .sum::<usize>()
    };
    let msaa = shadematrix::pipelines::Antialiasing::Msaa4;
    let (urp, builtin) = (partial(Pipeline::Urp, "lit", msaa), partial(Pipeline::Builtin, "standard", msaa));
    let urp_aliased = partial(Pipeline::Urp, "lit", shadematrix::pipelines::Antialiasing::None);
    eprintln!("partial pixels at 4× MSAA: URP {urp}, built-in {builtin}; URP without MSAA {urp_aliased}");
    // The quad fills the frame; the cut runs its height, 128 pixels.
    assert!(urp >= 100, "URP's cut is antialiased: {urp} partial pixels");
    assert!(builtin < 10 && urp_aliased < 10, "an alpha test's cut is not: {builtin}, {urp_aliased}");
}
