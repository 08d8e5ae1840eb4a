//! Encoding to bytes (the caller writes them atomically).

use std::io::Cursor;

use crate::error::Error as AppError;

/// OpenEXR, linear RGBA 32-bit float, uncompressed-to-ZIP as the exr crate chooses.
pub fn exr_bytes(width: u32, height: u32, rgba: &[f32]) -> Result<Vec<u8>, AppError> {
    use exr::prelude::*;
    let (w, h) = (width as usize, height as usize);
    let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
        let i = (y * w + x) * 4;
        (rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3])
    });
    let image = Image::from_channels((w, h), channels);
    let mut cursor = Cursor::new(Vec::new());
    image.write().to_buffered(&mut cursor).map_err(|e| AppError::encode("encoding EXR", e))?;
    Ok(cursor.into_inner())
}

/// Read an EXR back as linear RGBA (for tests, references and later comparisons).
pub fn read_exr(path: &std::path::Path) -> Result<(u32, u32, Vec<f32>), AppError> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |res, _| (res.width(), vec![0f32; res.width() * res.height() * 4]),
        |(w, px), pos, (r, g, b, a): (f32, f32, f32, f32)| {
            let i = (pos.y() * *w + pos.x()) * 4;
            px[i..i + 4].copy_from_slice(&[r, g, b, a]);
        },
    )
    .map_err(|e| AppError::encode(format!("reading {}", path.display()), e))?;
    let size = image.layer_data.size;
    Ok((size.width() as u32, size.height() as u32, image.layer_data.channel_data.pixels.1))
}

pub fn png_bytes(width: u32, height: u32, rgba8: &[u8]) -> Result<Vec<u8>, AppError> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(rgba8, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|e| AppError::encode("encoding PNG", e))?;
    Ok(out)
}
