//! FLIP through the `flip-rs` crate (a Rust port of NVIDIA's FLIP v1.7, matching `flip-evaluator`
//! exactly in mean and map; ~2.5× faster than the `nv-flip` bindings and the only one with HDR-FLIP).
//! Viewing condition: NVIDIA's default, 0.7 m from a 0.7 m wide 3840-pixel screen, 67.0206 pixels
//! per degree (nv-flip would round it to 67.0).

use flip_rs::{hdr_flip, ldr_flip, HdrOptions, RgbImage};

pub const PPD: f32 = flip_rs::DEFAULT_PPD;

pub struct FlipResult {
    pub mean: f64,
    pub map: flip_rs::ErrorMap,
}

fn rgb_from_rgba<T: Copy>(rgba: &[T]) -> Vec<T> {
    rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

/// LDR-FLIP of two sRGB RGBA8 images (alpha ignored).
pub fn ldr(reference: &[u8], test: &[u8], w: usize, h: usize) -> Result<FlipResult, String> {
    let r = RgbImage::new(w, h, rgb_from_rgba(reference)).map_err(|e| format!("{e:?}"))?;
    let t = RgbImage::new(w, h, rgb_from_rgba(test)).map_err(|e| format!("{e:?}"))?;
    let map = ldr_flip(&r, &t, PPD).map_err(|e| format!("{e:?}"))?;
    Ok(FlipResult { mean: map.statistics().mean as f64, map })
}

/// HDR-FLIP of two linear RGBA f32 images (alpha ignored); exposures chosen from the reference.
pub fn hdr(reference: &[f32], test: &[f32], w: usize, h: usize) -> Result<FlipResult, String> {
    let r = RgbImage::new(w, h, rgb_from_rgba(reference)).map_err(|e| format!("{e:?}"))?;
    let t = RgbImage::new(w, h, rgb_from_rgba(test)).map_err(|e| format!("{e:?}"))?;
    let mut options = HdrOptions::default();
    options.return_exposure_map = false;
    let result = hdr_flip(&r, &t, options).map_err(|e| format!("{e:?}"))?;
    Ok(FlipResult { mean: result.error_map.statistics().mean as f64, map: result.error_map })
}

/// The magma-coloured error map as RGBA8.
pub fn magma_rgba8(map: &flip_rs::ErrorMap) -> Result<Vec<u8>, String> {
    let rgb = map.colorize().map_err(|e| format!("{e:?}"))?;
    Ok(rgb.pixels().chunks_exact(3).flat_map(|p| [to8(p[0]), to8(p[1]), to8(p[2]), 255]).collect())
}

fn to8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}
