//! Error against run time, per composition: each cell's error against its reference next to its
//! GPU time (CPU wall time where the adapter has no timestamp queries, labelled), as
//! tables/error_vs_time.md|csv and plots/error_vs_time_<composition>.svg with the Pareto front.
//! The error is the LDR-FLIP mean; where every cell of a composition is compared with its
//! path-traced truth it is the linear images' relative MSE — the physical error, not the display
//! transforms' — with the truth's own noise as its error bar (`ZTest::noise_relative_mse`).

use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write;

use super::run_data::RunData;
use crate::error::Error;
use crate::fsutil::write_atomic;

#[derive(Debug, Clone, Serialize)]
pub struct Point {
    pub id: String,
    pub label: String,
    /// Its pipeline and shader: the plot's colour and marker.
    pub pipeline: String,
    pub shader: String,
    pub time_ms: f64,
    pub flip: f64,
    /// The plotted error (`ErrorMeasure`), on which the Pareto front is.
    pub error: f64,
    /// What the truth's noise adds to `error` in expectation (relMSE against a truth only).
    pub error_bar: Option<f64>,
    pub pareto: bool,
    /// The other errors, where measured: SSIM of the PNGs, HDR-FLIP of the EXRs, and against a
    /// truth the share of pixels its Z-test rejects.
    pub ssim: Option<f64>,
    pub hdr_flip: Option<f64>,
    /// The linear images' relative MSE (compare::stats::relative_mse).
    pub relative_mse: Option<f64>,
    pub z_rejected: Option<f64>,
    /// Against a truth: what its noise adds to the relMSE in expectation.
    pub truth_noise: Option<f64>,
    /// What the cell was compared with (its reference's label).
    pub reference: String,
    /// Its scene's bake: the wall time in s where this cell made it (a one-off cost, not per
    /// frame), 0 where it shared an earlier cell's; None where the scene bakes nothing.
    pub bake_seconds: Option<f64>,
}

/// Points not dominated by another (no other is at most as slow and at most as wrong, and better in one).
pub fn mark_pareto(points: &mut [Point]) {
    for i in 0..points.len() {
        let (t, e) = (points[i].time_ms, points[i].error);
        points[i].pareto = !points.iter().any(|q| q.time_ms <= t && q.error <= e && (q.time_ms < t || q.error < e));
    }
}

/// What a composition's points plot as their error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorMeasure {
    Flip,
    /// Every point is against its truth and has a relMSE.
    TruthRelativeMse,
}

impl ErrorMeasure {
    pub fn axis(self) -> &'static str {
        match self {
            ErrorMeasure::Flip => "FLIP mean against the reference",
            ErrorMeasure::TruthRelativeMse => "relative MSE against the truth (bar: ± its noise)",
        }
    }
}

/// The scatter of `points` (time against error): a log error axis with the truth-noise bars, a
/// colour per pipeline and a marker per shader, the Pareto front as a line, each point named on
/// hover (`report::scatter`).
pub fn svg(title: &str, time_label: &str, measure: ErrorMeasure, points: &[Point]) -> String {
    let scatter: Vec<super::scatter::ScatterPoint> = points
        .iter()
        .map(|p| {
            let bar = p.error_bar.map(|b| format!(" ± {b:.3e}")).unwrap_or_default();
            super::scatter::ScatterPoint {
                x: p.time_ms,
                y: p.error,
                bar: p.error_bar,
                colour_key: p.pipeline.clone(),
                marker_key: p.shader.clone(),
                title: format!(
                    "{}\n{}: error {:.4e}{bar}, {:.3} ms, against {}{}",
                    p.id,
                    p.label,
                    p.error,
                    p.time_ms,
                    p.reference,
                    if p.pareto { ", on the Pareto front" } else { "" }
                ),
                front: p.pareto,
            }
        })
        .collect();
    let text = super::scatter::ScatterText {
        caption: title,
        x_label: time_label,
        y_label: measure.axis(),
        colour_heading: "pipeline",
        marker_heading: "shader",
        levels: &[],
    };
    super::scatter::svg(&text, &scatter)
}

/// Build per-composition points, each with the composition's measure; cells without a reference
/// or a time are left out and counted.
#[allow(clippy::type_complexity)]
pub fn points(run: &RunData) -> (BTreeMap<String, (ErrorMeasure, Vec<Point>)>, bool, usize) {
    let gpu = run.cells.iter().any(|c| c.gpu_median_ms().is_some());
    let mut by: BTreeMap<String, Vec<Point>> = BTreeMap::new();
    let mut skipped = 0;
    for c in &run.cells {
        let time = if gpu { c.gpu_median_ms() } else { c.timing.cpu_wall.median_ms };
        let flip = c.metrics.ldr_flip();
        match (time, flip) {
            (Some(time_ms), Some(flip)) => by.entry(c.composition.clone()).or_default().push(Point {
                id: c.id.0.clone(),
                label: format!("{}/{}", c.pipeline.name(), c.shader),
                pipeline: c.pipeline.name().to_string(),
                shader: c.shader.clone(),
                time_ms,
                flip,
                error: flip,
                error_bar: None,
                pareto: false,
                ssim: c.metrics.ldr_ssim(),
                hdr_flip: c.metrics.hdr_flip(),
                relative_mse: c.metrics.hdr_relative_mse(),
                z_rejected: c.metrics.ztest.as_ref().and_then(|z| z.value()).map(|z| z.rejected),
                truth_noise: c.metrics.ztest.as_ref().and_then(|z| z.value()).and_then(|z| z.noise_relative_mse),
                reference: c.metrics.reference.value().map_or_else(String::new, |r| r.label()),
                bake_seconds: c.bake.as_ref().map(|b| if b.made { b.seconds } else { 0.0 }),
            }),
            _ => skipped += 1,
        }
    }
    let by = by
        .into_iter()
        .map(|(comp, mut pts)| {
            let truth = pts.iter().all(|p| p.relative_mse.is_some() && p.truth_noise.is_some());
            let measure = if truth { ErrorMeasure::TruthRelativeMse } else { ErrorMeasure::Flip };
            if truth {
                for p in &mut pts {
                    (p.error, p.error_bar) = (p.relative_mse.unwrap_or(p.flip), p.truth_noise);
                }
            }
            mark_pareto(&mut pts);
            (comp, (measure, pts))
        })
        .collect();
    (by, gpu, skipped)
}

pub fn write(run: &RunData) -> Result<(), Error> {
    let (by, gpu, skipped) = points(run);
    let time_label = if gpu {
        "GPU time, ms (timestamp queries)"
    } else {
        "CPU wall time, ms (no timestamp queries on this adapter)"
    };
    let mut md = format!("# Error against run time\n\nAdapter: **{}**. Time: {time_label}. Error: LDR-FLIP mean against each cell's reference, with SSIM, HDR-FLIP, the linear images' relative MSE and, against a path-traced truth, the share of pixels its Z-test rejects and the truth's noise: what it adds to the relMSE in expectation (`—`: not measured). The Pareto front is on the FLIP mean, or on the relMSE where every cell of the composition is compared with its truth. {skipped} cells have no reference (or no time) and are left out.\n", run.adapter());
    let mut csv = String::from(
        "composition,cell,pipeline_shader,reference,time_ms,flip_mean,ssim_mean,hdr_flip_mean,relative_mse,truth_noise_relative_mse,z_rejected,pareto,bake_seconds\n",
    );
    let opt = |v: Option<f64>, digits: usize| v.map_or("—".to_string(), |v| format!("{v:.digits$}"));
    let raw = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for (comp, (measure, pts)) in &by {
        // A baked scene's cells say what their bake cost, once (0: shared with an earlier cell).
        let baked = pts.iter().any(|p| p.bake_seconds.is_some());
        let (bake_head, bake_rule) = if baked { (" bake (s, once) |", "---|") } else { ("", "") };
        let _ = writeln!(md, "\n## {comp}\n\n![error vs time](../plots/error_vs_time_{comp}.svg)\n\nPareto front on: {}.\n\n| cell | reference | time (ms) | FLIP mean | SSIM | HDR-FLIP | relMSE | truth noise | Z-test rejects | Pareto |{bake_head}\n|---|---|---|---|---|---|---|---|---|---|{bake_rule}", measure.axis());
        let mut sorted: Vec<&Point> = pts.iter().collect();
        sorted.sort_by(|a, b| a.time_ms.total_cmp(&b.time_ms));
        for p in sorted {
            let _ = writeln!(
                md,
                "| `{}` | {} | {:.3} | {:.5} | {} | {} | {} | {} | {} | {} |{}",
                p.id,
                p.reference,
                p.time_ms,
                p.flip,
                opt(p.ssim, 4),
                opt(p.hdr_flip, 4),
                opt(p.relative_mse, 4),
                opt(p.truth_noise, 4),
                opt(p.z_rejected, 3),
                if p.pareto { "●" } else { "" },
                if baked { format!(" {} |", opt(p.bake_seconds, 2)) } else { String::new() }
            );
            let _ = writeln!(
                csv,
                "{comp},{},{},\"{}\",{},{},{},{},{},{},{},{},{}",
                p.id,
                p.label,
                p.reference,
                p.time_ms,
                p.flip,
                raw(p.ssim),
                raw(p.hdr_flip),
                raw(p.relative_mse),
                raw(p.truth_noise),
                raw(p.z_rejected),
                p.pareto,
                raw(p.bake_seconds)
            );
        }
        write_atomic(
            &run.dir.join("plots").join(format!("error_vs_time_{comp}.svg")),
            svg(&format!("{comp}: error against run time"), time_label, *measure, pts).as_bytes(),
        )?;
    }
    write_atomic(&run.dir.join("tables/error_vs_time.md"), md.as_bytes())?;
    write_atomic(&run.dir.join("tables/error_vs_time.csv"), csv.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_keeps_the_undominated() {
        let p = |t: f64, e: f64| Point {
            id: format!("{t}-{e}"),
            label: String::new(),
            pipeline: "urp".into(),
            shader: "lit".into(),
            time_ms: t,
            flip: e,
            error: e,
            error_bar: Some(e / 10.0),
            pareto: false,
            ssim: None,
            hdr_flip: None,
            relative_mse: None,
            z_rejected: None,
            truth_noise: None,
            reference: String::new(),
            bake_seconds: None,
        };
        let mut pts = vec![p(1.0, 0.5), p(2.0, 0.2), p(3.0, 0.3), p(4.0, 0.1), p(2.0, 0.2)];
        mark_pareto(&mut pts);
        let front: Vec<bool> = pts.iter().map(|q| q.pareto).collect();
        assert_eq!(front, vec![true, true, false, true, true]);
        let plot = svg("t <&>", "ms", ErrorMeasure::TruthRelativeMse, &pts);
        assert!(
            plot.starts_with("<svg") && plot.contains("<title>1-0.5") && plot.contains("t &lt;&amp;&gt;"),
            "{plot}"
        );
    }
}
