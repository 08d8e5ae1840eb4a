//! Range checks with messages that name the file, the key, the value and what is allowed.

use crate::error::InputError;

/// The largest light, sky or emission intensity an input may give: far past any engine's (HDRP's
/// sun is 1e5 lux), and small enough that no frame overflows f32 (a sky of 1e308 saturated every
/// pixel and passed `--fail-on overflow`).
pub const MAX_INTENSITY: f64 = 1e6;
/// The largest UV tiling, offset or texture-transform magnitude (Unity's `_MainTex_ST`).
pub const MAX_UV: f64 = 1e4;

pub struct Checker<'a> {
    file: &'a str,
}

impl<'a> Checker<'a> {
    pub fn new(file: &'a str) -> Self {
        Self { file }
    }

    pub fn file(&self) -> &'a str {
        self.file
    }

    pub fn err(&self, key: &str, message: impl Into<String>) -> InputError {
        InputError::at_key(self.file, key, message)
    }

    pub fn range(&self, key: &str, v: f64, lo: f64, hi: f64) -> Result<(), InputError> {
        if v.is_finite() && (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(self.err(key, format!("value {v} is out of range; allowed {lo}..={hi}")))
        }
    }

    pub fn unit(&self, key: &str, v: f64) -> Result<(), InputError> {
        self.range(key, v, 0.0, 1.0)
    }

    pub fn color(&self, key: &str, c: [f64; 3]) -> Result<(), InputError> {
        if c.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)) {
            Ok(())
        } else {
            Err(self.err(key, format!("colour {c:?} is out of range; each component allowed 0..=1")))
        }
    }

    pub fn non_negative(&self, key: &str, v: f64) -> Result<(), InputError> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(self.err(key, format!("value {v} is out of range; allowed >= 0 (finite)")))
        }
    }

    pub fn positive(&self, key: &str, v: f64) -> Result<(), InputError> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(self.err(key, format!("value {v} is out of range; allowed > 0 (finite)")))
        }
    }

    pub fn finite_vector(&self, key: &str, v: [f64; 3]) -> Result<(), InputError> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(())
        } else {
            Err(self.err(key, format!("vector {v:?} is not allowed; every component must be finite")))
        }
    }

    pub fn nonzero_vector(&self, key: &str, v: [f64; 3]) -> Result<(), InputError> {
        if v.iter().all(|c| c.is_finite()) && v.iter().any(|c| *c != 0.0) {
            Ok(())
        } else {
            Err(self.err(key, format!("vector {v:?} must be finite and non-zero")))
        }
    }

    /// Names end up in cell ids and file names: lower-case ASCII letters, digits, `_` and `-`.
    pub fn name(&self, key: &str, v: &str) -> Result<(), InputError> {
        if !v.is_empty() && v.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_' || c == '-') {
            Ok(())
        } else {
            Err(self.err(key, format!("name `{v}` is not allowed; use lower-case letters, digits, `_` and `-`")))
        }
    }
}
