//! `shadematrix bench [MATRIX]`: run a matrix and say what it cost — cells/s, wall, time per stage,
//! how well the stages overlapped (wall ÷ (stage sum ÷ cores)), peak memory — with the adapter.
//! Printed and written to `tables/bench.md` and `.json` in the run folder.

use std::fmt::Write;
use std::time::Instant;

use crate::error::Error;
use crate::fsutil::{write_atomic, write_json};
use crate::record::bench::{BenchRecord, BENCH_SCHEMA};
use crate::record::Maybe;
use crate::run::{run, ProcessUsage, RunOptions};
use crate::spec::matrix::Matrix;

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
    };
    let tables = summary.dir.join("tables");
    write_atomic(&tables.join("bench.md"), markdown(&record).as_bytes())?;
    write_json(&tables.join("bench.json"), &record)?;
    Ok(record)
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
    out
}
