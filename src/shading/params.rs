//! The built-in models' own parameters (`ParamSpec`): named, ranged floats in the slots of
//! `Surface::params`, with the engine property each stands for. The registry's table names them.

use serde::Serialize;
use std::borrow::Cow;

use super::twin;

/// One of a model's own parameters: a named, ranged float in a slot of `Surface::params`.
#[derive(Debug, Clone, Serialize)]
pub struct ParamSpec {
    pub name: Cow<'static, str>,
    pub slot: usize,
    pub default: f64,
    pub min: f64,
    pub max: f64,
    pub doc: Cow<'static, str>,
}

pub(super) const NORMALIZE: ParamSpec = ParamSpec {
    name: Cow::Borrowed("normalize"),
    slot: 0,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed("1: energy-normalise the lobe; 0: the textbook form"),
};
pub(super) const SIGMA: ParamSpec = ParamSpec {
    name: Cow::Borrowed("sigma"),
    slot: 0,
    default: 0.5,
    min: 0.0,
    max: std::f64::consts::FRAC_PI_2,
    doc: Cow::Borrowed("surface slope deviation σ, radians (from smoothness: σ = 1 − s)"),
};
pub(super) const IOR_15: ParamSpec = ParamSpec {
    name: Cow::Borrowed("ior"),
    slot: 0,
    default: 1.5,
    min: 1.0,
    max: 5.0,
    doc: Cow::Borrowed("index of refraction"),
};
pub(super) const IOR_145: ParamSpec = ParamSpec {
    name: Cow::Borrowed("ior"),
    slot: 0,
    default: 1.45,
    min: 1.0,
    max: 5.0,
    doc: Cow::Borrowed("index of refraction"),
};
pub(super) const FRESNEL_POWER: ParamSpec = ParamSpec {
    name: Cow::Borrowed("fresnel_power"),
    slot: 1,
    default: 5.0,
    min: 1.0,
    max: 8.0,
    doc: Cow::Borrowed("exponent p of (1 − N·V)^p"),
};
pub(super) const SPECULAR_HIGHLIGHTS: ParamSpec = ParamSpec {
    name: Cow::Borrowed("specular_highlights"),
    slot: 0,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "1: _SPECULAR_COLOR on; 0 (default): off, as a new Simple Lit material ships (_SpecularHighlights = 1 = SpecularSource.NoSpecular)",
    ),
};
pub(super) const FRESNEL_STRENGTH: ParamSpec = ParamSpec {
    name: Cow::Borrowed("fresnel_strength"),
    slot: 0,
    default: 1.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "the SRP tutorial's Fresnel slider: how far reflections go from the specular colour to brdf.fresnel at grazing angles",
    ),
};
pub(super) const ENERGY_COMPENSATION: ParamSpec = ParamSpec {
    name: Cow::Borrowed("energy_compensation"),
    slot: 0,
    default: 1.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed("1: multiply specular by 1 + F0·(1/y − 1) from the FGD table (HDRP default); 0: off"),
};

/// The specular setup of the engines' lit shaders (built-in Standard (Specular setup) with
/// StandardSpecular.shader's SpecularSetup, URP Lit's Workflow Mode Specular `_SPECULAR_SETUP`,
/// HDRP Lit's Material Type Specular Color): 1 takes `Surface::specular` as the specular colour.
pub(super) const fn specular_setup(slot: usize) -> ParamSpec {
    ParamSpec {
        name: Cow::Borrowed("specular_setup"),
        slot,
        default: 0.0,
        min: 0.0,
        max: 1.0,
        doc: Cow::Borrowed(
            "1: the specular workflow (albedo = colour·(1 − metallic), specular colour = lerp(0.04, colour, metallic), the F0 the metallic workflow gives; the engine's own energy rule: diffuse × (1 − max(specular))); 0: metallic (default)",
        ),
    }
}

pub(super) const SPECULAR_SETUP: ParamSpec = specular_setup(0);

/// URP Lit's Environment Reflections toggle turned off (`_EnvironmentReflections` 0, compiling
/// `_ENVIRONMENTREFLECTIONS_OFF`): the reflections are the constant `_GlossyEnvironmentColor`,
/// the ambient probe's L0 × reflectionIntensity (UniversalRenderPipeline
/// .SetupPerFrameShaderConstants). Built-in Standard's counterpart (`_GLOSSYREFLECTIONS_OFF`)
/// reads `unity_IndirectSpecColor`, which the engine computes in unpublished code: not modelled.
pub(super) const ENVIRONMENT_REFLECTIONS_OFF: ParamSpec = ParamSpec {
    name: Cow::Borrowed("environment_reflections_off"),
    slot: 2,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "1: _ENVIRONMENTREFLECTIONS_OFF (reflections = _GlossyEnvironmentColor, the environment's mean radiance); 0 (default): probes and sky",
    ),
};

/// Standard's and URP Lit's Specular Highlights toggle turned off (`_SpecularHighlights` 0, which
/// compiles `_SPECULARHIGHLIGHTS_OFF`; a new material has them on): no specular term from the
/// lights. Named for the keyword, so that zero parameters are the engines' default. Built-in
/// Standard's own passes honour it; Internal-DeferredShading does not (fragDeferred writes
/// diffColor, specColor and smoothness to the G-buffer, no flag), URP's deferred lighting does
/// (kMaterialFlagSpecularHighlightsOff in the G-buffer).
pub(super) const SPECULAR_HIGHLIGHTS_TOGGLE: ParamSpec = ParamSpec {
    name: Cow::Borrowed("specular_highlights_off"),
    slot: 1,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "1: _SPECULARHIGHLIGHTS_OFF (BRDF1's specularTerm = 0, URP's DirectBRDF returns the diffuse); 0 (default): highlights on; built-in's deferred lighting does not read it",
    ),
};
/// HDRP Lit's: slot 0 is its energy compensation.
pub(super) const SPECULAR_SETUP_HDRP: ParamSpec = specular_setup(1);

/// HDRP Lit's Coat Mask (`_CoatMask`, 0 in a new material; above 0 the inspector compiles
/// `_MATERIAL_FEATURE_CLEAR_COAT`): an IOR 1.5, roughness 0.01 layer over the base (Lit.hlsl).
pub(super) const COAT_MASK: ParamSpec = ParamSpec {
    name: Cow::Borrowed("coat_mask"),
    slot: twin::COAT_MASK_SLOT,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "HDRP's clear coat over the base: F0 0.04, α 0.01, the base rougher and its F0 seen from IOR 1.5, as Lit.hlsl splits the energy; 0 (default): no coat",
    ),
};

/// HDRP Lit's Iridescence material type, by its mask (`_IridescenceMask`, 1 when the type is
/// chosen): 0 is the Standard type, above 0 the thin film's F0 blended in by the mask.
pub(super) const IRIDESCENCE_MASK: ParamSpec = ParamSpec {
    name: Cow::Borrowed("iridescence_mask"),
    slot: twin::IRIDESCENCE_MASK_SLOT,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "the Iridescence material type: F0 → lerp(F0, EvalIridescence(…), mask), the film's Fresnel at NV for every light; 0 (default): the Standard type",
    ),
};

/// HDRP Lit's `_Anisotropy` of the Anisotropy material type (−1..1, 0 in a new material):
/// αT = α(1 + a), αB = α(1 − a) along the mesh's tangent; at 0 the type draws as Standard.
pub(super) const ANISOTROPY: ParamSpec = ParamSpec {
    name: Cow::Borrowed("anisotropy"),
    slot: twin::ANISOTROPY_SLOT,
    default: 0.0,
    min: -1.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "the Anisotropy material type: anisotropic GGX with αT = α(1 + a), αB = α(1 − a) along the mesh's tangent, the reflections fetched about GetAnisotropicModifiedNormal; 0 (default): isotropic",
    ),
};

/// Parameters read only while another is above 0: (parameter, its gate).
pub(super) const PARAM_GATES: &[(&str, &str)] = &[
    ("iridescence_thickness", "iridescence_mask"),
    ("thickness", "transmission"),
    ("subsurface_mask", "subsurface_scattering"),
];

/// HDRP Lit's Translucent material type (`_MaterialID` 5, MATERIALFEATUREFLAGS_LIT_TRANSMISSION)
/// with HDRP's default diffusion profile: the diffuse lobe also lit from behind through the
/// profile's transmittance, metallic 0, F0 the profile's.
pub(super) const TRANSMISSION: ParamSpec = ParamSpec {
    name: Cow::Borrowed("transmission"),
    slot: twin::TRANSMISSION_SLOT,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "1: the Translucent material type, thin-object transmission through the default diffusion profile (wrapped −NL × ComputeTransmittanceDisney), metallic 0, F0 0.0278; 0 (default): opaque",
    ),
};

/// HDRP Lit's Subsurface Scattering material type (`_MaterialID` 0,
/// MATERIALFEATUREFLAGS_LIT_SUBSURFACE_SCATTERING) with the default diffusion profile: its
/// diffuse lighting split off and blurred by the screen-space filter (plan::subsurface), metallic
/// 0, F0 the profile's. The type keeps Transmission on, as a new material does
/// (`_TransmissionEnable` 1).
pub(super) const SUBSURFACE_SCATTERING: ParamSpec = ParamSpec {
    name: Cow::Borrowed("subsurface_scattering"),
    slot: twin::SUBSURFACE_SLOT,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "1: the Subsurface Scattering material type: the diffuse lighting (× √albedo) split off, blurred by HDRP's screen-space Burley filter (default profile, Medium budget 40) and × √albedo again; metallic 0, F0 0.0278; 0 (default): none",
    ),
};

/// HDRP Lit's `_SubsurfaceMask` (0–1, default 1): the filter's distance scale.
pub(super) const SUBSURFACE_MASK: ParamSpec = ParamSpec {
    name: Cow::Borrowed("subsurface_mask"),
    slot: twin::SUBSURFACE_MASK_SLOT,
    default: 1.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "the subsurface mask: scales the filter's radius (0: the light stays where it fell); read only with subsurface_scattering on",
    ),
};

/// HDRP Lit's `_Thickness` (0–1, default 1): remapped to 0–5 mm by the default profile.
pub(super) const THICKNESS: ParamSpec = ParamSpec {
    name: Cow::Borrowed("thickness"),
    slot: twin::THICKNESS_SLOT,
    default: 1.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "the translucent slab's thickness, × 5 mm (the profile's remap); read only with transmission on",
    ),
};

/// HDRP Lit's `_IridescenceThickness` (0–1, default 1): a film of 3·t µm optical thickness and
/// IOR lerp(2, 1, t) (core BSDF.hlsl EvalIridescence).
pub(super) const IRIDESCENCE_THICKNESS: ParamSpec = ParamSpec {
    name: Cow::Borrowed("iridescence_thickness"),
    slot: twin::IRIDESCENCE_THICKNESS_SLOT,
    default: 1.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "the thin film's thickness t: optical path 3·t µm, IOR lerp(2, 1, t); read only with iridescence_mask above 0",
    ),
};

/// The name of the height map's scale parameter: it moves the material's maps, so a cell without
/// maps draws the same image whatever its value (cells::render_key).
pub const PARALLAX_PARAM: &str = "parallax";

/// Standard's and URP Lit's Height Map scale (`_Parallax`, compiling `_PARALLAXMAP` where a height
/// map is assigned): the maps are read at uv + ParallaxOffset1Step(h, scale, viewDirTS)
/// (UnityStandardInput.cginc Parallax, URP ParallaxMapping.hlsl), h the preset's height map.
/// 0 is the engines' default, no height map; the inspectors offer 0.005–0.08.
pub(super) const PARALLAX: ParamSpec = ParamSpec {
    name: Cow::Borrowed(PARALLAX_PARAM),
    slot: 3,
    default: 0.0,
    min: 0.0,
    max: 0.08,
    doc: Cow::Borrowed(
        "the height map's scale (_Parallax, 0.005–0.08 in the inspector): the maps are read at the parallax-offset uv; 0 (default): no height map. Needs the textured preset (`materials`)",
    ),
};

/// The name of Standard's secondary-maps switch: like the height map, it moves only what the maps
/// carry, so a cell without maps draws the same image whatever its value (cells::render_key).
pub const DETAIL_PARAM: &str = "detail";

/// Standard's and URP Lit's secondary maps assigned (`_DetailAlbedoMap` and `_DetailNormalMap`,
/// compiling Standard's `_DETAIL_MULX2`, URP's `_DETAIL`): the tool's detail grain
/// (materials::detail) tiled 4× over the main maps, where the main mask's detail mask lets it, each
/// engine blending it its own way. 0 is a new material's: no secondary maps.
pub(super) const DETAIL: ParamSpec = ParamSpec {
    name: Cow::Borrowed(DETAIL_PARAM),
    slot: 4,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "1: the secondary maps under the detail mask (Standard: albedo × unity_ColorSpaceDouble, BlendNormals; URP Lit: albedo × 2 as linear data, BlendNormalRNM); 0 (default): none. Needs the textured preset (`materials`)",
    ),
};

/// The name of Standard's and URP Lit's Source = Albedo Alpha: like the detail switch, it moves
/// only what the maps carry, so a cell without maps draws the same image whatever its value.
pub const SMOOTHNESS_SOURCE_PARAM: &str = "smoothness_from_albedo_alpha";

/// Standard's and URP Lit's smoothness Source (`_SmoothnessTextureChannel` 1, compiling
/// `_SMOOTHNESS_TEXTURE_ALBEDO_CHANNEL_A`; the default 0 reads the metallic or specular map's
/// alpha): smoothness = the albedo map's alpha × the Smoothness slider (UnityStandardInput.cginc
/// MetallicGloss and SpecularGloss; URP LitInput.hlsl SampleMetallicSpecGloss), and the surface's
/// alpha no longer takes the map's alpha (Standard's Alpha() returns _Color.a; URP's Alpha(),
/// SurfaceInput.hlsl, color.a). The presets' albedo maps are opaque (alpha 1), so their
/// smoothness is the slider's, without the map's variation; a glTF subject's base colour alpha
/// becomes its smoothness. Named for the keyword, so that zero is the engines' default.
pub(super) const SMOOTHNESS_FROM_ALBEDO_ALPHA: ParamSpec = ParamSpec {
    name: Cow::Borrowed(SMOOTHNESS_SOURCE_PARAM),
    slot: 5,
    default: 0.0,
    min: 0.0,
    max: 1.0,
    doc: Cow::Borrowed(
        "1: Source = Albedo Alpha (_SMOOTHNESS_TEXTURE_ALBEDO_CHANNEL_A: smoothness = the albedo map's alpha × the slider, the map's alpha no longer the surface's); 0 (default): the metallic/specular map's alpha. Needs the textured preset (`materials`)",
    ),
};

/// HDRP Lit's detail map assigned (`_DetailMap`, compiling `_DETAIL_MAP`): the same grain, overlaid
/// on the base colour and its normal blended by reoriented normal mapping (LitDataIndividualLayer.hlsl).
pub(super) const DETAIL_HDRP: ParamSpec = ParamSpec {
    slot: 10,
    doc: Cow::Borrowed(
        "1: the detail map under the detail mask (HDRP: the base colour overlaid towards black or white in √ space, BlendNormalRNM; its smoothness channel neutral); 0 (default): none. Needs the textured preset (`materials`)",
    ),
    ..DETAIL
};
