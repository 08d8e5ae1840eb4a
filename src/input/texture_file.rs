//! A base-colour map's pixels (`FixedMaterial::base_color_map`): a PNG (8- or 16-bit, its colour
//! sRGB-encoded) or an OpenEXR image (linear), read once when its scene is loaded. The header is
//! read first, so that a huge image is refused before its pixels are decoded. Decoding is the
//! `image` and `exr` crates'.

use std::path::Path;

use sha2::{Digest, Sha256};

/// The most texels a base-colour map may have (8192²).
pub const MAX_TEXTURE_TEXELS: usize = 8192 * 8192;
/// The largest texture file read.
const MAX_TEXTURE_FILE: crate::input::read::Limit =
    crate::input::read::Limit { bytes: 512 << 20, what: "a texture file" };

/// Linear RGB texels, row-major from the top (v = 0, as glTF and the tool's UVs put the image's
/// first row), and the file's digest.
#[derive(Clone, PartialEq)]
pub struct TextureFile {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<[f32; 3]>,
    /// SHA-256 of the file's bytes, hex: what keys see of the image.
    pub digest: String,
}

impl std::fmt::Debug for TextureFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "TextureFile({}×{}, sha256 {})", self.width, self.height, &self.digest[..12.min(self.digest.len())])
    }
}

/// The image at `path` (.png or .exr), or what is wrong with it.
pub fn read_file(path: &Path) -> Result<TextureFile, String> {
    let (bytes, extension) = crate::input::source::read_bounded(path, MAX_TEXTURE_FILE)?;
    read_bytes(&bytes, &extension)
}

/// The image in `bytes` of an `extension` ("png" or "exr") file.
pub fn read_bytes(bytes: &[u8], extension: &str) -> Result<TextureFile, String> {
    let (width, height, texels) = match extension {
        "png" => read_png(bytes)?,
        "exr" => crate::input::sky_image::read_exr(bytes, check_size)?,
        other => return Err(format!("`.{other}`: a texture is a PNG (.png, sRGB) or OpenEXR (.exr, linear) file")),
    };
    let bad = texels.iter().flatten().filter(|v| !v.is_finite() || **v < 0.0).count();
    if bad > 0 {
        return Err(format!("{bad} channel values are negative or not finite: a base colour is finite and ≥ 0"));
    }
    Ok(TextureFile { width, height, texels, digest: format!("{:x}", Sha256::digest(bytes)) })
}

fn check_size(width: usize, height: usize) -> Result<(), String> {
    if width == 0 || height == 0 || width.saturating_mul(height) > MAX_TEXTURE_TEXELS {
        return Err(format!("{width}×{height}: a texture has at most {MAX_TEXTURE_TEXELS} texels (8192²)"));
    }
    Ok(())
}

fn read_png(bytes: &[u8]) -> Result<crate::input::sky_image::Decoded, String> {
    use image::ImageDecoder;
    let decoder = image::codecs::png::PngDecoder::new(std::io::Cursor::new(bytes))
        .map_err(|e| format!("not a readable PNG file: {e}"))?;
    let (w, h) = decoder.dimensions();
    check_size(w as usize, h as usize)?;
    let image = image::DynamicImage::from_decoder(decoder).map_err(|e| format!("not a readable PNG image: {e}"))?;
    // 16 bits keep their precision; sRGB decoded per channel (the alpha channel is not colour).
    let rgb = image.to_rgb16();
    let decode = |v: u16| crate::color::srgb_to_linear(v as f64 / 65535.0) as f32;
    Ok((w as usize, h as usize, rgb.pixels().map(|p| p.0.map(decode)).collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×2 EXR whose header's data window is rewritten to `w`×`h`: what the size checks read,
    /// with no pixels behind it.
    fn exr_declaring(w: i32, h: i32) -> Vec<u8> {
        use exr::prelude::*;
        let image =
            Image::from_channels((2, 2), SpecificChannels::rgba(|_: Vec2<usize>| (0.5f32, 0.5f32, 0.5f32, 1.0f32)));
        let mut bytes = Vec::new();
        image.write().to_buffered(std::io::Cursor::new(&mut bytes)).unwrap();
        let at = bytes.windows(b"dataWindow\0box2i\0".len()).position(|x| x == b"dataWindow\0box2i\0").unwrap();
        let values = at + b"dataWindow\0box2i\0".len() + 4;
        for (k, v) in [0, 0, w - 1, h - 1].into_iter().enumerate() {
            bytes[values + 4 * k..values + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
        }
        bytes
    }

    #[test]
    fn a_texture_exr_is_held_to_the_texture_limit_not_the_skys() {
        // 4096² is a texture's to have (at most 8192²) and past a sky's (4096×2048): the size check
        // passes, and what fails is the missing pixels, not a message about skies.
        let err = read_bytes(&exr_declaring(4096, 4096), "exr").unwrap_err();
        assert!(!err.contains("sky") && !err.contains("at most"), "{err}");
        let err = read_bytes(&exr_declaring(8193, 8192), "exr").unwrap_err();
        assert!(err.contains("a texture has at most"), "{err}");
    }

    fn png(w: u32, h: u32, px: [u8; 3]) -> Vec<u8> {
        let img = image::RgbImage::from_pixel(w, h, image::Rgb(px));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    #[test]
    fn a_png_is_decoded_from_srgb_and_a_huge_one_is_refused_from_its_header() {
        let t = read_bytes(&png(3, 2, [188, 0, 255]), "png").unwrap();
        assert_eq!((t.width, t.height), (3, 2));
        let expected = crate::color::srgb_to_linear(188.0 / 255.0);
        assert!((t.texels[4][0] as f64 - expected).abs() < 1e-5, "{:?}", t.texels[4]);
        assert_eq!((t.texels[4][1], t.texels[4][2]), (0.0, 1.0));
        // A header that claims 9000² is refused before any pixel is decoded.
        let mut huge = png(1, 1, [0; 3]);
        huge[16..20].copy_from_slice(&9000u32.to_be_bytes());
        huge[20..24].copy_from_slice(&9000u32.to_be_bytes());
        let mut crc = flate2::Crc::new();
        crc.update(&huge[12..29]);
        huge[29..33].copy_from_slice(&crc.sum().to_be_bytes());
        let e = read_bytes(&huge, "png").unwrap_err();
        assert!(e.contains("9000×9000"), "{e}");
        assert!(read_bytes(&png(1, 1, [0; 3]), "jpg").unwrap_err().contains("PNG"));
    }
}
