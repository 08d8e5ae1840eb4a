//! What each real-time approximation costs and buys (the approximation study, run::study):
//! per composition and change, the change in error against the truth and in frame time when the
//! approximation is replaced by the term it approximates, over the same cells. Written as
//! tables/approximations.md|csv when a run has a study.

use std::collections::BTreeMap;
use std::fmt::Write;

use super::run_data::RunData;
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::record::CellRecord;

/// One cell's pair: the cell as the pipeline ships it and the same cell with one change.
#[derive(Debug, Clone)]
pub struct ChangeRow {
    pub composition: String,
    pub cell: String,
    pub variant: String,
    pub change: String,
    pub time: (f64, f64),
    pub flip: (f64, f64),
    pub ssim: (Option<f64>, Option<f64>),
    pub relative_mse: (Option<f64>, Option<f64>),
}

/// The mean change over a group of rows (exact − approximate).
#[derive(Debug, Clone, PartialEq)]
pub struct ChangeSummary {
    pub cells: usize,
    pub time_ms: f64,
    /// The time change over the approximate frame's time, mean.
    pub time_ratio: f64,
    pub flip: f64,
    pub ssim: Option<f64>,
    pub relative_mse: Option<f64>,
    /// Cells whose FLIP fell with the exact term.
    pub flip_lower: usize,
}

/// The study's rows of a run; `gpu`: times from timestamp queries (else CPU wall time).
pub fn rows(run: &RunData, gpu: bool) -> (Vec<ChangeRow>, BTreeMap<(String, String), usize>) {
    let mut rows = Vec::new();
    let mut left_out: BTreeMap<(String, String), usize> = BTreeMap::new();
    for c in &run.cells {
        let Some(base) = base_of(c, gpu) else { continue };
        for a in &c.approximations {
            let Some(r) = a.result.value() else {
                let why = a.result.why_missing().unwrap_or_default().to_string();
                *left_out.entry((a.change.clone(), why)).or_default() += 1;
                continue;
            };
            let time = if gpu { r.gpu_ms.value().copied() } else { Some(r.cpu_wall_ms) };
            let (Some(time), Some(flip)) = (time, r.flip.value().copied()) else { continue };
            rows.push(ChangeRow {
                composition: c.composition.clone(),
                cell: c.id.0.clone(),
                variant: a.variant.clone(),
                change: a.change.clone(),
                time: (base.0, time),
                flip: (base.1, flip),
                ssim: (c.metrics.ldr_ssim(), r.ssim.value().copied()),
                relative_mse: (c.metrics.hdr_relative_mse(), r.hdr_relative_mse.value().copied()),
            });
        }
    }
    (rows, left_out)
}

/// The cell's own time and LDR-FLIP.
fn base_of(c: &CellRecord, gpu: bool) -> Option<(f64, f64)> {
    let time = if gpu { c.gpu_median_ms() } else { c.timing.cpu_wall.median_ms };
    Some((time?, c.metrics.ldr_flip()?))
}

pub fn summarise(rows: &[&ChangeRow]) -> ChangeSummary {
    let n = rows.len().max(1) as f64;
    let mean_of = |f: &dyn Fn(&ChangeRow) -> Option<f64>| {
        let v: Vec<f64> = rows.iter().filter_map(|r| f(r)).collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    ChangeSummary {
        cells: rows.len(),
        time_ms: rows.iter().map(|r| r.time.1 - r.time.0).sum::<f64>() / n,
        time_ratio: rows.iter().map(|r| (r.time.1 - r.time.0) / r.time.0.max(1e-9)).sum::<f64>() / n,
        flip: rows.iter().map(|r| r.flip.1 - r.flip.0).sum::<f64>() / n,
        ssim: mean_of(&|r| Some(r.ssim.1? - r.ssim.0?)),
        relative_mse: mean_of(&|r| Some(r.relative_mse.1? - r.relative_mse.0?)),
        flip_lower: rows.iter().filter(|r| r.flip.1 < r.flip.0).count(),
    }
}

pub fn write(run: &RunData) -> Result<(), Error> {
    if run.cells.iter().all(|c| c.approximations.is_empty()) {
        return Ok(());
    }
    let gpu = run.cells.iter().any(|c| c.gpu_median_ms().is_some());
    let time_label = if gpu { "GPU time from timestamp queries" } else { "CPU wall time: no timestamp queries" };
    let (rows, left_out) = rows(run, gpu);
    let opt = |v: Option<f64>, digits: usize| v.map_or("—".to_string(), |v| format!("{v:+.digits$}"));
    let mut md = format!(
        "# What each approximation costs and buys\n\nAdapter: **{}**. Each cell is rendered again with one real-time approximation replaced by the term it approximates, and both frames are measured against the cell's truth. Δ = exact − approximate, averaged over the cells: a negative ΔFLIP is the error the approximation costs, a positive Δtime ({time_label}) what it saves. SSIM rises as error falls; relMSE is the linear images' relative MSE. \"FLIP lower\": cells whose error fell.\n",
        run.adapter()
    );
    let mut by: BTreeMap<(String, String), Vec<&ChangeRow>> = BTreeMap::new();
    for r in &rows {
        by.entry((r.composition.clone(), r.change.clone())).or_default().push(r);
        by.entry(("all compositions".into(), r.change.clone())).or_default().push(r);
    }
    let mut compositions: Vec<String> = by.keys().map(|(c, _)| c.clone()).collect();
    compositions.dedup();
    compositions.sort_by_key(|c| (c != "all compositions", c.clone()));
    for comp in compositions {
        let _ = writeln!(md, "\n## {comp}\n\n| change | cells | Δ time (ms) | Δ time | Δ FLIP | Δ SSIM | Δ relMSE | FLIP lower |\n|---|---|---|---|---|---|---|---|");
        for ((_, change), group) in by.iter().filter(|((c, _), _)| *c == comp) {
            let s = summarise(group);
            let _ = writeln!(
                md,
                "| {change} | {} | {:+.3} | {:+.0} % | {:+.5} | {} | {} | {}/{} |",
                s.cells,
                s.time_ms,
                100.0 * s.time_ratio,
                s.flip,
                opt(s.ssim, 4),
                opt(s.relative_mse, 4),
                s.flip_lower,
                s.cells
            );
        }
    }
    if !left_out.is_empty() {
        md.push_str("\n## Left out\n\n| change | cells | why |\n|---|---|---|\n");
        for ((change, why), n) in &left_out {
            let _ = writeln!(md, "| {change} | {n} | {why} |");
        }
    }
    let mut csv = String::from("composition,cell,variant,change,time_ms,exact_time_ms,flip,exact_flip,ssim,exact_ssim,relative_mse,exact_relative_mse\n");
    let raw = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for r in &rows {
        let _ = writeln!(
            csv,
            "{},{},{},\"{}\",{},{},{},{},{},{},{},{}",
            r.composition,
            r.cell,
            r.variant,
            r.change,
            r.time.0,
            r.time.1,
            r.flip.0,
            r.flip.1,
            raw(r.ssim.0),
            raw(r.ssim.1),
            raw(r.relative_mse.0),
            raw(r.relative_mse.1)
        );
    }
    write_atomic(&run.dir.join("tables/approximations.md"), md.as_bytes())?;
    write_atomic(&run.dir.join("tables/approximations.csv"), csv.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_is_the_mean_change() {
        let row = |t: (f64, f64), f: (f64, f64)| ChangeRow {
            composition: "c".into(),
            cell: "x".into(),
            variant: "v".into(),
            change: "a → b".into(),
            time: t,
            flip: f,
            ssim: (Some(0.5), None),
            relative_mse: (Some(1.0), Some(0.5)),
        };
        let a = row((1.0, 3.0), (0.2, 0.1));
        let b = row((2.0, 2.0), (0.1, 0.2));
        let s = summarise(&[&a, &b]);
        assert_eq!(s.cells, 2);
        assert!((s.time_ms - 1.0).abs() < 1e-12 && (s.time_ratio - 1.0).abs() < 1e-12);
        assert!(s.flip.abs() < 1e-12);
        assert_eq!(s.ssim, None);
        assert_eq!(s.relative_mse, Some(-0.5));
        assert_eq!(s.flip_lower, 1);
    }
}
