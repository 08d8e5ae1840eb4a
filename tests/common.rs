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
        settings: shadematrix::render::CellSettings { path, light_budget: Default::default() },
    }
}
