//! `shadematrix bench [MATRIX]`: run a matrix and say what it cost — cells/s, wall, time per stage,
//! how well the stages overlapped (wall ÷ (stage sum ÷ cores)), peak memory — with the adapter.
//! Printed and written to `tables/bench.md` and `.json` in the run folder.

use std::fmt::Write;
use std::time::Instant;

use crate::declarations::matrix::Matrix;
use crate::error::Error;
use crate::fsutil::{write_atomic, write_json};
use crate::record::bench::{BenchRecord, GpuPassRow, BENCH_SCHEMA};
use crate::record::Maybe;
use crate::run::{run, ProcessUsage, RunOptions};

pub fn bench(matrix: &Matrix, opts: &RunOptions) -> Result<BenchRecord, Error> {
    let started = Instant::now();
    let summary = run(matrix, opts)?;
    let cpu_before = ProcessUsage::now().cpu_seconds;
    crate::report::build(&summary.dir)?;
    let usage = ProcessUsage::now();
    let wall = started.elapsed().as_secs_f64();
    // The report runs alone after the run, so the process's CPU time over it is the report's.
    let report_ms = match (cpu_before.value(), usage.cpu_seconds.value()) {
        (Some(a), Some(b)) => (b - a) * 1e3,
        _ => 0.0,
    };
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let s = &summary.stages;
    let stage_sum_ms = s.prepare_ms + s.render_ms + s.readback_ms + s.encode_ms + s.metrics_ms + report_ms;
    let record = BenchRecord {
        schema: BENCH_SCHEMA,
        matrix: matrix.name.clone(),
        adapter: summary.adapter.clone(),
        cores,
        cells: summary.counts.cells,
        rendered: summary.counts.rendered,
        wall_seconds: wall,
        cells_per_second: summary.counts.cells as f64 / wall,
        stages: summary.stages.clone(),
        report_ms,
        stage_sum_ms,
        overlap_ratio: wall * 1e3 / (stage_sum_ms / cores as f64),
        utilisation: match usage.cpu_seconds {
            Maybe::Value(cpu) => Maybe::Value(cpu / (wall * cores as f64)),
            Maybe::Missing { missing } => Maybe::Missing { missing },
        },
        peak_rss_bytes: usage.peak_rss_bytes,
        gpu_passes: gpu_pass_rows(&summary.dir)?,
    };
    let tables = summary.dir.join("tables");
    write_atomic(&tables.join("bench.md"), markdown(&record).as_bytes())?;
    write_json(&tables.join("bench.json"), &record)?;
    Ok(record)
}

/// Median GPU time per pass of each composition × pipeline × path × shader, from the run's records.
fn gpu_pass_rows(dir: &std::path::Path) -> Result<Maybe<Vec<GpuPassRow>>, Error> {
    let data = crate::report::run_data::RunData::load(dir)?;
    let rows = crate::report::perf::rows(&data);
    let mut groups: std::collections::BTreeMap<(String, String, String, String), Vec<&crate::report::perf::PerfRow>> =
        Default::default();
    for r in rows.iter().filter(|r| !r.twin && r.gpu_median_ms.is_some()) {
        groups
            .entry((r.composition.clone(), r.pipeline.clone(), r.path.clone(), r.shader.clone()))
            .or_default()
            .push(r);
    }
    if groups.is_empty() {
        return Ok(Maybe::missing("no timestamp queries on this adapter"));
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(|a, b| a.total_cmp(b));
        v[v.len() / 2]
    };
    Ok(Maybe::Value(
        groups
            .into_iter()
            .map(|((composition, pipeline, path, shader), rs)| {
                let names: Vec<String> = rs[0].gpu_passes.iter().map(|(n, _)| n.clone()).collect();
                let passes = names
                    .iter()
                    .map(|name| {
                        let v = rs.iter().filter_map(|r| r.gpu_passes.iter().find(|(n, _)| n == name).map(|p| p.1));
                        (name.clone(), median(v.collect()))
                    })
                    .collect();
                GpuPassRow {
                    cells: rs.len(),
                    frame_ms: median(rs.iter().filter_map(|r| r.gpu_median_ms).collect()),
                    passes,
                    composition,
                    pipeline,
                    path,
                    shader,
                }
            })
            .collect(),
    ))
}

/// How much of the wall each stage's threads were busy, per thread: the render thread (prepare,
/// render, readback), an encode worker and a metric worker. The busiest bounds the run: speeding
/// up another stage cannot shorten it.
pub fn stage_busy(b: &BenchRecord) -> [(&'static str, f64); 3] {
    let s = &b.stages;
    let wall_ms = (b.wall_seconds * 1e3).max(1e-9);
    [
        ("render thread", (s.prepare_ms + s.render_ms + s.readback_ms) / wall_ms),
        ("encode workers", s.encode_ms / s.encode_workers.max(1) as f64 / wall_ms),
        ("metric workers", s.metrics_ms / s.metrics_workers.max(1) as f64 / wall_ms),
    ]
}

pub fn markdown(b: &BenchRecord) -> String {
    let s = &b.stages;
    let mut out = String::new();
    let _ = writeln!(out, "# Bench: {}\n", b.matrix);
    let _ = writeln!(out, "Adapter: **{}**, {} cores. Timings compare only within one adapter.\n", b.adapter, b.cores);
    let _ = writeln!(
        out,
        "{} cells ({} rendered) in {:.1} s: **{:.2} cells/s**.\n",
        b.cells, b.rendered, b.wall_seconds, b.cells_per_second
    );
    let _ = writeln!(out, "| stage | time (s) | measured as |\n|---|---|---|");
    let rows = [
        ("prepare (scene upload, probe)", s.prepare_ms, "wall, render thread"),
        ("render (submit + wait)", s.render_ms, "wall, render thread"),
        ("readback", s.readback_ms, "wall, render thread"),
        ("encode (tonemap, EXR, PNG, twins)", s.encode_ms, "CPU, encode workers"),
        ("metrics (FLIP, SSIM, maps, record)", s.metrics_ms, "CPU, metric workers"),
        ("report (tables, sheets, gallery)", b.report_ms, "CPU, process"),
        ("**sum**", b.stage_sum_ms, ""),
    ];
    for (name, ms, how) in rows {
        let _ = writeln!(out, "| {name} | {:.2} | {how} |", ms / 1e3);
    }
    let _ = writeln!(
        out,
        "\nRender thread blocked on a full encode queue: {:.2} s. Workers: {} encode, {} metrics; queue depth {}.\n",
        s.render_blocked_ms / 1e3,
        s.encode_workers,
        s.metrics_workers,
        s.queue_depth
    );
    let busy = stage_busy(b);
    let bound = busy.iter().max_by(|a, b| a.1.total_cmp(&b.1)).expect("three stages");
    let shares: Vec<String> = busy.iter().map(|(name, f)| format!("{name} {:.1} %", 100.0 * f)).collect();
    let _ =
        writeln!(out, "- bounding stage: **{}** (busy share of the wall, per thread: {})", bound.0, shares.join(", "));
    let _ = writeln!(
        out,
        "- wall ÷ (stage sum ÷ cores) = **{:.3}** (1: the stages overlap perfectly on every core)",
        b.overlap_ratio
    );
    let maybe = |m: &Maybe<f64>, f: &dyn Fn(f64) -> String| match m {
        Maybe::Value(v) => f(*v),
        Maybe::Missing { missing } => format!("missing ({missing})"),
    };
    let _ = writeln!(
        out,
        "- utilisation, process CPU ÷ (wall × cores) = {}",
        maybe(&b.utilisation, &|v| format!("{v:.3}"))
    );
    let rss = match &b.peak_rss_bytes {
        Maybe::Value(v) => format!("{:.1} MiB", *v as f64 / (1024.0 * 1024.0)),
        Maybe::Missing { missing } => format!("missing ({missing})"),
    };
    let _ = writeln!(out, "- peak RSS = {rss}");
    match &b.gpu_passes {
        Maybe::Value(rows) => {
            let _ = writeln!(
                out,
                "\n## GPU time per pass (median over each group's rendered cells, ms)\n\n| composition | pipeline | path | shader | cells | frame | passes |\n|---|---|---|---|---|---|---|"
            );
            for r in rows {
                let passes: Vec<String> = r.passes.iter().map(|(n, ms)| format!("{n} {ms:.3}")).collect();
                let _ = writeln!(
                    out,
                    "| {} | {} | {} | {} | {} | {:.3} | {} |",
                    r.composition,
                    r.pipeline,
                    r.path,
                    r.shader,
                    r.cells,
                    r.frame_ms,
                    passes.join("; ")
                );
            }
        }
        Maybe::Missing { missing } => {
            let _ = writeln!(out, "\nGPU time per pass: missing ({missing})");
        }
    }
    out
}
