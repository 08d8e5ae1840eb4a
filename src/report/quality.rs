//! The quality report of a run that sweeps engine settings (`[sweep.settings]`): for each pipeline,
//! every settings combination's error against its cells' references (relMSE with the truth's noise,
//! mean FLIP) next to its frame time per pass, the Pareto front, and the tiers — for each error
//! budget the cheapest combination that stays within it — beside what Unity's own presets (URP's
//! assets, built-in's quality levels, HDRP's defaults) cost and score. Written as
//! tables/quality.md|csv and plots/quality_<pipeline>.svg; a run that sweeps no setting has none.

use std::collections::BTreeMap;
use std::fmt::Write;

use super::error_time::ErrorMeasure;
use super::run_data::RunData;
use super::scatter::{ScatterPoint, ScatterText};
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::pipelines::settings::QualityLevel;
use crate::pipelines::settings_axes::{self, SettingValue};
use crate::pipelines::Pipeline;
use crate::record::CellRecord;

/// The error budgets of the tiers table, as the mean LDR-FLIP of a combination's cells.
pub const BUDGETS: [f64; 3] = [0.02, 0.05, 0.1];

/// One pipeline's cells that share their settings, summed up.
#[derive(Debug, Clone)]
pub struct Combination {
    pub pipeline: Pipeline,
    /// `key=value` pairs (`engine`: the engine's own settings).
    pub settings: String,
    /// The Unity preset it is, where it is one (`URP asset high_fidelity`, `quality level low`).
    pub preset: Option<String>,
    pub cells: usize,
    /// Means over its cells: the frame time, each pass's time, the LDR-FLIP mean, and against a
    /// truth the linear relMSE and what the truth's noise adds to it in expectation.
    pub time_ms: f64,
    pub passes: BTreeMap<String, f64>,
    pub flip: f64,
    pub relative_mse: Option<f64>,
    pub truth_noise: Option<f64>,
    /// The mean LDR-FLIP of its frames from the same cells at the pipeline's best combination (the
    /// least error against the references): what the settings cost the image, apart from what the
    /// pipeline's models cost it at their best. None where a PNG could not be read.
    pub flip_from_best: Option<f64>,
    /// On the Pareto front of time against the error against the references, and against the
    /// FLIP from the best combination.
    pub pareto: bool,
    pub pareto_from_best: bool,
    /// Its cells' ids by what they are apart from their settings (`same_but_settings`).
    pub ids: BTreeMap<String, String>,
}

impl Combination {
    /// The plotted error: relMSE against the truth where measured, else the FLIP mean.
    fn error(&self, measure: ErrorMeasure) -> f64 {
        match measure {
            ErrorMeasure::TruthRelativeMse => self.relative_mse.unwrap_or(self.flip),
            ErrorMeasure::Flip => self.flip,
        }
    }
}

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (n, sum) = v.fold((0usize, 0.0), |(n, s), x| (n + 1, s + x));
    (n > 0).then(|| sum / n as f64)
}

/// What the engine's own settings are, as Unity names them (the first cell's record says).
fn own_preset(pipeline: Pipeline, cell: &CellRecord) -> String {
    match pipeline {
        Pipeline::Urp => match &cell.engine.urp {
            Some(a) if a.preset.asset() == *a => format!("URP asset {}", a.preset.name()),
            Some(a) => format!("URP asset {} with the matrix's overrides", a.preset.name()),
            None => "URP asset default".into(),
        },
        Pipeline::Builtin => {
            let quality = cell.engine.builtin.map(|b| b.quality).unwrap_or_default();
            match QualityLevel::ALL.into_iter().find(|l| l.fields().0 == quality) {
                Some(level) => format!("quality level {}", level.name()),
                None => "the matrix's quality fields".into(),
            }
        }
        Pipeline::Hdrp => match &cell.engine.hdrp {
            None => "HDRP defaults".into(),
            Some(_) => "HDRP with the matrix's settings".into(),
        },
    }
}

/// The preset a combination of swept settings is: only presets swept (a URP asset, a quality
/// level), or none at all (the engine's own).
fn preset_of(pipeline: Pipeline, settings: &BTreeMap<String, SettingValue>, first: &CellRecord) -> Option<String> {
    if settings.is_empty() {
        return Some(format!("{} (own)", own_preset(pipeline, first)));
    }
    let only_presets = settings.keys().all(|k| settings_axes::find(pipeline, k).is_some_and(|r| r.preset));
    only_presets.then(|| {
        settings
            .iter()
            .map(|(k, v)| match k.as_str() {
                "asset" => format!("URP asset {}", v.label()),
                "quality_level" => format!("quality level {}", v.label()),
                _ => format!("{k} {}", v.label()),
            })
            .collect::<Vec<_>>()
            .join(", ")
    })
}

fn settings_text(settings: &BTreeMap<String, SettingValue>) -> String {
    match settings.is_empty() {
        true => "engine".into(),
        false => settings.iter().map(|(k, v)| format!("{k}={}", v.label())).collect::<Vec<_>>().join(", "),
    }
}

/// How many combinations the tables leave out, and why.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LeftOut {
    /// A cell without a reference or a time.
    pub unmeasured: usize,
    /// Its frames all another's: settings that cannot change those frames repeat a combination
    /// (the one with the fewest settings is kept, and Unity's presets, so each is named).
    pub twins: usize,
}

/// The combinations of each pipeline, and which were left out. None where no cell's settings are
/// swept.
#[allow(clippy::type_complexity)]
pub fn combinations(
    run: &RunData,
    gpu: bool,
) -> Option<(BTreeMap<Pipeline, (ErrorMeasure, Vec<Combination>)>, LeftOut)> {
    if run.cells.iter().all(|c| c.coords.settings.is_empty()) {
        return None;
    }
    let mut groups: BTreeMap<(Pipeline, String), Vec<&CellRecord>> = BTreeMap::new();
    for c in &run.cells {
        groups.entry((c.pipeline, settings_text(&c.coords.settings))).or_default().push(c);
    }
    // Combinations whose frames are the same ones (each cell or the cell it twins): one is kept.
    fn frames<'a>(cells: &[&'a CellRecord]) -> Vec<&'a str> {
        let mut ids: Vec<&str> = cells.iter().map(|c| c.twin_of.as_ref().unwrap_or(&c.id).0.as_str()).collect();
        ids.sort_unstable();
        ids
    }
    let mut kept: BTreeMap<(Pipeline, Vec<&str>), &str> = BTreeMap::new();
    for ((pipeline, settings), cells) in &groups {
        let slot = kept.entry((*pipeline, frames(cells))).or_insert(settings);
        if (settings.matches(", ").count(), settings.as_str()) < (slot.matches(", ").count(), *slot) {
            *slot = settings;
        }
    }
    let kept: Vec<(Pipeline, String)> = kept.into_iter().map(|((p, _), s)| (p, s.to_string())).collect();
    let time = |c: &CellRecord| if gpu { c.gpu_median_ms() } else { c.timing.cpu_wall.median_ms };
    let mut by: BTreeMap<Pipeline, Vec<Combination>> = BTreeMap::new();
    let mut left_out = LeftOut::default();
    for ((pipeline, settings), cells) in groups {
        // A mean over fewer cells than the others' would not compare: all its cells or none.
        if cells.iter().any(|c| time(c).is_none() || c.metrics.ldr_flip().is_none()) {
            left_out.unmeasured += 1;
            continue;
        }
        let preset = preset_of(pipeline, &cells[0].coords.settings, cells[0]);
        if preset.is_none() && !kept.contains(&(pipeline, settings.clone())) {
            left_out.twins += 1;
            continue;
        }
        let mut passes: BTreeMap<String, Vec<f64>> = BTreeMap::new();
        for c in &cells {
            for s in c.timing.gpu_passes.value().into_iter().flatten() {
                if let Some(ms) = s.median_ms {
                    passes.entry(s.kind.clone()).or_default().push(ms);
                }
            }
        }
        let truth = cells.iter().all(|c| c.metrics.hdr_relative_mse().is_some());
        let noise =
            |c: &&CellRecord| c.metrics.ztest.as_ref().and_then(|z| z.value()).and_then(|z| z.noise_relative_mse);
        by.entry(pipeline).or_default().push(Combination {
            pipeline,
            preset,
            settings,
            cells: cells.len(),
            time_ms: mean(cells.iter().filter_map(|c| time(c))).unwrap_or(0.0),
            passes: passes.into_iter().map(|(k, v)| (k, v.iter().sum::<f64>() / cells.len() as f64)).collect(),
            flip: mean(cells.iter().filter_map(|c| c.metrics.ldr_flip())).unwrap_or(0.0),
            relative_mse: truth.then(|| mean(cells.iter().filter_map(|c| c.metrics.hdr_relative_mse()))).flatten(),
            truth_noise: cells
                .iter()
                .all(|c| noise(c).is_some())
                .then(|| mean(cells.iter().filter_map(noise)))
                .flatten(),
            flip_from_best: None,
            pareto: false,
            pareto_from_best: false,
            ids: cells.iter().map(|c| (same_but_settings(c), c.id.0.clone())).collect(),
        });
    }
    let by = by
        .into_iter()
        .map(|(pipeline, mut combos)| {
            let truth = combos.iter().all(|c| c.relative_mse.is_some() && c.truth_noise.is_some());
            let measure = if truth { ErrorMeasure::TruthRelativeMse } else { ErrorMeasure::Flip };
            let front: Vec<bool> = combos
                .iter()
                .map(|c| {
                    let (t, e) = (c.time_ms, c.error(measure));
                    !combos.iter().any(|q| {
                        let qe = q.error(measure);
                        q.time_ms <= t && qe <= e && (q.time_ms < t || qe < e)
                    })
                })
                .collect();
            for (c, f) in combos.iter_mut().zip(front) {
                c.pareto = f;
            }
            combos.sort_by(|a, b| a.time_ms.total_cmp(&b.time_ms).then_with(|| a.settings.cmp(&b.settings)));
            from_best(run, measure, &mut combos);
            (pipeline, (measure, combos))
        })
        .collect();
    Some((by, left_out))
}

/// What a cell is apart from its settings: the cells of two combinations that show the same thing.
fn same_but_settings(c: &CellRecord) -> String {
    let mut coords = c.coords.clone();
    coords.settings.clear();
    serde_json::to_string(&coords).unwrap_or_default()
}

/// Each combination's `flip_from_best`: its frames against the same cells' at the combination
/// with the least error (ties: the cheaper).
fn from_best(run: &RunData, measure: ErrorMeasure, combos: &mut [Combination]) {
    let Some(best) = combos.iter().min_by(|a, b| a.error(measure).total_cmp(&b.error(measure))).map(|b| b.ids.clone())
    else {
        return;
    };
    let png = |id: &str| crate::images::encode::read_png(&run.cell_dir(id).join("image.png")).ok();
    let best_png: BTreeMap<&String, Option<image::RgbaImage>> = best.iter().map(|(k, id)| (k, png(id))).collect();
    for c in combos.iter_mut() {
        let flips: Vec<Option<f64>> = c
            .ids
            .iter()
            .map(|(key, id)| {
                let reference = best_png.get(key)?.as_ref()?;
                let test = png(id)?;
                let (w, h) = reference.dimensions();
                if test.dimensions() != (w, h) {
                    return None;
                }
                crate::compare::flip::ldr(reference.as_raw(), test.as_raw(), w as usize, h as usize)
                    .ok()
                    .map(|f| f.mean)
            })
            .collect();
        c.flip_from_best = flips.iter().all(Option::is_some).then(|| mean(flips.into_iter().flatten())).flatten();
    }
    let front: Vec<bool> = combos
        .iter()
        .map(|c| {
            let Some(e) = c.flip_from_best else { return false };
            !combos.iter().any(|q| {
                q.flip_from_best
                    .is_some_and(|qe| q.time_ms <= c.time_ms && qe <= e && (q.time_ms < c.time_ms || qe < e))
            })
        })
        .collect();
    for (c, f) in combos.iter_mut().zip(front) {
        c.pareto_from_best = f;
    }
}

/// The tiers plot of a pipeline: each combination's time against its FLIP from the best
/// combination (where every combination has one; else against its error against the references),
/// the budgets as lines, the Pareto front on the plotted error, Unity's presets marked apart.
fn svg(pipeline: Pipeline, time_label: &str, measure: ErrorMeasure, combos: &[Combination]) -> String {
    let from_best = combos.iter().all(|c| c.flip_from_best.is_some());
    let points: Vec<ScatterPoint> = combos
        .iter()
        .map(|c| ScatterPoint {
            x: c.time_ms,
            y: if from_best { c.flip_from_best.unwrap_or(0.0) } else { c.error(measure) },
            bar: if !from_best && measure == ErrorMeasure::TruthRelativeMse { c.truth_noise } else { None },
            colour_key: pipeline.name().to_string(),
            marker_key: if c.preset.is_some() { "a Unity preset".into() } else { "swept settings".into() },
            title: format!(
                "{}{}: {:.3} ms, FLIP from the best {}, mean FLIP {:.4}{}{}",
                c.settings,
                c.preset.as_ref().map(|p| format!(" ({p})")).unwrap_or_default(),
                c.time_ms,
                c.flip_from_best.map_or("—".into(), |f| format!("{f:.4}")),
                c.flip,
                c.relative_mse.map(|r| format!(", relMSE {r:.4e}")).unwrap_or_default(),
                if (from_best && c.pareto_from_best) || (!from_best && c.pareto) {
                    ", on the Pareto front"
                } else {
                    ""
                }
            ),
            front: if from_best { c.pareto_from_best } else { c.pareto },
        })
        .collect();
    let caption = format!("{}: what each settings combination costs and buys", pipeline.name());
    let levels: Vec<(f64, String)> = match from_best {
        true => BUDGETS.iter().map(|b| (*b, format!("FLIP {b}"))).collect(),
        false => Vec::new(),
    };
    let text = ScatterText {
        caption: &caption,
        x_label: time_label,
        y_label: if from_best { "mean FLIP from the best combination" } else { measure.axis() },
        colour_heading: "pipeline",
        marker_heading: "settings",
        levels: &levels,
    };
    super::scatter::svg(&text, &points)
}

/// Which error a tier holds within: the FLIP against each cell's reference, or from the same
/// cells at the pipeline's best combination.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TierError {
    AgainstReference,
    FromBest,
}

impl TierError {
    fn of(self, c: &Combination) -> Option<f64> {
        match self {
            TierError::AgainstReference => Some(c.flip),
            TierError::FromBest => c.flip_from_best,
        }
    }
}

/// The cheapest combination whose mean FLIP (`by`) is within `budget`.
pub fn cheapest_within(combos: &[Combination], budget: f64, by: TierError) -> Option<&Combination> {
    combos.iter().filter(|c| by.of(c).is_some_and(|e| e <= budget)).min_by(|a, b| a.time_ms.total_cmp(&b.time_ms))
}

/// The tightest budget a FLIP stays within.
fn tier(flip: Option<f64>) -> String {
    match flip {
        None => "—".into(),
        Some(f) => {
            BUDGETS.iter().find(|b| f <= **b).map_or_else(|| format!("over {}", BUDGETS[2]), |b| format!("≤ {b}"))
        }
    }
}

fn named(c: &Combination) -> String {
    format!("`{}`{}", c.settings, c.preset.as_ref().map(|p| format!(" ({p})")).unwrap_or_default())
}

/// A tier's cell: the cheapest combination within the budget, its time and error, or the least
/// error there is.
fn tier_cell(combos: &[Combination], budget: f64, by: TierError) -> String {
    match cheapest_within(combos, budget, by) {
        Some(c) => format!("{}, {:.3} ms, {:.4}", named(c), c.time_ms, by.of(c).unwrap_or(0.0)),
        None => match combos.iter().filter_map(|c| by.of(c)).min_by(f64::total_cmp) {
            Some(least) => format!("none (the least is {least:.4})"),
            None => "— (not measured)".into(),
        },
    }
}

/// The pass of a timing's `kind`, where it runs before the frames (its time is not a frame's).
fn before_frames(kind: &str) -> bool {
    crate::plan::Pass::named(kind).is_some_and(|p| p.before_frames())
}

pub fn write(run: &RunData) -> Result<(), Error> {
    let gpu = run.cells.iter().any(|c| c.gpu_median_ms().is_some());
    let Some((by, left_out)) = combinations(run, gpu) else { return Ok(()) };
    let time_label = if gpu {
        "GPU frame time, ms (timestamp queries)"
    } else {
        "CPU wall time, ms (no timestamp queries on this adapter)"
    };
    let budgets = BUDGETS.map(|b| b.to_string()).join(" / ");
    let mut md = format!(
        "# Quality settings: what each costs and buys\n\nAdapter: **{}** (timings compare only within one adapter). Time: {time_label}, the mean over a combination's cells; each pass's time beside it. Error: the mean LDR-FLIP against each cell's reference and, against a path-traced truth, the linear relMSE with what the truth's noise adds to it in expectation; and the mean LDR-FLIP from the same cells at the pipeline's best combination (the least error against the references), which is what the settings cost the image apart from what the pipeline's own models cost it. {} combinations are left out (a cell without a reference or a time), {} whose frames are another's (settings that cannot change those frames; the one with the fewest settings is kept, and Unity's presets).\n\n## Tiers\n\nFor each error budget (mean FLIP {budgets}), the cheapest settings that stay within it (settings, time, FLIP): against the references, and from the pipeline's best combination.\n\n| pipeline | mean FLIP ≤ | against the references | from the best combination |\n|---|---|---|---|\n",
        run.adapter(),
        left_out.unmeasured,
        left_out.twins
    );
    let opt = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.4e}"));
    let flip = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.4}"));
    for (pipeline, (_, combos)) in &by {
        for budget in BUDGETS {
            let _ = writeln!(
                md,
                "| {} | {budget} | {} | {} |",
                pipeline.name(),
                tier_cell(combos, budget, TierError::AgainstReference),
                tier_cell(combos, budget, TierError::FromBest)
            );
        }
    }
    md.push_str("\n## Unity's presets\n\nWhat the engines' own presets among the swept combinations cost and score, and the tightest budget each meets.\n\n| pipeline | preset | settings | time (ms) | mean FLIP | relMSE | tier | FLIP from the best | tier from the best |\n|---|---|---|---|---|---|---|---|---|\n");
    for (pipeline, (_, combos)) in &by {
        for c in combos {
            if let Some(preset) = &c.preset {
                let _ = writeln!(
                    md,
                    "| {} | {preset} | `{}` | {:.3} | {:.4} | {} | {} | {} | {} |",
                    pipeline.name(),
                    c.settings,
                    c.time_ms,
                    c.flip,
                    opt(c.relative_mse),
                    tier(Some(c.flip)),
                    flip(c.flip_from_best),
                    tier(c.flip_from_best)
                );
            }
        }
    }
    let mut csv = String::from(
        "pipeline,settings,preset,cells,time_ms,flip_mean,relative_mse,truth_noise_relative_mse,flip_from_best,pareto,passes_ms\n",
    );
    let raw = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for (pipeline, (measure, combos)) in &by {
        let kinds: Vec<&String> = {
            let mut k: Vec<&String> = combos.iter().flat_map(|c| c.passes.keys()).collect();
            k.sort_by_key(|k| (before_frames(k), k.to_string()));
            k.dedup();
            k
        };
        let head = |k: &str| match before_frames(k) {
            true => format!(" {k} (ms, once, not in the frame) |"),
            false => format!(" {k} (ms) |"),
        };
        let name = pipeline.name();
        let _ = writeln!(
            md,
            "\n## {name}\n\n![quality](../plots/quality_{name}.svg)\n\nPareto front on: {}.\n\n| settings | cells | time (ms) |{} mean FLIP | relMSE | truth noise | Pareto | FLIP from the best | Pareto from the best |\n|---|---|---|{}---|---|---|---|---|---|",
            measure.axis(),
            kinds.iter().map(|k| head(k)).collect::<String>(),
            "---|".repeat(kinds.len())
        );
        for c in combos {
            let passes: String =
                kinds.iter().map(|k| c.passes.get(*k).map_or(" — |".to_string(), |ms| format!(" {ms:.3} |"))).collect();
            let _ = writeln!(
                md,
                "| {} | {} | {:.3} |{passes} {:.4} | {} | {} | {} | {} | {} |",
                named(c),
                c.cells,
                c.time_ms,
                c.flip,
                opt(c.relative_mse),
                opt(c.truth_noise),
                if c.pareto { "●" } else { "" },
                flip(c.flip_from_best),
                if c.pareto_from_best { "●" } else { "" }
            );
            let _ = writeln!(
                csv,
                "{name},\"{}\",\"{}\",{},{},{},{},{},{},{},\"{}\"",
                c.settings,
                c.preset.clone().unwrap_or_default(),
                c.cells,
                c.time_ms,
                c.flip,
                raw(c.relative_mse),
                raw(c.truth_noise),
                raw(c.flip_from_best),
                c.pareto,
                c.passes.iter().map(|(k, ms)| format!("{k}={ms}")).collect::<Vec<_>>().join(";")
            );
        }
        write_atomic(
            &run.dir.join("plots").join(format!("quality_{name}.svg")),
            svg(*pipeline, time_label, *measure, combos).as_bytes(),
        )?;
    }
    write_atomic(&run.dir.join("tables/quality.md"), md.as_bytes())?;
    write_atomic(&run.dir.join("tables/quality.csv"), csv.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn combo(settings: &str, time_ms: f64, flip: f64) -> Combination {
        Combination {
            pipeline: Pipeline::Urp,
            settings: settings.into(),
            preset: None,
            cells: 1,
            time_ms,
            passes: BTreeMap::new(),
            flip,
            relative_mse: None,
            truth_noise: None,
            flip_from_best: Some(flip / 2.0),
            pareto: false,
            pareto_from_best: false,
            ids: BTreeMap::new(),
        }
    }

    #[test]
    fn each_budget_takes_the_cheapest_within_it() {
        let combos = vec![combo("a", 1.0, 0.2), combo("b", 2.0, 0.04), combo("c", 3.0, 0.01), combo("d", 4.0, 0.03)];
        let pick = |b: f64| cheapest_within(&combos, b, TierError::AgainstReference).map(|c| c.settings.as_str());
        assert_eq!(pick(0.02), Some("c"));
        assert_eq!(pick(0.05), Some("b"));
        assert_eq!(pick(0.1), Some("b"));
        assert_eq!(pick(0.005), None);
        // From the best combination the errors are halved here: a looser tier is cheaper.
        assert_eq!(cheapest_within(&combos, 0.1, TierError::FromBest).map(|c| c.settings.as_str()), Some("a"));
        assert_eq!(tier(Some(0.04)), "≤ 0.05");
        assert_eq!(tier(Some(0.5)), "over 0.1");
        assert!(tier_cell(&combos, 0.005, TierError::AgainstReference).starts_with("none (the least is 0.0100"));
    }
}
