//! Comparing two images of a kind: PNGs (display-referred sRGB: LDR-FLIP, SSIM, RMSE, PSNR) or
//! EXRs (linear: HDR-FLIP, RMSE, counts). A metric that cannot be computed is reported as missing,
//! with the reason, never as 0.

use serde::{Deserialize, Serialize};
use std::path::Path;

use super::stats::{bad_values, psnr, relative_mse, rmse, BadValues};
use super::{flip, ssim};
use crate::error::{Error, InputError};

#[derive(Clone)]
pub enum LoadedImage {
    /// sRGB RGBA8.
    Ldr { width: u32, height: u32, rgba8: Vec<u8> },
    /// Linear RGBA f32.
    Hdr { width: u32, height: u32, rgba: Vec<f32> },
}

impl LoadedImage {
    pub fn load(path: &Path) -> Result<LoadedImage, Error> {
        let shown = path.display().to_string();
        if !path.is_file() {
            return Err(InputError::new(shown, "image not found").into());
        }
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("png") => {
                let img =
                    image::open(path).map_err(|e| InputError::new(&shown, format!("cannot read PNG: {e}")))?.to_rgba8();
                Ok(LoadedImage::Ldr { width: img.width(), height: img.height(), rgba8: img.into_raw() })
            }
            Some("exr") => {
                let (width, height, rgba) = crate::images::encode::read_exr(path)
                    .map_err(|e| InputError::new(&shown, format!("cannot read EXR: {e}")))?;
                Ok(LoadedImage::Hdr { width, height, rgba })
            }
            _ => Err(InputError::new(shown, "unsupported image type; allowed: .png (sRGB) and .exr (linear)").into()),
        }
    }

    pub fn size(&self) -> (u32, u32) {
        match self {
            LoadedImage::Ldr { width, height, .. } | LoadedImage::Hdr { width, height, .. } => (*width, *height),
        }
    }
}

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
    #[serde(skip)]
    pub flip_map_rgba8: Option<Vec<u8>>,
    #[serde(skip)]
    pub ssim_map_rgba8: Option<Vec<u8>>,
}

/// 1 − SSIM as a heat map (the magma colour map FLIP uses, so both maps read alike).
fn ssim_heat(map: &[f64], w: usize, h: usize) -> Option<Vec<u8>> {
    let err = flip_rs::ErrorMap::new(w, h, map.iter().map(|s| (1.0 - s).clamp(0.0, 1.0) as f32).collect()).ok()?;
    flip::magma_rgba8(&err).ok()
}

/// Compare `test` against `reference` (same kind and size).
pub fn compare(reference: &LoadedImage, test: &LoadedImage, what: &str) -> Result<Comparison, Error> {
    compare_with(reference, test, what, false)
}

/// As `compare`, with per-channel SSIM when `per_channel` is set.
pub fn compare_with(
    reference: &LoadedImage,
    test: &LoadedImage,
    what: &str,
    per_channel: bool,
) -> Result<Comparison, Error> {
    let (w, h) = reference.size();
    if test.size() != (w, h) {
        return Err(
            InputError::new(what, format!("sizes differ: reference {:?}, test {:?}", (w, h), test.size())).into()
        );
    }
    let (wu, hu) = (w as usize, h as usize);
    match (reference, test) {
        (LoadedImage::Ldr { rgba8: r, .. }, LoadedImage::Ldr { rgba8: t, .. }) => {
            let flip_value = match flip::ldr(r, t, wu, hu) {
                Ok(f) => (Metric::Value { mean: f.mean }, flip::magma_rgba8(&f.map).ok()),
                Err(e) => (Metric::Missing { missing: format!("FLIP failed: {e}") }, None),
            };
            let (ssim_value, ssim_map) = match ssim::ssim(&ssim::luma(r), &ssim::luma(t), wu, hu) {
                Ok(s) => (Metric::Value { mean: s.mean }, ssim_heat(&s.map, wu, hu)),
                Err(e) => (Metric::Missing { missing: e }, None),
            };
            let to_f = |v: &[u8]| v.iter().map(|x| *x as f64 / 255.0).collect::<Vec<f64>>();
            let e = rmse(&to_f(r), &to_f(t));
            let ssim_channels = per_channel.then(|| {
                [0, 1, 2].map(|c| match ssim::ssim(&ssim::channel(r, c), &ssim::channel(t, c), wu, hu) {
                    Ok(s) => Metric::Value { mean: s.mean },
                    Err(e) => Metric::Missing { missing: e },
                })
            });
            Ok(Comparison {
                width: w,
                height: h,
                flip: FlipMetric { kind: "ldr".into(), ppd: flip::PPD, value: flip_value.0 },
                ssim: ssim_value,
                ssim_channels,
                rmse: e,
                psnr_db: psnr(e, 1.0),
                relative_mse: None,
                reference_bad: BadValues::default(),
                test_bad: BadValues::default(),
                flip_map_rgba8: flip_value.1,
                ssim_map_rgba8: ssim_map,
            })
        }
        (LoadedImage::Hdr { rgba: r, .. }, LoadedImage::Hdr { rgba: t, .. }) => {
            let rgb = |v: &[f32]| {
                v.chunks_exact(4).flat_map(|p| [p[0] as f64, p[1] as f64, p[2] as f64]).collect::<Vec<f64>>()
            };
            let (reference_bad, test_bad) = (bad_values(rgb(r).into_iter()), bad_values(rgb(t).into_iter()));
            let flip_value = if reference_bad != BadValues::default() || test_bad != BadValues::default() {
                (Metric::Missing { missing: "HDR-FLIP needs finite, non-negative pixels; see the counts".into() }, None)
            } else {
                match flip::hdr(r, t, wu, hu) {
                    Ok(f) => (Metric::Value { mean: f.mean }, flip::magma_rgba8(&f.map).ok()),
                    Err(e) => (Metric::Missing { missing: format!("HDR-FLIP failed: {e}") }, None),
                }
            };
            let to_f = |v: &[f32]| v.iter().map(|x| *x as f64).collect::<Vec<f64>>();
            Ok(Comparison {
                width: w,
                height: h,
                flip: FlipMetric { kind: "hdr".into(), ppd: flip::PPD, value: flip_value.0 },
                ssim: Metric::Missing {
                    missing: "SSIM is defined here on display-referred sRGB: compare the PNGs".into(),
                },
                ssim_channels: None,
                rmse: rmse(&to_f(r), &to_f(t)),
                psnr_db: None,
                relative_mse: relative_mse(r, t),
                reference_bad,
                test_bad,
                flip_map_rgba8: flip_value.1,
                ssim_map_rgba8: None,
            })
        }
        _ => Err(InputError::new(what, "one image is PNG and the other EXR; compare two of a kind").into()),
    }
}
