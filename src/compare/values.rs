//! What a comparison measured, as records hold it: plain data (no device, no image decoding), so
//! `record/` reads and writes it without the metric code or wgpu.

use serde::{Deserialize, Serialize};

use super::stats::BadValues;

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Metric {
    Value { mean: f64 },
    Missing { missing: String },
}

impl Metric {
    pub fn mean(&self) -> Option<f64> {
        match self {
            Metric::Value { mean } => Some(*mean),
            Metric::Missing { .. } => None,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct FlipMetric {
    /// "ldr" or "hdr".
    pub kind: String,
    pub ppd: f32,
    #[serde(flatten)]
    pub value: Metric,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Comparison {
    pub width: u32,
    pub height: u32,
    pub flip: FlipMetric,
    /// On the luma of the sRGB values (PNG inputs only).
    pub ssim: Metric,
    /// SSIM of R, G and B separately, when asked for (PNG inputs only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ssim_channels: Option<[Metric; 3]>,
    /// Over RGB: sRGB values in [0, 1] for PNGs, linear values for EXRs.
    pub rmse: f64,
    /// PNGs: peak 1; None for identical images, and for EXRs (no fixed peak).
    pub psnr_db: Option<f64>,
    /// Linear images: the relative MSE (`stats::relative_mse`); None for display-referred ones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relative_mse: Option<f64>,
    pub reference_bad: BadValues,
    pub test_bad: BadValues,
    /// Where FLIP and SSIM were computed: `gpu` (`compare::gpu`) or `cpu` (flip-rs and
    /// `compare::ssim`, the reference).
    #[serde(default)]
    pub computed_on: String,
    #[serde(skip)]
    pub flip_map_rgba8: Option<Vec<u8>>,
    #[serde(skip)]
    pub ssim_map_rgba8: Option<Vec<u8>>,
}
