//! The path-traced truth (`render::truth`): the white furnace, a convex subject under one
//! directional light against the real-time cell, and the noise's 1/√spp.

use shadematrix::declarations::scene::Scene;
use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::renderer::Renderer;
use shadematrix::render::truth::{Truth, TruthSettings};
use shadematrix::shading::registry::Sliders;

const SIZE: u32 = 64;

fn white() -> Sliders {
    Sliders { base_color_linear: [1.0, 1.0, 1.0], metallic: 0.0, smoothness: 0.5 }
}

fn scene_from(text: &str) -> Scene {
    crate::common::scene_from_text("truth_scene", text)
}

/// One directional light on a lone sphere, no environment and a black background.
const DIRECTIONAL: &str = r#"
name = "directional"
[camera]
position = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 40.0
[[lights]]
kind = "directional"
direction = [-0.4, -0.6, -0.7]
intensity = 1.0
key = true
[[objects]]
name = "sphere"
role = "subject"
mesh = { kind = "uv_sphere", radius = 0.8, rings = 96, segments = 192 }
[environment]
sky = { kind = "constant", color = [0.0, 0.0, 0.0] }
ambient_intensity = 0.0
background = false
"#;

fn subject_mean(t: &Truth) -> (f64, f64, usize) {
    let mut sum = 0.0;
    let mut se = 0.0;
    let mut n = 0;
    for (i, m) in t.mean.iter().enumerate() {
        if t.roles[i] == 2 {
            sum += (m[0] + m[1] + m[2]) as f64 / 3.0;
            se += t.std_error[i] as f64;
            n += 1;
        }
    }
    (sum / n as f64, se / n as f64, n)
}

#[test]
fn white_furnace_truth_equals_the_environment_and_the_lambert_cell_matches_it() {
    let _timer = crate::common::timed!();
    let scene = Scene::load("scenes/invariants/furnace.toml", None, "test", "composition").unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let cell = crate::common::cell_params(Pipeline::Urp, "lambert", white(), (1.0, 10.0), SIZE, RenderPath::Forward);
    let settings = TruthSettings { spp: 256, noise: 0.005, ..Default::default() };
    let truth = renderer.render_truth(&prepared, &cell, &settings).unwrap();
    let (mean, se, n) = subject_mean(&truth);
    eprintln!(
        "furnace truth: subject mean {mean:.5} over {n} pixels, mean per-pixel SE {se:.2e}, {} spp, noise {:?}, {:.2} s",
        truth.spp, truth.subject_noise, truth.seconds
    );
    // The mean over n pixels has a standard error near se/√n; allow 4 of them and f32 sums.
    assert!((mean - 1.0).abs() < 4.0 * se / (n as f64).sqrt() + 1e-4, "radiance {mean} vs 1");
    let cell_render = renderer.render(&prepared, &cell, 1, 0).unwrap();
    let mut worst: f64 = 0.0;
    for (i, m) in truth.mean.iter().enumerate() {
        if truth.roles[i] == 2 && cell_render.roles[i] == 2 {
            let rt = cell_render.hdr[4 * i] as f64;
            worst = worst.max((rt - m[0] as f64).abs() / m[0] as f64);
        }
    }
    let rt_mean: f64 =
        (0..truth.mean.len()).filter(|&i| truth.roles[i] == 2).map(|i| cell_render.hdr[4 * i] as f64).sum::<f64>()
            / n as f64;
    eprintln!("furnace URP Lambert cell: subject mean {rt_mean:.5}, worst pixel vs truth {worst:.4}");
    assert!((rt_mean / mean - 1.0).abs() < 0.01, "cell {rt_mean} vs truth {mean}");
}

#[test]
fn a_directional_light_on_a_convex_subject_agrees_with_the_real_time_cell() {
    let _timer = crate::common::timed!();
    let scene = scene_from(DIRECTIONAL);
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let sliders = Sliders { base_color_linear: [0.8, 0.5, 0.3], metallic: 0.0, smoothness: 0.6 };
    let cell = crate::common::cell_params(Pipeline::Urp, "lit", sliders, (1.0, 10.0), SIZE, RenderPath::Forward);
    let settings = TruthSettings { spp: 1024, noise: 0.001, bounces: 0, ..Default::default() };
    let truth = renderer.render_truth(&prepared, &cell, &settings).unwrap();
    let rt = renderer.render(&prepared, &cell, 1, 0).unwrap();
    // Interior: subject pixels whose 8 neighbours are subject pixels in both images.
    let w = SIZE as usize;
    let inside = |i: usize| {
        let (x, y) = ((i % w) as i64, (i / w) as i64);
        (-1..=1).all(|dy| {
            (-1..=1).all(|dx| {
                let (a, b) = (x + dx, y + dy);
                a >= 0 && b >= 0 && a < w as i64 && b < w as i64 && {
                    let j = (b as usize) * w + a as usize;
                    truth.roles[j] == 2 && rt.roles[j] == 2
                }
            })
        })
    };
    let encode = |c: f32| (shadematrix::color::linear_to_srgb((c as f64).clamp(0.0, 1.0)) * 255.0).round() as u8;
    let to_rgba8 = |px: &mut dyn Iterator<Item = [f32; 3]>| -> Vec<u8> {
        px.flat_map(|c| [encode(c[0]), encode(c[1]), encode(c[2]), 255]).collect()
    };
    let truth8 = to_rgba8(&mut truth.mean.iter().copied());
    let rt8 = to_rgba8(&mut rt.hdr.chunks(4).map(|p| [p[0], p[1], p[2]]));
    let flip = shadematrix::compare::flip::ldr(&truth8, &rt8, w, w).unwrap();
    let interior: Vec<usize> = (0..w * w).filter(|&i| inside(i)).collect();
    let mean_flip = interior.iter().map(|&i| flip.map.pixels()[i] as f64).sum::<f64>() / interior.len() as f64;
    eprintln!(
        "directional, URP Lit: interior FLIP {mean_flip:.4} over {} pixels (whole image {:.4}); truth {} spp, noise {:?}",
        interior.len(),
        flip.mean,
        truth.spp,
        truth.subject_noise
    );
    assert!(interior.len() > 1000, "a large interior: {}", interior.len());
    assert!(mean_flip <= 0.01, "interior FLIP {mean_flip}");
}

#[test]
fn doubling_the_samples_lowers_the_standard_error_by_root_two() {
    let _timer = crate::common::timed!();
    let scene = Scene::load("scenes/invariants/key_only.toml", None, "test", "composition").unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    let cell = crate::common::cell_params(Pipeline::Urp, "lit", white(), (2.0, 10.0), 32, RenderPath::Forward);
    let at = |spp: u32, renderer: &mut Renderer| {
        let settings = TruthSettings { spp, noise: 0.0, batch: 16, ..Default::default() };
        let t = renderer.render_truth(&prepared, &cell, &settings).unwrap();
        assert_eq!(t.spp, spp);
        let (_, se, _) = subject_mean(&t);
        se
    };
    let (a, b) = (at(32, &mut renderer), at(64, &mut renderer));
    eprintln!("noise: mean per-pixel SE {a:.4e} at 32 spp, {b:.4e} at 64 spp, ratio {:.3}", a / b);
    assert!((1.25..=1.6).contains(&(a / b)), "ratio {} (√2 = 1.414)", a / b);
}

/// A run against the truth: each cell's folder holds the truth as its reference (EXR, PNG and
/// noise map), its record says what the truth reached, and the metrics compare against it.
#[test]
fn a_run_compares_each_cell_with_its_truth() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let furnace = crate::common::repo().join("scenes/invariants/furnace.toml");
    let body = format!(
        "name = \"t\"\ncompositions = [\"{}\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lambert\"]\npresets = [\"plastic\"]\nreference = {{ truth = \"same-brdf\", spp = 32, noise = 0.01, bounces = 1 }}\n[image]\nwidth = 32\nheight = 32\n",
        furnace.display()
    );
    let out = crate::common::run_matrix(tmp.path(), &body, "run");
    let (_, listed, _) = crate::common::shadematrix(tmp.path(), &["list", "run.toml"], &[]);
    assert!(listed.contains("reference: the cell's path-traced same-brdf truth"), "{listed}");
    let cells: Vec<_> = std::fs::read_dir(out.join("cells")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(cells.len(), 2);
    for dir in cells {
        for f in ["reference.exr", "reference.png", "truth_noise.exr"] {
            assert!(dir.join(f).is_file(), "{} lacks {f}", dir.display());
        }
        let record = shadematrix::record::cell::CellRecord::load(&dir.join("cell.json")).unwrap();
        let truth = record.truth.as_ref().expect("the record says what the truth reached");
        assert!(truth.spp >= 16 && truth.spp <= 32, "{}", truth.spp);
        assert_eq!(truth.bounces, 1);
        match record.metrics.reference.value() {
            Some(shadematrix::record::cell::ReferenceRecord::Truth { truth, spp, .. }) => {
                assert_eq!((truth.as_str(), *spp), ("same-brdf", 32));
            }
            other => panic!("reference {other:?}"),
        }
        let z = record.metrics.ztest.as_ref().and_then(|z| z.value()).expect("a Z-test against the truth's noise");
        assert!((z.z_critical - 2.5758).abs() < 1e-3 && (0.0..=1.0).contains(&z.rejected), "{z:?}");
        eprintln!("{}: Z-test rejects {:.3} of pixels (mean |z| {:.2})", record.id, z.rejected, z.mean_abs_z);
        let flip = record.metrics.ldr_flip().expect("FLIP against the truth");
        // A furnace: the Lambert cell is the environment's radiance, as the truth is.
        assert!(flip < 0.05, "{}: FLIP {flip}", record.id);
        assert!(!truth.cached, "the first run traces");
    }
    // Error against run time is error against the truth, with the Z-test beside FLIP and SSIM.
    let table = std::fs::read_to_string(out.join("tables/error_vs_time.md")).unwrap();
    assert!(table.contains("truth (same-brdf)") && table.contains("Z-test rejects"), "{table}");
    // A second run beside the first reuses each truth from the cache: same bytes, marked cached.
    // (With an empty cell cache of its own, so that it is not handed the first run's cells whole;
    // `--no-cache` would leave the truth cache out too.)
    let empty = tmp.path().join("empty-cell-cache");
    let again = crate::common::run_matrix_with(tmp.path(), &body, "again", &["--cache", empty.to_str().unwrap()]);
    assert!(tmp.path().join(".truth-cache").is_dir(), "the cache sits beside the run folders");
    for entry in std::fs::read_dir(again.join("cells")).unwrap() {
        let dir = entry.unwrap().path();
        let record = shadematrix::record::cell::CellRecord::load(&dir.join("cell.json")).unwrap();
        assert!(record.truth.as_ref().unwrap().cached, "{} traced again", record.id);
        let first = out.join("cells").join(dir.file_name().unwrap());
        for f in ["reference.exr", "truth_noise.exr"] {
            assert_eq!(std::fs::read(first.join(f)).unwrap(), std::fs::read(dir.join(f)).unwrap(), "{f}");
        }
    }
}

/// The physical truth's WGSL model against its f64 twin (`render::truth::physical`).
#[test]
fn gpu_physical_model_matches_its_twin() {
    let _timer = crate::common::timed!();
    use glam::DVec3;
    use shadematrix::render::truth::physical::physical_response;
    let kernel = r#"
@group(0) @binding(0) var<storage, read> inputs: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4<f32>>;
@group(0) @binding(2) var fgd_lut: texture_2d<f32>;
fn fgd_lookup(nv: f32, pr: f32) -> vec3<f32> {
    return fgd_sample(fgd_lut, nv, pr);
}
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (4u * i >= arrayLength(&inputs)) { return; }
    var s: Surface;
    s.base_color = inputs[4u * i + 3u].rgb;
    s.metallic = inputs[4u * i].w;
    s.smoothness = inputs[4u * i + 1u].w;
    outputs[i] = vec4<f32>(physical_response(s, inputs[4u * i].xyz, inputs[4u * i + 1u].xyz, inputs[4u * i + 2u].xyz), 0.0);
}
"#;
    let common = shadematrix::shading::wgsl::common();
    let source = [common.as_str(), kernel, shadematrix::shading::wgsl::TRUTH_PHYSICAL].join("\n");
    let mut inputs: Vec<[f32; 4]> = Vec::new();
    let mut cases = Vec::new();
    let n = DVec3::Z;
    for (k, (metallic, smoothness)) in
        [(0.0, 0.1), (0.0, 0.8), (1.0, 0.3), (1.0, 0.95), (0.5, 0.5)].into_iter().enumerate()
    {
        for i in 0..40 {
            let a = i as f64 * 0.61 + k as f64;
            let v = DVec3::new(a.cos() * 0.6, a.sin() * 0.5, 0.6 + 0.35 * (i as f64 * 0.37).sin()).normalize();
            let l = DVec3::new((a * 1.7).sin() * 0.7, (a * 2.3).cos() * 0.6, 0.3 + 0.6 * (i as f64 * 0.53).cos().abs())
                .normalize();
            let base = DVec3::new(0.9, 0.6, 0.2);
            let f = |d: DVec3, w: f64| [d.x as f32, d.y as f32, d.z as f32, w as f32];
            inputs.extend([f(n, metallic), f(v, smoothness), f(l, 0.0), f(base, 0.0)]);
            cases.push((metallic, smoothness, v, l, base));
        }
    }
    let gpu = GpuContext::new().unwrap();
    let fgd = shadematrix::render::luts::fgd_texture(&gpu);
    let got =
        crate::common::run_kernel(&gpu, &source, &inputs, cases.len(), &[wgpu::BindingResource::TextureView(&fgd)]);
    let mut worst: f64 = 0.0;
    for ((metallic, smoothness, v, l, base), g) in cases.iter().zip(&got) {
        let s = shadematrix::shading::twin::Surface {
            base_color: *base,
            metallic: *metallic,
            smoothness: *smoothness,
            specular: DVec3::ZERO,
            params: [0.0; shadematrix::shading::twin::PARAM_SLOTS],
            diffuse_weight: 1.0,
            tangent: glam::DVec3::ZERO,
        };
        let twin = physical_response(&s, n, *v, *l);
        for c in 0..3 {
            worst = worst.max((g[c] as f64 - twin[c]).abs() / twin[c].abs().max(1e-3));
        }
    }
    eprintln!("physical model GPU vs twin: worst relative |Δ| {worst:.2e} over {} cases", cases.len());
    assert!(worst < 1e-3, "worst {worst}");
}

/// The physical truth through a run: one model and inverse-square light for every cell, recorded
/// as such; in a white furnace the sphere's centre reflects the physical model's directional
/// albedo (its f64 twin's quadrature) for the material the cell's shader received.
#[test]
fn a_physical_truth_in_the_furnace_reflects_the_models_albedo() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let furnace = crate::common::repo().join("scenes/invariants/furnace.toml");
    let body = format!(
        "name = \"p\"\ncompositions = [\"{}\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"silver\"]\nreference = {{ truth = \"physical\", spp = 512, noise = 0.001, bounces = 1 }}\n[sweep]\nsmoothness = [0.4]\n[image]\nwidth = 32\nheight = 32\n",
        furnace.display()
    );
    let out = crate::common::run_matrix(tmp.path(), &body, "run");
    let dir = std::fs::read_dir(out.join("cells")).unwrap().next().unwrap().unwrap().path();
    let record = shadematrix::record::cell::CellRecord::load(&dir.join("cell.json")).unwrap();
    assert_eq!(record.truth.as_ref().unwrap().kind, "physical");
    let (w, _, px) = shadematrix::images::encode::read_exr(&dir.join("reference.exr")).unwrap();
    let (_, _, se) = shadematrix::images::encode::read_exr(&dir.join("truth_noise.exr")).unwrap();
    let i = shadematrix::shading::twin::Surface {
        base_color: glam::DVec3::from(record.shader_inputs.base_color_linear),
        metallic: record.shader_inputs.metallic,
        smoothness: record.shader_inputs.smoothness,
        specular: glam::DVec3::ZERO,
        params: [0.0; shadematrix::shading::twin::PARAM_SLOTS],
        diffuse_weight: 1.0,
        tangent: glam::DVec3::ZERO,
    };
    let albedo = shadematrix::render::truth::physical::directional_albedo(&i, 1.0);
    // Mean over the 4×4 pixels at the centre (NV ≈ 1), against 4 standard errors of that mean.
    let (mut sum, mut var) = (glam::DVec3::ZERO, 0.0);
    for y in 14..18 {
        for x in 14..18 {
            let c = (y * w as usize + x) * 4;
            sum += glam::DVec3::new(px[c] as f64, px[c + 1] as f64, px[c + 2] as f64);
            var += (se[c] as f64).powi(2);
        }
    }
    let (mean, se_mean) = (sum / 16.0, var.sqrt() / 16.0);
    eprintln!("physical furnace: centre {mean:.4} (SE {se_mean:.4}) vs the twin's albedo {albedo:.4}");
    assert!((mean - albedo).abs().max_element() < 4.0 * se_mean + 0.01, "{mean} vs {albedo}");
}

/// The CPU tracer (`render::truth::cpu`) and the GPU's estimate one integral: on every shipped
/// composition, in both truths, their subject means agree within their standard errors and their
/// pixels' differences are as large as the pixels' noise says (a two-sample Z-test).
#[test]
fn the_cpu_and_gpu_truths_agree_within_noise_on_every_composition() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::matrix::TruthBackend;
    use shadematrix::render::truth::TruthKind;
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let sliders = Sliders { base_color_linear: [0.8, 0.5, 0.3], metallic: 0.5, smoothness: 0.7 };
    for (name, pipeline, shader, kind) in [
        ("default", Pipeline::Urp, "lit", TruthKind::SameBrdf),
        ("mitsuba", Pipeline::Builtin, "standard", TruthKind::SameBrdf),
        ("medusa", Pipeline::Hdrp, "lit", TruthKind::Physical),
        ("spikes", Pipeline::Hdrp, "lit", TruthKind::SameBrdf),
    ] {
        let path = format!("scenes/{name}.toml");
        let scene = Scene::load(&path, None, "test", "composition").unwrap();
        let prepared = renderer.prepare_scene(&scene).unwrap();
        let cell = crate::common::cell_params(pipeline, shader, sliders, (1.0, 10.0), 32, RenderPath::Forward);
        let at = |backend, renderer: &mut Renderer| {
            let settings =
                TruthSettings { kind, spp: 96, noise: 0.0, bounces: 1, batch: 32, backend, ..Default::default() };
            renderer.render_truth(&prepared, &cell, &settings).unwrap()
        };
        let (cpu, gpu) = (at(TruthBackend::Cpu, &mut renderer), at(TruthBackend::Gpu, &mut renderer));
        let lum = |c: [f32; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        let (mut diff, mut var, mut n, mut outliers, mut z2) = (0.0, 0.0, 0usize, 0usize, 0.0);
        // A pixel's role is its last sample's first hit: edge pixels may differ between runs.
        let edges = cpu.roles.iter().zip(&gpu.roles).filter(|(a, b)| a != b).count();
        assert!(edges * 10 <= cpu.roles.len(), "{name}: {edges} pixels see another first surface");
        for i in 0..cpu.mean.len() {
            let (a, b) = (lum(cpu.mean[i]), lum(gpu.mean[i]));
            let v = (cpu.std_error[i] as f64).powi(2) + (gpu.std_error[i] as f64).powi(2);
            if v <= 0.0 {
                assert!((a - b).abs() <= 1e-5 * a.abs().max(1.0), "{name} pixel {i}: {a} vs {b} without noise");
                continue;
            }
            let z = (a - b) / v.sqrt();
            z2 += z * z;
            outliers += (z.abs() > 4.5) as usize;
            if cpu.roles[i] == 2 && gpu.roles[i] == 2 {
                diff += a - b;
                var += v;
            }
            n += 1;
        }
        let z_subject = diff / var.sqrt();
        let rms = (z2 / n as f64).sqrt();
        eprintln!(
            "{name} {pipeline:?} {shader} {kind:?}: subject Z {z_subject:.2}, per-pixel Z RMS {rms:.3} over {n}, |Z| > 4.5: {outliers}; CPU {:.2} s, GPU {:.2} s",
            cpu.seconds, gpu.seconds
        );
        assert!(z_subject.abs() < 4.0, "{name}: subject means differ by {z_subject:.2} standard errors");
        // The per-pixel standard error bounds the luminance's from the channels' (render::truth
        // `summarise`), so the RMS may fall below 1 where channels correlate; above, it may not.
        assert!((0.5..1.3).contains(&rms), "{name}: per-pixel Z RMS {rms:.3}");
        assert!(outliers * 200 <= n, "{name}: {outliers} of {n} pixels beyond 4.5 standard errors");
    }
}

fn cell_truths(out: &std::path::Path) -> Vec<(String, shadematrix::record::cell::TruthRecord, Vec<u8>)> {
    let mut cells: Vec<_> = std::fs::read_dir(out.join("cells"))
        .unwrap()
        .map(|e| {
            let dir = e.unwrap().path();
            let record: shadematrix::record::cell::CellRecord =
                serde_json::from_slice(&std::fs::read(dir.join("cell.json")).unwrap()).unwrap();
            let name = dir.file_name().unwrap().to_string_lossy().to_string();
            (name, record.truth.expect("a truth record"), std::fs::read(dir.join("reference.exr")).unwrap())
        })
        .collect();
    cells.sort_by(|a, b| a.0.cmp(&b.0));
    cells
}

/// A physical truth reads no model: the cells of one preset with different shaders share one
/// truth (traced once, the others served it); same-brdf truths, which read the models, do not;
/// a value the truth reads (the light's intensity) makes another truth.
#[test]
fn cells_whose_truths_read_the_same_share_one() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let head = "name = \"share\"\ncompositions = [\"default\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\", \"lit\", \"simple_lit\"]\npresets = [\"plastic\"]\n";
    let image = "[image]\nwidth = 24\nheight = 24\n";
    let physical = format!("{head}reference = {{ truth = \"physical\", spp = 8, noise = 0.0, bounces = 1 }}\n{image}");
    let cells = cell_truths(&crate::common::run_matrix(tmp.path(), &physical, "physical"));
    assert_eq!(cells.len(), 3);
    assert_eq!(cells.iter().filter(|c| !c.1.cached).count(), 1, "one physical truth traced for three shaders");
    assert!(cells.windows(2).all(|w| w[0].2 == w[1].2), "the shared truth is each cell's reference");

    let same = format!("{head}reference = {{ truth = \"same-brdf\", spp = 8, noise = 0.0, bounces = 1 }}\n{image}");
    let cells = cell_truths(&crate::common::run_matrix(tmp.path(), &same, "same"));
    assert!(cells.iter().all(|c| !c.1.cached), "each shader's same-brdf truth is its own");

    let brighter = physical.replace("[image]", "[sweep]\nlight_intensity = [3.0]\n[image]");
    let cells = cell_truths(&crate::common::run_matrix(tmp.path(), &brighter, "brighter"));
    assert_eq!(cells.iter().filter(|c| !c.1.cached).count(), 1, "a brighter light is another truth");
}

/// `[outputs] truth_scene`: each cell's folder holds the scene as its physical truth traces it
/// (what tools/mitsuba_check.py renders); only with a physical truth.
#[test]
fn a_physical_truth_exports_its_scene() {
    let _timer = crate::common::timed!();
    use shadematrix::render::truth::export::{ExportedLight, TruthSceneRecord};
    let tmp = tempfile::tempdir().unwrap();
    let head = "name = \"export\"\ncompositions = [\"mitsuba\"]\npipelines = [\"hdrp\"]\nshaders = [\"lit\"]\npresets = [\"gold\"]\n[image]\nwidth = 16\nheight = 12\n[outputs]\ntruth_scene = true\n";
    let body =
        head.replace("[image]", "reference = { truth = \"physical\", spp = 4, noise = 0.0, bounces = 1 }\n[image]");
    let out = crate::common::run_matrix(tmp.path(), &body, "run");
    let cell = std::fs::read_dir(out.join("cells")).unwrap().next().unwrap().unwrap().path();
    let dir = cell.join("truth_scene");
    let record: TruthSceneRecord = serde_json::from_slice(&std::fs::read(dir.join("scene.json")).unwrap()).unwrap();
    assert_eq!((record.width, record.height, record.bounces), (16, 12, 1));
    assert!((record.camera.fov_y_deg - 38.0).abs() < 1e-3, "{:?}", record.camera);
    // HDRP: the 1.5 axis is 15 000 lm, a point light's candela = lm / 4π (the shader's units).
    let ExportedLight::Point { intensity, .. } = &record.lights[0] else { panic!("{:?}", record.lights) };
    assert!((intensity[0] - 15_000.0 / (4.0 * std::f64::consts::PI)).abs() < 0.05, "{intensity:?}");
    let shell = record.objects.iter().find(|o| o.name == "shell").unwrap();
    assert!(shell.subject && shell.metallic == 1.0 && shell.triangles > 1000);
    assert!(record.objects.iter().any(|o| o.checker.is_some()), "the backdrop's checker");
    for o in &record.objects {
        let ply = std::fs::read(dir.join(&o.mesh)).unwrap();
        assert!(ply.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
    }
    for f in ["truth.exr", "sky.exr", "fgd.exr"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    // A same-brdf truth cannot be exported: bad input, named.
    let same = body.replace("\"physical\"", "\"same-brdf\"");
    let m = crate::common::write_matrix(tmp.path(), "same.toml", &same);
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &["list", m.to_str().unwrap()], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("outputs.truth_scene") && err.contains("physical"), "{err}");
}

/// A renderer with the default composition prepared.
fn default_room() -> (Renderer, shadematrix::render::prepared::PreparedScene) {
    let scene = Scene::load("scenes/default.toml", None, "test", "composition").unwrap();
    let mut renderer = Renderer::new(GpuContext::new().unwrap());
    let prepared = renderer.prepare_scene(&scene).unwrap();
    (renderer, prepared)
}

/// Each bounce is sampled from the cell's own model's lobes: a Lambert same-brdf truth draws its
/// continuations from the cosine alone, so its noise does not grow with a smoothness it ignores
/// (it had 3× the variance at 0.75 when continuations followed a GGX lobe chosen from smoothness).
#[test]
fn a_lambert_truths_noise_does_not_depend_on_smoothness() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::matrix::TruthBackend;
    let (mut renderer, prepared) = default_room();
    for (backend, size, spp) in [(TruthBackend::Cpu, 48, 64), (TruthBackend::Gpu, 24, 32)] {
        let noise = |smoothness: f64, renderer: &mut Renderer| {
            let sliders = Sliders { base_color_linear: [0.5, 0.5, 0.5], metallic: 0.0, smoothness };
            let cell =
                crate::common::cell_params(Pipeline::Urp, "lambert", sliders, (2.0, 10.0), size, RenderPath::Forward);
            let settings = TruthSettings { spp, noise: 0.0, bounces: 2, backend, ..Default::default() };
            let t = renderer.render_truth(&prepared, &cell, &settings).unwrap();
            let (mean, se, _) = subject_mean(&t);
            se / mean
        };
        let (rough, smooth) = (noise(0.0, &mut renderer), noise(0.75, &mut renderer));
        eprintln!("{backend:?}: subject relative noise {rough:.4} at smoothness 0, {smooth:.4} at 0.75");
        assert!((smooth / rough - 1.0).abs() < 0.05, "{backend:?}: {smooth} against {rough}");
    }
}

/// The `sobol` sampler's Owen-scrambled Sobol points reach a lower error than independent samples
/// at the same count (measured against a 1024-sample truth), and its per-sample standard error
/// overstates that error (the noise it reports is conservative).
#[test]
fn sobol_samples_reach_a_lower_error_than_independent_ones() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::matrix::{TruthBackend, TruthKind, TruthSampler};
    let (mut renderer, prepared) = default_room();
    let sliders = Sliders { base_color_linear: [0.284, 0.284, 0.284], metallic: 0.0, smoothness: 0.75 };
    let cell = crate::common::cell_params(Pipeline::Urp, "lit", sliders, (2.0, 10.0), 40, RenderPath::Forward);
    let base = TruthSettings {
        kind: TruthKind::Physical,
        noise: 0.0,
        bounces: 1,
        backend: TruthBackend::Cpu,
        ..Default::default()
    };
    let reference = renderer.render_truth(&prepared, &cell, &TruthSettings { spp: 2048, ..base }).unwrap();
    let lum = |c: &[f32; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
    let mut error = |sampler| {
        let t = renderer.render_truth(&prepared, &cell, &TruthSettings { spp: 16, sampler, ..base }).unwrap();
        let (mut sq, mut se2, mut n) = (0.0, 0.0, 0);
        for i in 0..t.mean.len() {
            if t.roles[i] == 2 {
                sq += (lum(&t.mean[i]) - lum(&reference.mean[i])).powi(2);
                se2 += (t.std_error[i] as f64).powi(2);
                n += 1;
            }
        }
        ((sq / n as f64).sqrt(), (se2 / n as f64).sqrt())
    };
    let (independent, independent_se) = error(TruthSampler::Independent);
    let (sobol, sobol_se) = error(TruthSampler::Sobol);
    eprintln!("16 spp, RMS error over the subject: independent {independent:.5} (its SE {independent_se:.5}), sobol {sobol:.5} (its SE {sobol_se:.5})");
    assert!(sobol < 0.85 * independent, "sobol {sobol} against independent {independent}");
    assert!(sobol_se > sobol, "the reported noise is conservative");
}

/// Russian roulette past the bounce budget (`roulette = true`): one bounce then roulette is
/// every bounce, unbiased — it agrees with a budget of twelve (what is left past twelve is below
/// the noise at these albedos) and differs from a budget of one, on both backends.
#[test]
fn russian_roulette_past_the_budget_counts_every_bounce() {
    let _timer = crate::common::timed!();
    use shadematrix::declarations::matrix::{TruthBackend, TruthKind};
    let (mut renderer, prepared) = default_room();
    let sliders = Sliders { base_color_linear: [0.8, 0.8, 0.8], metallic: 0.0, smoothness: 0.3 };
    for (backend, size, spp) in [(TruthBackend::Cpu, 40, 128), (TruthBackend::Gpu, 24, 64)] {
        let cell = crate::common::cell_params(Pipeline::Urp, "lit", sliders, (2.0, 10.0), size, RenderPath::Forward);
        let mut subject = |bounces: u32, roulette: bool| {
            let settings = TruthSettings {
                kind: TruthKind::Physical,
                spp,
                noise: 0.0,
                bounces,
                backend,
                roulette,
                ..Default::default()
            };
            let t = renderer.render_truth(&prepared, &cell, &settings).unwrap();
            let (mut sum, mut var, mut n) = (0.0, 0.0, 0.0);
            for i in 0..t.mean.len() {
                if t.roles[i] == 2 {
                    sum += t.mean[i].iter().map(|&c| c as f64).sum::<f64>() / 3.0;
                    var += (t.std_error[i] as f64).powi(2);
                    n += 1.0;
                }
            }
            (sum / n, var.sqrt() / n)
        };
        let (one, one_se) = subject(1, false);
        let (twelve, twelve_se) = subject(12, false);
        let (roulette, roulette_se) = subject(1, true);
        let z = |a: f64, sa: f64, b: f64, sb: f64| (a - b) / (sa * sa + sb * sb).sqrt();
        eprintln!(
            "{backend:?}: subject mean, 1 bounce {one:.5} ± {one_se:.5}, 12 bounces {twelve:.5} ± {twelve_se:.5}, 1 + roulette {roulette:.5} ± {roulette_se:.5}"
        );
        assert!(z(roulette, roulette_se, twelve, twelve_se).abs() < 4.0, "{backend:?}: roulette against 12 bounces");
        assert!(z(twelve, twelve_se, one, one_se) > 6.0, "{backend:?}: more bounces must add light here");
    }
}

/// `--no-cache` reads no truth from earlier runs (each run traces its own), yet the cells of one
/// run whose truths read the same still share one.
#[test]
fn no_cache_retraces_truths_and_still_shares_them_within_the_run() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let body = "name = \"nocache\"\ncompositions = [\"default\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\", \"lit\"]\npresets = [\"plastic\"]\nreference = { truth = \"physical\", spp = 4, noise = 0.0, bounces = 1 }\n[image]\nwidth = 16\nheight = 16\n";
    let traced = |out: &str, extra: &[&str]| {
        let run = crate::common::run_matrix_with(tmp.path(), body, out, extra);
        cell_truths(&run).iter().filter(|c| !c.1.cached).count()
    };
    assert_eq!(traced("a", &[]), 1, "two cells, one truth (now in the truth cache)");
    assert_eq!(traced("c", &["--no-cache"]), 1, "--no-cache traces again, once for both cells");
    assert_eq!(traced("d", &["--no-cache"]), 1, "and again: its truths did not outlive it");
}
