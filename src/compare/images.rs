//! Comparing two images of a kind: PNGs (display-referred sRGB: LDR-FLIP, SSIM, RMSE, PSNR) or
//! EXRs (linear: HDR-FLIP, RMSE, counts). A metric that cannot be computed is reported as missing,
//! with the reason, never as 0.

use std::path::Path;

use super::stats::{bad_values, psnr, relative_mse, rmse, BadValues};
pub use super::values::{Comparison, FlipMetric, Metric};
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
        let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !matches!(extension.as_deref(), Some("png" | "exr")) {
            return Err(InputError::new(shown, "unsupported image type; allowed: .png (sRGB) and .exr (linear)").into());
        }
        let bytes = crate::input::read::read(path, crate::input::read::IMAGE).map_err(|e| match e {
            crate::input::read::ReadError::NotFound => InputError::new(&shown, "image not found"),
            e => InputError::new(&shown, e.to_string()),
        })?;
        match extension.as_deref() {
            Some("png") => {
                let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
                    .map_err(|e| InputError::new(&shown, format!("cannot read PNG: {e}")))?
                    .to_rgba8();
                Ok(LoadedImage::Ldr { width: img.width(), height: img.height(), rgba8: img.into_raw() })
            }
            Some("exr") => {
                let (width, height, rgba) = crate::images::encode::exr_from_bytes(&bytes)
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

/// 1 − SSIM as a heat map (the magma colour map FLIP uses, so both maps read alike).
fn ssim_heat(map: &[f64], w: usize, h: usize) -> Option<Vec<u8>> {
    let err = flip_rs::ErrorMap::new(w, h, map.iter().map(|s| (1.0 - s).clamp(0.0, 1.0) as f32).collect()).ok()?;
    flip::magma_rgba8(&err).ok()
}

/// Where FLIP and SSIM run.
#[derive(Clone, Copy)]
pub enum MetricsBackend<'a> {
    Cpu,
    Gpu(&'a super::gpu::GpuMetrics),
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
    compare_on(reference, test, what, per_channel, MetricsBackend::Cpu)
}

/// LDR-FLIP and SSIM of two sRGB images: (FLIP mean and map, SSIM mean and heat map).
type LdrMetrics = ((Metric, Option<Vec<u8>>), (Metric, Option<Vec<u8>>));

fn ldr_metrics(r: &[u8], t: &[u8], w: usize, h: usize, backend: MetricsBackend) -> LdrMetrics {
    match backend {
        MetricsBackend::Cpu => {
            let flip = match flip::ldr(r, t, w, h) {
                Ok(f) => (Metric::Value { mean: f.mean }, flip::magma_rgba8(&f.map).ok()),
                Err(e) => (Metric::Missing { missing: format!("FLIP failed: {e}") }, None),
            };
            let ssim = match ssim::ssim(&ssim::luma(r), &ssim::luma(t), w, h) {
                Ok(s) => (Metric::Value { mean: s.mean }, ssim_heat(&s.map, w, h)),
                Err(e) => (Metric::Missing { missing: e }, None),
            };
            (flip, ssim)
        }
        MetricsBackend::Gpu(gpu) => match gpu.ldr(r, t, w, h) {
            Ok((flip_map, ssim_map)) => {
                let flip = flip_from_map(flip_map, w, h, "FLIP");
                let ssim = if w < 2 * ssim::RADIUS + 1 || h < 2 * ssim::RADIUS + 1 {
                    (Metric::Missing { missing: format!("{w}×{h} is smaller than the 11×11 SSIM window") }, None)
                } else {
                    let map: Vec<f64> = ssim_map.iter().map(|v| *v as f64).collect();
                    (Metric::Value { mean: ssim::window_mean(&map, w, h) }, ssim_heat(&map, w, h))
                };
                (flip, ssim)
            }
            Err(e) => {
                let why = format!("GPU metrics failed: {e}");
                ((Metric::Missing { missing: why.clone() }, None), (Metric::Missing { missing: why }, None))
            }
        },
    }
}

/// A FLIP map as flip-rs pools it (its mean) and colours it.
fn flip_from_map(map: Vec<f32>, w: usize, h: usize, what: &str) -> (Metric, Option<Vec<u8>>) {
    match flip_rs::ErrorMap::new(w, h, map) {
        Ok(m) => (Metric::Value { mean: m.statistics().mean as f64 }, flip::magma_rgba8(&m).ok()),
        Err(e) => (Metric::Missing { missing: format!("{what} failed: {e}") }, None),
    }
}

/// As `compare_with`, FLIP and SSIM computed on `backend`.
pub fn compare_on(
    reference: &LoadedImage,
    test: &LoadedImage,
    what: &str,
    per_channel: bool,
    backend: MetricsBackend,
) -> Result<Comparison, Error> {
    let computed_on = match backend {
        MetricsBackend::Cpu => "cpu",
        MetricsBackend::Gpu(_) => "gpu",
    };
    let (w, h) = reference.size();
    if test.size() != (w, h) {
        return Err(
            InputError::new(what, format!("sizes differ: reference {:?}, test {:?}", (w, h), test.size())).into()
        );
    }
    let (wu, hu) = (w as usize, h as usize);
    match (reference, test) {
        (LoadedImage::Ldr { rgba8: r, .. }, LoadedImage::Ldr { rgba8: t, .. }) => {
            let (flip_value, (ssim_value, ssim_map)) = ldr_metrics(r, t, wu, hu, backend);
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
                computed_on: computed_on.into(),
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
                match backend {
                    MetricsBackend::Cpu => match flip::hdr(r, t, wu, hu) {
                        Ok(f) => (Metric::Value { mean: f.mean }, flip::magma_rgba8(&f.map).ok()),
                        Err(e) => (Metric::Missing { missing: format!("HDR-FLIP failed: {e}") }, None),
                    },
                    MetricsBackend::Gpu(gpu) => match gpu.hdr_flip(r, t, wu, hu) {
                        Ok(map) => flip_from_map(map, wu, hu, "HDR-FLIP"),
                        Err(e) => (Metric::Missing { missing: format!("HDR-FLIP failed: {e}") }, None),
                    },
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
                computed_on: computed_on.into(),
                flip_map_rgba8: flip_value.1,
                ssim_map_rgba8: None,
            })
        }
        _ => Err(InputError::new(what, "one image is PNG and the other EXR; compare two of a kind").into()),
    }
}
