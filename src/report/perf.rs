//! Performance tables from a run's records: tables/perf.md, .csv and .json, per cell and
//! aggregated per pipeline × path × shader, with the adapter named at the top.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt::Write;

use super::run_data::RunData;
use crate::error::Error;
use crate::fsutil::{write_atomic, write_json};

/// Version of `tables/perf.json`. 2: GPU time per pass; 3: `timed_as`.
pub const PERF_SCHEMA: u32 = 3;

/// `tables/perf.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PerfTable {
    pub schema: u32,
    pub adapter: String,
    /// What the GPU columns measure, or why they are missing.
    pub timing: String,
    pub groups: Vec<PerfGroup>,
    pub cells: Vec<PerfRow>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PerfRow {
    pub id: String,
    pub composition: String,
    pub pipeline: String,
    pub path: String,
    pub shader: String,
    /// Median GPU pass time (timestamp queries), ms; None when the adapter had none.
    pub gpu_median_ms: Option<f64>,
    pub gpu_min_ms: Option<f64>,
    pub gpu_max_ms: Option<f64>,
    pub cpu_wall_median_ms: Option<f64>,
    pub readback_ms: Option<f64>,
    pub encode_ms: Option<f64>,
    /// CPU time of the metrics pass for the cell (FLIP, SSIM, maps), ms.
    pub metrics_ms: Option<f64>,
    pub frames: u64,
    /// Copied from another cell (the shader ignores the axes they differ in).
    pub twin: bool,
    /// The cell of the same timing class whose timings this row carries (`plan::timing`).
    #[serde(default)]
    pub timed_as: Option<String>,
    /// Median GPU time of each pass of the frame, ms, in frame order (empty without timestamps).
    #[serde(default)]
    pub gpu_passes: Vec<(String, f64)>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PerfGroup {
    pub pipeline: String,
    pub path: String,
    pub shader: String,
    pub cells: usize,
    /// Median over the group's timed cells of their median GPU pass time.
    pub gpu_median_ms: Option<f64>,
    pub cpu_wall_median_ms: Option<f64>,
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    Some(v[v.len() / 2])
}

pub fn rows(run: &RunData) -> Vec<PerfRow> {
    run.cells
        .iter()
        .map(|c| {
            let t = &c.timing;
            let gpu = t.gpu.value();
            PerfRow {
                id: c.id.0.clone(),
                composition: c.composition.clone(),
                pipeline: c.pipeline.name().into(),
                path: c.path.name().into(),
                shader: c.shader.clone(),
                gpu_median_ms: gpu.and_then(|g| g.median_ms),
                gpu_min_ms: gpu.and_then(|g| g.min_ms),
                gpu_max_ms: gpu.and_then(|g| g.max_ms),
                cpu_wall_median_ms: t.cpu_wall.median_ms,
                readback_ms: Some(t.readback_ms),
                encode_ms: Some(t.encode_ms),
                metrics_ms: t.metrics_ms,
                frames: t.frames as u64,
                twin: c.twin_of.is_some(),
                timed_as: t.timed_as.as_ref().map(|id| id.0.clone()),
                gpu_passes: t
                    .gpu_passes
                    .value()
                    .map(|ps| ps.iter().filter_map(|p| p.median_ms.map(|m| (p.kind.clone(), m))).collect())
                    .unwrap_or_default(),
            }
        })
        .collect()
}

pub fn groups(rows: &[PerfRow]) -> Vec<PerfGroup> {
    let mut by: BTreeMap<(String, String, String), Vec<&PerfRow>> = BTreeMap::new();
    // Each measurement once: twins and cells timed as another carry a copy.
    for r in rows.iter().filter(|r| !r.twin && r.timed_as.is_none()) {
        by.entry((r.pipeline.clone(), r.path.clone(), r.shader.clone())).or_default().push(r);
    }
    by.into_iter()
        .map(|((pipeline, path, shader), rs)| PerfGroup {
            cells: rs.len(),
            gpu_median_ms: median(rs.iter().filter_map(|r| r.gpu_median_ms).collect()),
            cpu_wall_median_ms: median(rs.iter().filter_map(|r| r.cpu_wall_median_ms).collect()),
            pipeline,
            path,
            shader,
        })
        .collect()
}

fn ms(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.3}")).unwrap_or_else(|| "—".into())
}

pub fn write(run: &RunData) -> Result<(), Error> {
    let rows = rows(run);
    let groups = groups(&rows);
    let dir = run.dir.join("tables");
    let timing_kind = if rows.iter().any(|r| r.gpu_median_ms.is_some()) {
        "GPU time of the frame from timestamp queries (its passes summed; per pass in the last column)"
    } else {
        "no timestamp queries on this adapter: GPU columns are missing; CPU wall time (submit → idle) only"
    };
    let mut md = format!("# Performance\n\nAdapter: **{}**. Timings compare only within one adapter.\n\n{timing_kind}; median, min and max over the timed frames after warm-up. Twins are copies and carry their original's times; a cell marked *timed as* carries the times of the cell of its timing class that was timed (the classes: composition, pipeline, path, shader, resolution, anti-aliasing, light budget and range, textures, camera distance; `[timing] every_cell = true` times every cell). Groups count each timed cell once.\n\n## Per pipeline × path × shader\n\n| pipeline | path | shader | cells | GPU median (ms) | CPU wall median (ms) |\n|---|---|---|---|---|---|\n", run.adapter());
    for g in &groups {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} |",
            g.pipeline,
            g.path,
            g.shader,
            g.cells,
            ms(g.gpu_median_ms),
            ms(g.cpu_wall_median_ms)
        );
    }
    md.push_str("\n## Per cell\n\n| cell | GPU median | GPU min | GPU max | CPU wall median | readback | encode | metrics | frames | GPU per pass (median) |\n|---|---|---|---|---|---|---|---|---|---|\n");
    let mut csv = String::from("cell,composition,pipeline,path,shader,twin,timed_as,gpu_median_ms,gpu_min_ms,gpu_max_ms,cpu_wall_median_ms,readback_ms,encode_ms,metrics_ms,frames\n");
    for r in &rows {
        let twin = match (&r.timed_as, r.twin) {
            (_, true) => " (twin)".to_string(),
            (Some(id), false) => format!(" (timed as `{id}`)"),
            (None, false) => String::new(),
        };
        let _ = writeln!(
            md,
            "| `{}`{twin} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.id,
            ms(r.gpu_median_ms),
            ms(r.gpu_min_ms),
            ms(r.gpu_max_ms),
            ms(r.cpu_wall_median_ms),
            ms(r.readback_ms),
            ms(r.encode_ms),
            ms(r.metrics_ms),
            r.frames,
            if r.gpu_passes.is_empty() {
                "—".to_string()
            } else {
                r.gpu_passes.iter().map(|(name, m)| format!("{name} {m:.3}")).collect::<Vec<_>>().join("; ")
            }
        );
        let o = |v: Option<f64>| v.map(|x| x.to_string()).unwrap_or_default();
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.id,
            r.composition,
            r.pipeline,
            r.path,
            r.shader,
            r.twin,
            r.timed_as.as_deref().unwrap_or(""),
            o(r.gpu_median_ms),
            o(r.gpu_min_ms),
            o(r.gpu_max_ms),
            o(r.cpu_wall_median_ms),
            o(r.readback_ms),
            o(r.encode_ms),
            o(r.metrics_ms),
            r.frames
        );
    }
    write_atomic(&dir.join("perf.md"), md.as_bytes())?;
    write_atomic(&dir.join("perf.csv"), csv.as_bytes())?;
    write_json(
        &dir.join("perf.json"),
        &PerfTable { schema: PERF_SCHEMA, adapter: run.adapter(), timing: timing_kind.into(), groups, cells: rows },
    )
}
