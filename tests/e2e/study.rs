//! The approximation study (run::study, report::approximations): each cell with a truth rendered
//! again with one real-time approximation replaced by the exact term, measured against the truth.

use glam::DVec3;
use shadematrix::environment::irradiance::irradiance_map;
use shadematrix::environment::prefilter::EquirectImage;
use shadematrix::gpu::GpuContext;
use shadematrix::record::cell::CellRecord;

/// A WGSL function of a shader file, by name, as written there.
fn wgsl_function(source: &str, name: &str) -> String {
    let start = source.find(&format!("fn {name}(")).unwrap_or_else(|| panic!("no fn {name}"));
    let end = start + source[start..].find("\n}\n").expect("the function's end") + 3;
    source[start..end].to_string()
}

/// exact.wgsl's `irradiance_lookup` against its f64 twin (`IrradianceMap::lookup`) on the same map.
#[test]
fn gpu_exact_ambient_lookup_matches_its_twin() {
    let _timer = crate::common::timed!();
    let sky = |d: DVec3| {
        let sun = DVec3::new(-0.5, 0.6, 0.62).normalize();
        DVec3::new(2.0, 1.6, 1.0) * d.dot(sun).max(0.0).powi(16) * 20.0
            + if d.y > 0.0 { DVec3::new(0.2, 0.35, 0.7) * (0.3 + d.y) } else { DVec3::splat(0.08) }
    };
    let map = irradiance_map(&EquirectImage::sample(&sky, 256, 128, 2));
    let kernel = r#"
struct RaySceneInfo {
    env_size: vec4<u32>,
};
@group(0) @binding(0) var<storage, read> inputs: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> rays: RaySceneInfo;
@group(0) @binding(3) var<storage, read> irradiance_texels: array<vec4<f32>>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= arrayLength(&inputs)) { return; }
    outputs[id.x] = vec4<f32>(irradiance_lookup(inputs[id.x].xyz), 0.0);
}
"#;
    let source = [
        include_str!("../../shaders/common/math.wgsl").to_string(),
        kernel.to_string(),
        wgsl_function(include_str!("../../shaders/pass/scene.wgsl"), "equirect_uv"),
        wgsl_function(include_str!("../../shaders/pass/exact.wgsl"), "irradiance_lookup"),
    ]
    .join("\n");
    let mut dirs = vec![DVec3::Y, -DVec3::Y, DVec3::X, -DVec3::Z, DVec3::new(0.0, 0.0, 1.0)];
    for i in 0..300 {
        let a = i as f64 * 2.399963;
        let y = 1.0 - 2.0 * (i as f64 + 0.5) / 300.0;
        let r = (1.0 - y * y).sqrt();
        dirs.push(DVec3::new(r * a.cos(), y, r * a.sin()));
    }
    let inputs: Vec<[f32; 4]> = dirs.iter().map(|d| [d.x as f32, d.y as f32, d.z as f32, 0.0]).collect();
    let gpu = GpuContext::new().unwrap();
    use wgpu::util::DeviceExt;
    let storage = |bytes: &[u8]| {
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let info =
        storage(bytemuck::cast_slice(&[map.width as u32, map.height as u32, map.width as u32, map.height as u32]));
    let texels: Vec<[f32; 4]> = map.texels.iter().map(|c| [c.x as f32, c.y as f32, c.z as f32, 0.0]).collect();
    let texels = storage(bytemuck::cast_slice(&texels));
    let got = crate::common::run_kernel(
        &gpu,
        &source,
        &inputs,
        dirs.len(),
        &[info.as_entire_binding(), texels.as_entire_binding()],
    );
    let mut worst: f64 = 0.0;
    for (d, g) in dirs.iter().zip(&got) {
        let twin = map.lookup(*d);
        for c in 0..3 {
            worst = worst.max((g[c] as f64 - twin[c]).abs() / twin[c].abs().max(1e-3));
        }
    }
    eprintln!("exact ambient lookup GPU vs twin: worst relative |Δ| {worst:.2e} over {} directions", dirs.len());
    // f32 atan2 and acos place the lookup: measured 4.2e-4 on lavapipe.
    assert!(worst < 1e-3, "worst {worst}");
}

/// A study run: every approximation either measured against the truth (with its frame, time and
/// errors) or left out with the reason; traced visibility removes the shadow maps' error; the
/// table says what each change costs and buys. The study needs a truth and known names.
#[test]
fn the_study_measures_each_approximation_against_the_truth() {
    let _timer = crate::common::timed!();
    let tmp = tempfile::tempdir().unwrap();
    let head = "name = \"s\"\ncompositions = [\"default\"]\npipelines = [\"urp\", \"hdrp\"]\npaths = [\"forward\", \"deferred\"]\nshaders = [\"lit\"]\npresets = [\"plastic\"]\n";
    let body = format!(
        "{head}reference = {{ truth = \"same-brdf\", spp = 64, noise = 0.01, bounces = 1 }}\napproximations = [\"ambient\", \"environment\", \"visibility\", \"msaa\"]\n[image]\nwidth = 48\nheight = 48\n"
    );
    let out = crate::common::run_matrix(tmp.path(), &body, "run");
    let mut forward = 0;
    for entry in std::fs::read_dir(out.join("cells")).unwrap() {
        let dir = entry.unwrap().path();
        let record = CellRecord::load(&dir.join("cell.json")).unwrap();
        let base = record.metrics.ldr_flip().expect("FLIP against the truth");
        let by = |name: &str| record.approximations.iter().find(|a| a.variant == name);
        if record.path == shadematrix::pipelines::RenderPath::Deferred {
            for name in ["ambient", "environment", "visibility", "msaa"] {
                let a = by(name).unwrap_or_else(|| panic!("{}: no {name}", record.id));
                let why = a.result.why_missing().expect("left out on a deferred path");
                assert!(why.contains("deferred"), "{why}");
            }
            continue;
        }
        forward += 1;
        for name in ["ambient", "environment", "visibility"] {
            let a = by(name).unwrap_or_else(|| panic!("{}: no {name}", record.id));
            let r = a.result.value().unwrap_or_else(|| panic!("{name}: {:?}", a.result));
            assert!(dir.join(&r.image).is_file(), "{}", r.image);
            let flip = *r.flip.value().unwrap();
            eprintln!("{} {name}: FLIP {base:.4} → {flip:.4}, relMSE {:?}", record.id, r.hdr_relative_mse.value());
            assert!(r.hdr_relative_mse.value().is_some() && r.ssim.value().is_some());
            if name == "visibility" {
                // The truth's shadows are hard and ray traced: so is this frame's visibility.
                assert!(flip <= base + 1e-4, "{}: traced visibility FLIP {flip} above {base}", record.id);
                assert_ne!(
                    std::fs::read(dir.join(&r.image)).unwrap(),
                    std::fs::read(dir.join("image.png")).unwrap(),
                    "traced visibility changed nothing"
                );
            }
        }
        // Every other MSAA level: measured, or left out as a level the adapter gives already.
        let levels: Vec<_> = record.approximations.iter().filter(|a| a.approximation == "msaa").collect();
        assert_eq!(levels.len(), 3, "{levels:?}");
        for a in levels {
            if let Some(why) = a.result.why_missing() {
                assert!(why.contains("measured already"), "{why}");
            }
        }
    }
    assert_eq!(forward, 2);
    let table = std::fs::read_to_string(out.join("tables/approximations.md")).unwrap();
    for change in ["exact irradiance", "environment integrated over the BRDF", "ray-traced visibility", "Left out"] {
        assert!(table.contains(change), "{change}: {table}");
    }
    let (_, listed, _) = crate::common::shadematrix(tmp.path(), &["list", "run.toml"], &[]);
    assert!(listed.contains("approximation study: ambient, environment, visibility, msaa"), "{listed}");
    // Without a truth, or with a misspelt name: bad input, named.
    let no_truth =
        crate::common::write_matrix(tmp.path(), "no_truth.toml", &format!("{head}approximations = [\"ambient\"]\n"));
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &["list", no_truth.to_str().unwrap()], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("approximations") && err.contains("truth"), "{err}");
    let typo = crate::common::write_matrix(
        tmp.path(),
        "typo.toml",
        &format!("{head}reference = \"truth\"\napproximations = [\"visibilty\"]\n"),
    );
    let (code, _, err) = crate::common::shadematrix(tmp.path(), &["list", typo.to_str().unwrap()], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("approximations[0]") && err.contains("did you mean `visibility`"), "{err}");
}
