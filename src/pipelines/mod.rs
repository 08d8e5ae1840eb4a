//! Emulations of the three engine pipelines' conventions (models.md#conventions, models.md#display): light units
//! and colour handling, distance attenuation, tonemapping, and which shaders exist in each.
//! Per-pass plans live in `plan`; this module only states conventions.

use serde::{Deserialize, Serialize};

use crate::color::srgb_to_linear;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Pipeline {
    Builtin,
    Urp,
    Hdrp,
}

impl Pipeline {
    pub const ALL: [Pipeline; 3] = [Pipeline::Builtin, Pipeline::Urp, Pipeline::Hdrp];

    pub fn name(self) -> &'static str {
        match self {
            Pipeline::Builtin => "builtin",
            Pipeline::Urp => "urp",
            Pipeline::Hdrp => "hdrp",
        }
    }

    pub fn from_name(name: &str) -> Option<Pipeline> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|p| p.name()).collect()
    }

    /// Value of the WGSL override constant `PIPELINE` (shaders/common/conventions.wgsl).
    pub fn shader_id(self) -> u32 {
        self as u32
    }

    /// Scale from the matrix's light-intensity axis (0–100) to the pipeline's light units.
    /// HDRP works in physical units: the spec's "×10000 in the HDRP emulation" (models.md#hdrp
    /// derives ~3×10⁴ from 100 klux/π; 10⁴ is the order the comparison application uses).
    pub fn intensity_scale(self) -> f64 {
        match self {
            Pipeline::Builtin | Pipeline::Urp => 1.0,
            Pipeline::Hdrp => 10_000.0,
        }
    }

    /// Linear light colour × intensity as the pipeline's shaders receive it.
    /// Built-in defaults to `lightsUseLinearIntensity = false`: the gamma-space colour is multiplied
    /// by the intensity *before* linearising (models.md#builtin). URP and HDRP linearise first.
    pub fn light_radiance(self, srgb_color: [f64; 3], intensity: f64) -> [f64; 3] {
        match self {
            Pipeline::Builtin => srgb_color.map(|c| srgb_to_linear(c * intensity)),
            Pipeline::Urp | Pipeline::Hdrp => {
                srgb_color.map(|c| srgb_to_linear(c) * intensity * self.intensity_scale())
            }
        }
    }

    /// Environment radiance scale, so that ambient keeps its proportion to the direct light.
    pub fn environment_scale(self) -> f64 {
        self.intensity_scale()
    }

    /// The metallic slider as the shader receives it: built-in Standard and URP Lit gamma-decode it
    /// in linear colour space (0.5 → ≈0.214); HDRP takes it as is (presets.md).
    pub fn shader_metallic(self, slider: f64) -> f64 {
        match self {
            Pipeline::Builtin | Pipeline::Urp => srgb_to_linear(slider),
            Pipeline::Hdrp => slider,
        }
    }

    pub fn attenuation(self) -> Attenuation {
        match self {
            Pipeline::Builtin => Attenuation::BuiltinTextureApprox,
            Pipeline::Urp => Attenuation::UrpSmoothInverseSquare,
            Pipeline::Hdrp => Attenuation::HdrpPunctual,
        }
    }

    pub fn tonemap(self) -> Tonemap {
        match self {
            Pipeline::Builtin | Pipeline::Urp => Tonemap::None,
            Pipeline::Hdrp => Tonemap::AutoExposureAcesFit,
        }
    }

    /// The shader that fixed objects (walls, backdrop, inner ball) are drawn with: the pipeline's
    /// default lit shader, as a new material in that pipeline would be.
    pub fn fixed_object_shader(self) -> &'static str {
        match self {
            Pipeline::Builtin => "standard",
            Pipeline::Urp | Pipeline::Hdrp => "lit",
        }
    }
}

/// Rendering path. Only forward exists so far; deferred slots in here.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RenderPath {
    Forward,
}

impl RenderPath {
    pub const ALL: [RenderPath; 1] = [RenderPath::Forward];

    pub fn name(self) -> &'static str {
        match self {
            RenderPath::Forward => "forward",
        }
    }

    pub fn from_name(name: &str) -> Option<RenderPath> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|p| p.name()).collect()
    }
}

/// Point/spot distance attenuation, x = d / range (models.md#conventions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Attenuation {
    /// Built-in's falloff texture is not public. APPROXIMATION: 1/(1 + 25x²)·smoothstep(1, 0.8, x).
    BuiltinTextureApprox,
    /// URP: (1/max(d², HALF_MIN))·sat(1 − (d²/r²)²)².
    UrpSmoothInverseSquare,
    /// HDRP: [min(1/d, 100)·sat(1 − (d²/r²)²)]².
    HdrpPunctual,
}

impl Attenuation {
    /// f64 twin of `attenuation()` in shaders/common/conventions.wgsl.
    pub fn eval(self, distance: f64, range: f64) -> f64 {
        let d2 = distance * distance;
        match self {
            Attenuation::BuiltinTextureApprox => {
                let x = distance / range;
                let t = ((x - 1.0) / (0.8 - 1.0)).clamp(0.0, 1.0);
                let smooth = t * t * (3.0 - 2.0 * t);
                smooth / (1.0 + 25.0 * x * x)
            }
            Attenuation::UrpSmoothInverseSquare => {
                let a = 1.0 / (range * range).max(1e-4);
                let f = (1.0 - (d2 * a).powi(2)).clamp(0.0, 1.0);
                f * f / d2.max(crate::color::HALF_MIN)
            }
            Attenuation::HdrpPunctual => {
                let inv_d = (1.0 / distance).min(100.0);
                let f = (1.0 - (d2 / (range * range)).powi(2)).clamp(0.0, 1.0);
                (inv_d * f).powi(2)
            }
        }
    }
}

/// Display transform from linear HDR to the PNG (models.md#hdrp "Exposure", models.md#display).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Tonemap {
    /// Built-in and URP default: clamp, sRGB encode.
    None,
    /// HDRP default volume: automatic exposure (EV limits −10..10) then ACES. APPROXIMATION: the
    /// Narkowicz fit stands in for Unity's ACES LUT; exposure from the log-average luminance.
    AutoExposureAcesFit,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_multiplies_intensity_in_gamma_space() {
        let c = Pipeline::Builtin.light_radiance([0.5, 0.5, 0.5], 2.0);
        assert!((c[0] - 1.0).abs() < 1e-12, "gamma 0.5·2 = 1 → linear 1, got {}", c[0]);
        let u = Pipeline::Urp.light_radiance([0.5, 0.5, 0.5], 2.0);
        assert!((u[0] - 2.0 * srgb_to_linear(0.5)).abs() < 1e-12);
    }

    #[test]
    fn attenuation_reaches_zero_at_range() {
        for a in [Attenuation::BuiltinTextureApprox, Attenuation::UrpSmoothInverseSquare, Attenuation::HdrpPunctual] {
            assert_eq!(a.eval(10.0, 10.0), 0.0, "{a:?}");
            assert!(a.eval(1.0, 10.0) > a.eval(5.0, 10.0), "{a:?} must fall off");
        }
        assert!((Attenuation::UrpSmoothInverseSquare.eval(1.0, 1e6) - 1.0).abs() < 1e-9);
        assert!((Attenuation::HdrpPunctual.eval(0.001, 10.0) - 1e4).abs() < 1e-3, "HDRP clamps d to 1 cm");
    }

    #[test]
    fn metallic_slider_is_gamma_decoded_except_hdrp() {
        assert!((Pipeline::Builtin.shader_metallic(0.5) - 0.214).abs() < 1e-3);
        assert_eq!(Pipeline::Hdrp.shader_metallic(0.5), 0.5);
    }
}
