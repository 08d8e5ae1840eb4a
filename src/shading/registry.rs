//! The shader registry: every model the matrix can name, the pipelines it exists in, its WGSL
//! source and its f64 twin. Models are keyed by (pipeline, name), so `urp/lit` and `hdrp/lit`
//! can be different models with one name. The built-in models are a table of named fields
//! (`BUILTIN_MODELS`); a `Registry` is a value, built once per command with the user's models and
//! passed to whatever resolves names — no global state.

use serde::Serialize;
use std::borrow::Cow;
use std::sync::Arc;

use glam::DVec3;

use super::params::*;
pub use super::params::{ParamSpec, DETAIL_PARAM, PARALLAX_PARAM, SMOOTHNESS_SOURCE_PARAM};
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

/// The sweep's values for a cell, in slider units (colour already linear).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sliders {
    pub base_color_linear: [f64; 3],
    pub metallic: f64,
    pub smoothness: f64,
}

pub struct ShaderModel {
    pub name: Cow<'static, str>,
    pub pipelines: Vec<Pipeline>,
    /// Path of the WGSL file, relative to the repository or as the user named it (for messages and
    /// `shaders` listings).
    pub source_path: Cow<'static, str>,
    pub wgsl: Cow<'static, str>,
    pub reads: Reads,
    pub summary: Cow<'static, str>,
    /// The f64 twin; `None` for user-supplied WGSL models (GPU-side checks only).
    pub twin: Option<&'static dyn SurfaceTwin>,
    /// The model's own parameters.
    pub params: Vec<ParamSpec>,
    /// How the sweep's metallic / smoothness / colour become the model's inputs (for `shaders`).
    pub mapping: Cow<'static, str>,
    /// That mapping, in code.
    pub from_sliders: fn(&ShaderModel, Pipeline, &Sliders) -> Surface,
    pub expected: Expected,
    /// Gouraud: the lighting sum evaluated per vertex and interpolated.
    pub per_vertex: bool,
    /// Whether the engine shader adds emission (see `emits`).
    pub emits: bool,
    /// The WGSL functions that guard the stiff terms and what they clamp (spec §6).
    pub stiff_terms: Cow<'static, str>,
    /// Which of its engine's passes the model's shader has beyond forward.
    pub passes: EnginePasses,
    /// A built-in ForwardBase-only shader: lit by the main directional light alone.
    pub main_light_only: bool,
    /// The parameter slot without which smoothness is not read (Simple Lit's highlights toggle).
    pub smoothness_gate: Option<usize>,
    /// Largest relative GPU-f32 vs f64 error allowed on the well-conditioned domain: 1e-4, unless
    /// f32 cannot reach it for a reason stated at the model.
    pub parity_tolerance: f64,
}

impl ShaderModel {
    /// Whether the engine's shader has an emission term (Standard in all its BRDF tiers, URP Lit
    /// and Simple Lit, HDRP Lit, the custom roughness/metallic shader's final stage, which adds
    /// its emission as is): the emission axis reaches only these; the classic models, Unlit and
    /// user models have none.
    pub fn emits(&self) -> bool {
        self.emits
    }

    /// Whether a deferred path draws the model into its G-buffer: only where the engine's shader
    /// has a G-buffer pass (`EnginePasses::gbuffer`); everything else is drawn forward after the
    /// deferred lighting, as the engines draw shaders without one.
    pub fn deferrable(&self) -> bool {
        self.passes.gbuffer && !self.per_vertex && !self.main_light_only
    }

    /// Whether the model keeps its diffuse lobe apart, reading `diffuse_weight` (shaders/common/
    /// conventions.wgsl; the twin's `Surface::diffuse_weight`): what the premultiplied surface
    /// types need (`SurfaceType::premultiplies_diffuse`). The engines' lit shaders do; the
    /// classic models, whose engines had no such surface, do not. The WGSL decides, so a user
    /// model that reads it has it too.
    pub fn splits_diffuse(&self) -> bool {
        self.wgsl.contains("diffuse_weight")
    }

    /// Whether the model wraps its lobes in the term functions (`direct_diffuse(…)` and the
    /// rest, shaders/common/conventions.wgsl), so a cell's term layers split its diffuse from its
    /// specular (pipelines::terms). The WGSL decides: a user model that wraps them has them too.
    pub fn splits_lobes(&self) -> bool {
        ["direct_diffuse(", "direct_specular(", "indirect_diffuse(", "indirect_specular(", "emitted("]
            .iter()
            .any(|f| self.wgsl.contains(f))
    }

    /// Whether a cell of this model with surface `s` draws Standard's secondary maps (its `detail`
    /// parameter on; WGSL `model_detail`).
    pub fn draws_detail(&self, s: &Surface) -> bool {
        self.params.iter().any(|p| p.name == DETAIL_PARAM && s.params[p.slot] > 0.5)
    }

    /// Whether a cell of this model with surface `s` reads its smoothness from the albedo map's
    /// alpha (its `smoothness_from_albedo_alpha` parameter on).
    pub fn smoothness_from_albedo_alpha(&self, s: &Surface) -> bool {
        self.params.iter().any(|p| p.name == SMOOTHNESS_SOURCE_PARAM && s.params[p.slot] > 0.5)
    }

    /// Whether the model evaluates rect lights (`model_rect`, shaders/common/area.wgsl): HDRP's Lit
    /// family and Lambert do; a model without one leaves them out (plan::lights::area_left_out).
    pub fn area_lights(&self) -> bool {
        self.wgsl.contains("fn model_rect")
    }

    /// Why a same-BRDF truth cannot trace a surface of this model with these parameters: HDRP Lit's
    /// transmission lights the diffuse lobe from behind through the diffusion profile, light the
    /// tracer's reflection-only surfaces do not pass; its subsurface scattering moves the diffuse
    /// light across the surface, which a BRDF at one point does not.
    pub fn untraceable(&self, params: &[f64; twin::PARAM_SLOTS]) -> Option<String> {
        let on = |name: &str| self.params.iter().any(|p| p.name == name && params[p.slot] > 0.5);
        if on("subsurface_scattering") {
            return Some(
                "the subject scatters beneath its surface (HDRP's Subsurface Scattering type: its diffuse light \
                 blurred across the screen by the diffusion profile, and transmitted from behind), and the truth \
                 traces reflection at the surface alone"
                    .to_string(),
            );
        }
        on("transmission").then(|| {
            "the subject transmits (HDRP's Translucent type: its diffuse lobe lit from behind through the \
             diffusion profile), and the truth traces reflection alone"
                .to_string()
        })
    }

    /// The parameters the model does not read at these values: a parameter whose gate (the
    /// parameter that turns its feature on, `PARAM_GATES`) is 0. Cells that differ only in them
    /// draw the same image (cells::render_key).
    pub fn unread_params(&self, params: &[f64; twin::PARAM_SLOTS]) -> Vec<&str> {
        let slot = |name: &str| self.params.iter().find(|p| p.name == name).map(|p| p.slot);
        PARAM_GATES
            .iter()
            .filter(|(_, gate)| slot(gate).is_some_and(|s| params[s] <= 0.0))
            .map(|(param, _)| *param)
            .collect()
    }

    /// The model's inputs for a cell: the mapping applied to the sliders.
    pub fn surface(&self, pipeline: Pipeline, sliders: &Sliders) -> Surface {
        (self.from_sliders)(self, pipeline, sliders)
    }

    /// The axes a cell with these parameter values reads: `reads`, less smoothness when the
    /// model's smoothness gate is off (Simple Lit without highlights is Lambert).
    pub fn reads_for(&self, params: &[f64; twin::PARAM_SLOTS]) -> Reads {
        let mut r = self.reads;
        if self.smoothness_gate.is_some_and(|slot| params[slot] < 0.5) {
            r.smoothness = false;
        }
        r
    }

    /// Whether a cell with these parameter values reads `Surface::specular` (the `specular` axis):
    /// the lit shaders in their specular workflow (`specular_setup` on), Simple Lit with its
    /// highlights on, and the models that always take one (Phong, Blinn-Phong, the custom shader).
    pub fn reads_specular(&self, params: &[f64; twin::PARAM_SLOTS]) -> bool {
        let gate = |name: &str| self.params.iter().find(|p| p.name == name).map(|p| params[p.slot] >= 0.5);
        gate("specular_setup")
            .or_else(|| gate("specular_highlights"))
            .unwrap_or_else(|| self.wgsl.contains("s.specular"))
    }

    /// Parameters at their defaults, by slot.
    pub fn default_params(&self) -> [f64; twin::PARAM_SLOTS] {
        let mut p = [0.0; twin::PARAM_SLOTS];
        for spec in &self.params {
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
        diffuse_weight: 1.0,
        tangent: DVec3::ZERO,
    }
}

const METALLIC_WORKFLOW: &str =
    "colour → base colour; metallic → the pipeline's conversion (built-in: sRGB-decoded, Standard's [Gamma] _Metallic; URP and HDRP: as is); smoothness as is";

impl std::fmt::Debug for ShaderModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShaderModel").field("name", &self.name).field("pipelines", &self.pipelines).finish()
    }
}

/// Which engine passes a model's shader has besides its forward pass(es).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct EnginePasses {
    /// A G-buffer pass. Built-in: only the Standard shader has a `Deferred` pass
    /// (Internal-DeferredShading.shader lights the G-buffer with the Standard BRDF alone); URP:
    /// Lit and Simple Lit have `UniversalGBuffer` (Lit.shader, SimpleLit.shader; StencilDeferred.shader
    /// lights them with separate Lit and SimpleLit passes chosen by the material-type stencil bits);
    /// HDRP: Lit has `GBuffer` (Lit.shader), Unlit is ForwardOnly. Classic, legacy and user models
    /// have none.
    pub gbuffer: bool,
    /// Built-in: compiled with `#pragma surface … fullforwardshadows` (Standard's ForwardAdd pass
    /// has `multi_compile_fwdadd_fullshadows`): ForwardAdd lights cast shadows. Without it only the
    /// main directional light shadows the object (`multi_compile_fwdadd`, Unity manual "Surface
    /// Shaders: fullforwardshadows").
    pub full_forward_shadows: bool,
    /// Built-in: the shader has no `Vertex` pass, so the legacy vertex-lit path draws its fallback,
    /// Legacy Shaders/VertexLit (Standard.shader ends `FallBack "VertexLit"`; Legacy
    /// Shaders/Diffuse and Specular fall back to it too). The other classic models are drawn with
    /// their own lighting at the vertices, as a shader with a Vertex pass is.
    pub vertex_lit_fallback: bool,
    /// Built-in: a surface shader whose lighting function has a `_Deferred` variant
    /// (Lighting.cginc LightingLambert_Deferred, LightingBlinnPhong_Deferred), so the surface
    /// compiler gives it a Deferred pass writing UnityStandardData, which Internal-DeferredShading
    /// lights with BRDF1 (`plan::draws::legacy_deferred`). Custom lighting functions have none.
    pub legacy_deferred: Option<LegacyLighting>,
}

/// Built-in's Lighting.cginc lighting functions that have a `_Deferred` variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum LegacyLighting {
    /// LightingLambert_Deferred: specularColor 0, smoothness 0.
    Lambert,
    /// LightingBlinnPhong_Deferred: specularColor = _SpecColor·Gloss/π, smoothness = Specular.
    BlinnPhong,
}

impl LegacyLighting {
    /// The value the deferred lighting reads (forward.wgsl `LEGACY_DEFERRED`; 0: none).
    pub fn shader_value(self) -> u32 {
        match self {
            LegacyLighting::Lambert => 1,
            LegacyLighting::BlinnPhong => 2,
        }
    }
}

/// Standard and its BRDF tiers: a G-buffer pass, shadows from every forward light, VertexLit on
/// the vertex-lit path.
const STANDARD_PASSES: EnginePasses =
    EnginePasses { gbuffer: true, full_forward_shadows: true, vertex_lit_fallback: true, legacy_deferred: None };
/// The SRP lit shaders: a G-buffer pass (full forward shadows is a built-in notion).
const GBUFFER_PASS: EnginePasses =
    EnginePasses { gbuffer: true, full_forward_shadows: false, vertex_lit_fallback: false, legacy_deferred: None };
/// Lambert and Blinn-Phong, which built-in's surface shaders light with Lighting.cginc's functions:
/// a Deferred pass of UnityStandardData there, and Legacy Shaders/VertexLit on the vertex-lit path.
const fn legacy_surface_passes(lighting: LegacyLighting) -> EnginePasses {
    EnginePasses {
        gbuffer: false,
        full_forward_shadows: false,
        vertex_lit_fallback: true,
        legacy_deferred: Some(lighting),
    }
}
/// Forward only: the other classic models, Unlit, user models.
pub const FORWARD_PASSES: EnginePasses =
    EnginePasses { gbuffer: false, full_forward_shadows: false, vertex_lit_fallback: false, legacy_deferred: None };

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
/// HDRP: view-only clamps (ClampNdotV, partLambdaV from the unclamped roughness) and an N·V-dependent energy
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

/// A cell's sliders in the specular workflow where the model's `specular_setup` parameter is on:
/// the metallic workflow's look carried over (albedo = colour·(1 − metallic), specular colour =
/// the F0 lerp(0.04, colour, metallic)), metallic 0 as the engines' specular shaders have none.
pub fn apply_workflow(model: &ShaderModel, s: &mut Surface) {
    apply_workflow_with(model, s, DVec3::splat(0.04));
}

/// What the specular workflow is carried over from, kept for the shader to carry it over texel by
/// texel where maps vary the metallic (scene.wgsl `carried_specular`): the metallic workflow's
/// colour and metallic (as the shader receives it) and the dielectric F0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkflowSource {
    pub base_color: DVec3,
    pub metallic: f64,
    pub dielectric: DVec3,
}

/// The surface's `WorkflowSource` where `apply_workflow_with` would carry it over (the model's
/// `specular_setup` on), before it does.
pub fn workflow_source(model: &ShaderModel, s: &Surface, dielectric: DVec3) -> Option<WorkflowSource> {
    let spec = model.params.iter().find(|p| p.name == "specular_setup")?;
    (s.params[spec.slot] >= 0.5).then_some(WorkflowSource {
        base_color: s.base_color,
        metallic: s.metallic,
        dielectric,
    })
}

/// `apply_workflow` with the dielectric F0 `dielectric` in place of 0.04 (a glTF's
/// KHR_materials_specular: min(0.04·specularColorFactor, 1)·specularFactor; its F90 weight,
/// specularFactor, has no counterpart in the engines, whose F90 is 1).
pub fn apply_workflow_with(model: &ShaderModel, s: &mut Surface, dielectric: DVec3) {
    let Some(w) = workflow_source(model, s, dielectric) else { return };
    s.specular = w.dielectric.lerp(w.base_color, w.metallic);
    s.base_color = w.base_color * (1.0 - w.metallic);
    s.metallic = 0.0;
}

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
        diffuse_weight: 1.0,
        tangent: DVec3::ZERO,
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
        diffuse_weight: 1.0,
        tangent: DVec3::ZERO,
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
        diffuse_weight: 1.0,
        tangent: DVec3::ZERO,
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
        diffuse_weight: 1.0,
        tangent: DVec3::ZERO,
    }
}

const LAMBERT_MAPPING: &str = "colour → albedo ρ; metallic and smoothness unused";
const ON_MAPPING: &str = "colour → albedo ρ; σ = 1 − smoothness (radians); metallic unused";
const CUSTOM_MAPPING: &str =
    "colour → albedo; metallic as is (no gamma decode); roughness r = 1 − smoothness; metallic tint white";

/// A WGSL file of `shaders/brdf/`, embedded: its path (for messages) and text.
macro_rules! brdf_file {
    ($file:literal) => {
        WgslSource { path: concat!("shaders/brdf/", $file), text: include_str!(concat!("../../shaders/brdf/", $file)) }
    };
}

/// The built-in models, one entry of named fields each.
static BUILTIN_MODELS: &[BuiltinModel] = &[
    BuiltinModel {
        name: "lambert",
        pipelines: ALL_PIPELINES,
        wgsl: brdf_file!("lambert.wgsl"),
        reads: COLOR_ONLY,
        expected: PHYSICAL,
        twin: &twin::Lambert,
        params: &[],
        mapping: LAMBERT_MAPPING,
        from_sliders: metallic_workflow,
        summary: "Lambert: ρ/π·E·NL (models.md#lambert)",
        gouraud: Some("Lambert evaluated per vertex (Gouraud, models.md#gouraud)"),
        emits: false,
        stiff_terms: "none needed: the model reads no roughness",
        passes: legacy_surface_passes(LegacyLighting::Lambert),
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "half_lambert",
        pipelines: ALL_PIPELINES,
        wgsl: brdf_file!("half_lambert.wgsl"),
        reads: COLOR_ONLY,
        expected: NEITHER,
        twin: &twin::HalfLambert,
        params: &[],
        mapping: LAMBERT_MAPPING,
        from_sliders: metallic_workflow,
        summary: "Half-Lambert: ρ/π·E·(0.5·NL + 0.5), not squared (models.md#half-lambert)",
        gouraud: Some("Half-Lambert per vertex (Gouraud)"),
        emits: false,
        stiff_terms: "none needed: the model reads no roughness",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "phong",
        pipelines: ALL_PIPELINES,
        wgsl: brdf_file!("phong.wgsl"),
        reads: ALL_AXES,
        expected: NEITHER,
        twin: &twin::Phong,
        params: &[NORMALIZE],
        mapping: CLASSIC_SPECULAR,
        from_sliders: classic_specular,
        summary: "Phong: kd·NL + ks·max(0, R·V)ⁿ, unnormalised by default; departs from the reading note by gating the lobe with NL > 0 and scaling the ambient by kd (models.md#phong)",
        gouraud: Some("Phong per vertex (Gouraud)"),
        emits: false,
        stiff_terms: "shininess_from_smoothness (n = 2..2048)",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "blinn_phong",
        pipelines: ALL_PIPELINES,
        wgsl: brdf_file!("blinn_phong.wgsl"),
        reads: ALL_AXES,
        expected: NEITHER,
        twin: &twin::BlinnPhong,
        params: &[NORMALIZE],
        mapping: CLASSIC_SPECULAR,
        from_sliders: classic_specular,
        summary: "Blinn-Phong: kd·NL + ks·max(0, N·H)ⁿ, unnormalised by default; the NL > 0 gate and ambient × kd as Phong's (models.md#blinn-phong)",
        gouraud: Some("Blinn-Phong per vertex (Gouraud)"),
        emits: false,
        stiff_terms: "shininess_from_smoothness (n = 2..2048)",
        passes: legacy_surface_passes(LegacyLighting::BlinnPhong),
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    // f32 cannot reach 1e-4 with the trigonometric form: near θ → 0, acos(x) turns the rounding of
    // x (~6e-8) into ~6e-8/sinθ of angle, so sin a·tan b carries ~5e-4 relative (measured 4.9e-4 on
    // lavapipe); the trig-free form of the same quantity (`oren_nayar_057`) reaches 2e-7.
    BuiltinModel {
        name: "oren_nayar",
        pipelines: ALL_PIPELINES,
        wgsl: brdf_file!("oren_nayar.wgsl"),
        reads: COLOR_SMOOTHNESS,
        expected: RECIPROCAL_ONLY,
        twin: &twin::OrenNayar { trig_form: true },
        params: &[SIGMA],
        mapping: ON_MAPPING,
        from_sliders: oren_nayar_sliders,
        summary: "Oren-Nayar qualitative model, A with 0.33, trigonometric form (models.md#oren-nayar)",
        gouraud: None,
        emits: false,
        stiff_terms: "model_direct: tan β over max(cos β, 1e-4)",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-3,
    },
    BuiltinModel {
        name: "oren_nayar_057",
        pipelines: ALL_PIPELINES,
        wgsl: brdf_file!("oren_nayar_057.wgsl"),
        reads: COLOR_SMOOTHNESS,
        expected: RECIPROCAL_ONLY,
        twin: &twin::OrenNayar { trig_form: false },
        params: &[SIGMA],
        mapping: ON_MAPPING,
        from_sliders: oren_nayar_sliders,
        summary: "Oren-Nayar trig-free form with 0.57 in A (the custom shader's, models.md#oren-nayar-057)",
        gouraud: None,
        emits: false,
        stiff_terms: "model_direct: max(max(NL, NV), 1e-4)",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "cook_torrance",
        pipelines: ALL_PIPELINES,
        wgsl: brdf_file!("cook_torrance.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::CookTorrance,
        params: &[IOR_15],
        mapping: "colour → albedo (diffuse × (1 − metallic)) and metal F0; m = α = (1 − smoothness)²; F: dielectric from IOR, lerped to Schlick(colour) by metallic",
        from_sliders: metallic_as_is,
        summary: "Cook-Torrance: Beckmann D, full dielectric Fresnel, Cook-Torrance G, 1/(4·NL·NV) (models.md#cook-torrance)",
        gouraud: None,
        emits: false,
        stiff_terms: "d_beckmann (NH² ≥ ε, m ≥ 1e-3), g_cook_torrance (VH ≥ ε)",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "cook_torrance_1982",
        pipelines: ALL_PIPELINES,
        wgsl: brdf_file!("cook_torrance_1982.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::CookTorrance1982,
        params: &[IOR_15],
        mapping: "as cook_torrance",
        from_sliders: metallic_as_is,
        summary: "Cook-Torrance as the 1982 paper writes it: (F/π)·D·G/(NL·NV), un-normalised Beckmann D; specular 4× the modern form (models.md#cook-torrance-1982)",
        gouraud: None,
        emits: false,
        stiff_terms: "d_beckmann_unnormalised (NH² ≥ ε, m ≥ 1e-3), g_cook_torrance (VH ≥ ε)",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "torrance_sparrow",
        pipelines: BUILTIN,
        wgsl: brdf_file!("torrance_sparrow.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::TorranceSparrow { as_written: true },
        params: &[IOR_145, FRESNEL_POWER],
        mapping: CUSTOM_MAPPING,
        from_sliders: custom_shader_sliders,
        summary: "custom roughness/metallic PBR shader AS WRITTEN: scalar Fresnel (red channel), reflect(v, n), ambient × light colour, main directional light only (models.md#torrance-sparrow)",
        gouraud: None,
        emits: true,
        stiff_terms: "ts_direct (d_ggx, v_smith_schlick: no floor on α)",
        passes: FORWARD_PASSES,
        main_light_only: true,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "torrance_sparrow_corrected",
        pipelines: BUILTIN,
        wgsl: brdf_file!("torrance_sparrow_corrected.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::TorranceSparrow { as_written: false },
        params: &[IOR_145, FRESNEL_POWER],
        mapping: CUSTOM_MAPPING,
        from_sliders: custom_shader_sliders,
        summary: "the custom shader corrected: colour Fresnel, reflect(−v, n), ambient alone, every light (models.md#torrance-sparrow-corrected)",
        gouraud: None,
        emits: true,
        stiff_terms: "ts_direct (d_ggx, v_smith_schlick: no floor on α)",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "fresnel",
        pipelines: BUILTIN,
        wgsl: brdf_file!("fresnel.wgsl"),
        reads: Reads { color: true, metallic: true, smoothness: false, light: false },
        expected: NOT_A_BRDF,
        twin: &twin::FresnelView,
        params: &[IOR_145, FRESNEL_POWER],
        mapping: CUSTOM_MAPPING,
        from_sliders: custom_shader_sliders,
        summary: "the Schlick term F0 + (1 − F0)(1 − N·V)^p shown as colour (models.md#fresnel)",
        gouraud: None,
        emits: false,
        stiff_terms: "none needed: the model reads no roughness",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "standard",
        pipelines: BUILTIN,
        wgsl: brdf_file!("standard.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::Standard,
        params: &[SPECULAR_SETUP, SPECULAR_HIGHLIGHTS_TOGGLE, PARALLAX, DETAIL, SMOOTHNESS_FROM_ALBEDO_ALPHA],
        mapping: METALLIC_WORKFLOW,
        from_sliders: metallic_workflow,
        summary: "built-in Standard, BRDF1: Disney diffuse, approx. joint Smith, GGX, clamps (models.md#standard)",
        gouraud: None,
        emits: true,
        stiff_terms: "roughness_clamped (α ≥ 0.002); v_smith_joint_approx (+1e-5)",
        passes: STANDARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "standard_brdf2",
        pipelines: BUILTIN,
        wgsl: brdf_file!("standard_brdf2.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::StandardBrdf2,
        params: &[],
        mapping: METALLIC_WORKFLOW,
        from_sliders: metallic_workflow,
        summary: "built-in Standard, BRDF2: minimalist Cook-Torrance (models.md#standard-brdf2)",
        gouraud: None,
        emits: true,
        stiff_terms: "spec_brdf2 (d = NH²(α² − 1) + 1.00001, max(0.1, LH²))",
        passes: STANDARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "standard_brdf3",
        pipelines: BUILTIN,
        wgsl: brdf_file!("standard_brdf3.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::StandardBrdf3,
        params: &[],
        mapping: METALLIC_WORKFLOW,
        from_sliders: metallic_workflow,
        summary: "built-in Standard, BRDF3; its lookup lobe APPROXIMATED by normalised Phong (models.md#standard-brdf3)",
        gouraud: None,
        emits: true,
        stiff_terms: "spec_brdf3 (n ≥ 1e-4, LUT range cap)",
        passes: STANDARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "lit",
        pipelines: URP,
        wgsl: brdf_file!("urp_lit.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::UrpLit,
        params: &[
            SPECULAR_SETUP,
            SPECULAR_HIGHLIGHTS_TOGGLE,
            ENVIRONMENT_REFLECTIONS_OFF,
            PARALLAX,
            DETAIL,
            SMOOTHNESS_FROM_ALBEDO_ALPHA,
        ],
        mapping: METALLIC_WORKFLOW,
        from_sliders: metallic_workflow,
        summary: "URP Lit: minimal Cook-Torrance specular, Lambert without 1/π, EnvironmentBRDF (models.md#urp-lit)",
        gouraud: None,
        emits: true,
        stiff_terms: "urp_brdf_data (α ≥ 2⁻⁷, α² ≥ 2⁻¹⁴), spec_urp (+1.00001, max(0.1, LH²))",
        passes: GBUFFER_PASS,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "srp_lit",
        pipelines: URP,
        wgsl: brdf_file!("srp_lit.wgsl"),
        reads: ALL_AXES,
        expected: RECIPROCAL_ONLY,
        twin: &twin::SrpLit,
        params: &[FRESNEL_STRENGTH],
        mapping: METALLIC_WORKFLOW,
        from_sliders: metallic_workflow,
        summary: "the custom SRP tutorial's Lit: URP's minimal Cook-Torrance without roughness floors, reflections with a Fresnel slider (shading.md §4d)",
        gouraud: None,
        emits: true,
        stiff_terms: "specular_strength (d = NH²(r² − 1) + 1.00001, max(0.1, LH²); no floor on r, as the tutorial)",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "simple_lit",
        pipelines: URP,
        wgsl: brdf_file!("urp_simple_lit.wgsl"),
        reads: COLOR_SMOOTHNESS,
        expected: NEITHER,
        twin: &twin::UrpSimpleLit,
        params: &[SPECULAR_HIGHLIGHTS],
        mapping: "colour → albedo; specular colour 0.214 (URP's default _SpecColor 0.5 sRGB); shininess = exp2(10·smoothness + 1); metallic unused; highlights off unless specular_highlights = 1",
        from_sliders: simple_lit_sliders,
        summary: "URP Simple Lit: Lambert, plus unnormalised Blinn-Phong when specular_highlights = 1 (off in a new material) (models.md#urp-simple-lit)",
        gouraud: None,
        emits: true,
        stiff_terms: "shininess_from_smoothness (n = 2..2048)",
        passes: GBUFFER_PASS,
        main_light_only: false,
        smoothness_gate: Some(SPECULAR_HIGHLIGHTS.slot),
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "unlit",
        pipelines: URP,
        wgsl: brdf_file!("unlit.wgsl"),
        reads: UNLIT_READS,
        expected: NOT_A_BRDF,
        twin: &twin::Unlit,
        params: &[],
        mapping: "colour → emitted colour; nothing else",
        from_sliders: metallic_workflow,
        summary: "URP Unlit: the colour, no lighting",
        gouraud: None,
        emits: false,
        stiff_terms: "none needed: the model reads no roughness",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "lit",
        pipelines: HDRP,
        wgsl: brdf_file!("hdrp_lit.wgsl"),
        reads: ALL_AXES,
        expected: HDRP_LIT,
        twin: &twin::HdrpLit,
        params: &[
            ENERGY_COMPENSATION,
            SPECULAR_SETUP_HDRP,
            COAT_MASK,
            IRIDESCENCE_MASK,
            IRIDESCENCE_THICKNESS,
            ANISOTROPY,
            TRANSMISSION,
            THICKNESS,
            SUBSURFACE_SCATTERING,
            SUBSURFACE_MASK,
            DETAIL_HDRP,
        ],
        mapping: METALLIC_WORKFLOW,
        from_sliders: metallic_workflow,
        summary: "HDRP Lit: renormalised Disney diffuse, height-correlated Smith GGX, F_Schlick(f90), FGD energy compensation (models.md#hdrp-lit)",
        gouraud: None,
        emits: true,
        stiff_terms: "dv_smith_joint_ggx (max(…, REAL_MIN)), clamp_n_dot_v (NV ≥ 1e-4), light_min_roughness (per light)",
        passes: GBUFFER_PASS,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
    BuiltinModel {
        name: "unlit",
        pipelines: HDRP,
        wgsl: brdf_file!("unlit.wgsl"),
        reads: UNLIT_READS,
        expected: NOT_A_BRDF,
        twin: &twin::Unlit,
        params: &[],
        mapping: "colour → emitted colour; nothing else",
        from_sliders: metallic_workflow,
        summary: "HDRP Unlit: the colour, no lighting",
        gouraud: None,
        emits: false,
        stiff_terms: "none needed: the model reads no roughness",
        passes: FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: 1e-4,
    },
];

/// Metallic taken as the slider gives it in every pipeline (models that are not Unity's).
fn metallic_as_is(model: &ShaderModel, _: Pipeline, s: &Sliders) -> Surface {
    Surface {
        base_color: DVec3::from(s.base_color_linear),
        metallic: s.metallic,
        smoothness: s.smoothness,
        specular: DVec3::ZERO,
        params: model.default_params(),
        diffuse_weight: 1.0,
        tangent: DVec3::ZERO,
    }
}

/// An embedded WGSL file.
pub struct WgslSource {
    pub path: &'static str,
    pub text: &'static str,
}

/// A row of the built-in model table: every field named.
pub struct BuiltinModel {
    pub name: &'static str,
    pub pipelines: &'static [Pipeline],
    pub wgsl: WgslSource,
    pub reads: Reads,
    pub expected: Expected,
    pub twin: &'static dyn SurfaceTwin,
    pub params: &'static [ParamSpec],
    pub mapping: &'static str,
    pub from_sliders: fn(&ShaderModel, Pipeline, &Sliders) -> Surface,
    pub summary: &'static str,
    /// The summary of the model's per-vertex (Gouraud) variant `NAME_vertex`, derived from this
    /// row (same WGSL, twin and mapping, evaluated at the vertices), when it has one.
    pub gouraud: Option<&'static str>,
    /// Whether the engine shader adds emission (`_EmissionColor`): the emission axis reaches it.
    pub emits: bool,
    /// The WGSL functions that guard the model's stiff terms and what they clamp (spec §6), as the
    /// conditioning and stability tables name them.
    pub stiff_terms: &'static str,
    pub passes: EnginePasses,
    pub main_light_only: bool,
    pub smoothness_gate: Option<usize>,
    pub parity_tolerance: f64,
}

impl BuiltinModel {
    /// The row's model, and its per-vertex (Gouraud) variant where it has one.
    fn models(&self) -> impl Iterator<Item = ShaderModel> + '_ {
        // A per-vertex variant is a shader with a Vertex pass of its own: no fallback, no G-buffer.
        let gouraud = self.gouraud.map(|summary| ShaderModel {
            name: Cow::Owned(format!("{}_vertex", self.name)),
            summary: Cow::Borrowed(summary),
            per_vertex: true,
            passes: FORWARD_PASSES,
            ..self.model()
        });
        std::iter::once(self.model()).chain(gouraud)
    }

    fn model(&self) -> ShaderModel {
        ShaderModel {
            name: Cow::Borrowed(self.name),
            pipelines: self.pipelines.to_vec(),
            source_path: Cow::Borrowed(self.wgsl.path),
            wgsl: Cow::Borrowed(self.wgsl.text),
            reads: self.reads,
            summary: Cow::Borrowed(self.summary),
            twin: Some(self.twin),
            params: self.params.to_vec(),
            mapping: Cow::Borrowed(self.mapping),
            from_sliders: self.from_sliders,
            expected: self.expected,
            per_vertex: false,
            emits: self.emits,
            stiff_terms: Cow::Borrowed(self.stiff_terms),
            passes: self.passes,
            main_light_only: self.main_light_only,
            smoothness_gate: self.smoothness_gate,
            parity_tolerance: self.parity_tolerance,
        }
    }
}

/// Every model a matrix can name: the built-in ones, then the user's. A value, built once per
/// command and passed where it is needed; models are keyed by (pipeline, name).
#[derive(Debug, Clone)]
pub struct Registry {
    models: Vec<Arc<ShaderModel>>,
}

impl Registry {
    /// The built-in models only.
    pub fn builtin() -> Registry {
        Registry { models: BUILTIN_MODELS.iter().flat_map(BuiltinModel::models).map(Arc::new).collect() }
    }

    /// The registry with `model` added (a user's, `shading::user`).
    pub fn with(mut self, model: ShaderModel) -> Registry {
        self.models.push(Arc::new(model));
        self
    }

    pub fn models(&self) -> &[Arc<ShaderModel>] {
        &self.models
    }

    pub fn find(&self, pipeline: Pipeline, name: &str) -> Option<&Arc<ShaderModel>> {
        self.models.iter().find(|m| m.name == name && m.pipelines.contains(&pipeline))
    }

    /// All model names (any pipeline), sorted, for "did you mean" suggestions.
    pub fn names(&self) -> Vec<&str> {
        let mut names: Vec<&str> = self.models.iter().map(|m| m.name.as_ref()).collect();
        names.sort();
        names.dedup();
        names
    }

    pub fn names_for(&self, pipeline: Pipeline) -> Vec<&str> {
        self.models.iter().filter(|m| m.pipelines.contains(&pipeline)).map(|m| m.name.as_ref()).collect()
    }

    /// The WGSL file names of the built-in models (a user folder may hold copies of them).
    pub fn builtin_files() -> Vec<&'static str> {
        BUILTIN_MODELS.iter().map(|m| m.wgsl.path.rsplit('/').next().unwrap_or("")).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gouraud_variants_derive_from_their_base_rows() {
        let r = Registry::builtin();
        let vertex: Vec<&Arc<ShaderModel>> = r.models().iter().filter(|m| m.per_vertex).collect();
        assert_eq!(vertex.len(), 4, "lambert, half_lambert, phong and blinn_phong each have a Gouraud variant");
        for v in vertex {
            let base_name = v.name.strip_suffix("_vertex").expect("a per-vertex model is NAME_vertex");
            let base = r.find(v.pipelines[0], base_name).expect("its base row");
            assert!(!base.per_vertex && base.wgsl == v.wgsl && base.params.len() == v.params.len());
            assert_eq!((base.reads, base.expected, base.emits), (v.reads, v.expected, v.emits));
            assert_eq!(base.stiff_terms, v.stiff_terms);
        }
    }

    #[test]
    fn emission_and_guards_are_stated_by_each_row() {
        let r = Registry::builtin();
        let emitting: Vec<String> =
            r.models().iter().filter(|m| m.emits()).map(|m| format!("{}/{}", m.pipelines[0].name(), m.name)).collect();
        assert_eq!(
            emitting,
            [
                "builtin/torrance_sparrow",
                "builtin/torrance_sparrow_corrected",
                "builtin/standard",
                "builtin/standard_brdf2",
                "builtin/standard_brdf3",
                "urp/lit",
                "urp/srp_lit",
                "urp/simple_lit",
                "hdrp/lit"
            ]
        );
        // A model that reads roughness names the function guarding it.
        for m in r.models().iter().filter(|m| m.reads.smoothness && !m.name.contains("unlit")) {
            assert!(!m.stiff_terms.starts_with("none"), "{}: no guard stated", m.name);
        }
    }
}
