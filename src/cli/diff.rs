//! `shadematrix diff A B`: FLIP and SSIM (and RMSE, PSNR, bad-value counts) of two images.

use std::path::Path;

use crate::compare::images::{compare_with, Metric};
use crate::compare::LoadedImage;
use crate::error::Error;

pub fn diff(a: &Path, b: &Path, json: bool, out: Option<&Path>, per_channel: bool) -> Result<(), Error> {
    let what = format!("{} vs {}", a.display(), b.display());
    let c = compare_with(&LoadedImage::load(a)?, &LoadedImage::load(b)?, &what, per_channel)?;
    if let Some(dir) = out {
        let png = |name: &str, px: &Option<Vec<u8>>| -> Result<(), Error> {
            if let Some(px) = px {
                let bytes = crate::images::encode::map_png_bytes(c.width, c.height, px)?;
                crate::fsutil::write_atomic(&dir.join(name), &bytes)?;
            }
            Ok(())
        };
        png("flip.png", &c.flip_map_rgba8)?;
        png("ssim.png", &c.ssim_map_rgba8)?;
    }
    if json {
        super::outln!("{}", serde_json::to_string_pretty(&c).unwrap_or_default());
    } else {
        let show = |m: &Metric| match m {
            Metric::Value { mean } => format!("{mean:.6}"),
            Metric::Missing { missing } => format!("missing ({missing})"),
        };
        super::outln!(
            "{}×{}: {}-FLIP mean {}, SSIM mean {}, RMSE {:.6}, PSNR {}",
            c.width,
            c.height,
            c.flip.kind.to_uppercase(),
            show(&c.flip.value),
            show(&c.ssim),
            c.rmse,
            c.psnr_db.map(|p| format!("{p:.2} dB")).unwrap_or_else(|| "—".into())
        );
    }
    Ok(())
}
