//! Encoding to bytes (the caller writes them atomically).

use std::io::Cursor;

use crate::error::Error as AppError;

// OpenEXR, linear RGBA, lossless, scan lines in increasing order: the same pixels give the same
// bytes. Measured on eight 256² URP and HDRP Lit cells (release, one core): half channels with
// ZIP16 70–140 KB in 5–8 ms; PIZ 116–178 KB in 7–17 ms; RLE 188–247 KB in 3 ms; 32-bit channels
// ZIP16 632–758 KB in 14–22 ms, RLE 931 KB (32-bit mantissas barely compress). PNG at the fast
// level 26–49 KB in 0.5–0.9 ms against 19–40 KB in 5.5–20 ms at the default level.

/// Scan lines in increasing order: the crate compresses blocks on several threads, and only a
/// fixed order makes the same pixels give the same bytes. (A macro: the crate's channel types
/// borrow the pixels, which its writer traits' bounds make awkward to name in a function.)
macro_rules! write_exr {
    ($width:expr, $height:expr, $compression:expr, $channels:expr) => {{
        let encoding =
            Encoding { compression: $compression, blocks: Blocks::ScanLines, line_order: LineOrder::Increasing };
        let image = Image::from_encoded_channels(($width as usize, $height as usize), encoding, $channels);
        let mut cursor = Cursor::new(Vec::new());
        image.write().to_buffered(&mut cursor).map_err(|e| AppError::encode("encoding EXR", e))?;
        Ok(cursor.into_inner())
    }};
}

/// 32-bit channels, ZIP (the records the run keeps beside cells: truths, noise maps).
pub fn exr_bytes(width: u32, height: u32, rgba: &[f32]) -> Result<Vec<u8>, AppError> {
    exr_bytes_with(width, height, rgba, exr::compression::Compression::ZIP16)
}

/// An EXR of `rgba` (32-bit float) with `compression`, scan lines written in increasing order:
/// the crate compresses blocks in parallel, and only a fixed line order makes the same pixels give
/// the same bytes.
pub fn exr_bytes_with(
    width: u32,
    height: u32,
    rgba: &[f32],
    compression: exr::compression::Compression,
) -> Result<Vec<u8>, AppError> {
    use exr::prelude::*;
    let w = width as usize;
    let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
        let i = (y * w + x) * 4;
        (rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3])
    });
    write_exr!(width, height, compression, channels)
}

/// The same with 16-bit channels: each value rounded to the nearest half (`fits_half` says when
/// that loses nothing but rounding).
pub fn exr_half_bytes_with(
    width: u32,
    height: u32,
    rgba: &[f32],
    compression: exr::compression::Compression,
) -> Result<Vec<u8>, AppError> {
    use exr::prelude::*;
    let w = width as usize;
    let h = |v: f32| f16::from_f32(v);
    let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
        let i = (y * w + x) * 4;
        (h(rgba[i]), h(rgba[i + 1]), h(rgba[i + 2]), h(rgba[i + 3]))
    });
    write_exr!(width, height, compression, channels)
}

/// An EXR of `rgba` with extra RGB layers, the OpenEXR convention for AOVs in one part: the
/// image's channels R, G, B, A, then `<layer>.R`, `.G`, `.B` for each of `layers` (each RGBA at
/// the image's size; its alpha is not written). Readers of the image's RGBA see the image alone.
/// `half`: 16-bit channels (each value rounded to the nearest half), else 32-bit.
pub fn exr_with_layers_bytes(
    width: u32,
    height: u32,
    rgba: &[f32],
    layers: &[(&str, &[f32])],
    half: bool,
    compression: exr::compression::Compression,
) -> Result<Vec<u8>, AppError> {
    use exr::prelude::*;
    let samples = |px: &[f32], k: usize| {
        let values = px.chunks_exact(4).map(|p| p[k]);
        if half {
            FlatSamples::F16(values.map(f16::from_f32).collect())
        } else {
            FlatSamples::F32(values.collect())
        }
    };
    let mut list: Vec<AnyChannel<FlatSamples>> =
        ["R", "G", "B", "A"].iter().enumerate().map(|(k, c)| AnyChannel::new(*c, samples(rgba, k))).collect();
    for (name, px) in layers {
        for (k, c) in ["R", "G", "B"].iter().enumerate() {
            list.push(AnyChannel::new(format!("{name}.{c}").as_str(), samples(px, k)));
        }
    }
    let channels = AnyChannels::sort(SmallVec::from_vec(list));
    write_exr!(width, height, compression, channels)
}

/// Read the RGB layer `name` of an EXR written by `exr_with_layers_bytes`, as RGBA (alpha 1).
pub fn read_exr_layer(path: &std::path::Path, name: &str) -> Result<Vec<f32>, AppError> {
    use exr::prelude::*;
    let bytes = read_output(path)?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| AppError::encode(format!("reading {}", path.display()), e))?;
    let layer = image.layer_data.first().ok_or_else(|| AppError::Other(format!("{}: no layer", path.display())))?;
    let channel = |c: &str| {
        let full = format!("{name}.{c}");
        layer.channel_data.list.iter().find(|ch| ch.name.to_string() == full).ok_or_else(|| {
            AppError::Other(format!("{}: no channel {full} (layer `{name}` is not in the file)", path.display()))
        })
    };
    let rgb = [channel("R")?, channel("G")?, channel("B")?];
    let n = layer.size.area();
    let mut out = vec![1f32; n * 4];
    for (k, ch) in rgb.iter().enumerate() {
        for (i, v) in ch.sample_data.values_as_f32().enumerate() {
            out[i * 4 + k] = v;
        }
    }
    Ok(out)
}

/// Whether every finite value of `rgba` lies in the half-float range (no finite value would become
/// an infinity).
pub fn fits_half(rgba: &[f32]) -> bool {
    rgba.iter().all(|v| !v.is_finite() || v.abs() <= crate::images::stats::HALF_MAX)
}

/// Round every value to the nearest half float, as a 16-bit EXR stores it.
pub fn round_to_half(rgba: &mut [f32]) {
    for v in rgba {
        *v = half::f16::from_f32(*v).to_f32();
    }
}

/// Read an EXR back as linear RGBA (for tests, references and later comparisons).
pub fn read_exr(path: &std::path::Path) -> Result<(u32, u32, Vec<f32>), AppError> {
    exr_from_bytes(&read_output(path)?).map_err(|e| AppError::Other(format!("reading {}: {e}", path.display())))
}

/// The first RGBA layer of the EXR file in `bytes`, as linear RGBA.
pub fn exr_from_bytes(bytes: &[u8]) -> Result<(u32, u32, Vec<f32>), String> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |res, _| (res.width(), vec![0f32; res.width() * res.height() * 4]),
            |(w, px), pos, (r, g, b, a): (f32, f32, f32, f32)| {
                let i = (pos.y() * *w + pos.x()) * 4;
                px[i..i + 4].copy_from_slice(&[r, g, b, a]);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let size = image.layer_data.size;
    Ok((size.width() as u32, size.height() as u32, image.layer_data.channel_data.pixels.1))
}

/// The PNG at `path` (a run's own image), as 8-bit RGBA.
pub fn read_png(path: &std::path::Path) -> Result<image::RgbaImage, AppError> {
    let bytes = read_output(path)?;
    image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .map(|i| i.to_rgba8())
        .map_err(|e| AppError::Other(format!("reading {}: {e}", path.display())))
}

/// A file of a run folder, through the bounded reader.
fn read_output(path: &std::path::Path) -> Result<Vec<u8>, AppError> {
    crate::input::read::read(path, crate::input::read::OUTPUT)
        .map_err(|e| AppError::Other(format!("reading {}: {e}", path.display())))
}

/// A PNG at the fast deflate level with adaptive filters: measured in the README against the
/// default level (size and time), the encode stage's largest cost after the EXR.
pub fn png_bytes(width: u32, height: u32, rgba8: &[u8]) -> Result<Vec<u8>, AppError> {
    png_bytes_with(width, height, rgba8, image::codecs::png::CompressionType::Fast)
}

/// A colour-mapped image (the FLIP and SSIM maps: at most 256 colours, opaque) as an 8-bit palette
/// PNG, a quarter of the RGBA bytes before compression and shown the same; any other image as RGBA.
/// The palette is the image's colours in ascending order, so the same pixels give the same bytes.
pub fn map_png_bytes(width: u32, height: u32, rgba8: &[u8]) -> Result<Vec<u8>, AppError> {
    let mut colours: Vec<[u8; 3]> = Vec::new();
    let opaque = rgba8.chunks_exact(4).all(|p| p[3] == 255);
    if opaque {
        let mut seen = std::collections::BTreeSet::new();
        for p in rgba8.chunks_exact(4) {
            seen.insert([p[0], p[1], p[2]]);
            if seen.len() > 256 {
                break;
            }
        }
        colours = seen.into_iter().collect();
    }
    if !opaque || colours.len() > 256 || colours.is_empty() {
        return png_bytes(width, height, rgba8);
    }
    let index: std::collections::HashMap<[u8; 3], u8> =
        colours.iter().enumerate().map(|(i, c)| (*c, i as u8)).collect();
    let indices: Vec<u8> = rgba8.chunks_exact(4).map(|p| index[&[p[0], p[1], p[2]]]).collect();
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(png::ColorType::Indexed);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_palette(colours.concat());
        encoder.set_compression(png::Compression::Fast);
        let mut writer = encoder.write_header().map_err(|e| AppError::encode("encoding a map PNG", e))?;
        writer.write_image_data(&indices).map_err(|e| AppError::encode("encoding a map PNG", e))?;
        writer.finish().map_err(|e| AppError::encode("encoding a map PNG", e))?;
    }
    Ok(out)
}

pub fn png_bytes_with(
    width: u32,
    height: u32,
    rgba8: &[u8],
    level: image::codecs::png::CompressionType,
) -> Result<Vec<u8>, AppError> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new_with_quality(&mut out, level, image::codecs::png::FilterType::Adaptive)
        .write_image(rgba8, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|e| AppError::encode("encoding PNG", e))?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_png_shows_the_same_pixels_in_fewer_bytes() {
        let (w, h) = (64u32, 48u32);
        let map: Vec<u8> = (0..w * h)
            .flat_map(|i| {
                let v = ((i % w) * 4 + i / w) as u8;
                [v, 255 - v, v / 2, 255]
            })
            .collect();
        let indexed = map_png_bytes(w, h, &map).unwrap();
        let rgba = png_bytes(w, h, &map).unwrap();
        let decoded = image::load_from_memory(&indexed).unwrap().to_rgba8();
        assert_eq!(decoded.as_raw(), &map, "the palette PNG decodes to the same RGBA");
        assert!(indexed.len() < rgba.len(), "{} vs {}", indexed.len(), rgba.len());
        assert_eq!(indexed, map_png_bytes(w, h, &map).unwrap(), "deterministic");
        // More than 256 colours, or any transparency: RGBA as before.
        let many: Vec<u8> = (0..w * h).flat_map(|i| [(i % 256) as u8, (i / 256) as u8, 7, 255]).collect();
        assert_eq!(map_png_bytes(w, h, &many).unwrap(), png_bytes(w, h, &many).unwrap());
    }

    #[test]
    fn exr_bytes_are_deterministic_and_lossless() {
        let (w, h) = (97u32, 61u32);
        let rgba: Vec<f32> = (0..w * h * 4).map(|i| ((i as f32 * 0.37).sin() * 3.0).abs() + (i % 7) as f32).collect();
        let first = exr_bytes(w, h, &rgba).unwrap();
        for _ in 0..4 {
            assert_eq!(exr_bytes(w, h, &rgba).unwrap(), first, "same pixels, other bytes");
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        std::fs::write(&path, &first).unwrap();
        let (rw, rh, back) = read_exr(&path).unwrap();
        assert_eq!((rw, rh), (w, h));
        assert!(back.iter().zip(&rgba).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}
