//! Pixel statistics of a rendered frame: bad values and the subject's brightness, recorded with
//! every cell so a NaN or a black subject is visible without opening the image.

use serde::{Deserialize, Serialize};

use crate::render::uniforms::ROLE_SUBJECT;
use crate::render::CellRender;

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct PixelStats {
    pub pixels: usize,
    pub subject_pixels: usize,
    pub nan: usize,
    pub inf: usize,
    pub negative: usize,
    /// Mean linear luminance over subject pixels (None when the subject is not visible).
    pub subject_mean_luminance: Option<f64>,
    pub max_luminance: f64,
}

pub fn pixel_stats(r: &CellRender) -> PixelStats {
    let mut s = PixelStats {
        pixels: r.roles.len(),
        subject_pixels: 0,
        nan: 0,
        inf: 0,
        negative: 0,
        subject_mean_luminance: None,
        max_luminance: 0.0,
    };
    let mut sum = 0.0;
    for (px, role) in r.hdr.chunks_exact(4).zip(&r.roles) {
        let rgb = &px[..3];
        s.nan += rgb.iter().filter(|v| v.is_nan()).count();
        s.inf += rgb.iter().filter(|v| v.is_infinite()).count();
        s.negative += rgb.iter().filter(|v| **v < 0.0).count();
        let l = crate::color::luminance([rgb[0] as f64, rgb[1] as f64, rgb[2] as f64]);
        if l.is_finite() {
            s.max_luminance = s.max_luminance.max(l);
        }
        if *role == ROLE_SUBJECT {
            s.subject_pixels += 1;
            sum += l;
        }
    }
    if s.subject_pixels > 0 {
        s.subject_mean_luminance = Some(sum / s.subject_pixels as f64);
    }
    s
}
