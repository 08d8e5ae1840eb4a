//! Helpers shared by the end-to-end tests.

use std::path::{Path, PathBuf};
use std::process::Command;

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
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
pub fn load_matrix(path: &Path) -> shadematrix::spec::matrix::Matrix {
    let registry = std::sync::Arc::new(shadematrix::shading::Registry::builtin());
    shadematrix::spec::matrix::Matrix::load(path, registry).unwrap()
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

/// The worst relative difference, over lit colour channels, between the image of all of `base`'s
/// lights and the sum of the images of one light each (the others at intensity 0); `render(scene,
/// key intensity)` returns a scene's linear RGBA.
pub fn superposition_error(
    base: &shadematrix::spec::scene::Scene,
    mut render: impl FnMut(&shadematrix::spec::scene::Scene, f64) -> Vec<f32>,
) -> f64 {
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
