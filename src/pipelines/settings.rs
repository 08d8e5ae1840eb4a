//! The engine settings a cell renders with besides its path and budgets: the URP asset (its code
//! defaults or the URP template's High Fidelity asset, each field overridable) and built-in's
//! forward pass structure. A matrix's `[pipeline_settings]` table sets them; every cell records
//! the values it rendered with.

use serde::{Deserialize, Serialize};

use super::Antialiasing;

/// `[pipeline_settings]`, resolved.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PipelineSettings {
    pub builtin: BuiltinSettings,
    pub urp: UrpAsset,
    #[serde(default)]
    pub hdrp: HdrpSettings,
}

/// HDRP's settings: how it reads the key-light axis, its lights' shadow-map resolution and
/// filtering, and its ambient occlusion and bloom (on where the scene keeps them: `[hdrp]`), each
/// at a quality level. Every field at its default reads as records did before it existed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HdrpSettings {
    #[serde(default)]
    pub light_unit: HdrpLightUnit,
    /// The shadow-map resolution of a light whose scene entry sets none: HDAdditionalLightData's
    /// `m_ShadowResolution` override, 512 on a new light.
    #[serde(default = "hdrp_shadow_resolution", skip_serializing_if = "is_hdrp_shadow_resolution")]
    pub shadow_resolution: u32,
    /// The HDRP asset's Filtering Quality (HDShadowInitParameters.shadowFilteringQuality, Medium in
    /// a new asset): the PCF tent a shadow map is read with, or at High PCSS (`plan::shadows`).
    #[serde(default, skip_serializing_if = "HdrpQuality::is_medium")]
    pub shadow_filtering: HdrpQuality,
    /// The volume's Ambient Occlusion (on in HDRP's default profile) and its quality level
    /// (GlobalLightingQualitySettings: `render::passes::ssao::SsaoSettings::at`).
    #[serde(default = "yes", skip_serializing_if = "is_yes")]
    pub ssao: bool,
    #[serde(default, skip_serializing_if = "HdrpQuality::is_medium")]
    pub ssao_quality: HdrpQuality,
    /// The volume's Bloom (on in HDRP's default profile) and its quality level.
    #[serde(default = "yes", skip_serializing_if = "is_yes")]
    pub bloom: bool,
    #[serde(default, skip_serializing_if = "HdrpQuality::is_medium")]
    pub bloom_quality: HdrpQuality,
}

fn is_yes(v: &bool) -> bool {
    *v
}

/// A scalable setting's level (ScalableSettingLevelParameter: Low, Medium, High); a volume
/// component's own `quality` starts at Medium (VolumeComponentWithQuality), as the HDRP asset's
/// shadow filtering does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HdrpQuality {
    Low,
    #[default]
    Medium,
    High,
}

impl HdrpQuality {
    pub const ALL: [HdrpQuality; 3] = [HdrpQuality::Low, HdrpQuality::Medium, HdrpQuality::High];

    pub fn name(self) -> &'static str {
        match self {
            HdrpQuality::Low => "low",
            HdrpQuality::Medium => "medium",
            HdrpQuality::High => "high",
        }
    }

    pub fn is_medium(&self) -> bool {
        *self == HdrpQuality::Medium
    }

    /// Every level's name.
    pub fn names() -> Vec<&'static str> {
        HdrpQuality::ALL.map(HdrpQuality::name).to_vec()
    }
}

/// HDAdditionalLightData's default shadow resolution override.
pub const HDRP_SHADOW_RESOLUTION: u32 = 512;

fn hdrp_shadow_resolution() -> u32 {
    HDRP_SHADOW_RESOLUTION
}

fn is_hdrp_shadow_resolution(v: &u32) -> bool {
    *v == HDRP_SHADOW_RESOLUTION
}

impl Default for HdrpSettings {
    fn default() -> Self {
        HdrpSettings {
            light_unit: HdrpLightUnit::default(),
            shadow_resolution: HDRP_SHADOW_RESOLUTION,
            shadow_filtering: HdrpQuality::Medium,
            ssao: true,
            ssao_quality: HdrpQuality::Medium,
            bloom: true,
            bloom_quality: HdrpQuality::Medium,
        }
    }
}

/// The HDRP reading of the light-intensity axis (0–100), always × 10⁴ as the app's slider was.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HdrpLightUnit {
    /// The app's: lumen for point and spot lights (candela by the shape, LightUtils.cs), lux for
    /// directional ones.
    #[default]
    Lumen,
    /// Candela for point and spot lights (no shape conversion), lux for directional ones.
    Candela,
    /// Built-in's and URP's unitless intensity I, converted to what delivers the same irradiance
    /// there (π·I): candela or lux = π·I, × 10⁴ as HDRP's sky is, so the sky and the key light keep
    /// URP's balance.
    Unity,
}

impl HdrpLightUnit {
    pub const ALL: [HdrpLightUnit; 3] = [HdrpLightUnit::Lumen, HdrpLightUnit::Candela, HdrpLightUnit::Unity];

    pub fn name(self) -> &'static str {
        match self {
            HdrpLightUnit::Lumen => "lumen",
            HdrpLightUnit::Candela => "candela",
            HdrpLightUnit::Unity => "unity",
        }
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|u| u.name()).collect()
    }
}

/// Built-in's forward pass structure and its quality level's shadow fields (the level's pixel
/// light count and anti-aliasing are the cell's light budget and anti-aliasing).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuiltinSettings {
    /// true (Unity): every pixel light past the main directional one is its own additive
    /// ForwardAdd draw of the object. false: those lights are summed in the base draw instead —
    /// not an engine setting, but the single-pass image the additive passes must add up to, and
    /// the cost they add.
    #[serde(default = "yes")]
    pub forward_add: bool,
    /// The quality level's shadow fields; Ultra's unless a matrix says otherwise (a record of
    /// Ultra's cells reads as it did before the fields existed).
    #[serde(default, skip_serializing_if = "BuiltinQuality::is_ultra")]
    pub quality: BuiltinQuality,
}

impl Default for BuiltinSettings {
    fn default() -> Self {
        BuiltinSettings { forward_add: true, quality: BuiltinQuality::default() }
    }
}

/// A built-in quality level's shadow fields (QualitySettings: shadows, shadowResolution,
/// shadowCascades, shadowDistance, the 2- and 4-cascade splits at their defaults).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuiltinQuality {
    /// The level the fields started from.
    #[serde(default)]
    pub level: QualityLevel,
    #[serde(default = "all_shadows")]
    pub shadows: BuiltinShadows,
    #[serde(default = "high_resolution")]
    pub shadow_resolution: ShadowResolutionLevel,
    /// 1, 2 or 4 (built-in has no three-cascade setting).
    #[serde(default = "four_cascades")]
    pub shadow_cascades: u32,
    /// Metres.
    #[serde(default = "ultra_distance")]
    pub shadow_distance: f64,
    /// QualitySettings.lodBias: LOD groups switch as if their screen height were this much larger.
    #[serde(default = "ultra_lod_bias")]
    pub lod_bias: f64,
}

fn all_shadows() -> BuiltinShadows {
    BuiltinShadows::All
}
fn high_resolution() -> ShadowResolutionLevel {
    ShadowResolutionLevel::High
}
fn four_cascades() -> u32 {
    4
}
fn ultra_distance() -> f64 {
    150.0
}
fn ultra_lod_bias() -> f64 {
    2.0
}

impl Default for BuiltinQuality {
    fn default() -> Self {
        QualityLevel::Ultra.fields().0
    }
}

impl BuiltinQuality {
    fn is_ultra(&self) -> bool {
        *self == BuiltinQuality::default()
    }

    /// The directional cascades' far edges as fractions of the shadow distance
    /// (shadowCascade2Split 1/3, shadowCascade4Split (0.067, 0.2, 0.467)).
    pub fn cascade_splits(&self) -> Vec<f64> {
        match self.shadow_cascades {
            2 => vec![1.0 / 3.0, 1.0],
            4 => vec![0.067, 0.2, 0.467, 1.0],
            _ => vec![1.0],
        }
    }
}

/// QualitySettings.shadows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BuiltinShadows {
    /// No real-time shadows.
    Disable,
    /// Hard shadows only: a light asking for soft ones gets hard ones.
    HardOnly,
    All,
}

impl BuiltinShadows {
    pub const ALL: [BuiltinShadows; 3] = [BuiltinShadows::Disable, BuiltinShadows::HardOnly, BuiltinShadows::All];

    pub fn name(self) -> &'static str {
        match self {
            BuiltinShadows::Disable => "disable",
            BuiltinShadows::HardOnly => "hard_only",
            BuiltinShadows::All => "all",
        }
    }
}

/// QualitySettings.shadowResolution: the multiplier of the built-in shadow-map size (Unity manual,
/// "Configure shadow resolution in the Built-In Render Pipeline": Very High 1, High 0.5, Medium
/// 0.25, Low 0.125).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShadowResolutionLevel {
    Low,
    Medium,
    High,
    VeryHigh,
}

impl ShadowResolutionLevel {
    pub const ALL: [ShadowResolutionLevel; 4] = [
        ShadowResolutionLevel::Low,
        ShadowResolutionLevel::Medium,
        ShadowResolutionLevel::High,
        ShadowResolutionLevel::VeryHigh,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ShadowResolutionLevel::Low => "low",
            ShadowResolutionLevel::Medium => "medium",
            ShadowResolutionLevel::High => "high",
            ShadowResolutionLevel::VeryHigh => "very_high",
        }
    }

    pub fn multiplier(self) -> f64 {
        match self {
            ShadowResolutionLevel::Low => 0.125,
            ShadowResolutionLevel::Medium => 0.25,
            ShadowResolutionLevel::High => 0.5,
            ShadowResolutionLevel::VeryHigh => 1.0,
        }
    }
}

/// The six quality levels of a new built-in project's ProjectSettings/QualitySettings.asset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum QualityLevel {
    VeryLow,
    Low,
    Medium,
    High,
    VeryHigh,
    /// The level a new project renders with on desktop (m_CurrentQuality 5).
    #[default]
    Ultra,
}

impl QualityLevel {
    pub const ALL: [QualityLevel; 6] = [
        QualityLevel::VeryLow,
        QualityLevel::Low,
        QualityLevel::Medium,
        QualityLevel::High,
        QualityLevel::VeryHigh,
        QualityLevel::Ultra,
    ];

    pub fn name(self) -> &'static str {
        match self {
            QualityLevel::VeryLow => "very_low",
            QualityLevel::Low => "low",
            QualityLevel::Medium => "medium",
            QualityLevel::High => "high",
            QualityLevel::VeryHigh => "very_high",
            QualityLevel::Ultra => "ultra",
        }
    }

    /// The level's shadow fields, LOD bias, pixel light count and anti-aliasing, as the default
    /// QualitySettings.asset lists them (pixelLightCount, shadows, shadowResolution,
    /// shadowCascades, shadowDistance, lodBias, antiAliasing): Very Low 0/Disable/Low/1/15 m/0.3/off,
    /// Low 0/Disable/Low/1/20 m/0.4/off, Medium 1/HardOnly/Low/1/20 m/0.7/off, High
    /// 2/All/Medium/2/40 m/1/off, Very High 3/All/High/2/70 m/1.5/2×, Ultra 4/All/High/4/150 m/2/4×.
    pub fn fields(self) -> (BuiltinQuality, u32, Antialiasing) {
        use BuiltinShadows::*;
        use ShadowResolutionLevel as R;
        let (pixel, shadows, resolution, cascades, distance, lod_bias, aa) = match self {
            QualityLevel::VeryLow => (0, Disable, R::Low, 1, 15.0, 0.3, Antialiasing::None),
            QualityLevel::Low => (0, Disable, R::Low, 1, 20.0, 0.4, Antialiasing::None),
            QualityLevel::Medium => (1, HardOnly, R::Low, 1, 20.0, 0.7, Antialiasing::None),
            QualityLevel::High => (2, All, R::Medium, 2, 40.0, 1.0, Antialiasing::None),
            QualityLevel::VeryHigh => (3, All, R::High, 2, 70.0, 1.5, Antialiasing::Msaa2),
            QualityLevel::Ultra => (4, All, R::High, 4, 150.0, 2.0, Antialiasing::Msaa4),
        };
        let quality = BuiltinQuality {
            level: self,
            shadows,
            shadow_resolution: resolution,
            shadow_cascades: cascades,
            shadow_distance: distance,
            lod_bias,
        };
        (quality, pixel, aa)
    }
}

fn yes() -> bool {
    true
}

/// The named URP assets a matrix starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UrpAssetPreset {
    /// What *Create ▸ Rendering ▸ URP Asset* makes: the field initialisers of
    /// UniversalRenderPipelineAsset.cs (com.unity.render-pipelines.universal/Runtime/Data).
    #[default]
    Default,
    /// The URP project template's `Assets/Settings/URP-HighFidelity.asset` (URP 14, asset version 11).
    HighFidelity,
}

impl UrpAssetPreset {
    pub const ALL: [UrpAssetPreset; 2] = [UrpAssetPreset::Default, UrpAssetPreset::HighFidelity];

    pub fn name(self) -> &'static str {
        match self {
            UrpAssetPreset::Default => "default",
            UrpAssetPreset::HighFidelity => "high_fidelity",
        }
    }

    pub fn from_name(name: &str) -> Option<UrpAssetPreset> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|p| p.name()).collect()
    }

    /// The asset's fields.
    pub fn asset(self) -> UrpAsset {
        match self {
            // UniversalRenderPipelineAsset.cs: m_MSAA = Disabled, m_MainLightShadowmapResolution =
            // _2048, m_AdditionalLightsPerObjectLimit = 4, m_AdditionalLightShadowsSupported = false,
            // m_AdditionalLightsShadowResolutionTierHigh = 1024, m_ReflectionProbeBlending = false,
            // m_ReflectionProbeBoxProjection = false, m_ShadowDistance = 50, m_ShadowCascadeCount = 1,
            // m_ShadowDepthBias = 1, m_ShadowNormalBias = 1, m_SoftShadowsSupported = false.
            UrpAssetPreset::Default => UrpAsset {
                preset: self,
                msaa: Antialiasing::None,
                main_light_shadow_resolution: 2048,
                additional_lights_per_object_limit: 4,
                additional_light_shadows: false,
                additional_light_shadow_resolution: 1024,
                reflection_probe_blending: false,
                reflection_probe_box_projection: false,
                shadow_distance: 50.0,
                cascade_count: 1,
                depth_bias: 1.0,
                normal_bias: 1.0,
                soft_shadows: false,
                ssao: None,
            },
            // URP-HighFidelity.asset: m_MSAA: 4, m_MainLightShadowmapResolution: 4096,
            // m_AdditionalLightsPerObjectLimit: 8, m_AdditionalLightShadowsSupported: 1,
            // m_AdditionalLightsShadowResolutionTierHigh: 512, m_ReflectionProbeBlending: 1,
            // m_ReflectionProbeBoxProjection: 1, m_ShadowDistance: 150, m_ShadowCascadeCount: 2
            // (m_Cascade2Split 0.25), biases 1 / 1, m_SoftShadowsSupported: 1; its renderer,
            // URP-HighFidelity-Renderer.asset, has the SSAO feature (UrpSsaoFeature::HIGH_FIDELITY).
            UrpAssetPreset::HighFidelity => UrpAsset {
                preset: self,
                msaa: Antialiasing::Msaa4,
                main_light_shadow_resolution: 4096,
                additional_lights_per_object_limit: 8,
                additional_light_shadows: true,
                additional_light_shadow_resolution: 512,
                reflection_probe_blending: true,
                reflection_probe_box_projection: true,
                shadow_distance: 150.0,
                cascade_count: 2,
                depth_bias: 1.0,
                normal_bias: 1.0,
                soft_shadows: true,
                ssao: Some(UrpSsaoFeature::HIGH_FIDELITY),
            },
        }
    }
}

/// The URP asset's fields that change a frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct UrpAsset {
    /// The asset the fields started from.
    pub preset: UrpAssetPreset,
    /// Anti-aliasing (m_MSAA); the matrix's `antialiasing.urp`, where it names one, wins.
    pub msaa: Antialiasing,
    /// m_MainLightShadowmapResolution, texels.
    pub main_light_shadow_resolution: u32,
    /// m_AdditionalLightsPerObjectLimit; `[lights] urp_per_object_limit`, where given, wins.
    pub additional_lights_per_object_limit: u32,
    /// m_AdditionalLightShadowsSupported: without it a point or spot light casts no shadow,
    /// whatever the light says.
    pub additional_light_shadows: bool,
    /// m_AdditionalLightsShadowResolutionTierHigh: a light's default tier is High.
    pub additional_light_shadow_resolution: u32,
    /// m_ReflectionProbeBlending, m_ReflectionProbeBoxProjection: recorded; the compositions have
    /// one probe, so blending changes nothing, and box projection is not drawn (docs/deviations.md).
    pub reflection_probe_blending: bool,
    pub reflection_probe_box_projection: bool,
    /// m_ShadowDistance, metres, and m_ShadowCascadeCount (splits: m_Cascade2Split 0.25,
    /// m_Cascade3Split (0.1, 0.3), m_Cascade4Split (0.067, 0.2, 0.467)).
    pub shadow_distance: f64,
    pub cascade_count: u32,
    /// m_ShadowDepthBias and m_ShadowNormalBias, in shadow-map texels (URP's
    /// ShadowUtils.GetShadowBias scales both by the texel size, and by 2.5 with soft shadows).
    pub depth_bias: f64,
    pub normal_bias: f64,
    /// m_SoftShadowsSupported: lights asking for soft shadows get them only with it.
    pub soft_shadows: bool,
    /// The asset's renderer's Screen Space Ambient Occlusion feature, where it has one (the
    /// default asset's renderer has none; `[pipeline_settings.urp] ssao` adds or removes it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ssao: Option<UrpSsaoFeature>,
}

/// URP's Screen Space Ambient Occlusion renderer feature (ScreenSpaceAmbientOcclusion.cs
/// ScreenSpaceAmbientOcclusionSettings), the fields a frame reads. The rest are fixed at what the
/// High Fidelity renderer ships and this tool draws: AOMethod InterleavedGradient (1), Source
/// DepthNormals, full resolution (Downsample 0), BlurQuality High (bilateral), AfterOpaque off (the
/// lit shaders read it).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UrpSsaoFeature {
    /// Intensity (_SSAOParams.x).
    pub intensity: f64,
    /// Radius, metres (_SSAOParams.y; the Interleaved Gradient method passes it as is).
    pub radius: f64,
    /// DirectLightingStrength: how much of the occlusion reaches the direct light
    /// (_AmbientOcclusionParam.w; AmbientOcclusion.hlsl lerp(1, SSAO, w)).
    pub direct_lighting_strength: f64,
    /// Samples per pixel: the Samples option's count (High 12, Medium 8, Low 4; SSAO.hlsl SAMPLE_COUNT).
    pub samples: u32,
    /// Falloff distance, metres (_SSAOParams.w): no occlusion beyond it.
    pub falloff: f64,
}

impl UrpSsaoFeature {
    /// URP-HighFidelity-Renderer.asset's feature (the URP template, URP 14): AOMethod 1, Downsample
    /// 0, AfterOpaque 0, Source 1, NormalSamples 1, Intensity 0.5, DirectLightingStrength 0.25,
    /// Radius 0.25, Samples 0 (High), BlurQuality 0 (High), Falloff 100.
    pub const HIGH_FIDELITY: UrpSsaoFeature =
        UrpSsaoFeature { intensity: 0.5, radius: 0.25, direct_lighting_strength: 0.25, samples: 12, falloff: 100.0 };
}

impl Default for UrpAsset {
    fn default() -> Self {
        UrpAssetPreset::Default.asset()
    }
}

impl UrpAsset {
    /// The cascades' far edges as fractions of the shadow distance (the asset's split fields).
    pub fn cascade_splits(&self) -> Vec<f64> {
        match self.cascade_count {
            2 => vec![0.25, 1.0],
            3 => vec![0.1, 0.3, 1.0],
            4 => vec![0.067, 0.2, 0.467, 1.0],
            _ => vec![1.0],
        }
    }
}

/// `[pipeline_settings.urp]` as written: an asset name and any field overridden.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UrpAssetFile {
    pub asset: Option<String>,
    pub msaa: Option<String>,
    pub main_light_shadow_resolution: Option<u32>,
    pub additional_lights_per_object_limit: Option<u32>,
    pub additional_light_shadows: Option<bool>,
    pub additional_light_shadow_resolution: Option<u32>,
    pub reflection_probe_blending: Option<bool>,
    pub reflection_probe_box_projection: Option<bool>,
    pub shadow_distance: Option<f64>,
    pub cascade_count: Option<u32>,
    pub depth_bias: Option<f64>,
    pub normal_bias: Option<f64>,
    pub soft_shadows: Option<bool>,
    /// The renderer's SSAO feature: false removes it; true gives an asset without one the High
    /// Fidelity renderer's.
    pub ssao: Option<bool>,
}

/// `[pipeline_settings.builtin]` as written: the pass structure, a quality level and any of its
/// shadow fields overridden (its pixel light count and anti-aliasing are `[lights]` and
/// `[antialiasing]`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuiltinSettingsFile {
    pub forward_add: Option<bool>,
    pub quality_level: Option<QualityLevel>,
    pub shadows: Option<BuiltinShadows>,
    pub shadow_resolution: Option<ShadowResolutionLevel>,
    pub shadow_cascades: Option<u32>,
    pub shadow_distance: Option<f64>,
    pub lod_bias: Option<f64>,
}

impl BuiltinSettingsFile {
    fn resolve(&self) -> Result<BuiltinSettings, SettingsError> {
        let mut quality = self.quality_level.unwrap_or_default().fields().0;
        if let Some(v) = self.shadows {
            quality.shadows = v;
        }
        if let Some(v) = self.shadow_resolution {
            quality.shadow_resolution = v;
        }
        if let Some(v) = self.shadow_cascades {
            if ![1, 2, 4].contains(&v) {
                return Err(("builtin.shadow_cascades".into(), format!("{v}: allowed 1, 2, 4")));
            }
            quality.shadow_cascades = v;
        }
        if let Some(v) = self.shadow_distance {
            if !(v.is_finite() && (0.0..=10_000.0).contains(&v)) {
                return Err(("builtin.shadow_distance".into(), format!("{v}: allowed 0..=10000")));
            }
            quality.shadow_distance = v;
        }
        if let Some(v) = self.lod_bias {
            if !(v.is_finite() && (0.01..=10.0).contains(&v)) {
                return Err(("builtin.lod_bias".into(), format!("{v}: allowed 0.01..=10")));
            }
            quality.lod_bias = v;
        }
        Ok(BuiltinSettings { forward_add: self.forward_add.unwrap_or(true), quality })
    }
}

/// `[pipeline_settings]` as written.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PipelineSettingsFile {
    #[serde(default)]
    pub builtin: BuiltinSettingsFile,
    #[serde(default)]
    pub urp: UrpAssetFile,
    #[serde(default)]
    pub hdrp: HdrpSettingsFile,
}

/// `[pipeline_settings.hdrp]` as written.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HdrpSettingsFile {
    pub light_unit: Option<String>,
    pub shadow_resolution: Option<u32>,
    pub shadow_filtering: Option<String>,
    pub ssao: Option<bool>,
    pub ssao_quality: Option<String>,
    pub bloom: Option<bool>,
    pub bloom_quality: Option<String>,
}

/// A quality level as `[pipeline_settings.hdrp]` names it.
fn hdrp_quality(key: &str, value: &Option<String>) -> Result<HdrpQuality, SettingsError> {
    let Some(name) = value else { return Ok(HdrpQuality::Medium) };
    match HdrpQuality::ALL.into_iter().find(|q| q.name() == name) {
        Some(q) => Ok(q),
        None => Err((format!("hdrp.{key}"), format!("`{name}`: allowed {}", HdrpQuality::names().join(", ")))),
    }
}

/// Why a `[pipeline_settings]` value was refused: the key under `pipeline_settings` and the message.
pub type SettingsError = (String, String);

impl PipelineSettingsFile {
    /// The settings: the named asset with the overrides applied, each checked against its range.
    pub fn resolve(&self) -> Result<PipelineSettings, SettingsError> {
        let u = &self.urp;
        let preset = match &u.asset {
            None => UrpAssetPreset::Default,
            Some(name) => UrpAssetPreset::from_name(name).ok_or_else(|| {
                ("urp.asset".to_string(), format!("`{name}`: allowed {}", UrpAssetPreset::names().join(", ")))
            })?,
        };
        let mut a = preset.asset();
        if let Some(name) = &u.msaa {
            a.msaa = Antialiasing::from_name(name).ok_or_else(|| {
                ("urp.msaa".to_string(), format!("`{name}`: allowed {}", Antialiasing::names().join(", ")))
            })?;
        }
        let resolution = |key: &str, v: Option<u32>, into: &mut u32| -> Result<(), SettingsError> {
            if let Some(v) = v {
                if !(v.is_power_of_two() && (128..=8192).contains(&v)) {
                    return Err((format!("urp.{key}"), format!("{v}: allowed a power of two from 128 to 8192")));
                }
                *into = v;
            }
            Ok(())
        };
        resolution(
            "main_light_shadow_resolution",
            u.main_light_shadow_resolution,
            &mut a.main_light_shadow_resolution,
        )?;
        resolution(
            "additional_light_shadow_resolution",
            u.additional_light_shadow_resolution,
            &mut a.additional_light_shadow_resolution,
        )?;
        if let Some(v) = u.additional_lights_per_object_limit {
            if v > 8 {
                return Err(("urp.additional_lights_per_object_limit".into(), format!("{v}: allowed 0..=8")));
            }
            a.additional_lights_per_object_limit = v;
        }
        if let Some(v) = u.cascade_count {
            if !(1..=4).contains(&v) {
                return Err(("urp.cascade_count".into(), format!("{v}: allowed 1..=4")));
            }
            a.cascade_count = v;
        }
        for (key, v, into) in [
            ("shadow_distance", u.shadow_distance, &mut a.shadow_distance),
            ("depth_bias", u.depth_bias, &mut a.depth_bias),
            ("normal_bias", u.normal_bias, &mut a.normal_bias),
        ] {
            if let Some(v) = v {
                let hi = if key == "shadow_distance" { 10_000.0 } else { 10.0 };
                if !(v.is_finite() && (0.0..=hi).contains(&v)) {
                    return Err((format!("urp.{key}"), format!("{v}: allowed 0..={hi}")));
                }
                *into = v;
            }
        }
        for (v, into) in [
            (u.additional_light_shadows, &mut a.additional_light_shadows),
            (u.reflection_probe_blending, &mut a.reflection_probe_blending),
            (u.reflection_probe_box_projection, &mut a.reflection_probe_box_projection),
            (u.soft_shadows, &mut a.soft_shadows),
        ] {
            if let Some(v) = v {
                *into = v;
            }
        }
        match u.ssao {
            Some(false) => a.ssao = None,
            Some(true) => a.ssao = a.ssao.or(Some(UrpSsaoFeature::HIGH_FIDELITY)),
            None => {}
        }
        let light_unit = match &self.hdrp.light_unit {
            None => HdrpLightUnit::default(),
            Some(name) => HdrpLightUnit::ALL.into_iter().find(|u| u.name() == name).ok_or_else(|| {
                ("hdrp.light_unit".to_string(), format!("`{name}`: allowed {}", HdrpLightUnit::names().join(", ")))
            })?,
        };
        if let Some(v) = self.hdrp.shadow_resolution {
            if !(v.is_power_of_two() && (128..=8192).contains(&v)) {
                return Err(("hdrp.shadow_resolution".into(), format!("{v}: allowed a power of two from 128 to 8192")));
            }
        }
        let h = &self.hdrp;
        let hdrp = HdrpSettings {
            light_unit,
            shadow_resolution: h.shadow_resolution.unwrap_or(HDRP_SHADOW_RESOLUTION),
            shadow_filtering: hdrp_quality("shadow_filtering", &h.shadow_filtering)?,
            ssao: h.ssao.unwrap_or(true),
            ssao_quality: hdrp_quality("ssao_quality", &h.ssao_quality)?,
            bloom: h.bloom.unwrap_or(true),
            bloom_quality: hdrp_quality("bloom_quality", &h.bloom_quality)?,
        };
        Ok(PipelineSettings { builtin: self.builtin.resolve()?, urp: a, hdrp })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_code_defaults_turn_additional_and_soft_shadows_off() {
        let a = PipelineSettingsFile::default().resolve().unwrap().urp;
        assert!(!a.additional_light_shadows && !a.soft_shadows && !a.reflection_probe_box_projection);
        assert_eq!((a.main_light_shadow_resolution, a.cascade_count, a.shadow_distance), (2048, 1, 50.0));
    }

    #[test]
    fn a_preset_field_can_be_overridden_and_ranges_are_checked() {
        let f: PipelineSettingsFile =
            toml::from_str("[urp]\nasset = \"high_fidelity\"\nsoft_shadows = false\n").unwrap();
        let a = f.resolve().unwrap().urp;
        assert_eq!(a.preset, UrpAssetPreset::HighFidelity);
        assert!(a.additional_light_shadows && !a.soft_shadows);
        assert_eq!(a.cascade_splits(), vec![0.25, 1.0]);
        let bad: PipelineSettingsFile = toml::from_str("[urp]\nasset = \"hifi\"\n").unwrap();
        assert_eq!(bad.resolve().unwrap_err().0, "urp.asset");
        let bad: PipelineSettingsFile = toml::from_str("[urp]\ncascade_count = 5\n").unwrap();
        assert_eq!(bad.resolve().unwrap_err().0, "urp.cascade_count");
    }

    #[test]
    fn hdrps_quality_levels_are_read_and_an_unknown_one_is_refused() {
        let f: PipelineSettingsFile =
            toml::from_str("[hdrp]\nshadow_filtering = \"high\"\nbloom_quality = \"low\"\nssao_quality = \"high\"\n")
                .unwrap();
        let h = f.resolve().unwrap().hdrp;
        assert_eq!(
            (h.shadow_filtering, h.bloom_quality, h.ssao_quality),
            (HdrpQuality::High, HdrpQuality::Low, HdrpQuality::High)
        );
        let bad: PipelineSettingsFile = toml::from_str("[hdrp]\nssao_quality = \"ultra\"\n").unwrap();
        let (key, why) = bad.resolve().unwrap_err();
        assert_eq!((key.as_str(), why.as_str()), ("hdrp.ssao_quality", "`ultra`: allowed low, medium, high"));
    }

    #[test]
    fn only_the_high_fidelity_renderer_has_the_ssao_feature_and_the_switch_moves_it() {
        assert_eq!(UrpAssetPreset::Default.asset().ssao, None);
        let hf = UrpAssetPreset::HighFidelity.asset().ssao.unwrap();
        assert_eq!((hf.intensity, hf.radius, hf.direct_lighting_strength), (0.5, 0.25, 0.25));
        assert_eq!((hf.samples, hf.falloff), (12, 100.0));
        let off: PipelineSettingsFile = toml::from_str("[urp]\nasset = \"high_fidelity\"\nssao = false\n").unwrap();
        assert_eq!(off.resolve().unwrap().urp.ssao, None);
        let on: PipelineSettingsFile = toml::from_str("[urp]\nssao = true\n").unwrap();
        assert_eq!(on.resolve().unwrap().urp.ssao, Some(hf));
        // A default asset's record is what it was before the feature existed (its cells' ids hold).
        let json = serde_json::to_string(&UrpAssetPreset::Default.asset()).unwrap();
        assert!(!json.contains("ssao"), "{json}");
    }
}
