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
    /// The f64 twin; `None` for user-supplied WGSL models (GPU-side checks only).
    pub twin: Option<&'static dyn SurfaceTwin>,
    /// The model's own parameters.
    pub params: &'static [ParamSpec],
    /// How the sweep's metallic / smoothness / colour become the model's inputs (for `shaders`).
    pub mapping: &'static str,
    /// That mapping, in code.
    pub from_sliders: fn(&ShaderModel, Pipeline, &Sliders) -> Surface,
    pub expected: Expected,
    /// Gouraud: the lighting sum evaluated per vertex and interpolated.
    pub per_vertex: bool,
    /// Largest relative GPU-f32 vs f64 error allowed on the well-conditioned domain: 1e-4, unless
    /// f32 cannot reach it for a reason stated at the model.
    pub parity_tolerance: f64,
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
pub fn metallic_workflow(model: &ShaderModel, pipeline: Pipeline, s: &Sliders) -> Surface {
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

/// Properties a model is expected to have, for the audit: a model not expected to conserve energy
/// (unnormalised Phong) that does not is a finding, not a failure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Expected {
    /// f(l, v) = f(v, l).
    pub reciprocal: bool,
    /// Directional albedo ≤ 1 for albedo ≤ 1.
    pub energy_conserving: bool,
    /// A BRDF at all (false for colour views such as `fresnel` and for `unlit`).
    pub is_brdf: bool,
}

const PHYSICAL: Expected = Expected { reciprocal: true, energy_conserving: true, is_brdf: true };
/// Symmetric in L and V, but adds a specular lobe to a diffuse term that is not reduced by 1 − F
/// (Unity's constant 0.96, Cook-Torrance's Lambert, the custom shader's unweighted lobes), or
/// approximates (qualitative Oren-Nayar): white surfaces exceed albedo 1 at grazing views.
const RECIPROCAL_ONLY: Expected = Expected { reciprocal: true, energy_conserving: false, is_brdf: true };
/// HDRP: view-only clamps (ClampNdotV, view-reflected normal) and an N·V-dependent energy
/// compensation make it non-reciprocal; diffuse is not reduced by 1 − F either.
const HDRP_LIT: Expected = Expected { reciprocal: false, energy_conserving: false, is_brdf: true };
const NEITHER: Expected = Expected { reciprocal: false, energy_conserving: false, is_brdf: true };
const NOT_A_BRDF: Expected = Expected { reciprocal: false, energy_conserving: false, is_brdf: false };

const ALL_PIPELINES: &[Pipeline] = &[Pipeline::Builtin, Pipeline::Urp, Pipeline::Hdrp];
const BUILTIN: &[Pipeline] = &[Pipeline::Builtin];
const URP: &[Pipeline] = &[Pipeline::Urp];
const HDRP: &[Pipeline] = &[Pipeline::Hdrp];

const COLOR_ONLY: Reads = Reads { color: true, metallic: false, smoothness: false, light: true };
const COLOR_SMOOTHNESS: Reads = Reads { color: true, metallic: false, smoothness: true, light: true };
const UNLIT_READS: Reads = Reads { color: true, metallic: false, smoothness: false, light: false };

const NORMALIZE: ParamSpec = ParamSpec {
    name: "normalize",
    slot: 0,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: "1: energy-normalise the lobe; 0: the textbook form",
};
const SIGMA: ParamSpec = ParamSpec {
    name: "sigma",
    slot: 0,
    default: 0.5,
    min: 0.0,
    max: std::f64::consts::FRAC_PI_2,
    doc: "surface slope deviation σ, radians (from smoothness: σ = 1 − s)",
};
const IOR_15: ParamSpec =
    ParamSpec { name: "ior", slot: 0, default: 1.5, min: 1.0, max: 5.0, doc: "index of refraction" };
const IOR_145: ParamSpec =
    ParamSpec { name: "ior", slot: 0, default: 1.45, min: 1.0, max: 5.0, doc: "index of refraction" };
const FRESNEL_POWER: ParamSpec =
    ParamSpec { name: "fresnel_power", slot: 1, default: 5.0, min: 1.0, max: 8.0, doc: "exponent p of (1 − N·V)^p" };
const ENERGY_COMPENSATION: ParamSpec = ParamSpec {
    name: "energy_compensation",
    slot: 0,
    default: 1.0,
    min: 0.0,
    max: 1.0,
    doc: "1: multiply specular by 1 + F0·(1/y − 1) from the FGD table (HDRP default); 0: off",
};

/// Phong-type models: kd = colour·(1 − metallic), ks = lerp(0.5 grey, colour, metallic),
/// shininess = exp2(10·smoothness + 1) in the shader.
fn classic_specular(model: &ShaderModel, _: Pipeline, s: &Sliders) -> Surface {
    let c = DVec3::from(s.base_color_linear);
    Surface {
        base_color: c * (1.0 - s.metallic),
        metallic: s.metallic,
        smoothness: s.smoothness,
        specular: DVec3::splat(0.5).lerp(c, s.metallic),
        params: model.default_params(),
    }
}

const CLASSIC_SPECULAR: &str =
    "kd = colour·(1 − metallic); ks = lerp(0.5 grey, colour, metallic); shininess n = exp2(10·smoothness + 1)";

/// Oren-Nayar: σ (radians) = 1 − smoothness.
fn oren_nayar_sliders(model: &ShaderModel, _: Pipeline, s: &Sliders) -> Surface {
    let mut params = model.default_params();
    params[SIGMA.slot] = 1.0 - s.smoothness;
    Surface {
        base_color: DVec3::from(s.base_color_linear),
        metallic: 0.0,
        smoothness: s.smoothness,
        specular: DVec3::ZERO,
        params,
    }
}

/// The custom shader's sliders are taken as they are (no gamma decode); the metallic tint is white.
fn custom_shader_sliders(model: &ShaderModel, _: Pipeline, s: &Sliders) -> Surface {
    Surface {
        base_color: DVec3::from(s.base_color_linear),
        metallic: s.metallic,
        smoothness: s.smoothness,
        specular: DVec3::ONE,
        params: model.default_params(),
    }
}

/// URP Simple Lit: _SpecColor is the material default (0.5, 0.5, 0.5) sRGB = 0.214 linear.
fn simple_lit_sliders(model: &ShaderModel, _: Pipeline, s: &Sliders) -> Surface {
    Surface {
        base_color: DVec3::from(s.base_color_linear),
        metallic: 0.0,
        smoothness: s.smoothness,
        specular: DVec3::splat(crate::color::srgb_to_linear(0.5)),
        params: model.default_params(),
    }
}

macro_rules! model {
    ($name:expr, $pipelines:expr, $file:expr, $reads:expr, $expected:expr, $twin:expr, $params:expr, $mapping:expr, $from:expr, $summary:expr) => {
        model!($name, $pipelines, $file, $reads, $expected, $twin, $params, $mapping, $from, $summary, false)
    };
    ($name:expr, $pipelines:expr, $file:expr, $reads:expr, $expected:expr, $twin:expr, $params:expr, $mapping:expr, $from:expr, $summary:expr, $per_vertex:expr) => {
        ShaderModel {
            name: $name,
            pipelines: $pipelines,
            source_path: concat!("shaders/brdf/", $file),
            wgsl: include_str!(concat!("../../shaders/brdf/", $file)),
            reads: $reads,
            summary: $summary,
            twin: Some($twin),
            params: $params,
            mapping: $mapping,
            from_sliders: $from,
            expected: $expected,
            per_vertex: $per_vertex,
            parity_tolerance: 1e-4,
        }
    };
}

const LAMBERT_MAPPING: &str = "colour → albedo ρ; metallic and smoothness unused";
const ON_MAPPING: &str = "colour → albedo ρ; σ = 1 − smoothness (radians); metallic unused";
const CUSTOM_MAPPING: &str =
    "colour → albedo; metallic as is (no gamma decode); roughness r = 1 − smoothness; metallic tint white";

pub static MODELS: [ShaderModel; 21] = [
    model!("lambert", ALL_PIPELINES, "lambert.wgsl", COLOR_ONLY, PHYSICAL, &twin::Lambert, &[], LAMBERT_MAPPING, metallic_workflow,
        "Lambert: ρ/π·E·NL (models.md#lambert)"),
    model!("lambert_vertex", ALL_PIPELINES, "lambert.wgsl", COLOR_ONLY, PHYSICAL, &twin::Lambert, &[], LAMBERT_MAPPING, metallic_workflow,
        "Lambert evaluated per vertex (Gouraud, models.md#gouraud)", true),
    model!("half_lambert", ALL_PIPELINES, "half_lambert.wgsl", COLOR_ONLY, NEITHER, &twin::HalfLambert, &[], LAMBERT_MAPPING,
        metallic_workflow, "Half-Lambert: ρ/π·E·(0.5·NL + 0.5), not squared (models.md#half-lambert)"),
    model!("half_lambert_vertex", ALL_PIPELINES, "half_lambert.wgsl", COLOR_ONLY, NEITHER, &twin::HalfLambert, &[], LAMBERT_MAPPING,
        metallic_workflow, "Half-Lambert per vertex (Gouraud)", true),
    model!("phong", ALL_PIPELINES, "phong.wgsl", ALL_AXES, NEITHER, &twin::Phong, &[NORMALIZE], CLASSIC_SPECULAR, classic_specular,
        "Phong: kd·NL + ks·max(0, R·V)ⁿ, unnormalised by default (models.md#phong)"),
    model!("phong_vertex", ALL_PIPELINES, "phong.wgsl", ALL_AXES, NEITHER, &twin::Phong, &[NORMALIZE], CLASSIC_SPECULAR, classic_specular,
        "Phong per vertex (Gouraud)", true),
    model!("blinn_phong", ALL_PIPELINES, "blinn_phong.wgsl", ALL_AXES, NEITHER, &twin::BlinnPhong, &[NORMALIZE], CLASSIC_SPECULAR,
        classic_specular, "Blinn-Phong: kd·NL + ks·max(0, N·H)ⁿ, unnormalised by default (models.md#blinn-phong)"),
    model!("blinn_phong_vertex", ALL_PIPELINES, "blinn_phong.wgsl", ALL_AXES, NEITHER, &twin::BlinnPhong, &[NORMALIZE],
        CLASSIC_SPECULAR, classic_specular, "Blinn-Phong per vertex (Gouraud)", true),
    // f32 cannot reach 1e-4 with the trigonometric form: near θ → 0, acos(x) turns the rounding of
    // x (~6e-8) into ~6e-8/sinθ of angle, so sin a·tan b carries ~5e-4 relative (measured 4.9e-4 on
    // lavapipe); the trig-free form of the same quantity (`oren_nayar_057`) reaches 2e-7.
    ShaderModel {
        parity_tolerance: 1e-3,
        ..model!("oren_nayar", ALL_PIPELINES, "oren_nayar.wgsl", COLOR_SMOOTHNESS, RECIPROCAL_ONLY, &twin::OrenNayar { trig_form: true },
            &[SIGMA], ON_MAPPING, oren_nayar_sliders, "Oren-Nayar qualitative model, A with 0.33, trigonometric form (models.md#oren-nayar)")
    },
    model!("oren_nayar_057", ALL_PIPELINES, "oren_nayar_057.wgsl", COLOR_SMOOTHNESS, RECIPROCAL_ONLY, &twin::OrenNayar { trig_form: false },
        &[SIGMA], ON_MAPPING, oren_nayar_sliders, "Oren-Nayar trig-free form with 0.57 in A (the custom shader's, models.md#oren-nayar-057)"),
    model!("cook_torrance", ALL_PIPELINES, "cook_torrance.wgsl", ALL_AXES, RECIPROCAL_ONLY, &twin::CookTorrance, &[IOR_15],
        "colour → albedo (diffuse × (1 − metallic)) and metal F0; m = α = (1 − smoothness)²; F: dielectric from IOR, lerped to Schlick(colour) by metallic",
        metallic_as_is, "Cook-Torrance: Beckmann D, full dielectric Fresnel, Cook-Torrance G, 1/(4·NL·NV) (models.md#cook-torrance)"),
    model!("torrance_sparrow", BUILTIN, "torrance_sparrow.wgsl", ALL_AXES, RECIPROCAL_ONLY, &twin::TorranceSparrow,
        &[IOR_145, FRESNEL_POWER], CUSTOM_MAPPING, custom_shader_sliders,
        "custom roughness/metallic PBR shader: GGX D, Smith-Schlick k = r²/2, Schlick Fresnel on N·V (models.md#torrance-sparrow)"),
    model!("fresnel", BUILTIN, "fresnel.wgsl", Reads { color: true, metallic: true, smoothness: false, light: false }, NOT_A_BRDF,
        &twin::FresnelView, &[IOR_145, FRESNEL_POWER], CUSTOM_MAPPING, custom_shader_sliders,
        "the Schlick term F0 + (1 − F0)(1 − N·V)^p shown as colour (models.md#fresnel)"),
    model!("standard", BUILTIN, "standard.wgsl", ALL_AXES, RECIPROCAL_ONLY, &twin::Standard, &[], METALLIC_WORKFLOW, metallic_workflow,
        "built-in Standard, BRDF1: Disney diffuse, approx. joint Smith, GGX, clamps (models.md#standard)"),
    model!("standard_brdf2", BUILTIN, "standard_brdf2.wgsl", ALL_AXES, RECIPROCAL_ONLY, &twin::StandardBrdf2, &[], METALLIC_WORKFLOW,
        metallic_workflow, "built-in Standard, BRDF2: minimalist Cook-Torrance (models.md#standard-brdf2)"),
    model!("standard_brdf3", BUILTIN, "standard_brdf3.wgsl", ALL_AXES, RECIPROCAL_ONLY, &twin::StandardBrdf3, &[], METALLIC_WORKFLOW,
        metallic_workflow, "built-in Standard, BRDF3; its lookup lobe APPROXIMATED by normalised Phong (models.md#standard-brdf3)"),
    model!("lit", URP, "urp_lit.wgsl", ALL_AXES, RECIPROCAL_ONLY, &twin::UrpLit, &[], METALLIC_WORKFLOW, metallic_workflow,
        "URP Lit: minimal Cook-Torrance specular, Lambert without 1/π, EnvironmentBRDF (models.md#urp-lit)"),
    model!("simple_lit", URP, "urp_simple_lit.wgsl", COLOR_SMOOTHNESS, NEITHER, &twin::UrpSimpleLit, &[],
        "colour → albedo; specular colour 0.214 (URP's default _SpecColor 0.5 sRGB); shininess = exp2(10·smoothness + 1); metallic unused",
        simple_lit_sliders, "URP Simple Lit: Blinn-Phong without normalisation (models.md#urp-simple-lit)"),
    model!("unlit", URP, "unlit.wgsl", UNLIT_READS, NOT_A_BRDF, &twin::Unlit, &[], "colour → emitted colour; nothing else",
        metallic_workflow, "URP Unlit: the colour, no lighting"),
    model!("lit", HDRP, "hdrp_lit.wgsl", ALL_AXES, HDRP_LIT, &twin::HdrpLit, &[ENERGY_COMPENSATION], METALLIC_WORKFLOW,
        metallic_workflow, "HDRP Lit: renormalised Disney diffuse, height-correlated Smith GGX, F_Schlick(f90), FGD energy compensation (models.md#hdrp-lit)"),
    model!("unlit", HDRP, "unlit.wgsl", UNLIT_READS, NOT_A_BRDF, &twin::Unlit, &[], "colour → emitted colour; nothing else",
        metallic_workflow, "HDRP Unlit: the colour, no lighting"),
];

/// Metallic taken as the slider gives it in every pipeline (models that are not Unity's).
fn metallic_as_is(model: &ShaderModel, _: Pipeline, s: &Sliders) -> Surface {
    Surface {
        base_color: DVec3::from(s.base_color_linear),
        metallic: s.metallic,
        smoothness: s.smoothness,
        specular: DVec3::ZERO,
        params: model.default_params(),
    }
}

/// User-supplied models, registered at start-up (`shading::user`); they live for the process.
static USER_MODELS: std::sync::RwLock<Vec<&'static ShaderModel>> = std::sync::RwLock::new(Vec::new());

pub fn register_user_model(model: &'static ShaderModel) {
    USER_MODELS.write().unwrap_or_else(|e| e.into_inner()).push(model);
}

/// Built-in models, then user-supplied ones.
pub fn all_models() -> Vec<&'static ShaderModel> {
    let user = USER_MODELS.read().unwrap_or_else(|e| e.into_inner());
    MODELS.iter().chain(user.iter().copied()).collect()
}

pub fn find_model(pipeline: Pipeline, name: &str) -> Option<&'static ShaderModel> {
    all_models().into_iter().find(|m| m.name == name && m.pipelines.contains(&pipeline))
}

/// All model names (any pipeline), for "did you mean" suggestions.
pub fn all_model_names() -> Vec<&'static str> {
    let mut names: Vec<&str> = all_models().iter().map(|m| m.name).collect();
    names.sort();
    names.dedup();
    names
}

pub fn model_names_for(pipeline: Pipeline) -> Vec<&'static str> {
    all_models().iter().filter(|m| m.pipelines.contains(&pipeline)).map(|m| m.name).collect()
}
