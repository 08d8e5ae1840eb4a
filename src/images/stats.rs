//! Pixel statistics of a rendered frame: bad values and the subject's brightness, recorded with
//! every cell so a NaN or a black subject is visible without opening the image. The bad values are
//! counted in the linear HDR colour target the images come from: NaN, ±Inf, negative, and finite
//! values above the half-float maximum (65504, where an engine's Rgba16Float or R11G11B10 target
//! would overflow) once multiplied by the pre-exposure the pipeline writes with (HDRP renders
//! pre-exposed; built-in and URP write unexposed), each kind with its first pixel (row-major from
//! the top-left), the channel, the value and the pass that wrote it. They are counted in what the
//! passes wrote, before the half-float store (`images::target`) saturates the overflow.

use serde::{Deserialize, Serialize};

use crate::plan::roles::{ROLE_FIXED, ROLE_SUBJECT};

/// The largest finite half-float value.
pub const HALF_MAX: f32 = 65504.0;

/// A kind of bad value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Defect {
    Nan,
    Inf,
    Negative,
    /// Finite and above `HALF_MAX`.
    Overflow,
}

impl Defect {
    pub const ALL: [Defect; 4] = [Defect::Nan, Defect::Inf, Defect::Negative, Defect::Overflow];

    pub fn name(self) -> &'static str {
        match self {
            Defect::Nan => "nan",
            Defect::Inf => "inf",
            Defect::Negative => "negative",
            Defect::Overflow => "overflow",
        }
    }

    pub fn from_name(name: &str) -> Option<Defect> {
        Self::ALL.into_iter().find(|d| d.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|d| d.name()).collect()
    }

    /// The defect of a value that an engine writes multiplied by `pre_exposure`.
    pub fn of(v: f32, pre_exposure: f64) -> Option<Defect> {
        if v.is_nan() {
            Some(Defect::Nan)
        } else if v.is_infinite() {
            Some(Defect::Inf)
        } else if v < 0.0 {
            Some(Defect::Negative)
        } else if v as f64 * pre_exposure > HALF_MAX as f64 {
            Some(Defect::Overflow)
        } else {
            None
        }
    }
}

/// The first pixel holding a kind of bad value.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct DefectPixel {
    pub kind: Defect,
    pub x: u32,
    pub y: u32,
    pub channel: char,
    /// As text (JSON has no NaN or Inf), before any pre-exposure.
    pub value: String,
    /// subject, fixed or background.
    pub role: String,
    /// The pass that wrote the pixel (`FramePlan::passes_for`'s names).
    pub pass: String,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct PixelStats {
    pub pixels: usize,
    pub subject_pixels: usize,
    pub nan: usize,
    pub inf: usize,
    pub negative: usize,
    /// Finite values the shaders wrote above the half-float maximum (after pre-exposure). The camera
    /// target saturates them at 65504 (`images::target`), so the written images hold none: a count
    /// here says the guard acted, and where.
    pub overflow: usize,
    /// The first pixel of each kind found, in `Defect` order.
    pub first: Vec<DefectPixel>,
    /// Largest and smallest finite channel values (linear, before any pre-exposure).
    #[serde(default)]
    pub max_value: f64,
    #[serde(default)]
    pub min_value: f64,
    /// Mean linear luminance over subject pixels (None when the subject is not visible).
    pub subject_mean_luminance: Option<f64>,
    /// Largest finite linear luminance over subject pixels (None when the subject is not visible).
    #[serde(default)]
    pub subject_max_luminance: Option<f64>,
    pub max_luminance: f64,
}

/// A frame as read back: linear RGBA and the role mask (`plan::roles`), `width` pixels a row.
pub struct FramePixels<'a> {
    pub width: u32,
    pub hdr: &'a [f32],
    pub roles: &'a [u8],
}

/// `pass_of(role)`: the pass that wrote a pixel of that role in this cell's frame; `pre_exposure`:
/// what the pipeline multiplies its colour target by (HDRP's exposure, else 1).
pub fn pixel_stats(r: FramePixels, pre_exposure: f64, pass_of: impl Fn(u8) -> String) -> PixelStats {
    let mut s = PixelStats {
        pixels: r.roles.len(),
        subject_pixels: 0,
        nan: 0,
        inf: 0,
        negative: 0,
        overflow: 0,
        first: Vec::new(),
        max_value: 0.0,
        min_value: 0.0,
        subject_mean_luminance: None,
        subject_max_luminance: None,
        max_luminance: 0.0,
    };
    let mut sum = 0.0;
    for (i, (px, role)) in r.hdr.chunks_exact(4).zip(r.roles).enumerate() {
        let rgb = &px[..3];
        for (c, &v) in rgb.iter().enumerate() {
            if v.is_finite() {
                s.max_value = s.max_value.max(v as f64);
                s.min_value = s.min_value.min(v as f64);
            }
            let Some(kind) = Defect::of(v, pre_exposure) else { continue };
            let count = match kind {
                Defect::Nan => &mut s.nan,
                Defect::Inf => &mut s.inf,
                Defect::Negative => &mut s.negative,
                Defect::Overflow => &mut s.overflow,
            };
            *count += 1;
            if *count == 1 {
                s.first.push(DefectPixel {
                    kind,
                    x: (i % r.width as usize) as u32,
                    y: (i / r.width as usize) as u32,
                    channel: ['r', 'g', 'b'][c],
                    value: v.to_string(),
                    role: match *role {
                        ROLE_SUBJECT => "subject",
                        ROLE_FIXED => "fixed",
                        _ => "background",
                    }
                    .into(),
                    pass: pass_of(*role),
                });
            }
        }
        let l = crate::color::luminance([rgb[0] as f64, rgb[1] as f64, rgb[2] as f64]);
        if l.is_finite() {
            s.max_luminance = s.max_luminance.max(l);
        }
        if *role == ROLE_SUBJECT {
            s.subject_pixels += 1;
            sum += l;
            if l.is_finite() {
                s.subject_max_luminance = Some(s.subject_max_luminance.map_or(l, |m: f64| m.max(l)));
            }
        }
    }
    if s.subject_pixels > 0 {
        s.subject_mean_luminance = Some(sum / s.subject_pixels as f64);
    }
    s.first.sort_by_key(|d| d.kind);
    s
}

impl PixelStats {
    pub fn count(&self, kind: Defect) -> usize {
        match kind {
            Defect::Nan => self.nan,
            Defect::Inf => self.inf,
            Defect::Negative => self.negative,
            Defect::Overflow => self.overflow,
        }
    }
}
