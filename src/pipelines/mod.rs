//! Emulations of the three engine pipelines' conventions (models.md#conventions, models.md#display): light units
//! and colour handling, distance attenuation, tonemapping, and which shaders exist in each.
//! Per-pass plans live in `plan`; this module only states conventions.

use serde::{Deserialize, Serialize};

pub mod hdrp_light;
pub mod settings;
pub mod settings_axes;
pub mod surface;
pub mod terms;
pub mod volume;

use crate::color::{gamma_to_linear_space_exact, srgb_to_linear};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Pipeline {
    Builtin,
    Urp,
    Hdrp,
}

impl Pipeline {
    pub const ALL: [Pipeline; 3] = [Pipeline::Builtin, Pipeline::Urp, Pipeline::Hdrp];

    pub fn name(self) -> &'static str {
        match self {
            Pipeline::Builtin => "builtin",
            Pipeline::Urp => "urp",
            Pipeline::Hdrp => "hdrp",
        }
    }

    pub fn from_name(name: &str) -> Option<Pipeline> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|p| p.name()).collect()
    }

    /// Value of the WGSL override constant `PIPELINE` (shaders/common/conventions.wgsl).
    pub fn shader_id(self) -> u32 {
        self as u32
    }

    /// Scale from the matrix's light-intensity axis (0–100) to the pipeline's UI unit. HDRP works
    /// in physical units and the comparison application's HDRP slider is ×10000: lumen for point
    /// and spot lights, lux for directional ones (`Emitter::candela_per_ui_unit`, models.md#hdrp-units).
    pub fn intensity_scale(self) -> f64 {
        match self {
            Pipeline::Builtin | Pipeline::Urp => 1.0,
            Pipeline::Hdrp => 10_000.0,
        }
    }

    /// The unit the key light's intensity axis stands for in this pipeline, for records and `list`.
    pub fn intensity_unit(self, emitter: Emitter) -> &'static str {
        match (self, emitter) {
            (Pipeline::Builtin | Pipeline::Urp, _) => "unitless (an intensity I delivers irradiance π·I)",
            (Pipeline::Hdrp, Emitter::Directional { .. }) => "lux (axis × 10000)",
            (Pipeline::Hdrp, Emitter::Rect { .. } | Emitter::Disc { .. }) => {
                "lumen (axis × 10000), converted to nits by the light's area"
            }
            (Pipeline::Hdrp, _) => "lumen (axis × 10000), converted to candela by the light's shape",
        }
    }

    /// Linear light colour × intensity as the pipeline's shaders receive it (per unit attenuation).
    /// - Built-in defaults to `GraphicsSettings.lightsUseLinearIntensity = false`: the gamma-space
    ///   colour is multiplied by the intensity and then linearised with UnityCG.cginc
    ///   GammaToLinearSpaceExact, which is pow(v, 2.2) above 1 (models.md#builtin).
    /// - URP linearises the colour first and multiplies by the unitless intensity.
    /// - HDRP: point and spot intensities are lumen (the UI unit) and the shader receives candela
    ///   (LightUtils.cs); directional lights are lux, used as is.
    pub fn light_radiance(self, srgb_color: [f64; 3], intensity: f64, emitter: Emitter) -> [f64; 3] {
        match self {
            Pipeline::Builtin => srgb_color.map(|c| gamma_to_linear_space_exact(c * intensity)),
            Pipeline::Urp => srgb_color.map(|c| srgb_to_linear(c) * intensity),
            Pipeline::Hdrp => {
                let scale = intensity * self.intensity_scale() * emitter.candela_per_ui_unit();
                srgb_color.map(|c| srgb_to_linear(c) * scale)
            }
        }
    }

    /// `light_radiance` with the matrix's engine settings: HDRP reads the axis in the unit
    /// `[pipeline_settings.hdrp] light_unit` names (`settings::HdrpLightUnit`).
    pub fn light_radiance_with(
        self,
        srgb_color: [f64; 3],
        intensity: f64,
        emitter: Emitter,
        engine: &settings::PipelineSettings,
    ) -> [f64; 3] {
        use settings::HdrpLightUnit;
        let per_unit = match (self, engine.hdrp.light_unit, emitter) {
            (Pipeline::Hdrp, HdrpLightUnit::Candela, Emitter::Point { .. } | Emitter::Spot { .. })
                if !emitter.is_box() =>
            {
                1.0
            }
            (Pipeline::Hdrp, HdrpLightUnit::Unity, _) => std::f64::consts::PI,
            _ => return self.light_radiance(srgb_color, intensity, emitter),
        };
        let scale = intensity * self.intensity_scale() * per_unit;
        srgb_color.map(|c| srgb_to_linear(c) * scale)
    }

    /// `intensity_unit` with the matrix's engine settings.
    pub fn intensity_unit_with(self, emitter: Emitter, engine: &settings::PipelineSettings) -> &'static str {
        use settings::HdrpLightUnit;
        match (self, engine.hdrp.light_unit, emitter) {
            (Pipeline::Hdrp, HdrpLightUnit::Candela, Emitter::Point { .. } | Emitter::Spot { .. })
                if !emitter.is_box() =>
            {
                "candela (axis × 10000)"
            }
            (Pipeline::Hdrp, HdrpLightUnit::Unity, Emitter::Directional { .. }) => {
                "unitless as URP's, read as lux π·axis × 10000"
            }
            (Pipeline::Hdrp, HdrpLightUnit::Unity, _) => "unitless as URP's, read as candela π·axis × 10000",
            _ => self.intensity_unit(emitter),
        }
    }

    /// Environment radiance scale, so that ambient keeps its proportion to the direct light.
    pub fn environment_scale(self) -> f64 {
        self.intensity_scale()
    }

    /// The metallic slider as the shader receives it. Built-in Standard declares `[Gamma] _Metallic`,
    /// so in linear colour space it is sRGB-decoded (0.5 → ≈0.214). URP Lit dropped the tag in 2020
    /// (ScriptableRenderPipeline PR #6194) and HDRP never had it: both take the slider as is (presets.md).
    pub fn shader_metallic(self, slider: f64) -> f64 {
        match self {
            Pipeline::Builtin => srgb_to_linear(slider),
            Pipeline::Urp | Pipeline::Hdrp => slider,
        }
    }

    pub fn attenuation(self) -> Attenuation {
        match self {
            Pipeline::Builtin => Attenuation::BuiltinLegacy,
            Pipeline::Urp => Attenuation::UrpSmoothInverseSquare,
            Pipeline::Hdrp => Attenuation::HdrpPunctual,
        }
    }

    /// The falloff Unity's Progressive Lightmapper bakes this pipeline's point and spot lights
    /// with (`LightDataGI.falloff`): URP's lights delegate (UniversalRenderPipeline.cs
    /// `lightsDelegate`) and HDRP's (GlobalIlluminationUtils.cs `LightDataGIExtract`, range
    /// attenuation on) set InverseSquared; built-in sets no delegate and bakes the Legacy falloff.
    pub fn baked_falloff(self) -> BakedFalloff {
        match self {
            Pipeline::Builtin => BakedFalloff::Legacy,
            Pipeline::Urp | Pipeline::Hdrp => BakedFalloff::InverseSquared,
        }
    }

    /// The tonemapper each pipeline ships with: none for built-in (no post-processing stack) and
    /// URP (its Tonemapping override defaults to None); ACES for HDRP, whose default volume profile
    /// sets Tonemapping mode ACES (DefaultSettingsVolumeProfile.asset, models.md#display).
    pub fn default_tonemap(self) -> Tonemap {
        match self {
            Pipeline::Builtin | Pipeline::Urp => Tonemap::None,
            Pipeline::Hdrp => Tonemap::Aces,
        }
    }

    /// The anti-aliasing each pipeline ships with: built-in's top quality level (Ultra) sets
    /// `antiAliasing: 4` (the default ProjectSettings/QualitySettings.asset); URP's asset has
    /// `m_MSAA = MsaaQuality.Disabled` (UniversalRenderPipelineAsset.cs); HDRP's
    /// RenderPipelineSettings default `msaaSampleCount` is None, and HDRP multisamples only in
    /// forward-only lit mode anyway.
    pub fn default_antialiasing(self) -> Antialiasing {
        match self {
            Pipeline::Builtin => Antialiasing::Msaa4,
            Pipeline::Urp | Pipeline::Hdrp => Antialiasing::None,
        }
    }

    /// The shadow-map resolution (texels per side; per cube face for a point light) a light gets
    /// when its scene entry sets none. `pixel_size`: the larger screen extent in pixels of what the
    /// light can reach (the whole image for a directional light).
    ///
    /// Built-in (Unity manual, "Shadow resolution in the Built-In Render Pipeline"):
    /// NextPowerOfTwo(pixel size × quality multiplier × 3.8 directional, 2 spot, 1 point), at most
    /// 4096 / 2048 / 1024; the multiplier is 0.5 at the Ultra level's `shadowResolution: 2` (High).
    /// URP: the asset's `m_MainLightShadowmapResolution = 2048` for the directional light, the
    /// additional lights' default tier High (`AdditionalLightsShadowDefaultResolutionTier`) =
    /// `AdditionalLightsDefaultShadowResolutionTierHigh` = 1024 for spots and point faces.
    /// HDRP: HDAdditionalLightData `m_ShadowResolution` override 512 for every light.
    pub fn default_shadow_resolution(self, emitter: Emitter, pixel_size: f64) -> u32 {
        self.shadow_resolution_with(&settings::PipelineSettings::default(), emitter, pixel_size)
    }

    /// `default_shadow_resolution` with the cell's engine settings: built-in's quality level's
    /// Shadow Resolution multiplier, URP's asset, HDRP's lights' resolution.
    pub fn shadow_resolution_with(self, engine: &settings::PipelineSettings, emitter: Emitter, pixel_size: f64) -> u32 {
        match self {
            Pipeline::Builtin => {
                let multiplier = engine.builtin.quality.shadow_resolution.multiplier();
                let (factor, max) = match emitter {
                    Emitter::Directional { .. } => (3.8, 4096),
                    // Area lights cast no real-time shadows (declarations::area_light): the spot's row.
                    Emitter::Spot { .. } | Emitter::Rect { .. } | Emitter::Disc { .. } => (2.0, 2048),
                    Emitter::Point { .. } => (1.0, 1024),
                };
                let size = (pixel_size * multiplier * factor).ceil().max(1.0) as u32;
                size.next_power_of_two().min(max)
            }
            // The asset's main-light resolution, and its High tier for the others.
            Pipeline::Urp => match emitter {
                Emitter::Directional { .. } => engine.urp.main_light_shadow_resolution,
                _ => engine.urp.additional_light_shadow_resolution,
            },
            Pipeline::Hdrp => engine.hdrp.shadow_resolution,
        }
    }

    /// The directional-light shadow cascades each pipeline ships with: built-in QualitySettings
    /// (4 cascades, 150 m, splits 0.067/0.2/0.467), URP's asset (code defaults: 1 cascade, 50 m),
    /// HDRP's HDShadowSettings splits 0.05/0.15/0.3 with the Max Distance its Default Volume Profile
    /// overrides to 150 m (Editor/RenderPipelineResources/DefaultSettingsVolumeProfile.asset,
    /// `maxShadowDistance: 150`; the class's own default, 500 m, is not what a project gets).
    pub fn shadow_cascades(self) -> ShadowCascades {
        self.shadow_cascades_with(&settings::PipelineSettings::default())
    }

    /// The cascades with the cell's engine settings (built-in's from its quality level, URP's from
    /// its asset).
    pub fn shadow_cascades_with(self, engine: &settings::PipelineSettings) -> ShadowCascades {
        match self {
            Pipeline::Builtin => {
                let q = &engine.builtin.quality;
                ShadowCascades { splits: q.cascade_splits(), max_distance: q.shadow_distance }
            }
            Pipeline::Urp => {
                ShadowCascades { splits: engine.urp.cascade_splits(), max_distance: engine.urp.shadow_distance }
            }
            Pipeline::Hdrp => ShadowCascades { splits: vec![0.05, 0.15, 0.3, 1.0], max_distance: 150.0 },
        }
    }

    /// A spot light's inner half-angle (radians) when the scene sets none, from its outer one.
    /// Built-in and URP: Unity's fallback atan(tan(outer)·46/64) (models.md#urp). HDRP: the inner
    /// cone is a percentage of the outer, 0 % by default (HDAdditionalLightData
    /// `m_InnerSpotPercent`; GPU light data cosSpotInnerHalfAngle = cos(angle/2 · percent)), so
    /// the falloff spans the whole cone.
    pub fn default_inner_spot_half_angle(self, outer: f64) -> f64 {
        match self {
            Pipeline::Builtin | Pipeline::Urp => (outer.tan() * 46.0 / 64.0).atan(),
            Pipeline::Hdrp => 0.0,
        }
    }

    /// QualitySettings.lodBias of the quality level a new project renders with: built-in's Ultra
    /// (Unity's default QualitySettings.asset, lodBias 2); the URP template's High Fidelity level
    /// (its QualitySettings.asset, lodBias 2, the Standalone default); HDRP's frame settings read
    /// QualitySettings (lodBiasMode FromQualitySettings) and its template's level is not emulated:
    /// 1, APPROXIMATED.
    pub fn quality_lod_bias(self) -> f64 {
        self.quality_lod_bias_with(&settings::PipelineSettings::default())
    }

    /// `quality_lod_bias` with the cell's engine settings: built-in's from its quality level.
    pub fn quality_lod_bias_with(self, engine: &settings::PipelineSettings) -> f64 {
        match self {
            Pipeline::Builtin => engine.builtin.quality.lod_bias,
            Pipeline::Urp => 2.0,
            Pipeline::Hdrp => 1.0,
        }
    }

    /// Whether the deferred path lights through a tiled light loop (HDRP's compute light list);
    /// built-in and URP deferred draw light volumes instead, emulated by looping over every light.
    pub fn tiled_light_loop(self) -> bool {
        self == Pipeline::Hdrp
    }

    /// The rendering paths the pipeline has: built-in also keeps its legacy vertex-lit path.
    pub fn paths(self) -> &'static [RenderPath] {
        match self {
            Pipeline::Builtin => &[RenderPath::Forward, RenderPath::Deferred, RenderPath::VertexLit],
            Pipeline::Urp | Pipeline::Hdrp => &[RenderPath::Forward, RenderPath::Deferred],
        }
    }

    /// The shader that fixed objects (walls, backdrop, inner ball) are drawn with: the pipeline's
    /// default lit shader, as a new material in that pipeline would be.
    pub fn fixed_object_shader(self) -> &'static str {
        match self {
            Pipeline::Builtin => "standard",
            Pipeline::Urp | Pipeline::Hdrp => "lit",
        }
    }
}

/// Rendering path: forward (lights per object, with each pipeline's budget) or deferred (a
/// G-buffer lit in screen space, every light per pixel; `render::passes::deferred`). Every pipeline has both.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RenderPath {
    #[default]
    Forward,
    Deferred,
    /// Built-in's legacy vertex-lit path: lighting at the vertices, up to 8 lights, no shadows.
    VertexLit,
}

impl RenderPath {
    pub const ALL: [RenderPath; 3] = [RenderPath::Forward, RenderPath::Deferred, RenderPath::VertexLit];

    pub fn name(self) -> &'static str {
        match self {
            RenderPath::Forward => "forward",
            RenderPath::Deferred => "deferred",
            RenderPath::VertexLit => "vertex_lit",
        }
    }

    pub fn from_name(name: &str) -> Option<RenderPath> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|p| p.name()).collect()
    }
}

/// Point/spot distance attenuation, x = d / range (models.md#conventions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Attenuation {
    /// Built-in: its falloff texture (_LightTextureB0, read at x²) holds Unity's legacy curve,
    /// which core's LightFalloffLUT.cs LegacyUnityFalloff reproduces for the lightmapper:
    /// 1/(1 + 25x²), x clamped to 1, faded linearly in x² to 0 from x² = 0.64
    /// (`BakedFalloff::Legacy`), evaluated exactly where Unity samples a texture.
    #[serde(alias = "builtin_texture_approx")]
    BuiltinLegacy,
    /// URP: (1/max(d², HALF_MIN))·sat(1 − (d²/r²)²)².
    UrpSmoothInverseSquare,
    /// HDRP: [min(1/d, 100)·sat(1 − (d²/r²)²)]².
    HdrpPunctual,
}

impl Attenuation {
    /// f64 twin of `attenuation()` in shaders/common/conventions.wgsl.
    pub fn eval(self, distance: f64, range: f64) -> f64 {
        let d2 = distance * distance;
        match self {
            Attenuation::BuiltinLegacy => BakedFalloff::Legacy.eval(distance, range),
            Attenuation::UrpSmoothInverseSquare => {
                let a = 1.0 / (range * range).max(1e-4);
                let f = (1.0 - (d2 * a).powi(2)).clamp(0.0, 1.0);
                f * f / d2.max(crate::color::HALF_MIN)
            }
            Attenuation::HdrpPunctual => {
                let inv_d = (1.0 / distance).min(100.0);
                let f = (1.0 - (d2 / (range * range)).powi(2)).clamp(0.0, 1.0);
                (inv_d * f).powi(2)
            }
        }
    }
}

/// A baked light's distance falloff (`FalloffType`), as core's path tracer builds its falloff
/// tables (com.unity.render-pipelines.core Runtime/PathTracing/LightFalloffLUT.cs). The tables
/// sample these curves at 1024 points; the bake evaluates them exactly.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BakedFalloff {
    /// `LegacyUnityFalloff`: 1/(1 + 25x²), x = d/range clamped to 1, faded linearly in x² to 0
    /// from x² = 0.64 to 1.
    Legacy,
    /// `InverseSquaredFalloffSmooth`: (1/max(d², 10⁻⁴))·sat(1 − (d²/r²)²)², r² floored at 10⁻⁴.
    InverseSquared,
}

impl BakedFalloff {
    /// f64 twin of truth.wgsl `baked_distance_attenuation`.
    pub fn eval(self, distance: f64, range: f64) -> f64 {
        match self {
            BakedFalloff::Legacy => {
                let x2 = (distance / range).clamp(0.0, 1.0).powi(2);
                let atten = 1.0 / (1.0 + 25.0 * x2);
                if x2 >= 0.64 {
                    atten * (1.0 - (x2 - 0.64) / (1.0 - 0.64))
                } else {
                    atten
                }
            }
            BakedFalloff::InverseSquared => {
                let d2 = distance * distance;
                let factor = d2 / (range * range).max(1e-4);
                let smooth = (1.0 - factor * factor).clamp(0.0, 1.0);
                smooth * smooth / d2.max(1e-4)
            }
        }
    }
}

/// The curve from exposed linear HDR to display-linear values before sRGB encoding
/// (models.md#display); the matrix's `tonemap` key picks one per pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Tonemap {
    /// Clamp to [0, 1].
    None,
    /// Unity's fitted ACES (core ACES.hlsl / Color.hlsl `AcesTonemap`), fed sRGB→AP0.
    Aces,
    /// Unity's Neutral curve (core Color.hlsl `NeutralTonemap`).
    Neutral,
    /// Narkowicz's luminance fit of ACES, per channel; not Unity's (×2.8 brighter at the exposure target).
    Narkowicz,
}

impl Tonemap {
    pub const ALL: [Tonemap; 4] = [Tonemap::None, Tonemap::Aces, Tonemap::Neutral, Tonemap::Narkowicz];

    pub fn name(self) -> &'static str {
        match self {
            Tonemap::None => "none",
            Tonemap::Aces => "aces",
            Tonemap::Neutral => "neutral",
            Tonemap::Narkowicz => "narkowicz",
        }
    }

    pub fn from_name(name: &str) -> Option<Tonemap> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|t| t.name()).collect()
    }
}

/// Multisample anti-aliasing. It applies to forward paths only: Unity renders its deferred paths
/// without MSAA (built-in and URP ignore the setting there; HDRP multisamples only in forward-only
/// mode), so a deferred cell renders one sample and its record says why.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Antialiasing {
    #[default]
    None,
    Msaa2,
    Msaa4,
    Msaa8,
}

impl Antialiasing {
    pub const ALL: [Antialiasing; 4] =
        [Antialiasing::None, Antialiasing::Msaa2, Antialiasing::Msaa4, Antialiasing::Msaa8];

    pub fn name(self) -> &'static str {
        match self {
            Antialiasing::None => "none",
            Antialiasing::Msaa2 => "msaa2",
            Antialiasing::Msaa4 => "msaa4",
            Antialiasing::Msaa8 => "msaa8",
        }
    }

    pub fn from_name(name: &str) -> Option<Antialiasing> {
        Self::ALL.into_iter().find(|a| a.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|a| a.name()).collect()
    }

    /// Samples per pixel asked for.
    pub fn samples(self) -> u32 {
        match self {
            Antialiasing::None => 1,
            Antialiasing::Msaa2 => 2,
            Antialiasing::Msaa4 => 4,
            Antialiasing::Msaa8 => 8,
        }
    }

    /// Samples per pixel on `path`: one on deferred paths, with the reason.
    pub fn samples_on(self, path: RenderPath) -> (u32, Option<&'static str>) {
        match (self, path) {
            (Antialiasing::None, _) => (1, None),
            (_, RenderPath::Deferred) => {
                (1, Some("MSAA applies to forward paths only: Unity renders its deferred paths without it"))
            }
            (a, _) => (a.samples(), None),
        }
    }
}

/// How a cell's HDR image becomes its PNG: HDRP's exposure (None elsewhere: built-in and URP
/// have no exposure stage) and the tonemapper.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DisplayTransform {
    pub tonemap: Tonemap,
    pub exposure: Option<volume::ExposureSettings>,
}

impl DisplayTransform {
    /// `tonemap` in `pipeline`, with the scene's HDRP volume where the pipeline has one.
    pub fn new(pipeline: Pipeline, tonemap: Tonemap, hdrp: &volume::HdrpVolume) -> DisplayTransform {
        DisplayTransform { tonemap, exposure: (pipeline == Pipeline::Hdrp).then_some(hdrp.exposure) }
    }
}

/// The budgets, with Unity's defaults; the matrix's `[lights]` table sets them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightBudget {
    /// QualitySettings.pixelLightCount (built-in forward), default 4.
    #[serde(default = "four")]
    pub pixel_light_count: u32,
    /// URP asset's per-object limit of additional lights, default 4, at most 8.
    #[serde(default = "four")]
    pub urp_per_object_limit: u32,
}

fn four() -> u32 {
    4
}

impl Default for LightBudget {
    fn default() -> Self {
        LightBudget { pixel_light_count: 4, urp_per_object_limit: 4 }
    }
}

/// What a light is, as far as units and specular size go (spec's `LightKind` with its shape).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Emitter {
    Directional {
        /// Angular diameter of the sun disc, degrees (HDRP default 0.5°).
        angular_diameter_deg: f64,
    },
    Point {
        /// Shape radius, metres (HDRP default 0.025).
        radius: f64,
    },
    Spot {
        radius: f64,
        /// Full outer cone angle, degrees.
        angle_deg: f64,
        /// HDRP "Reflector": the lumen go into the cone instead of the sphere (HDAdditionalLightData
        /// `m_EnableSpotReflector = true` by default).
        reflector: bool,
        /// HDRP's spot shape (cone, pyramid, box); the other engines' spots are cones.
        #[serde(default, skip_serializing_if = "hdrp_light::SpotShape::is_cone")]
        shape: hdrp_light::SpotShape,
    },
    /// A rectangle light, metres.
    Rect { width: f64, height: f64 },
    /// A disc light, metres.
    Disc { radius: f64 },
}

/// Cascaded shadow maps of a directional light: each cascade's far edge as a fraction of the
/// shadow distance (the last is 1); beyond the distance nothing is shadowed.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadowCascades {
    pub splits: Vec<f64>,
    pub max_distance: f64,
}

/// Most cascades any pipeline uses (the layers a directional light reserves).
pub const MAX_CASCADES: usize = 4;

/// HDRP's default light shapes (HDAdditionalLightData): point/spot radius 0.025 m, sun 0.5°.
pub const HDRP_DEFAULT_SHAPE_RADIUS: f64 = 0.025;
pub const HDRP_DEFAULT_ANGULAR_DIAMETER_DEG: f64 = 0.5;

impl Emitter {
    /// Candela per lumen for points and spots, 1 for directional lux (LightUtils.cs): point
    /// I = Φ/(4π); spot with reflector I = Φ/(2π(1 − cos(θ/2))), without Φ/(4π).
    pub fn candela_per_ui_unit(self) -> f64 {
        use std::f64::consts::PI;
        match self {
            Emitter::Directional { .. } => 1.0,
            Emitter::Point { .. } => 1.0 / (4.0 * PI),
            // A box light's intensity is lux, as a directional light's (HDRP's box unit).
            Emitter::Spot { shape: hdrp_light::SpotShape::Box { .. }, .. } => 1.0,
            Emitter::Spot {
                angle_deg,
                reflector: true,
                shape: hdrp_light::SpotShape::Pyramid { aspect_ratio },
                ..
            } => 1.0 / hdrp_light::pyramid_solid_angle(angle_deg, aspect_ratio),
            Emitter::Spot { angle_deg, reflector: true, .. } => {
                1.0 / (2.0 * PI * (1.0 - (0.5 * angle_deg).to_radians().cos()))
            }
            Emitter::Spot { reflector: false, .. } => 1.0 / (4.0 * PI),
            // Nits per lumen: LightUtils.ConvertRectLightLumenToLuminance Φ/(w·h·π) and
            // ConvertDiscLightLumenToLuminance Φ/(π·r²·π).
            Emitter::Rect { width, height } => 1.0 / (width * height * PI),
            Emitter::Disc { radius } => 1.0 / (PI * radius * radius * PI),
        }
    }

    /// HDRP's per-light roughness floor, minRoughness = (1 − maxSmoothness)² (models.md#hdrp-lit):
    /// punctual maxSmoothness = clamp01(1.1725/(1.01 + (radius + 0.1)²) − 0.15); directional
    /// clamp01(1.35/(1 + (1.15·(0.0315·angularDiameter + 0.4))²) − 0.11).
    pub fn hdrp_min_roughness(self) -> f64 {
        let max_smoothness = match self {
            Emitter::Directional { angular_diameter_deg: d } => {
                1.35 / (1.0 + (1.15 * (0.0315 * d + 0.4)).powi(2)) - 0.11
            }
            Emitter::Point { radius } | Emitter::Spot { radius, .. } => 1.1725 / (1.01 + (radius + 0.1).powi(2)) - 0.15,
            // Area lights have no floor: maxSmoothness 1 (HDAdditionalLightData).
            Emitter::Rect { .. } | Emitter::Disc { .. } => 1.0,
        };
        (1.0 - max_smoothness.clamp(0.0, 1.0)).powi(2)
    }

    /// HDRP's box spot: an orthographic projector, whose intensity is lux.
    pub fn is_box(self) -> bool {
        matches!(self, Emitter::Spot { shape: hdrp_light::SpotShape::Box { .. }, .. })
    }

    /// Shader light kind: 0 directional, 1 point, 2 spot, 3 rect, 4 disc (shaders/pass/scene.wgsl `Light`).
    pub fn shader_kind(self) -> u32 {
        match self {
            Emitter::Directional { .. } => 0,
            Emitter::Point { .. } => 1,
            Emitter::Spot { .. } => 2,
            Emitter::Rect { .. } => 3,
            Emitter::Disc { .. } => 4,
        }
    }

    /// The emitting area of an area light, m² (0 for the others).
    pub fn area(self) -> f64 {
        match self {
            Emitter::Rect { width, height } => width * height,
            Emitter::Disc { radius } => std::f64::consts::PI * radius * radius,
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn baked_falloffs_follow_the_lightmappers_curves() {
        let range = 10.0;
        // Legacy: the vertex-lighting curve 1/(1 + 25x²) inside x² < 0.64, a linear fade in x²
        // after it, zero at and past the range.
        for d in [0.0, 2.0, 5.0, 7.9] {
            let x = d / range;
            assert!((BakedFalloff::Legacy.eval(d, range) - 1.0 / (1.0 + 25.0 * x * x)).abs() < 1e-15);
        }
        let x2: f64 = 0.82;
        let half_way = BakedFalloff::Legacy.eval(x2.sqrt() * range, range);
        assert!((half_way - 0.5 / (1.0 + 25.0 * x2)).abs() < 1e-12, "{half_way}");
        assert_eq!(BakedFalloff::Legacy.eval(range, range), 0.0);
        assert_eq!(BakedFalloff::Legacy.eval(2.0 * range, range), 0.0);
        // Inverse squared: URP's and HDRP's real-time curves past their floors.
        for d in [0.5, 3.0, 9.0, 9.99] {
            let baked = BakedFalloff::InverseSquared.eval(d, range);
            for a in [Attenuation::UrpSmoothInverseSquare, Attenuation::HdrpPunctual] {
                assert!((baked - a.eval(d, range)).abs() <= 1e-12 * baked.max(1.0), "{a:?} at {d}");
            }
        }
        assert!((BakedFalloff::InverseSquared.eval(0.001, range) - 1e4).abs() < 1e-6, "floored at 1 cm");
        assert_eq!(Pipeline::Builtin.baked_falloff(), BakedFalloff::Legacy);
        assert_eq!(Pipeline::Hdrp.baked_falloff(), BakedFalloff::InverseSquared);
    }

    #[test]
    fn shadow_resolution_defaults_follow_each_pipeline() {
        let sun = Emitter::Directional { angular_diameter_deg: 0.5 };
        let point = Emitter::Point { radius: 0.025 };
        // Built-in at a 256-pixel image: NextPow2(256 × 0.5 × 3.8 = 486.4) = 512; a point light
        // covering 100 pixels: NextPow2(50) = 64; capped at 4096 for a 4000-pixel image.
        assert_eq!(Pipeline::Builtin.default_shadow_resolution(sun, 256.0), 512);
        assert_eq!(Pipeline::Builtin.default_shadow_resolution(point, 100.0), 64);
        assert_eq!(Pipeline::Builtin.default_shadow_resolution(sun, 4000.0), 4096);
        assert_eq!(Pipeline::Urp.default_shadow_resolution(sun, 256.0), 2048);
        assert_eq!(Pipeline::Urp.default_shadow_resolution(point, 256.0), 1024);
        assert_eq!(Pipeline::Hdrp.default_shadow_resolution(point, 256.0), 512);
    }

    #[test]
    fn builtin_multiplies_intensity_in_gamma_space() {
        let point = Emitter::Point { radius: 0.0 };
        let c = Pipeline::Builtin.light_radiance([0.5, 0.5, 0.5], 2.0, point);
        assert!((c[0] - 1.0).abs() < 1e-12, "gamma 0.5·2 = 1 → linear 1, got {}", c[0]);
        let u = Pipeline::Urp.light_radiance([0.5, 0.5, 0.5], 2.0, point);
        assert!((u[0] - 2.0 * srgb_to_linear(0.5)).abs() < 1e-12);
        // GammaToLinearSpaceExact: pow(v, 2.2) above 1, so white × 2 → 2^2.2, not the sRGB curve's 4.95.
        let w = Pipeline::Builtin.light_radiance([1.0; 3], 2.0, point);
        assert!((w[0] - 2f64.powf(2.2)).abs() < 1e-12 && (w[0] - 4.595).abs() < 1e-3, "{}", w[0]);
    }

    #[test]
    fn hdrp_lumen_become_candela_by_shape() {
        use std::f64::consts::PI;
        let lm = |e| Pipeline::Hdrp.light_radiance([1.0; 3], 0.06, e)[0];
        // 600 lm (HDRP's default punctual intensity) is ≈ 47.7 cd.
        assert!((lm(Emitter::Point { radius: 0.025 }) - 600.0 / (4.0 * PI)).abs() < 1e-9);
        let spot = Emitter::Spot { radius: 0.025, angle_deg: 60.0, reflector: true, shape: Default::default() };
        assert!((lm(spot) - 600.0 / (2.0 * PI * (1.0 - 30f64.to_radians().cos()))).abs() < 1e-9);
        assert_eq!(lm(Emitter::Directional { angular_diameter_deg: 0.5 }), 600.0, "directional: lux as is");
    }

    #[test]
    fn hdrp_min_roughness_from_light_shape() {
        let p = Emitter::Point { radius: HDRP_DEFAULT_SHAPE_RADIUS }.hdrp_min_roughness();
        assert!((p - 4.6e-5).abs() < 0.1e-5, "spec: ≈4.6e-5, got {p:e}");
        let p0 = Emitter::Point { radius: 0.0 }.hdrp_min_roughness();
        assert!((p0 - 2.4e-7).abs() < 0.1e-7, "spec: ≈2.4e-7, got {p0:e}");
        let d = Emitter::Directional { angular_diameter_deg: HDRP_DEFAULT_ANGULAR_DIAMETER_DEG }.hdrp_min_roughness();
        assert!((d - 1.25e-4).abs() < 0.05e-4, "spec: ≈1.25e-4, got {d:e}");
    }

    #[test]
    fn builtins_realtime_falloff_is_the_legacy_curve_its_bake_uses() {
        for range in [0.5, 6.0, 40.0] {
            for x in [0.01, 0.3, 0.7, 0.8, 0.85, 0.9, 0.95, 0.99, 1.0, 1.2] {
                let (realtime, baked) = (
                    Pipeline::Builtin.attenuation().eval(x * range, range),
                    BakedFalloff::Legacy.eval(x * range, range),
                );
                assert!((realtime - baked).abs() <= 1e-12, "x {x} of range {range}: {realtime} vs the bake's {baked}");
            }
        }
    }

    #[test]
    fn attenuation_reaches_zero_at_range() {
        for a in [Attenuation::BuiltinLegacy, Attenuation::UrpSmoothInverseSquare, Attenuation::HdrpPunctual] {
            assert_eq!(a.eval(10.0, 10.0), 0.0, "{a:?}");
            assert!(a.eval(1.0, 10.0) > a.eval(5.0, 10.0), "{a:?} must fall off");
        }
        assert!((Attenuation::UrpSmoothInverseSquare.eval(1.0, 1e6) - 1.0).abs() < 1e-9);
        assert!((Attenuation::HdrpPunctual.eval(0.001, 10.0) - 1e4).abs() < 1e-3, "HDRP clamps d to 1 cm");
    }

    #[test]
    fn hdrp_spots_fall_off_over_the_whole_cone_by_default() {
        let outer = 30f64.to_radians();
        assert_eq!(Pipeline::Hdrp.default_inner_spot_half_angle(outer), 0.0);
        let urp = Pipeline::Urp.default_inner_spot_half_angle(outer);
        assert!((urp.tan() / outer.tan() - 46.0 / 64.0).abs() < 1e-12);
    }

    #[test]
    fn metallic_slider_is_gamma_decoded_in_builtin_only() {
        assert!((Pipeline::Builtin.shader_metallic(0.5) - 0.214).abs() < 1e-3);
        assert_eq!(Pipeline::Urp.shader_metallic(0.5), 0.5);
        assert_eq!(Pipeline::Hdrp.shader_metallic(0.5), 0.5);
    }
}
