//! The shader registry: every model the matrix can name, the pipelines it exists in, its WGSL
//! source and its f64 twin. Models are keyed by (pipeline, name), so `urp/lit` and `hdrp/lit`
//! can be different models with one name.

use serde::Serialize;

use glam::DVec3;

use super::twin::{self, Surface, SurfaceTwin};
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

/// One of a model's own parameters: a named, ranged float in a slot of `Surface::params`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ParamSpec {
    pub name: &'static str,
    pub slot: usize,
    pub default: f64,
    pub min: f64,
    pub max: f64,
    pub doc: &'static str,
}

/// The sweep's values for a cell, in slider units (colour already linear).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sliders {
    pub base_color_linear: [f64; 3],
    pub metallic: f64,
    pub smoothness: f64,
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
    /// The model's own parameters.
    pub params: &'static [ParamSpec],
    /// How the sweep's metallic / smoothness / colour become the model's inputs (for `shaders`).
    pub mapping: &'static str,
    /// That mapping, in code.
    pub from_sliders: fn(&ShaderModel, Pipeline, &Sliders) -> Surface,
}

impl ShaderModel {
    /// The model's inputs for a cell: the mapping applied to the sliders.
    pub fn surface(&self, pipeline: Pipeline, sliders: &Sliders) -> Surface {
        (self.from_sliders)(self, pipeline, sliders)
    }

    /// Parameters at their defaults, by slot.
    pub fn default_params(&self) -> [f64; 8] {
        let mut p = [0.0; 8];
        for spec in self.params {
            p[spec.slot] = spec.default;
        }
        p
    }
}

/// Colour as base colour, the pipeline's metallic conversion, smoothness as is, defaults for the rest.
fn metallic_workflow(model: &ShaderModel, pipeline: Pipeline, s: &Sliders) -> Surface {
    Surface {
        base_color: DVec3::from(s.base_color_linear),
        metallic: pipeline.shader_metallic(s.metallic),
        smoothness: s.smoothness,
        specular: DVec3::ZERO,
        params: model.default_params(),
    }
}

const METALLIC_WORKFLOW: &str =
    "colour → base colour; metallic → the pipeline's conversion (built-in/URP: sRGB-decoded); smoothness as is";

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
        params: &[],
        mapping: "colour → albedo ρ; metallic and smoothness unused",
        from_sliders: metallic_workflow,
    },
    ShaderModel {
        name: "standard",
        pipelines: &[Pipeline::Builtin],
        source_path: "shaders/brdf/standard.wgsl",
        wgsl: include_str!("../../shaders/brdf/standard.wgsl"),
        reads: ALL_AXES,
        summary: "built-in Standard, BRDF1_Unity_PBS: Disney diffuse, approx. joint Smith, GGX (spec §1)",
        twin: &twin::Standard,
        params: &[],
        mapping: METALLIC_WORKFLOW,
        from_sliders: metallic_workflow,
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
