//! f64 twin of HDRP's bloom as `render::passes::bloom` runs it (shaders/pass/bloom.wgsl): the same
//! Karis-weighted prefilter, pyramid, binomial blur, bicubic or bilinear upsample and lerp
//! composite, on a linear RGB image, from the volume's settings through HDRP's remaps
//! (`BloomSettings::composite_weight`, `upsample_scatter`, `bicubic`). Used to test the GPU chain
//! and to reason about what bloom can change.

use glam::DVec3;

/// A linear RGB image, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<DVec3>,
}

impl Image {
    fn new(width: usize, height: usize) -> Image {
        Image { width, height, texels: vec![DVec3::ZERO; width * height] }
    }

    fn load(&self, x: i64, y: i64) -> DVec3 {
        let x = x.clamp(0, self.width as i64 - 1) as usize;
        let y = y.clamp(0, self.height as i64 - 1) as usize;
        self.texels[y * self.width + x]
    }

    fn bilinear(&self, u: f64, v: f64) -> DVec3 {
        let (x, y) = (u * self.width as f64 - 0.5, v * self.height as f64 - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let a = self.load(x0, y0).lerp(self.load(x0 + 1, y0), fx);
        let b = self.load(x0, y0 + 1).lerp(self.load(x0 + 1, y0 + 1), fx);
        a.lerp(b, fy)
    }

    fn bicubic(&self, u: f64, v: f64) -> DVec3 {
        let (x, y) = (u * self.width as f64 - 0.5, v * self.height as f64 - 0.5);
        let (wx, wy) = (bspline(x - x.floor()), bspline(y - y.floor()));
        let (x0, y0) = (x.floor() as i64, y.floor() as i64);
        let mut c = DVec3::ZERO;
        for (j, wj) in wy.iter().enumerate() {
            for (i, wi) in wx.iter().enumerate() {
                c += self.load(x0 + i as i64 - 1, y0 + j as i64 - 1) * (wi * wj);
            }
        }
        c
    }

    fn map(width: usize, height: usize, f: impl Fn(usize, usize, f64, f64) -> DVec3) -> Image {
        let mut out = Image::new(width, height);
        for y in 0..height {
            for x in 0..width {
                let (u, v) = ((x as f64 + 0.5) / width as f64, (y as f64 + 0.5) / height as f64);
                out.texels[y * width + x] = f(x, y, u, v);
            }
        }
        out
    }

    fn blur(&self, dx: i64, dy: i64) -> Image {
        const W: [f64; 5] = [0.2734375, 0.21875, 0.109375, 0.03125, 0.00390625];
        Image::map(self.width, self.height, |x, y, _, _| {
            let (x, y) = (x as i64, y as i64);
            let mut c = self.load(x, y) * W[0];
            for (k, w) in W.iter().enumerate().skip(1) {
                let k = k as i64;
                c += (self.load(x + dx * k, y + dy * k) + self.load(x - dx * k, y - dy * k)) * *w;
            }
            c
        })
    }
}

/// Cubic B-spline weights of the four texels around fraction f.
fn bspline(f: f64) -> [f64; 4] {
    let g = 1.0 - f;
    [g * g * g, 4.0 - 6.0 * f * f + 3.0 * f * f * f, 4.0 - 6.0 * g * g + 3.0 * g * g * g, f * f * f].map(|w| w / 6.0)
}

/// BloomCommon.hlsl QuadraticThreshold at threshold 0 (knee 1e-5).
fn quadratic_threshold(c: DVec3) -> DVec3 {
    let br = c.max_element();
    let rq = (br + 1e-5).clamp(0.0, 2e-5);
    let rq = 25000.0 * rq * rq;
    c * (rq.max(br) / br.max(1e-4))
}

/// Core Color.hlsl Luminance.
fn luminance(c: DVec3) -> f64 {
    c.dot(DVec3::new(0.2126729, 0.7151522, 0.0721750))
}

/// BilinearSample: `image` at (u, v) offset by `offset` of its texels, through the threshold, with
/// its Karis weight 1/(1 + luminance).
fn prefilter_tap(image: &Image, u: f64, v: f64, offset: (f64, f64)) -> (DVec3, f64) {
    let c = quadratic_threshold(image.bilinear(u + offset.0 / image.width as f64, v + offset.1 / image.height as f64));
    (c, 1.0 / (luminance(c) + 1.0))
}

/// PartialAverage: four taps' Karis-weighted mean.
fn partial_average(taps: [(DVec3, f64); 4]) -> DVec3 {
    let sum: DVec3 = taps.iter().map(|(c, w)| *c * *w).sum();
    sum / taps.iter().map(|(_, w)| w).sum::<f64>()
}

/// BloomPrefilter.compute HIGH_QUALITY [Jimenez14]: the inner 2×2 block half a texel out weighs
/// 1/2, the four corner blocks one texel out 1/8 each, each block a Karis-weighted mean.
fn prefilter_high(image: &Image, u: f64, v: f64) -> DVec3 {
    let t = |x: f64, y: f64| prefilter_tap(image, u, v, (x, y));
    let (a, b, c) = (t(-1.0, -1.0), t(0.0, -1.0), t(1.0, -1.0));
    let (d, e) = (t(-0.5, -0.5), t(0.5, -0.5));
    let (f, g, h) = (t(-1.0, 0.0), t(0.0, 0.0), t(1.0, 0.0));
    let (i, j) = (t(-0.5, 0.5), t(0.5, 0.5));
    let (k, l, m) = (t(-1.0, 1.0), t(0.0, 1.0), t(1.0, 1.0));
    partial_average([d, e, i, j]) * 0.5
        + (partial_average([a, b, f, g])
            + partial_average([b, c, g, h])
            + partial_average([f, g, k, l])
            + partial_average([g, h, l, m]))
            * 0.125
}

/// `image` bloomed as HDRP's volume `settings` say.
pub fn bloom(image: &Image, settings: &crate::render::passes::bloom::BloomSettings) -> Image {
    let sizes = crate::render::passes::bloom::level_sizes(image.width as u32, image.height as u32, settings.quarter);
    let bicubic = settings.bicubic(image.width as u32, image.height as u32);
    let filter = |img: &Image, u: f64, v: f64| if bicubic { img.bicubic(u, v) } else { img.bilinear(u, v) };
    let taps = [(0.0, 0.0), (0.9, -0.4), (-0.9, 0.4), (0.4, 0.9), (-0.4, -0.9)];
    let mut levels: Vec<Image> = Vec::new();
    for (k, &(w, h)) in sizes.iter().enumerate() {
        let (w, h) = (w as usize, h as usize);
        let input = match k {
            0 if settings.high_quality_prefiltering => Image::map(w, h, |_, _, u, v| prefilter_high(image, u, v)),
            0 => Image::map(w, h, |_, _, u, v| {
                let (mut c, mut weights) = (DVec3::ZERO, 0.0);
                for (tx, ty) in taps {
                    let (tap, weight) = prefilter_tap(image, u, v, (tx, ty));
                    c += tap * weight;
                    weights += weight;
                }
                c / weights
            }),
            _ => {
                let prev = &levels[k - 1];
                Image::map(w, h, |_, _, u, v| prev.bilinear(u, v))
            }
        };
        levels.push(input.blur(1, 0).blur(0, 1));
    }
    let scatter = settings.upsample_scatter();
    let mut up = levels.pop().expect("at least one level");
    while let Some(level) = levels.pop() {
        up = Image::map(level.width, level.height, |x, y, u, v| {
            level.texels[y * level.width + x].lerp(filter(&up, u, v), scatter)
        });
    }
    composite(image, &up, settings)
}

/// UberPost.compute's composite of `bloom` over `image`: lerp(colour, bicubic(bloom), weight),
/// bicubic at every size (its bilinear fetch is compiled out, `#if 0`), unlike the upsamples.
fn composite(image: &Image, bloom: &Image, settings: &crate::render::passes::bloom::BloomSettings) -> Image {
    let weight = settings.composite_weight();
    Image::map(image.width, image.height, |x, y, u, v| {
        image.texels[y * image.width + x].lerp(bloom.bicubic(u, v), weight)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::render::passes::bloom::BloomSettings;

    #[test]
    fn the_composite_filters_bicubically_below_800_by_450_where_the_upsamples_do_not() {
        let hdrp = BloomSettings::default();
        assert!(!hdrp.bicubic(96, 64), "the upsamples are bilinear at 96×64");
        // A 4×4 bloom with one lit texel over a black 96×64 frame: the composite reads it with
        // core's B-spline SampleTexture2DBicubic, which a bilinear fetch does not match.
        let mut spot = Image { width: 4, height: 4, texels: vec![DVec3::ZERO; 16] };
        spot.texels[5] = DVec3::ONE;
        let black = Image { width: 96, height: 64, texels: vec![DVec3::ZERO; 96 * 64] };
        let out = composite(&black, &spot, &hdrp);
        let w = hdrp.composite_weight();
        let (mut bicubic, mut bilinear) = (0.0f64, 0.0f64);
        for (i, t) in out.texels.iter().enumerate() {
            let (u, v) = (((i % 96) as f64 + 0.5) / 96.0, ((i / 96) as f64 + 0.5) / 64.0);
            bicubic = bicubic.max((t.x - w * spot.bicubic(u, v).x).abs());
            bilinear = bilinear.max((t.x - w * spot.bilinear(u, v).x).abs());
        }
        assert!(bicubic < 1e-12, "bicubic: {bicubic}");
        assert!(bilinear > 1e-3, "not bilinear: {bilinear}");
    }

    #[test]
    fn the_high_quality_prefilter_weighs_its_blocks_as_jimenez14() {
        use crate::pipelines::settings::HdrpQuality;
        // A uniform image: every block's Karis mean is the colour, the blocks' weights sum to 1.
        let flat = Image { width: 16, height: 16, texels: vec![DVec3::splat(2.0); 256] };
        let c = prefilter_high(&flat, 0.5, 0.5);
        assert!((c - DVec3::splat(2.0)).abs().max_element() < 1e-12, "{c}");
        // A lone bright texel under the centre: the inner block (weight 1/2) and all four corner
        // blocks see it, so High keeps more of it than the five rotated taps do.
        let mut spot = flat.clone();
        spot.texels.iter_mut().for_each(|t| *t = DVec3::ZERO);
        spot.texels[8 * 16 + 8] = DVec3::splat(50.0);
        let high = prefilter_high(&spot, 8.5 / 16.0, 8.5 / 16.0);
        assert!(high.x > 0.0 && high.x < 50.0, "{high}");
        let (hi, med) = (BloomSettings::at(HdrpQuality::High), BloomSettings::at(HdrpQuality::Medium));
        assert!(hi.high_quality_prefiltering && !med.high_quality_prefiltering && !hi.quarter);
        let (a, b) = (bloom(&spot, &hi), bloom(&spot, &med));
        assert!(a != b, "the prefilter changes the bloom");
    }

    #[test]
    fn a_uniform_image_is_unchanged_and_an_impulse_spreads() {
        let hdrp = BloomSettings::default();
        let flat = Image { width: 32, height: 24, texels: vec![DVec3::splat(3.0); 32 * 24] };
        let out = bloom(&flat, &hdrp);
        assert!(out.texels.iter().all(|t| (*t - DVec3::splat(3.0)).abs().max_element() < 1e-12));
        let mut spot = Image { width: 64, height: 64, texels: vec![DVec3::ZERO; 64 * 64] };
        spot.texels[32 * 64 + 32] = DVec3::splat(100.0);
        let out = bloom(&spot, &hdrp);
        // The composite keeps 1 − (2^0.2 − 1) of the pixel; the Karis weights (1/(1 + luma)) let a
        // lone bright pixel into the pyramid at a fraction of its energy, as HDRP's prefilter does.
        assert!((out.texels[32 * 64 + 32].x - 100.0 * (1.0 - hdrp.composite_weight())).abs() < 1.0);
        let total: f64 = out.texels.iter().map(|t| t.x).sum();
        assert!(total < 100.0 && total > 100.0 * (1.0 - hdrp.composite_weight()), "energy {total}");
        assert!(out.texels[32 * 64 + 40].x > 0.0, "light spreads 8 pixels out");
    }
}
