//! The path-traced truth (`render::truth`): the white furnace, a convex subject under one
//! directional light against the real-time cell, and the noise's 1/√spp.

use shadematrix::gpu::GpuContext;
use shadematrix::pipelines::{Pipeline, RenderPath};
use shadematrix::render::renderer::Renderer;
use shadematrix::render::truth::{Truth, TruthSettings};
use shadematrix::shading::registry::Sliders;
use shadematrix::spec::scene::Scene;

const SIZE: u32 = 64;

fn white() -> Sliders {
    Sliders { base_color_linear: [1.0, 1.0, 1.0], metallic: 0.0, smoothness: 0.5 }
}

fn scene_from(text: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("truth_scene.toml");
    std::fs::write(&path, text).unwrap();
    Scene::load_file(&path).unwrap()
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
    let tmp = tempfile::tempdir().unwrap();
    let furnace = crate::common::repo().join("scenes/invariants/furnace.toml");
    let body = format!(
        "name = \"t\"\ncompositions = [\"{}\"]\npipelines = [\"urp\", \"hdrp\"]\nshaders = [\"lambert\"]\npresets = [\"plastic\"]\nreference = {{ truth = \"same-brdf\", spp = 32, noise = 0.01, bounces = 1 }}\n[image]\nwidth = 32\nheight = 32\n",
        furnace.display()
    );
    let m = crate::common::write_matrix(tmp.path(), "m.toml", &body);
    let out = tmp.path().join("run");
    let (code, _, err) =
        crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()], &[]);
    assert_eq!(code, 0, "{err}");
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
    // A second run beside the first reuses each truth from the cache: same bytes, marked cached.
    let again = tmp.path().join("again");
    let (code, _, err) =
        crate::common::shadematrix(tmp.path(), &["run", m.to_str().unwrap(), "--out", again.to_str().unwrap()], &[]);
    assert_eq!(code, 0, "{err}");
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
