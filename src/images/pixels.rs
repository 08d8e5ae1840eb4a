//! `pixels.js` beside a cell's image: the displayed sRGB bytes (image.png's) and the linear values
//! image.exr holds, for the viewer's magnifier readout.
//!
//! Why a script: browsers decode no EXR, and a page opened from `file://` cannot read a PNG's pixels
//! either (a canvas drawn from a file image is tainted, and fetch/XHR of file URLs is refused). A
//! `<script src>` loads from `file://`, so the values travel as a script that hands them to the page:
//! `shadematrixPixels({...})`. The file names no cell, so a twin's copy is byte-identical to its
//! original's. Each channel is stored as the difference of each value from the one before it
//! (wrapping; sRGB bytes, or the half/f32 bit patterns), in byte planes (sRGB R, G, B; linear R, G,
//! B each as high byte then low byte, or four planes for f32), zlib-deflated (the page inflates
//! with DecompressionStream) and base64-encoded. Hand-written: no crate
//! writes this viewer-specific layout; flate2 and base64 do the encoding.

use std::io::Write;

use base64::Engine;

use crate::error::Error as AppError;

pub const PIXELS_FILE: &str = "pixels.js";

/// The script for a `width`×`height` frame: `srgba8` as displayed (RGBA8, alpha ignored), `rgba` the
/// linear frame as the EXR holds it, written as half floats when `half` (the EXR's channels are
/// 16-bit), else as 32-bit floats.
pub fn pixels_js(width: u32, height: u32, srgba8: &[u8], rgba: &[f32], half: bool) -> Result<Vec<u8>, AppError> {
    let n = (width * height) as usize;
    let mut srgb = Vec::with_capacity(3 * n);
    for c in 0..3 {
        let mut previous = 0u8;
        srgb.extend((0..n).map(|i| {
            let v = srgba8[4 * i + c];
            let delta = v.wrapping_sub(previous);
            previous = v;
            delta
        }));
    }
    let bytes_per_value = if half { 2 } else { 4 };
    let mut linear = Vec::with_capacity(3 * bytes_per_value * n);
    for c in 0..3 {
        // Each value's bits less the previous value's (wrapping): smooth frames give small deltas,
        // which deflate far better than the raw low bytes (as EXR's ZIP predictor does).
        let mut previous = 0u32;
        let deltas: Vec<u32> = (0..n)
            .map(|i| {
                let v = rgba[4 * i + c];
                let bits = if half { half::f16::from_f32(v).to_bits() as u32 } else { v.to_bits() };
                let delta = if half { (bits.wrapping_sub(previous)) & 0xffff } else { bits.wrapping_sub(previous) };
                previous = bits;
                delta
            })
            .collect();
        for byte in 0..bytes_per_value {
            let shift = 8 * (bytes_per_value - 1 - byte);
            linear.extend(deltas.iter().map(|d| (d >> shift) as u8));
        }
    }
    let b64 = |data: &[u8]| -> Result<String, AppError> {
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
        z.write_all(data).map_err(|e| AppError::encode("deflating pixels.js", e))?;
        let deflated = z.finish().map_err(|e| AppError::encode("deflating pixels.js", e))?;
        Ok(base64::engine::general_purpose::STANDARD.encode(deflated))
    };
    let script = format!(
        "shadematrixPixels({{\"width\":{width},\"height\":{height},\"linear\":\"{}\",\"srgb_planes\":\"{}\",\"linear_planes\":\"{}\"}});\n",
        if half { "half" } else { "float" },
        b64(&srgb)?,
        b64(&linear)?
    );
    Ok(script.into_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    fn field<'a>(script: &'a str, name: &str) -> &'a str {
        script.split(&format!("\"{name}\":")).nth(1).unwrap().split([',', '}']).next().unwrap().trim_matches('"')
    }

    fn inflate(b64: &str) -> Vec<u8> {
        let z = base64::engine::general_purpose::STANDARD.decode(b64).unwrap();
        let mut out = Vec::new();
        flate2::read::ZlibDecoder::new(&z[..]).read_to_end(&mut out).unwrap();
        out
    }

    #[test]
    fn planes_round_trip_to_the_values_written() {
        let (w, h) = (3u32, 2u32);
        let rgba: Vec<f32> = (0..24).map(|i| i as f32 * 0.37 - 2.0).collect();
        let srgba8: Vec<u8> = (0..24).map(|i| (i * 10) as u8).collect();
        for half in [true, false] {
            let script = String::from_utf8(pixels_js(w, h, &srgba8, &rgba, half).unwrap()).unwrap();
            assert!(script.starts_with("shadematrixPixels({"));
            assert_eq!(field(&script, "linear"), if half { "half" } else { "float" });
            let srgb = inflate(field(&script, "srgb_planes"));
            let linear = inflate(field(&script, "linear_planes"));
            let n = 6;
            for c in 0..3 {
                let (mut s_prev, mut l_prev) = (0u8, 0u32);
                for i in 0..n {
                    s_prev = s_prev.wrapping_add(srgb[c * n + i]);
                    assert_eq!(s_prev, srgba8[4 * i + c]);
                    let v = rgba[4 * i + c];
                    let got = if half {
                        let base = c * 2 * n;
                        let d = u16::from_be_bytes([linear[base + i], linear[base + n + i]]) as u32;
                        l_prev = (l_prev + d) & 0xffff;
                        half::f16::from_bits(l_prev as u16).to_f32()
                    } else {
                        let base = c * 4 * n;
                        let d = u32::from_be_bytes(std::array::from_fn(|k| linear[base + k * n + i]));
                        l_prev = l_prev.wrapping_add(d);
                        f32::from_bits(l_prev)
                    };
                    let want = if half { half::f16::from_f32(v).to_f32() } else { v };
                    assert_eq!(got, want, "pixel {i} channel {c} half {half}");
                }
            }
        }
    }
}
