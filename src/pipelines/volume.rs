//! HDRP volume settings the emulation honours: the Exposure override. Defaults are those of HDRP's
//! default volume profile (Editor/RenderPipelineResources/DefaultSettingsVolumeProfile.asset):
//! mode Automatic, metering CenterWeighted, limits −10..10 EV100, no compensation. A scene may
//! override them under `[hdrp.exposure]`, as an HDRP project's own volume would (models.md#exposure).
//! The metering itself is an image operation (`images::exposure`).

use serde::{Deserialize, Serialize};

/// HDRP `ExposureMode` values this tool emulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExposureMode {
    /// Weighted mean of every pixel's EV100 (Exposure.compute, KPrePass + KReduction).
    Automatic,
    /// Mean over a percentile band of the EV100 histogram (default 40–90 %).
    AutomaticHistogram,
    /// `fixed_ev` as is.
    Fixed,
}

/// HDRP `MeteringMode` values this tool emulates (ExposureCommon.hlsl `WeightSample`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MeteringMode {
    /// Every pixel weighs 1.
    Average,
    /// 1 − sat(|centre − pixel| / (0.5·(width + height))).
    CenterWeighted,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExposureSettings {
    #[serde(default = "automatic")]
    pub mode: ExposureMode,
    #[serde(default = "center_weighted")]
    pub metering: MeteringMode,
    /// EV100 limits of the automatic modes.
    #[serde(default = "limit_min")]
    pub limit_min: f64,
    #[serde(default = "limit_max")]
    pub limit_max: f64,
    /// Subtracted from the metered (or fixed) EV100: +1 brightens the image by one stop.
    #[serde(default)]
    pub compensation: f64,
    /// EV100 of the fixed mode.
    #[serde(default)]
    pub fixed_ev: f64,
    /// Histogram mode: the percentile band that sets the exposure, percent.
    #[serde(default = "histogram_percent")]
    pub histogram_percent: [f64; 2],
}

fn automatic() -> ExposureMode {
    ExposureMode::Automatic
}
fn center_weighted() -> MeteringMode {
    MeteringMode::CenterWeighted
}
fn limit_min() -> f64 {
    -10.0
}
fn limit_max() -> f64 {
    10.0
}
fn histogram_percent() -> [f64; 2] {
    [40.0, 90.0]
}

impl Default for ExposureSettings {
    fn default() -> Self {
        ExposureSettings {
            mode: automatic(),
            metering: center_weighted(),
            limit_min: limit_min(),
            limit_max: limit_max(),
            compensation: 0.0,
            fixed_ev: 0.0,
            histogram_percent: histogram_percent(),
        }
    }
}

/// The HDRP volume overrides a scene may carry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HdrpVolume {
    #[serde(default)]
    pub exposure: ExposureSettings,
    /// The default volume's bloom (intensity 0.2, scatter 0.7, threshold 0; `render::passes::bloom`); on
    /// as HDRP ships it.
    #[serde(default = "enabled")]
    pub bloom: bool,
    /// The default volume's screen-space ambient occlusion (GTAO, intensity 0.5, radius 1.5,
    /// Medium quality; `render::passes::ssao`); on as HDRP ships it.
    #[serde(default = "enabled")]
    pub ssao: bool,
}

impl Default for HdrpVolume {
    fn default() -> Self {
        HdrpVolume { exposure: ExposureSettings::default(), bloom: true, ssao: true }
    }
}

fn enabled() -> bool {
    true
}

/// The lens attenuation term of ColorUtils.cs: exposure = 1/(1.2·2^EV100), 1.2 = 78/(100·0.65).
pub const LENS_IMPERFECTION_EXPOSURE_SCALE: f64 = 1.2;

/// ColorUtils.ConvertEV100ToExposure.
pub fn ev100_to_exposure(ev100: f64) -> f64 {
    1.0 / (LENS_IMPERFECTION_EXPOSURE_SCALE * ev100.exp2())
}

/// HDRP effects of the default volume this emulation does not render, for `list` and the README.
pub const LEFT_OUT_EFFECTS: &str = "HDRP's default volume also enables contact shadows, but a light casts them only where its own \"Contact Shadows\" setting is on, and HDRP lights ship with it off (HDAdditionalLightData.useContactShadow); no scene light here opts in, so they cannot change an image and are not rendered. Bloom and SSAO are rendered ([hdrp] bloom, [hdrp] ssao); SSAO runs HDRP's non-temporal path, as a still batch frame has no history to accumulate";
