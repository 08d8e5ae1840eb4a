//! The shader registry: every model the matrix can name, the pipelines it exists in, its WGSL
//! source and its f64 twin. Models are keyed by (pipeline, name), so `urp/lit` and `hdrp/lit`
//! can be different models with one name.

use serde::Serialize;

use super::twin::{self, SurfaceTwin};
use crate::pipelines::Pipeline;

/// Which sweep axes change a model's output. Cells that differ only in axes a model does not read
/// are rendered once (DESIGN.md "leave out what a scene does not need").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Reads {
    pub color: bool,
    pub metallic: bool,
    pub smoothness: bool,
    pub light: bool,
}

pub struct ShaderModel {
    pub name: &'static str,
    pub pipelines: &'static [Pipeline],
    /// Path of the WGSL file, relative to the repository (for messages and `shaders` listings).
    pub source_path: &'static str,
    pub wgsl: &'static str,
    pub reads: Reads,
    pub summary: &'static str,
    pub twin: &'static dyn SurfaceTwin,
}

impl std::fmt::Debug for ShaderModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShaderModel").field("name", &self.name).field("pipelines", &self.pipelines).finish()
    }
}

const ALL_AXES: Reads = Reads { color: true, metallic: true, smoothness: true, light: true };

pub static MODELS: [ShaderModel; 2] = [
    ShaderModel {
        name: "lambert",
        pipelines: &[Pipeline::Builtin, Pipeline::Urp, Pipeline::Hdrp],
        source_path: "shaders/brdf/lambert.wgsl",
        wgsl: include_str!("../../shaders/brdf/lambert.wgsl"),
        reads: Reads { color: true, metallic: false, smoothness: false, light: true },
        summary: "Lambert: ρ/π·E·NL (spec §4)",
        twin: &twin::Lambert,
    },
    ShaderModel {
        name: "standard",
        pipelines: &[Pipeline::Builtin],
        source_path: "shaders/brdf/standard.wgsl",
        wgsl: include_str!("../../shaders/brdf/standard.wgsl"),
        reads: ALL_AXES,
        summary: "built-in Standard, BRDF1_Unity_PBS: Disney diffuse, approx. joint Smith, GGX (spec §1)",
        twin: &twin::Standard,
    },
];

pub fn find_model(pipeline: Pipeline, name: &str) -> Option<&'static ShaderModel> {
    MODELS.iter().find(|m| m.name == name && m.pipelines.contains(&pipeline))
}

/// All model names (any pipeline), for "did you mean" suggestions.
pub fn all_model_names() -> Vec<&'static str> {
    let mut names: Vec<&str> = MODELS.iter().map(|m| m.name).collect();
    names.dedup();
    names
}

pub fn model_names_for(pipeline: Pipeline) -> Vec<&'static str> {
    MODELS.iter().filter(|m| m.pipelines.contains(&pipeline)).map(|m| m.name).collect()
}
