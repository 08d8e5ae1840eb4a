//! An image sky's pixels: an equirectangular (2:1) OpenEXR or Radiance HDR image of linear
//! radiance, read once when its scene is loaded. The header is read first, so that a huge image is
//! refused before its pixels are decoded; a texel that is negative or not finite is refused, not
//! clamped. Decoding is the `exr` and `image` crates'.

use std::path::Path;

use sha2::{Digest, Sha256};

/// The most texels an image sky may have (4096 × 2048: 100 MB as f32 RGB).
pub const MAX_SKY_TEXELS: usize = 4096 * 2048;
/// The largest sky file read.
const MAX_SKY_FILE: crate::input::read::Limit =
    crate::input::read::Limit { bytes: 256 << 20, what: "an image sky file" };

/// Linear RGB texels, row-major from the top (v = 0, +Y), and the file's digest.
#[derive(Clone, PartialEq)]
pub struct SkyImage {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<[f32; 3]>,
    /// SHA-256 of the file's bytes, hex: what keys see of the image.
    pub digest: String,
}

impl SkyImage {
    /// Bilinear between texel centres at (u, v) in [0, 1]²; u wraps when `wrap_u`, else clamps.
    pub fn bilinear(&self, u: f64, v: f64, wrap_u: bool) -> [f64; 3] {
        let (w, h) = (self.width, self.height);
        let x = u * w as f64 - 0.5;
        let x = if wrap_u { x } else { x.clamp(0.0, (w - 1) as f64) };
        let y = (v * h as f64 - 0.5).clamp(0.0, (h - 1) as f64);
        let (x0, y0) = (x.floor(), y.floor());
        let (tx, ty) = (x - x0, y - y0);
        let texel = |xi: f64, yi: f64| {
            let xi = if wrap_u { (xi as i64).rem_euclid(w as i64) as usize } else { (xi as usize).min(w - 1) };
            self.texels[(yi as usize).min(h - 1) * w + xi].map(f64::from)
        };
        let lerp = |a: [f64; 3], b: [f64; 3], t: f64| [0, 1, 2].map(|c| a[c] + (b[c] - a[c]) * t);
        let top = lerp(texel(x0, y0), texel(x0 + 1.0, y0), tx);
        let bottom = lerp(texel(x0, y0 + 1.0), texel(x0 + 1.0, y0 + 1.0), tx);
        lerp(top, bottom, ty)
    }
}

impl std::fmt::Debug for SkyImage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SkyImage({}×{}, sha256 {})", self.width, self.height, &self.digest[..12.min(self.digest.len())])
    }
}

/// The equirectangular sky at `path` (.exr or .hdr), or what is wrong with it.
pub fn read_file(path: &Path) -> Result<SkyImage, String> {
    let image = read_any_file(path)?;
    if image.width != 2 * image.height {
        return Err(format!("{}×{}: an equirectangular sky is twice as wide as it is high", image.width, image.height));
    }
    Ok(image)
}

fn read_any_file(path: &Path) -> Result<SkyImage, String> {
    let (bytes, extension) = crate::input::source::read_bounded(path, MAX_SKY_FILE)?;
    decode(&bytes, &extension)
}

/// The image in `bytes`, an `extension` ("exr" or "hdr") file: an equirectangular sky, 2:1.
pub fn read_bytes(bytes: &[u8], extension: &str) -> Result<SkyImage, String> {
    let image = decode(bytes, extension)?;
    if image.width != 2 * image.height {
        return Err(format!("{}×{}: an equirectangular sky is twice as wide as it is high", image.width, image.height));
    }
    Ok(image)
}

/// One face of a cube-map sky at `path`: square.
pub fn read_face_file(path: &Path) -> Result<SkyImage, String> {
    let image = read_any_file(path)?;
    if image.width != image.height {
        return Err(format!("{}×{}: a cube-map face is square", image.width, image.height));
    }
    Ok(image)
}

fn decode(bytes: &[u8], extension: &str) -> Result<SkyImage, String> {
    let (width, height, texels) = match extension {
        "exr" => read_exr(bytes, check_size)?,
        "hdr" => read_hdr(bytes)?,
        other => {
            return Err(format!(
                "`.{other}`: an image sky is an equirectangular OpenEXR (.exr) or Radiance HDR (.hdr) file"
            ))
        }
    };
    let bad = texels.iter().flatten().filter(|v| !v.is_finite() || **v < 0.0).count();
    if bad > 0 {
        return Err(format!("{bad} channel values are negative or not finite: radiance is finite and ≥ 0"));
    }
    let digest = format!("{:x}", Sha256::digest(bytes));
    Ok(SkyImage { width, height, texels, digest })
}

pub(crate) fn check_size(width: usize, height: usize) -> Result<(), String> {
    if width == 0 || height == 0 || width.saturating_mul(height) > MAX_SKY_TEXELS {
        return Err(format!("{width}×{height}: an image sky has at most {MAX_SKY_TEXELS} texels (4096×2048)"));
    }
    Ok(())
}

pub(crate) type Decoded = (usize, usize, Vec<[f32; 3]>);

/// The first RGB(A) layer of the OpenEXR file in `bytes`. Every part's declared size passes
/// `check_size` before any pixel is decoded: the decoder may read any of the parts.
pub(crate) fn read_exr(bytes: &[u8], check_size: fn(usize, usize) -> Result<(), String>) -> Result<Decoded, String> {
    use exr::prelude::*;
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(|e| format!("not a readable OpenEXR file: {e}"))?;
    if meta.headers.is_empty() {
        return Err("an OpenEXR file without a layer".into());
    }
    for (i, header) in meta.headers.iter().enumerate() {
        check_size(header.layer_size.width(), header.layer_size.height()).map_err(|e| {
            if meta.headers.len() > 1 {
                format!("part {i}: {e}")
            } else {
                e
            }
        })?;
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |res, _| (res.width(), vec![[0f32; 3]; res.width() * res.height()]),
            |(w, px), pos, (r, g, b, _a): (f32, f32, f32, f32)| px[pos.y() * *w + pos.x()] = [r, g, b],
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| format!("not a readable RGB(A) OpenEXR image: {e}"))?;
    let size = image.layer_data.size;
    Ok((size.width(), size.height(), image.layer_data.channel_data.pixels.1))
}

fn read_hdr(bytes: &[u8]) -> Result<Decoded, String> {
    use image::ImageDecoder;
    let decoder = image::codecs::hdr::HdrDecoder::new(std::io::Cursor::new(bytes))
        .map_err(|e| format!("not a readable Radiance HDR file: {e}"))?;
    let (w, h) = decoder.dimensions();
    check_size(w as usize, h as usize)?;
    let mut buffer = vec![0u8; decoder.total_bytes() as usize];
    decoder.read_image(&mut buffer).map_err(|e| format!("not a readable Radiance HDR image: {e}"))?;
    let floats: &[f32] = bytemuck::cast_slice(&buffer);
    Ok((w as usize, h as usize, floats.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_part_of_a_multi_part_exr_is_size_checked_before_decoding() {
        use exr::prelude::*;
        let channels = |names: &[&str], n: usize| {
            AnyChannels::sort(names.iter().map(|c| AnyChannel::new(*c, FlatSamples::F32(vec![0.5; n]))).collect())
        };
        // A first part the RGB reader skips (luminance only, 2 texels), a second it decodes (32).
        let small = Layer::new((2, 1), LayerAttributes::named("y"), Encoding::FAST_LOSSLESS, channels(&["Y"], 2));
        let big =
            Layer::new((8, 4), LayerAttributes::named("rgb"), Encoding::FAST_LOSSLESS, channels(&["B", "G", "R"], 32));
        let image = Image::from_layers(ImageAttributes::new(IntegerBounds::from_dimensions((8, 4))), vec![small, big]);
        let mut bytes = Vec::new();
        image.write().to_buffered(std::io::Cursor::new(&mut bytes)).unwrap();
        let at_most_16 = |w: usize, h: usize| if w * h <= 16 { Ok(()) } else { Err(format!("{w}×{h}: too large")) };
        let err = read_exr(&bytes, at_most_16).unwrap_err();
        assert!(err.contains("part 1") && err.contains("8×4"), "{err}");
        assert_eq!(read_exr(&bytes, |_, _| Ok(())).map(|d| (d.0, d.1)), Ok((8, 4)));
    }

    #[test]
    fn a_sky_that_is_not_two_to_one_or_holds_negative_radiance_is_refused() {
        let exr = |w: u32, h: u32, v: f32| {
            let px = vec![v; (w * h * 4) as usize];
            use exr::prelude::*;
            let channels = SpecificChannels::rgba(|_: Vec2<usize>| (px[0], px[1], px[2], 1.0f32));
            let mut out = std::io::Cursor::new(Vec::new());
            Image::from_channels((w as usize, h as usize), channels).write().to_buffered(&mut out).unwrap();
            out.into_inner()
        };
        let ok = read_bytes(&exr(8, 4, 0.5), "exr").unwrap();
        assert_eq!((ok.width, ok.height, ok.texels[5]), (8, 4, [0.5; 3]));
        assert!(read_bytes(&exr(8, 8, 0.5), "exr").unwrap_err().contains("twice as wide"));
        assert!(read_bytes(&exr(8, 4, -1.0), "exr").unwrap_err().contains("negative"));
        assert!(read_bytes(&exr(8, 4, 0.5), "png").unwrap_err().contains("OpenEXR"));
        assert!(read_bytes(b"not an image", "exr").unwrap_err().contains("OpenEXR"));
    }
}
