//! Helpers shared by the end-to-end tests.

use std::path::{Path, PathBuf};
use std::process::Command;

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every Rust file under `src/`: its path from the repository's root and its code before any
/// unit-test module (`#[cfg(test)]`), for tests that scan what the crate does.
pub fn crate_code() -> Vec<(String, String)> {
    let mut files = Vec::new();
    let mut stack = vec![repo().join("src")];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p.strip_prefix(repo()).unwrap().to_string_lossy().replace('\\', "/");
                let text = std::fs::read_to_string(&p).unwrap();
                files.push((rel, text.split("#[cfg(test)]").next().unwrap_or("").to_string()));
            }
        }
    }
    files.sort();
    assert!(files.len() > 100, "src/ read as {} Rust files: a scan that reads nothing proves nothing", files.len());
    files
}

pub fn fixture(name: &str) -> PathBuf {
    repo().join("tests/fixtures").join(name)
}

/// Run the binary in `cwd`; returns (exit code, stdout, stderr).
pub fn shadematrix(cwd: &Path, args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_shadematrix"));
    cmd.current_dir(cwd).args(args);
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("run shadematrix");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// A matrix file in `dir` with the given body (compositions may be fixture paths).
pub fn write_matrix(dir: &Path, name: &str, body: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, body).unwrap();
    p
}

/// The built-in models, built once for the tests.
/// A scene from its TOML text, loaded as a file named `name`.toml would be (from a folder that
/// goes away once it is read).
pub fn scene_from_text(name: &str, text: &str) -> shadematrix::declarations::scene::Scene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    shadematrix::declarations::scene::Scene::load_file(&path).unwrap()
}

pub fn models() -> &'static shadematrix::shading::Registry {
    static MODELS: std::sync::OnceLock<shadematrix::shading::Registry> = std::sync::OnceLock::new();
    MODELS.get_or_init(shadematrix::shading::Registry::builtin)
}

pub fn find_model(
    pipeline: shadematrix::pipelines::Pipeline,
    name: &str,
) -> Option<&'static shadematrix::shading::ShaderModel> {
    models().find(pipeline, name).map(|m| &**m)
}

/// A matrix file, its shaders resolved among the built-in models.
pub fn load_matrix(path: &Path) -> shadematrix::declarations::matrix::Matrix {
    let registry = std::sync::Arc::new(shadematrix::shading::Registry::builtin());
    shadematrix::declarations::matrix::Matrix::load(path, registry).unwrap()
}

/// A cell of `shader` in `pipeline` with the sweep values `sliders`, the key light at
/// `intensity`/`range`, a square image, on `path`.
pub fn cell_params(
    pipeline: shadematrix::pipelines::Pipeline,
    shader: &str,
    sliders: shadematrix::shading::registry::Sliders,
    (intensity, range): (f64, f64),
    size: u32,
    path: shadematrix::pipelines::RenderPath,
) -> shadematrix::render::CellParams<'static> {
    let model = find_model(pipeline, shader).unwrap_or_else(|| panic!("no {shader} in {}", pipeline.name()));
    shadematrix::render::CellParams {
        pipeline,
        model,
        surface: model.surface(pipeline, &sliders),
        light_intensity: intensity,
        light_range: range,
        width: size,
        height: size,
        view: Default::default(),
        settings: shadematrix::render::CellSettings { path, ..Default::default() },
    }
}

/// A same-BRDF truth of `cell` with direct light alone (no bounces), 64 samples per pixel, no
/// noise target: what the map tests compare a tracer's reading of the maps with.
pub fn same_brdf_truth(
    renderer: &mut shadematrix::render::Renderer,
    prepared: &shadematrix::render::PreparedScene,
    cell: &shadematrix::render::CellParams,
    backend: shadematrix::declarations::matrix::TruthBackend,
) -> shadematrix::render::truth::Truth {
    let settings = shadematrix::render::truth::TruthSettings {
        kind: shadematrix::render::truth::TruthKind::SameBrdf,
        spp: 64,
        noise: 0.0,
        bounces: 0,
        batch: 32,
        backend,
        ..Default::default()
    };
    renderer.render_truth(prepared, cell, &settings).unwrap()
}

/// How many standard errors apart two truths' sums of red over the pixels where both see the
/// subject are (the CPU tracer against the GPU one).
pub fn subject_z(a: &shadematrix::render::truth::Truth, b: &shadematrix::render::truth::Truth) -> f64 {
    let subject = shadematrix::render::uniforms::ROLE_SUBJECT;
    let (mut diff, mut var) = (0.0f64, 0.0f64);
    for i in (0..a.roles.len()).filter(|&i| a.roles[i] == subject && b.roles[i] == subject) {
        diff += a.mean[i][0] as f64 - b.mean[i][0] as f64;
        var += (a.std_error[i] as f64).powi(2) + (b.std_error[i] as f64).powi(2);
    }
    diff / var.sqrt()
}

/// The mean of `values` over the subject's pixels (`roles`).
pub fn subject_mean(roles: &[u8], values: impl Fn(usize) -> f64) -> f64 {
    let subject = (0..roles.len()).filter(|&i| roles[i] == shadematrix::render::uniforms::ROLE_SUBJECT);
    let (sum, count) = subject.fold((0.0, 0usize), |(s, c), i| (s + values(i), c + 1));
    sum / count as f64
}

/// The worst relative difference, over lit colour channels, between the image of all of `base`'s
/// lights and the sum of the images of one light each (the others at intensity 0); `render(scene,
/// key intensity)` returns a scene's linear RGBA.
pub fn superposition_error(
    base: &shadematrix::declarations::scene::Scene,
    mut render: impl FnMut(&shadematrix::declarations::scene::Scene, f64) -> Vec<f32>,
) -> f64 {
    // HDRP's bloom prefilter weights each tap by 1/(1 + luminance) (Karis): not linear in the
    // light, so the lights' superposition is checked without it.
    let mut base = base.clone();
    base.hdrp.bloom = false;
    let base = &base;
    let key = base.lights[0].intensity;
    let all = render(base, key);
    let mut sum = vec![0.0f64; all.len()];
    for i in 0..base.lights.len() {
        let mut one = base.clone();
        for (j, l) in one.lights.iter_mut().enumerate() {
            if j != i {
                l.intensity = 0.0;
            }
        }
        for (acc, v) in sum.iter_mut().zip(render(&one, if i == 0 { key } else { 0.0 })) {
            *acc += v as f64;
        }
    }
    let mut worst: f64 = 0.0;
    for (k, (a, s)) in all.iter().zip(&sum).enumerate() {
        if k % 4 != 3 && *s > 1e-6 {
            worst = worst.max((*a as f64 - s).abs() / s);
        }
    }
    worst
}

/// A textured glTF plane the test writes: base colour red in the half u < 0.5 and blue beyond,
/// emissive green in the half v < 0.5 (both factors white), with its buffer and PNGs beside it.
pub fn write_textured_gltf(dir: &std::path::Path) -> std::path::PathBuf {
    let png = |name: &str, f: &dyn Fn(u32, u32) -> [u8; 4]| {
        image::RgbaImage::from_fn(8, 8, |x, y| image::Rgba(f(x, y))).save(dir.join(name)).unwrap();
    };
    png("base.png", &|x, _| if x < 4 { [255, 0, 0, 255] } else { [0, 0, 255, 255] });
    png("emissive.png", &|_, y| if y < 4 { [0, 255, 0, 255] } else { [0, 0, 0, 255] });
    write_quad_gltf(
        dir,
        "plane",
        r#"{"name": "test", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 1,
      "baseColorTexture": {"index": 0}}, "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 1}}"#,
        &["base.png", "emissive.png"],
    )
}

/// A 2 m quad at y = 0 facing +y, uv (0, 0)…(1, 1) across x and z, as `<stem>.gltf` and
/// `<stem>.bin` with `material` (a glTF material object) and one texture per image in `images`.
pub fn write_quad_gltf(dir: &std::path::Path, stem: &str, material: &str, images: &[&str]) -> std::path::PathBuf {
    let positions: [[f32; 3]; 4] = [[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]];
    let normals = [[0.0f32, 1.0, 0.0]; 4];
    let uvs: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let indices: [u32; 6] = [0, 3, 2, 0, 2, 1];
    let mut bin = Vec::new();
    bin.extend_from_slice(bytemuck::cast_slice(&positions));
    bin.extend_from_slice(bytemuck::cast_slice(&normals));
    bin.extend_from_slice(bytemuck::cast_slice(&uvs));
    bin.extend_from_slice(bytemuck::cast_slice(&indices));
    std::fs::write(dir.join(format!("{stem}.bin")), &bin).unwrap();
    let textures: Vec<String> = (0..images.len()).map(|i| format!("{{\"source\": {i}}}")).collect();
    let uris: Vec<String> = images.iter().map(|u| format!("{{\"uri\": \"{u}\"}}")).collect();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}}, "indices": 3, "material": 0}}]}}],
  "materials": [{material}],
  "textures": [{textures}], "images": [{uris}],
  "buffers": [{{"uri": "{stem}.bin", "byteLength": {len}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 48}},
      {{"buffer": 0, "byteOffset": 96, "byteLength": 32}}, {{"buffer": 0, "byteOffset": 128, "byteLength": 24}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]}},
      {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}},
      {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}},
      {{"bufferView": 3, "componentType": 5125, "count": 6, "type": "SCALAR"}}]}}"#,
        textures = textures.join(", "),
        uris = uris.join(", "),
        len = bin.len()
    );
    let path = dir.join(format!("{stem}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

/// A run's cells along a parameter that moves only the subject's maps (the height scale, the
/// secondary maps), checked against the cell at `off` of the same pipeline and texturing: a flat
/// subject's is a twin, a textured one's image changes in the subject's pixels (and the edge
/// pixels it shares) only. Returns how many textured cells were compared; `excluded`: a pipeline
/// whose cells must not take the parameter.
pub fn check_map_parameter(
    run: &shadematrix::report::run_data::RunData,
    param: &str,
    (on, off): (f64, f64),
    excluded: Option<shadematrix::pipelines::Pipeline>,
) -> usize {
    let image = |r: &shadematrix::record::cell::CellRecord| {
        shadematrix::images::encode::read_exr(&run.cell_dir(&r.id.0).join("image.exr")).unwrap().2
    };
    let mut checked = 0;
    for r in run.cells.iter().filter(|r| r.coords.params.get(param) == Some(&on)) {
        let base = run
            .cells
            .iter()
            .find(|b| {
                b.coords.params.get(param) == Some(&off)
                    && b.coords.pipeline == r.coords.pipeline
                    && b.coords.textured == r.coords.textured
            })
            .expect("the cell at the parameter's other value");
        if !r.coords.textured {
            assert!(r.twin_of.is_some(), "{}: a flat subject has no maps for {param} to move", r.id);
            continue;
        }
        assert!(r.twin_of.is_none(), "{}", r.id);
        let (a, b) = (image(r), image(base));
        let changed = a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| p != q).count();
        let subject = r.stats.subject_pixels;
        assert!(changed > subject / 4, "{}: {changed} pixels changed of {subject} subject pixels", r.id);
        // The subject's pixels and the anti-aliased edge pixels it shares with what is behind it.
        assert!(changed <= subject * 11 / 10, "{}: only the subject changes ({changed} of {subject})", r.id);
        checked += 1;
    }
    if let Some(excluded) = excluded {
        assert!(
            run.cells.iter().all(|r| r.coords.pipeline != excluded || !r.coords.params.contains_key(param)),
            "{} takes no {param}",
            excluded.name()
        );
    }
    checked
}

/// A kernel over input pairs for `run_kernel`, after the shared WGSL (`shading::wgsl::common`):
/// each output is `expr`, reading the pair's vec4s `a` and `b`.
pub fn pair_kernel(expr: &str) -> String {
    let kernel = format!(
        r#"
@group(0) @binding(0) var<storage, read> inputs: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4<f32>>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    if (id.x >= arrayLength(&inputs) / 2u) {{
        return;
    }}
    let a = inputs[2u * id.x];
    let b = inputs[2u * id.x + 1u];
    outputs[id.x] = {expr};
}}
"#
    );
    [shadematrix::shading::wgsl::common().as_str(), &kernel].join("\n")
}

/// Run `source`'s compute entry `main` (workgroup 64) over `inputs`: binding 0 the inputs, 1 the
/// `outputs` results (vec4 each), then `extra` bindings from 2 on; returns the results.
pub fn run_kernel(
    gpu: &shadematrix::gpu::GpuContext,
    source: &str,
    inputs: &[[f32; 4]],
    outputs: usize,
    extra: &[wgpu::BindingResource],
) -> Vec<[f32; 4]> {
    use wgpu::util::DeviceExt;
    let device = &gpu.device;
    let module = gpu.shader_module("test kernel", source).unwrap();
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(inputs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = (outputs * 16) as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut entries = vec![
        wgpu::BindGroupEntry { binding: 0, resource: input.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 1, resource: output.as_entire_binding() },
    ];
    entries.extend(
        extra.iter().enumerate().map(|(i, r)| wgpu::BindGroupEntry { binding: 2 + i as u32, resource: r.clone() }),
    );
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((outputs as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &read, 0, size);
    gpu.queue.submit([encoder.finish()]);
    let bytes = shadematrix::gpu::readback::map_read(device, &read).unwrap();
    bytemuck::cast_slice(&bytes).to_vec()
}

/// Run the matrix `body` (a matrix file's text) into `<dir>/<out>`; panics on a failed run.
pub fn run_matrix(dir: &Path, body: &str, out: &str) -> PathBuf {
    run_matrix_with(dir, body, out, &[])
}

/// `run_matrix` with more arguments (`--no-cache`, `--shard 1/3`).
pub fn run_matrix_with(dir: &Path, body: &str, out: &str, extra: &[&str]) -> PathBuf {
    let m = write_matrix(dir, &format!("{out}.toml"), body);
    let out = dir.join(out);
    let mut args = vec!["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let (code, _, err) = shadematrix(dir, &args, &[]);
    assert_eq!(code, 0, "{err}");
    out
}

/// The Chromium binary, or None (with a note) where this machine has none; CI must have one.
pub fn chromium() -> Option<String> {
    let found = ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find(|c| std::process::Command::new(c).arg("--version").output().is_ok())
        .map(|c| c.to_string());
    if found.is_none() {
        assert!(std::env::var("CI").is_err(), "CI must have Chromium: .ci/run installs it");
        eprintln!("SKIPPED: no Chromium on this machine (apt-get install chromium); CI runs this test");
    }
    found
}

/// Headless Chromium's flags for the page tests: no GPU, no network chatter, a private profile.
pub fn chromium_flags(profile: &Path) -> Vec<String> {
    [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--no-first-run",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([format!("--user-data-dir={}", profile.display())])
    .collect()
}

/// One end-to-end test's wall time, recorded when the test ends (passed or failed): libtest on
/// stable Rust reports no per-test times. Every ended test of this process rewrites
/// `target/tmp/test-times.tsv` (seconds, outcome, name; slowest first), so after a run it holds
/// them all.
pub struct TestTimer {
    name: &'static str,
    start: std::time::Instant,
}

impl TestTimer {
    pub fn start(function: &'static str) -> TestTimer {
        let name = function.strip_suffix("::here").unwrap_or(function);
        TestTimer { name: name.strip_prefix("main::").unwrap_or(name), start: std::time::Instant::now() }
    }
}

impl Drop for TestTimer {
    fn drop(&mut self) {
        static ENDED: std::sync::Mutex<Vec<(f64, bool, &'static str)>> = std::sync::Mutex::new(Vec::new());
        let mut ended = ENDED.lock().unwrap_or_else(|e| e.into_inner());
        ended.push((self.start.elapsed().as_secs_f64(), !std::thread::panicking(), self.name));
        ended.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.2.cmp(b.2)));
        let mut table = String::from("seconds\toutcome\ttest\n");
        for (seconds, passed, name) in ended.iter() {
            table.push_str(&format!("{seconds:.3}\t{}\t{name}\n", if *passed { "ok" } else { "FAILED" }));
        }
        let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("test-times.tsv");
        let partial = path.with_extension("tsv.partial");
        // Written whole and renamed: a reader never sees half a table.
        if std::fs::write(&partial, table).is_ok() {
            let _ = std::fs::rename(&partial, &path);
        }
    }
}

/// A `TestTimer` named after the test function it starts in.
macro_rules! timed {
    () => {{
        fn here() {}
        crate::common::TestTimer::start(std::any::type_name_of_val(&here))
    }};
}
pub(crate) use timed;
