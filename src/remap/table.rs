//! A match's record (`tables/match.json`) and its tables (`match.md`, `match.csv`): per source
//! material, the fitted target values, the error with the values copied and with the fitted ones.

use serde::{Deserialize, Serialize};

use super::{MatchError, MatchSpace, MaterialValues};

/// The version of `MatchRecord`'s layout.
/// 2: a row's `frames` folder; a material's `params` (its model parameters, where swept).
pub const MATCH_SCHEMA: u32 = 2;

/// One source material's match.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatchRow {
    /// The preset the source material comes from.
    pub preset: String,
    pub source: MaterialValues,
    pub fitted: MaterialValues,
    /// The target with the source's values copied (Unity's material upgraders).
    pub copied_error: MatchError,
    /// The target with the fitted values: what no value removes.
    pub fitted_error: MatchError,
    /// Frames rendered per scene for the fit (the grid's basis pairs only where first needed).
    pub renders: u32,
    /// The folder, relative to the match's, of the row's frames: `<composition>-source.png`,
    /// `-copied.png`, `-fitted.png` (as compared: exposed, on the displayed image).
    pub frames: String,
}

/// What a match's rows depend on besides their own material: a row of an interrupted match is
/// taken again only under the same key.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatchKey {
    pub from: String,
    pub to: String,
    pub space: MatchSpace,
    pub size: u32,
    pub iterations: u64,
    /// The matrix's hash (its text and the files it names).
    pub matrix: String,
    /// The calibrated exposure (1 on the displayed image).
    pub exposure: f64,
    /// The source values the fit keeps.
    pub kept: super::fit::Kept,
    /// The shadematrix version that rendered the rows.
    pub version: String,
}

/// The rows a match has finished (`tables/match.progress.json`), written after each: a match
/// interrupted and run again with the same key takes them instead of fitting them again.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MatchProgress {
    pub schema: u32,
    pub key: MatchKey,
    pub rows: Vec<MatchRow>,
}

/// One preset's rows summarised: the mean error copied and fitted.
#[derive(Debug, Clone, PartialEq)]
pub struct PresetSummary {
    pub preset: String,
    pub rows: usize,
    pub copied_flip: f64,
    pub fitted_flip: f64,
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
    /// The source's values the fit kept as they are (`--keep`): smoothness, metallic, color.
    #[serde(default)]
    pub kept: Vec<String>,
    pub adapter: String,
    pub rows: Vec<MatchRow>,
}

/// `name=value` of a material's model parameters, `–` for none.
fn params(v: &MaterialValues) -> String {
    if v.params.is_empty() {
        return "–".into();
    }
    v.params.iter().map(|(k, v)| format!("{k}={v:.3}")).collect::<Vec<_>>().join(" ")
}

fn rgb(c: [f64; 3]) -> String {
    format!("{:.4}, {:.4}, {:.4}", c[0], c[1], c[2])
}

impl MatchRecord {
    /// Per preset (in the rows' order), then `all`: the mean FLIP over its rows, copied and fitted.
    pub fn summary(&self) -> Vec<PresetSummary> {
        let empty = |preset: &str| PresetSummary { preset: preset.into(), rows: 0, copied_flip: 0.0, fitted_flip: 0.0 };
        let mut out: Vec<PresetSummary> = Vec::new();
        let mut all = empty("all");
        for r in &self.rows {
            let i = match out.iter().position(|p| p.preset == r.preset) {
                Some(i) => i,
                None => {
                    out.push(empty(&r.preset));
                    out.len() - 1
                }
            };
            for p in [&mut out[i], &mut all] {
                p.rows += 1;
                p.copied_flip += r.copied_error.flip;
                p.fitted_flip += r.fitted_error.flip;
            }
        }
        out.push(all);
        out.retain(|p| p.rows > 0);
        for p in &mut out {
            p.copied_flip /= p.rows as f64;
            p.fitted_flip /= p.rows as f64;
        }
        out
    }

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
        if !self.kept.is_empty() {
            s += &format!(" Kept from the source: {}.", self.kept.join(", "));
        }
        s += "\n\n| preset | materials | mean FLIP copied | mean FLIP fitted |\n|---|---|---|---|\n";
        for p in self.summary() {
            s += &format!("| {} | {} | {:.4} | {:.4} |\n", p.preset, p.rows, p.copied_flip, p.fitted_flip);
        }
        s +=
            "\n\n| preset | source smoothness | source metallic | source colour | fitted smoothness | fitted metallic \
              | fitted colour | fitted parameters | FLIP copied | FLIP fitted | relMSE copied | relMSE fitted |\n\
              |---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for r in &self.rows {
            s += &format!(
                "| {} | {:.3} | {:.3} | {} | {:.3} | {:.3} | {} | {} | {:.4} | {:.4} | {:.4e} | {:.4e} |\n",
                r.preset,
                r.source.smoothness,
                r.source.metallic,
                rgb(r.source.color),
                r.fitted.smoothness,
                r.fitted.metallic,
                rgb(r.fitted.color),
                params(&r.fitted),
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
             fitted_metallic,fitted_r,fitted_g,fitted_b,flip_copied,flip_fitted,rel_mse_copied,rel_mse_fitted,\
             fitted_params\n",
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
            // `name=value` pairs joined by spaces: no comma to quote.
            let p: Vec<String> = r.fitted.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
            s += &format!(",{}\n", p.join(" "));
        }
        s
    }
}

/// A display-space match of `rows` from built-in Standard to URP Lit, for tests.
#[cfg(test)]
pub(crate) fn record_of(rows: Vec<MatchRow>) -> MatchRecord {
    MatchRecord {
        schema: MATCH_SCHEMA,
        from: "builtin/standard".into(),
        to: "urp/lit".into(),
        space: MatchSpace::Display,
        compositions: vec![],
        size: 16,
        exposure: 1.0,
        kept: vec![],
        adapter: String::new(),
        rows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_averages_each_presets_own_rows() {
        let row = |preset: &str, copied: f64, fitted: f64| MatchRow {
            preset: preset.into(),
            source: MaterialValues::new(0.5, 0.0, [0.5; 3]),
            fitted: MaterialValues::new(0.5, 0.0, [0.5; 3]),
            copied_error: MatchError { flip: copied, rel_mse: 0.0 },
            fitted_error: MatchError { flip: fitted, rel_mse: 0.0 },
            renders: 1,
            frames: String::new(),
        };
        let record = record_of(vec![row("gold", 0.4, 0.2), row("wood", 0.1, 0.1), row("gold", 0.6, 0.4)]);
        let got: Vec<(String, usize, f64, f64)> =
            record.summary().into_iter().map(|p| (p.preset, p.rows, p.copied_flip, p.fitted_flip)).collect();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert_eq!(got.iter().map(|g| (g.0.as_str(), g.1)).collect::<Vec<_>>(), [("gold", 2), ("wood", 1), ("all", 3)]);
        assert!(close(got[0].2, 0.5) && close(got[0].3, 0.3) && close(got[1].2, 0.1), "{got:?}");
        assert!(close(got[2].2, 1.1 / 3.0) && close(got[2].3, 0.7 / 3.0), "{got:?}");
    }
}
