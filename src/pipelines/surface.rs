//! Surface types: how each engine's lit shaders draw a surface whose base colour has an alpha —
//! the material panels' Rendering Mode (built-in Standard), Surface Type with Blending Mode and
//! Alpha Clipping (URP Lit), Surface Type with Blend Mode and Alpha Clipping (HDRP Lit) — as the
//! engines set them up, with the blend each leaves to the ROP and what the shader does first:
//!
//! - Built-in (StandardShaderGUI.SetupMaterialWithBlendMode; UnityStandardUtils.cginc
//!   PreMultiplyAlpha; UnityStandardCore.cginc OutputForward): Cutout clips at `_Cutoff`; Fade
//!   blends `SrcAlpha OneMinusSrcAlpha`; Transparent (`_ALPHAPREMULTIPLY_ON`) multiplies diffColor by
//!   alpha, outputs alpha' = 1 − oneMinusReflectivity + alpha·oneMinusReflectivity and blends
//!   `One OneMinusSrcAlpha`, so reflections stay. ForwardAdd blends `[_SrcBlend] One`.
//! - URP (BaseShaderGUI.SetupMaterialBlendModeInternal; BRDF.hlsl InitializeBRDFDataDirect): Lit's
//!   `_BlendModePreserveSpecular` defaults to 1, so Alpha and Additive draw with `_ALPHAPREMULTIPLY_ON`
//!   (brdfData.diffuse × alpha, src blend One); Premultiply blends `One OneMinusSrcAlpha` with the
//!   colour as lit; Multiply outputs lerp(1, colour, alpha) (`_ALPHAMODULATE_ON`) blended `DstColor
//!   Zero`. Emission is added after the BRDF, not multiplied.
//! - HDRP (Material.hlsl ApplyBlendMode, with `_EnableBlendModePreserveSpecularLighting` on as a new
//!   Lit has it): Alpha and Additive output diffuse·opacity + specular, blended `One
//!   OneMinusSrcAlpha` and `One One`; Premultiply outputs diffuse + specular. The diffuse lighting
//!   holds the emission (Lit.hlsl PostEvaluateBSDF), so it is multiplied too.
//!
//! Every transparent type is drawn after the opaque objects and the sky, without depth writes
//! (the engines' Transparent queue), and is drawn forward on deferred paths.

use serde::{Deserialize, Serialize};

use super::Pipeline;

/// A surface type as a matrix names it (the `surface` axis).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceType {
    /// Every engine's default: no alpha.
    #[default]
    Opaque,
    /// Built-in Cutout; URP and HDRP Opaque with Alpha Clipping.
    Cutout,
    /// Built-in Fade: the whole lit colour alpha-blended.
    Fade,
    /// Built-in Transparent; URP and HDRP Transparent with Blending Mode Alpha (preserving the
    /// specular lighting).
    Transparent,
    /// URP and HDRP Transparent, Premultiply.
    Premultiply,
    /// URP and HDRP Transparent, Additive.
    Additive,
    /// URP Transparent, Multiply.
    Multiply,
}

/// How the ROP blends a source colour `s` (alpha `a`) over a destination `d`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Blend {
    /// s (no blending).
    Replace,
    /// s·a + d·(1 − a).
    SrcAlphaOver,
    /// s + d·(1 − a).
    PremultipliedOver,
    /// s + d.
    Add,
    /// s·a + d.
    SrcAlphaAdd,
    /// s·d.
    Multiply,
}

impl Blend {
    /// The blended colour, channel by channel (the CPU twin of the blend state).
    pub fn apply(self, s: [f64; 3], a: f64, d: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| match self {
            Blend::Replace => s[i],
            Blend::SrcAlphaOver => s[i] * a + d[i] * (1.0 - a),
            Blend::PremultipliedOver => s[i] + d[i] * (1.0 - a),
            Blend::Add => s[i] + d[i],
            Blend::SrcAlphaAdd => s[i] * a + d[i],
            Blend::Multiply => s[i] * d[i],
        })
    }
}

/// The lit colour of a surface split as the blend needs it: what the diffuse share of the
/// material reflects, the rest of the reflection, and the emission.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LitTerms {
    /// Direct and indirect light reflected by the diffuse lobe.
    pub diffuse: [f64; 3],
    /// Direct and indirect light reflected by the specular lobe.
    pub specular: [f64; 3],
    pub emission: [f64; 3],
}

impl SurfaceType {
    pub const ALL: [SurfaceType; 7] = [
        SurfaceType::Opaque,
        SurfaceType::Cutout,
        SurfaceType::Fade,
        SurfaceType::Transparent,
        SurfaceType::Premultiply,
        SurfaceType::Additive,
        SurfaceType::Multiply,
    ];

    pub fn name(self) -> &'static str {
        match self {
            SurfaceType::Opaque => "opaque",
            SurfaceType::Cutout => "cutout",
            SurfaceType::Fade => "fade",
            SurfaceType::Transparent => "transparent",
            SurfaceType::Premultiply => "premultiply",
            SurfaceType::Additive => "additive",
            SurfaceType::Multiply => "multiply",
        }
    }

    pub fn from_name(name: &str) -> Option<SurfaceType> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|s| s.name()).collect()
    }

    /// Value of the WGSL override constant `SURFACE` (shaders/pass/forward.wgsl).
    pub fn shader_id(self) -> u32 {
        self as u32
    }

    /// The surface types a pipeline's lit shaders offer.
    pub fn of(pipeline: Pipeline) -> &'static [SurfaceType] {
        use SurfaceType::*;
        match pipeline {
            Pipeline::Builtin => &[Opaque, Cutout, Fade, Transparent],
            Pipeline::Urp => &[Opaque, Cutout, Transparent, Premultiply, Additive, Multiply],
            Pipeline::Hdrp => &[Opaque, Cutout, Transparent, Premultiply, Additive],
        }
    }

    /// Blended in the Transparent queue: drawn after the opaque objects and the sky, sorted back
    /// to front, without depth writes, and forward on a deferred path.
    pub fn is_transparent(self) -> bool {
        !matches!(self, SurfaceType::Opaque | SurfaceType::Cutout)
    }

    /// Whether the shader clips at the cutoff.
    pub fn clips(self) -> bool {
        self == SurfaceType::Cutout
    }

    /// Whether the shader multiplies the diffuse reflectance by alpha before lighting (built-in's
    /// and URP's `_ALPHAPREMULTIPLY_ON`, HDRP's preserved specular lighting): the model must keep
    /// its diffuse lobe apart (`ShaderModel::splits_diffuse`).
    pub fn premultiplies_diffuse(self, pipeline: Pipeline) -> bool {
        match self {
            SurfaceType::Transparent => true,
            SurfaceType::Additive => pipeline != Pipeline::Builtin,
            _ => false,
        }
    }

    /// Whether the emission is multiplied by alpha with the diffuse (HDRP: it is part of the
    /// diffuse lighting that ApplyBlendMode multiplies).
    pub fn premultiplies_emission(self, pipeline: Pipeline) -> bool {
        pipeline == Pipeline::Hdrp && self.premultiplies_diffuse(pipeline)
    }

    /// The ROP blend of the main (or ForwardBase) draw.
    pub fn blend(self) -> Blend {
        match self {
            SurfaceType::Opaque | SurfaceType::Cutout => Blend::Replace,
            SurfaceType::Fade => Blend::SrcAlphaOver,
            SurfaceType::Transparent | SurfaceType::Premultiply => Blend::PremultipliedOver,
            SurfaceType::Additive => Blend::Add,
            SurfaceType::Multiply => Blend::Multiply,
        }
    }

    /// Built-in's ForwardAdd blend, `[_SrcBlend] One`: Fade's SrcAlpha, Transparent's One.
    pub fn forward_add_blend(self) -> Blend {
        match self {
            SurfaceType::Fade => Blend::SrcAlphaAdd,
            _ => Blend::Add,
        }
    }

    /// The alpha the shader outputs: built-in Transparent's alpha' = 1 − (1 − alpha)·(1 −
    /// reflectivity), where reflectivity = 1 − oneMinusReflectivity; alpha else.
    pub fn output_alpha(self, pipeline: Pipeline, alpha: f64, reflectivity: f64) -> f64 {
        match (self, pipeline) {
            (SurfaceType::Transparent, Pipeline::Builtin) => 1.0 - (1.0 - alpha) * (1.0 - reflectivity),
            (SurfaceType::Opaque | SurfaceType::Cutout, _) => 1.0,
            _ => alpha,
        }
    }

    /// The colour the shader outputs from its lit terms (the diffuse already multiplied by alpha
    /// where `premultiplies_diffuse`): their sum, with HDRP's premultiplied emission and URP's
    /// Multiply lerp(1, colour, alpha).
    pub fn output_color(self, pipeline: Pipeline, lit: &LitTerms, alpha: f64) -> [f64; 3] {
        let emission = if self.premultiplies_emission(pipeline) { alpha } else { 1.0 };
        std::array::from_fn(|i| {
            let c = lit.diffuse[i] + lit.specular[i] + lit.emission[i] * emission;
            match self {
                SurfaceType::Multiply => 1.0 + (c - 1.0) * alpha,
                _ => c,
            }
        })
    }

    /// What a pixel of this surface becomes over `dst` (the CPU twin of shader output and blend):
    /// `lit` with the diffuse as the shader lights it (multiplied by alpha where it premultiplies).
    pub fn composite(
        self,
        pipeline: Pipeline,
        lit: &LitTerms,
        alpha: f64,
        reflectivity: f64,
        dst: [f64; 3],
    ) -> [f64; 3] {
        let a = self.output_alpha(pipeline, alpha, reflectivity);
        self.blend().apply(self.output_color(pipeline, lit, alpha), a, dst)
    }

    /// Why `pipeline` has no such surface type, if it has none.
    pub fn missing_in(self, pipeline: Pipeline) -> Option<String> {
        if Self::of(pipeline).contains(&self) {
            return None;
        }
        let has: Vec<&str> = Self::of(pipeline).iter().map(|s| s.name()).collect();
        Some(format!(
            "the {} pipeline's lit shaders have no `{}` surface (they have: {})",
            pipeline.name(),
            self.name(),
            has.join(", ")
        ))
    }
}

/// Which faces of a mesh are drawn (URP Lit's Render Face, `_Cull`; HDRP Lit's Double-Sided; built-in
/// Standard draws front faces alone, `Cull Back`). Every engine's default is `Front`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum RenderFace {
    #[default]
    Front,
    Back,
    Both,
}

impl RenderFace {
    pub const ALL: [RenderFace; 3] = [RenderFace::Front, RenderFace::Back, RenderFace::Both];

    pub fn name(self) -> &'static str {
        match self {
            RenderFace::Front => "front",
            RenderFace::Back => "back",
            RenderFace::Both => "both",
        }
    }

    /// The faces the rasteriser culls (Cull Back, Cull Front, Cull Off).
    pub fn culled(self) -> Option<wgpu::Face> {
        match self {
            RenderFace::Front => Some(wgpu::Face::Back),
            RenderFace::Back => Some(wgpu::Face::Front),
            RenderFace::Both => None,
        }
    }
}

/// Unity's default `_Cutoff` (Standard, URP Lit, HDRP Lit's Alpha Cutoff).
pub const DEFAULT_CUTOFF: f64 = 0.5;

/// A material's Surface Options: its surface type, its base colour's alpha (times its albedo
/// map's) and where a cutout clips.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SurfaceOptions {
    pub kind: SurfaceType,
    pub alpha: f64,
    pub cutoff: f64,
}

impl Default for SurfaceOptions {
    fn default() -> Self {
        SurfaceOptions { kind: SurfaceType::Opaque, alpha: 1.0, cutoff: DEFAULT_CUTOFF }
    }
}

impl SurfaceOptions {
    /// The cutoff the shaders clip at: 0 (nothing clips) unless the surface is a cutout.
    pub fn clip_threshold(&self) -> f64 {
        if self.kind.clips() {
            self.cutoff
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back_and_every_pipeline_has_opaque_and_cutout() {
        for s in SurfaceType::ALL {
            assert_eq!(SurfaceType::from_name(s.name()), Some(s));
        }
        for p in Pipeline::ALL {
            assert!(SurfaceType::of(p).starts_with(&[SurfaceType::Opaque, SurfaceType::Cutout]));
        }
        assert!(SurfaceType::Fade.missing_in(Pipeline::Urp).unwrap().contains("premultiply"));
        assert!(SurfaceType::Multiply.missing_in(Pipeline::Hdrp).is_some());
    }

    #[test]
    fn builtin_transparent_keeps_the_reflection_fade_fades() {
        // Over black, Fade is alpha × everything; Transparent is alpha × diffuse + specular.
        let lit = LitTerms { diffuse: [0.4; 3], specular: [0.2; 3], emission: [0.0; 3] };
        let alpha = 0.25;
        let fade = SurfaceType::Fade.composite(Pipeline::Builtin, &lit, alpha, 0.04, [0.0; 3]);
        assert!((fade[0] - 0.25 * 0.6).abs() < 1e-15);
        let premultiplied = LitTerms { diffuse: [0.4 * alpha; 3], ..lit };
        let t = SurfaceType::Transparent.composite(Pipeline::Builtin, &premultiplied, alpha, 0.04, [0.0; 3]);
        assert!((t[0] - (0.1 + 0.2)).abs() < 1e-15);
        // Over white the background shows through (1 − alpha)(1 − reflectivity).
        let t = SurfaceType::Transparent.composite(Pipeline::Builtin, &premultiplied, alpha, 0.04, [1.0; 3]);
        assert!((t[0] - (0.3 + 0.75 * 0.96)).abs() < 1e-15);
    }

    #[test]
    fn urp_multiply_is_neutral_at_zero_alpha() {
        let lit = LitTerms { diffuse: [0.3; 3], ..Default::default() };
        let out = SurfaceType::Multiply.composite(Pipeline::Urp, &lit, 0.0, 0.0, [0.7; 3]);
        assert!((out[0] - 0.7).abs() < 1e-15);
    }
}
