//! Unity's fitted ACES tonemapper, ported from the Graphics repository's core ShaderLibrary
//! (ACES.hlsl helpers, `AcesTonemap` with TONEMAPPING_USE_FULL_ACES = 0 in Color.hlsl), in f64.
//! Written by hand: no crate implements Unity's fit (the RRT glow and red modifier, the a…e
//! luminance fit, the dark→dim surround and the D60→D65 adaptation); the published ACES crates
//! implement the full CTL transforms instead. URP and HDRP bake this function into a 32³ ACEScc
//! LUT; applying it per pixel leaves out only the LUT's interpolation.

type Mat3 = [[f64; 3]; 3];

fn mul(m: &Mat3, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Rows as written in ACES.hlsl ("pre-transposed" for `mul(M, v)`).
const SRGB_2_AP0: Mat3 =
    [[0.4397010, 0.3829780, 0.1773350], [0.0897923, 0.8134230, 0.0967616], [0.0175440, 0.1115440, 0.8707040]];
const AP0_2_AP1: Mat3 = [
    [1.4514393161, -0.2365107469, -0.2149285693],
    [-0.0765537734, 1.1762296998, -0.0996759264],
    [0.0083161484, -0.0060324498, 0.9977163014],
];
const AP1_2_XYZ: Mat3 = [
    [0.6624541811, 0.1340042065, 0.1561876870],
    [0.2722287168, 0.6740817658, 0.0536895174],
    [-0.0055746495, 0.0040607335, 1.0103391003],
];
const XYZ_2_AP1: Mat3 = [
    [1.6410233797, -0.3248032942, -0.2364246952],
    [-0.6636628587, 1.6153315917, 0.0167563477],
    [0.0117218943, -0.0082844420, 0.9883948585],
];
const XYZ_2_REC709: Mat3 = crate::color::XYZ_TO_REC709;
const D60_2_D65_CAT: Mat3 =
    [[0.98722400, -0.00611327, 0.0159533], [-0.00759836, 1.00186000, 0.0053302], [0.00307257, -0.00509595, 1.0816800]];
const AP1_RGB2Y: [f64; 3] = [0.272229, 0.674082, 0.0536895];

const RRT_GLOW_GAIN: f64 = 0.05;
const RRT_GLOW_MID: f64 = 0.08;
const RRT_RED_SCALE: f64 = 0.82;
const RRT_RED_PIVOT: f64 = 0.03;
const RRT_RED_HUE: f64 = 0.0;
const RRT_RED_WIDTH: f64 = 135.0;
const RRT_SAT_FACTOR: f64 = 0.96;
const ODT_SAT_FACTOR: f64 = 0.93;
const DIM_SURROUND_GAMMA: f64 = 0.9811;
/// HALF_MAX, the clamp of darkSurround_to_dimSurround.
const HALF_MAX: f64 = 65504.0;

/// unity_to_ACES: linear sRGB primaries → ACES2065-1 (AP0).
pub fn unity_to_aces(rgb: [f64; 3]) -> [f64; 3] {
    mul(&SRGB_2_AP0, rgb)
}

/// rgb_2_saturation: (max(ma, 1e-4) − max(mi, 1e-4)) / max(ma, 1e-2).
fn rgb_2_saturation(rgb: [f64; 3]) -> f64 {
    let mi = rgb[0].min(rgb[1]).min(rgb[2]);
    let ma = rgb[0].max(rgb[1]).max(rgb[2]);
    (ma.max(1e-4) - mi.max(1e-4)) / ma.max(1e-2)
}

/// rgb_2_yc: (b + g + r + 1.75·√(b(b − g) + g(g − r) + r(r − b))) / 3.
fn rgb_2_yc(rgb: [f64; 3]) -> f64 {
    let [r, g, b] = rgb;
    let k = (b * (b - g) + g * (g - r) + r * (r - b)).max(0.0);
    (b + g + r + 1.75 * k.sqrt()) / 3.0
}

/// rgb_2_hue in degrees, 0 for neutrals.
fn rgb_2_hue(rgb: [f64; 3]) -> f64 {
    let hue = if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
        0.0
    } else {
        (180.0 / std::f64::consts::PI) * (3f64.sqrt() * (rgb[1] - rgb[2])).atan2(2.0 * rgb[0] - rgb[1] - rgb[2])
    };
    if hue < 0.0 {
        hue + 360.0
    } else {
        hue
    }
}

fn center_hue(hue: f64, center: f64) -> f64 {
    let h = hue - center;
    if h < -180.0 {
        h + 360.0
    } else if h > 180.0 {
        h - 360.0
    } else {
        h
    }
}

/// sigmoid_shaper: 0..1 over −2..2. FastSign(0) is +1 in Unity's Common.hlsl.
fn sigmoid_shaper(x: f64) -> f64 {
    let t = (1.0 - (x / 2.0).abs()).max(0.0);
    let sign = if x >= 0.0 { 1.0 } else { -1.0 };
    (1.0 + sign * (1.0 - t * t)) / 2.0
}

fn glow_fwd(yc_in: f64, glow_gain_in: f64, glow_mid: f64) -> f64 {
    if yc_in <= 2.0 / 3.0 * glow_mid {
        glow_gain_in
    } else if yc_in >= 2.0 * glow_mid {
        0.0
    } else {
        glow_gain_in * (glow_mid / yc_in - 0.5)
    }
}

fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn desaturate(rgb: [f64; 3], factor: f64) -> [f64; 3] {
    let y = dot(rgb, AP1_RGB2Y);
    rgb.map(|c| y + (c - y) * factor)
}

/// darkSurround_to_dimSurround: AP1 → XYZ → xyY, Y^0.9811, back to AP1.
fn dark_to_dim_surround(linear_cv: [f64; 3]) -> [f64; 3] {
    let xyz = mul(&AP1_2_XYZ, linear_cv);
    let divisor = (xyz[0] + xyz[1] + xyz[2]).max(1e-4);
    let (x, y) = (xyz[0] / divisor, xyz[1] / divisor);
    let big_y = xyz[1].clamp(0.0, HALF_MAX).powf(DIM_SURROUND_GAMMA);
    let m = big_y / y.max(1e-4);
    let xyz = [x * m, big_y, (1.0 - x - y) * m];
    mul(&XYZ_2_AP1, xyz)
}

/// AcesTonemap (fitted): ACES2065-1 in, display-linear Rec.709 out (not clamped; the sRGB target
/// clamps). The fit is Unity's luminance fit of RRT + ODT.RGBmonitor_100nits_dim.
pub fn aces_tonemap(aces_in: [f64; 3]) -> [f64; 3] {
    let mut aces = aces_in;
    // Glow module
    let saturation = rgb_2_saturation(aces);
    let yc_in = rgb_2_yc(aces);
    let s = sigmoid_shaper((saturation - 0.4) / 0.2);
    let added_glow = 1.0 + glow_fwd(yc_in, RRT_GLOW_GAIN * s, RRT_GLOW_MID);
    aces = aces.map(|c| c * added_glow);
    // Red modifier
    let hue = rgb_2_hue(aces);
    let centered_hue = center_hue(hue, RRT_RED_HUE);
    let hue_weight = smoothstep(0.0, 1.0, 1.0 - (2.0 * centered_hue / RRT_RED_WIDTH).abs()).powi(2);
    aces[0] += hue_weight * saturation * (RRT_RED_PIVOT - aces[0]) * (1.0 - RRT_RED_SCALE);
    // ACES → ACEScg, clamped at 0, global desaturation
    let acescg = desaturate(mul(&AP0_2_AP1, aces).map(|c| c.max(0.0)), RRT_SAT_FACTOR);
    // Luminance fit x(ax + b)/(x(cx + d) + e)
    let (a, b, c, d, e) = (278.5085, 10.7772, 293.6045, 88.7122, 80.6889);
    let rgb_post = acescg.map(|x| (x * (a * x + b)) / (x * (c * x + d) + e));
    let linear_cv = desaturate(dark_to_dim_surround(rgb_post), ODT_SAT_FACTOR);
    let xyz = mul(&D60_2_D65_CAT, mul(&AP1_2_XYZ, linear_cv));
    mul(&XYZ_2_REC709, xyz)
}

/// The HDRP/URP ACES display transform of a linear sRGB-primaries colour.
pub fn aces_display(rgb: [f64; 3]) -> [f64; 3] {
    aces_tonemap(unity_to_aces(rgb))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grey_reference_points_of_the_spec() {
        // models.md#display: exposed 0.104 (the auto-exposure target) → 0.047; 0.18 → 0.108.
        let at = |x: f64| aces_display([x; 3]);
        let g = at(0.104);
        assert!((g[1] - 0.047).abs() < 0.002, "{g:?}");
        let g = at(0.18);
        assert!((g[1] - 0.108).abs() < 0.002, "{g:?}");
        assert!((g[0] - g[2]).abs() < 0.01, "neutral stays near neutral: {g:?}");
        assert!(at(0.0).iter().all(|c| c.abs() < 1e-6), "black stays black: {:?}", at(0.0));
    }

    #[test]
    fn monotonic_and_saturating() {
        let mut last = -1.0;
        for i in 0..200 {
            let x = 1e-3 * 1.08f64.powi(i);
            let y = aces_display([x; 3])[1];
            assert!(y > last, "{x}: {y} ≤ {last}");
            last = y;
        }
        assert!(last < 1.05 && last > 0.9, "white level {last}");
    }
}
