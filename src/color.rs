//! Colour transfer functions and constants shared by every stage (models.md#display).

/// Smallest normal half-precision value, 2⁻¹⁴ (URP's HALF_MIN).
pub const HALF_MIN: f64 = 6.103_515_625e-5;

/// CIE XYZ to linear Rec. 709 (sRGB) primaries, D65, by rows (core Color.hlsl XYZ_2_REC709_MAT).
pub const XYZ_TO_REC709: [[f64; 3]; 3] = [
    [3.2409699419, -1.5373831776, -0.4986107603],
    [-0.9692436363, 1.8759675015, 0.0415550574],
    [0.0556300797, -0.2039769589, 1.0569715142],
];

/// sRGB decode (IEC 61966-2-1), extended above 1 with the same power law.
pub fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// UnityCG.cginc GammaToLinearSpaceExact: the sRGB curve up to 1 and pow(v, 2.2) above, which is
/// how the built-in pipeline linearises a light's gamma-space colour × intensity (models.md#builtin).
pub fn gamma_to_linear_space_exact(v: f64) -> f64 {
    if v <= 0.04045 {
        v / 12.92
    } else if v < 1.0 {
        ((v + 0.055) / 1.055).powf(2.4)
    } else {
        v.powf(2.2)
    }
}

/// sRGB encode.
pub fn linear_to_srgb(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Rec. 709 / sRGB-primaries luminance of linear RGB.
pub fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips() {
        for i in 0..=100 {
            let c = i as f64 / 100.0;
            assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-12);
        }
        assert!((linear_to_srgb(0.04) - 0.220_916_301).abs() < 1e-6, "models.md#builtin gamma dielectric spec");
    }
}
