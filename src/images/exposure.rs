//! HDRP exposure metering on a linear HDR image (models.md#exposure). Automatic mode follows
//! Exposure.compute: every pixel's EV100 = log2(max(L, 1e-4)·100/12.5), weighted by the metering
//! mode, averaged over all pixels (dark ones included), compensation subtracted, clamped to the
//! limits, exposure = 1/(1.2·2^EV100). HDRP meters a 1024² downsample of the previous frame's
//! pre-exposed buffer; a single still frame is metered here at its own resolution, without
//! temporal adaptation (the converged value of HDRP's "progressive" adaptation).

use serde::{Deserialize, Serialize};

use crate::pipelines::volume::{ev100_to_exposure, ExposureMode, ExposureSettings, MeteringMode};

/// HDRP's reflected-light meter calibration constant K (MeterCalibrationConstant).
pub const METER_CALIBRATION: f64 = 12.5;
/// Luminance floor before the log (Exposure.compute KPrePass).
pub const LUMINANCE_FLOOR: f64 = 1e-4;

/// What metering measured and chose, recorded in `cell.json`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ExposureRecord {
    pub mode: ExposureMode,
    pub metering: MeteringMode,
    /// Metered EV100 before compensation and limits (the fixed EV in fixed mode).
    pub metered_ev100: f64,
    /// EV100 used: metered − compensation, clamped to the limits.
    pub ev100: f64,
    pub limits: [f64; 2],
    pub compensation: f64,
    /// Whether the limits changed the EV (the scene is outside them).
    pub clamped: bool,
    /// Multiplier applied to the HDR values before the tonemapper: 1/(1.2·2^EV100).
    pub exposure: f64,
}

/// Rec.709 luminance with Unity's constants (Color.hlsl `Luminance`).
pub fn unity_luminance(rgb: [f64; 3]) -> f64 {
    0.2126729 * rgb[0] + 0.7151522 * rgb[1] + 0.0721750 * rgb[2]
}

/// ExposureCommon.hlsl WeightSample for pixel (x, y) of a w×h image.
pub fn metering_weight(mode: MeteringMode, x: u32, y: u32, w: u32, h: u32) -> f64 {
    match mode {
        MeteringMode::Average => 1.0,
        MeteringMode::CenterWeighted => {
            let diagonal = 0.5 * (w as f64 + h as f64);
            let (dx, dy) = (w as f64 * 0.5 - x as f64, h as f64 * 0.5 - y as f64);
            1.0 - ((dx * dx + dy * dy).sqrt() / diagonal).clamp(0.0, 1.0)
        }
    }
}

/// EV100 of a luminance: log2(max(L, 1e-4)·100/K).
pub fn ev100_of_luminance(l: f64) -> f64 {
    (l.max(LUMINANCE_FLOOR) * 100.0 / METER_CALIBRATION).log2()
}

/// Meter `hdr` (RGBA f32, row-major, w×h) with `settings`. Non-finite pixels are skipped.
pub fn meter(hdr: &[f32], w: u32, h: u32, settings: &ExposureSettings) -> ExposureRecord {
    let metered = match settings.mode {
        ExposureMode::Fixed => settings.fixed_ev,
        ExposureMode::Automatic => weighted_mean_ev(hdr, w, h, settings.metering),
        ExposureMode::AutomaticHistogram => histogram_ev(hdr, w, h, settings),
    };
    let limits = [settings.limit_min, settings.limit_max];
    let wanted = metered - settings.compensation;
    let ev100 = match settings.mode {
        ExposureMode::Fixed => wanted,
        _ => wanted.clamp(limits[0], limits[1]),
    };
    ExposureRecord {
        mode: settings.mode,
        metering: settings.metering,
        metered_ev100: metered,
        ev100,
        limits,
        compensation: settings.compensation,
        clamped: ev100 != wanted,
        exposure: ev100_to_exposure(ev100),
    }
}

fn pixels(hdr: &[f32], w: u32) -> impl Iterator<Item = (u32, u32, f64)> + '_ {
    hdr.chunks_exact(4).enumerate().filter_map(move |(i, px)| {
        let l = unity_luminance([px[0] as f64, px[1] as f64, px[2] as f64]);
        l.is_finite().then_some(((i as u32) % w, (i as u32) / w, l))
    })
}

fn weighted_mean_ev(hdr: &[f32], w: u32, h: u32, metering: MeteringMode) -> f64 {
    let (mut sum, mut weight) = (0.0, 0.0);
    for (x, y, l) in pixels(hdr, w) {
        let k = metering_weight(metering, x, y, w, h);
        sum += k * ev100_of_luminance(l);
        weight += k;
    }
    if weight > 0.0 {
        sum / weight
    } else {
        0.0
    }
}

/// APPROXIMATION of HDRP's histogram mode: exact weighted percentiles of the per-pixel EV100
/// instead of its 128 bins over a fixed EV range; the weighted mean EV inside the band.
fn histogram_ev(hdr: &[f32], w: u32, h: u32, settings: &ExposureSettings) -> f64 {
    let mut evs: Vec<(f64, f64)> = pixels(hdr, w)
        .map(|(x, y, l)| (ev100_of_luminance(l), metering_weight(settings.metering, x, y, w, h)))
        .collect();
    evs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = evs.iter().map(|e| e.1).sum();
    if total <= 0.0 {
        return 0.0;
    }
    let (lo, hi) = (total * settings.histogram_percent[0] / 100.0, total * settings.histogram_percent[1] / 100.0);
    let (mut seen, mut sum, mut weight) = (0.0, 0.0, 0.0);
    for (ev, k) in evs {
        let (start, end) = (seen, seen + k);
        seen = end;
        let inside = (end.min(hi) - start.max(lo)).max(0.0);
        sum += ev * inside;
        weight += inside;
    }
    if weight > 0.0 {
        sum / weight
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_image_meters_its_own_ev() {
        let img = vec![1.0f32; 8 * 8 * 4];
        let r = meter(&img, 8, 8, &ExposureSettings::default());
        assert!((r.ev100 - 3.0).abs() < 1e-6, "L = 1 → log2(100/12.5) = 3, got {}", r.ev100);
        assert!((r.exposure - 1.0 / 9.6).abs() < 1e-6);
        assert!(!r.clamped);
    }

    #[test]
    fn dark_pixels_count_and_limits_clamp() {
        // Half the pixels black (floored at 1e-4 → EV −6.97), half at L = 1 (EV 3): average metering
        // gives the mean of the two.
        let mut img = vec![0.0f32; 2 * 4];
        img.extend([1.0f32; 2 * 4]);
        let s = ExposureSettings { metering: MeteringMode::Average, ..Default::default() };
        let r = meter(&img, 2, 2, &s);
        let want = 0.5 * (ev100_of_luminance(0.0) + 3.0);
        assert!((r.ev100 - want).abs() < 1e-6, "{} vs {want}", r.ev100);
        let bright = vec![1e5f32; 16];
        let r = meter(&bright, 2, 2, &ExposureSettings::default());
        assert!(r.clamped && r.ev100 == 10.0 && r.metered_ev100 > 19.0, "{r:?}");
    }

    #[test]
    fn histogram_band_ignores_the_dark_and_the_bright_ends_and_fixed_ignores_the_image() {
        // 30 % black, 60 % at L = 1 (EV 3), 10 % at L = 1000: the 40–90 % band holds only L = 1.
        let mut img = vec![0.0f32; 30 * 4];
        img.extend(std::iter::repeat_n(1.0f32, 60 * 4));
        img.extend(std::iter::repeat_n(1000.0f32, 10 * 4));
        let s = ExposureSettings {
            mode: ExposureMode::AutomaticHistogram,
            metering: MeteringMode::Average,
            ..Default::default()
        };
        let r = meter(&img, 10, 10, &s);
        assert!((r.ev100 - 3.0).abs() < 1e-6, "{r:?}");
        let fixed = ExposureSettings { mode: ExposureMode::Fixed, fixed_ev: 12.0, compensation: 1.0, ..s };
        let r = meter(&img, 10, 10, &fixed);
        assert_eq!((r.ev100, r.clamped), (11.0, false), "EV − compensation, no limits");
        assert!((r.exposure - 1.0 / (1.2 * 2f64.powi(11))).abs() < 1e-15);
    }

    #[test]
    fn centre_weight_falls_to_zero_at_half_the_diagonal_sum() {
        assert_eq!(metering_weight(MeteringMode::CenterWeighted, 50, 50, 100, 100), 1.0);
        assert!(metering_weight(MeteringMode::CenterWeighted, 0, 0, 100, 100) > 0.29);
        assert!(metering_weight(MeteringMode::CenterWeighted, 0, 0, 100, 100) < 0.30);
    }
}
