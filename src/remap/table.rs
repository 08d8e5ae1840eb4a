//! A match's record (`tables/match.json`) and its tables (`match.md`, `match.csv`): per source
//! material, the fitted target values, the error with the values copied and with the fitted ones.

use serde::{Deserialize, Serialize};

use super::{MatchError, MatchSpace, MaterialValues};

/// The version of `MatchRecord`'s layout.
pub const MATCH_SCHEMA: u32 = 1;

/// One source material's match.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MatchRow {
    /// The preset the source material comes from.
    pub preset: String,
    pub source: MaterialValues,
    pub fitted: MaterialValues,
    /// The target with the source's values copied (Unity's material upgraders).
    pub copied_error: MatchError,
    /// The target with the fitted values: what no value removes.
    pub fitted_error: MatchError,
    /// Frames rendered per scene for the fit.
    pub renders: u32,
}

/// A whole match: which sides, on which image, over which scenes.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MatchRecord {
    pub schema: u32,
    /// `pipeline/shader` of the source and the target.
    pub from: String,
    pub to: String,
    pub space: MatchSpace,
    /// The compositions every fit spans.
    pub compositions: Vec<String>,
    /// The frames' side, pixels.
    pub size: u32,
    /// On the linear image, the factor on the target's frames calibrated on a matte grey
    /// (smoothness 0, metallic 0, colour 0.5); 1 on the displayed image.
    pub exposure: f64,
    pub adapter: String,
    pub rows: Vec<MatchRow>,
}

fn rgb(c: [f64; 3]) -> String {
    format!("{:.4}, {:.4}, {:.4}", c[0], c[1], c[2])
}

impl MatchRecord {
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "# Match: {} → {}\n\nOn the {} image over {} ({}×{} frames, {}); mean FLIP and relative MSE over \
             the subject's pixels, with the source's values copied (as Unity's material upgraders copy \
             them) and with the fitted ones.",
            self.from,
            self.to,
            self.space.name(),
            self.compositions.join(", "),
            self.size,
            self.size,
            self.adapter
        );
        if self.space == MatchSpace::Linear {
            s += &format!(" The target's linear frames × {:.4e} (calibrated on a matte grey).", self.exposure);
        }
        s +=
            "\n\n| preset | source smoothness | source metallic | source colour | fitted smoothness | fitted metallic \
              | fitted colour | FLIP copied | FLIP fitted | relMSE copied | relMSE fitted |\n\
              |---|---|---|---|---|---|---|---|---|---|---|\n";
        for r in &self.rows {
            s += &format!(
                "| {} | {:.3} | {:.3} | {} | {:.3} | {:.3} | {} | {:.4} | {:.4} | {:.4e} | {:.4e} |\n",
                r.preset,
                r.source.smoothness,
                r.source.metallic,
                rgb(r.source.color),
                r.fitted.smoothness,
                r.fitted.metallic,
                rgb(r.fitted.color),
                r.copied_error.flip,
                r.fitted_error.flip,
                r.copied_error.rel_mse,
                r.fitted_error.rel_mse
            );
        }
        s
    }

    pub fn csv(&self) -> String {
        let mut s = String::from(
            "preset,source_smoothness,source_metallic,source_r,source_g,source_b,fitted_smoothness,\
             fitted_metallic,fitted_r,fitted_g,fitted_b,flip_copied,flip_fitted,rel_mse_copied,rel_mse_fitted\n",
        );
        for r in &self.rows {
            let values = [
                r.source.smoothness,
                r.source.metallic,
                r.source.color[0],
                r.source.color[1],
                r.source.color[2],
                r.fitted.smoothness,
                r.fitted.metallic,
                r.fitted.color[0],
                r.fitted.color[1],
                r.fitted.color[2],
                r.copied_error.flip,
                r.fitted_error.flip,
                r.copied_error.rel_mse,
                r.fitted_error.rel_mse,
            ];
            s += &r.preset;
            for v in values {
                s += &format!(",{v}");
            }
            s.push('\n');
        }
        s
    }
}
