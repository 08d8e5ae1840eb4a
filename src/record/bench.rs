//! `tables/bench.json`: what `shadematrix bench` measured.

use serde::{Deserialize, Serialize};

use super::run::StageTimes;
use super::Maybe;

/// Version of `tables/bench.json`. 2: GPU time per pass by composition × pipeline × path.
pub const BENCH_SCHEMA: u32 = 2;

/// Median GPU times of one composition × pipeline × path × shader group of rendered cells, ms.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GpuPassRow {
    pub composition: String,
    pub pipeline: String,
    pub path: String,
    pub shader: String,
    pub cells: usize,
    /// The frame (every pass summed).
    pub frame_ms: f64,
    /// Each pass, in frame order.
    pub passes: Vec<(String, f64)>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BenchRecord {
    pub schema: u32,
    pub matrix: String,
    pub adapter: String,
    pub cores: usize,
    pub cells: usize,
    pub rendered: usize,
    /// Run plus report, seconds.
    pub wall_seconds: f64,
    pub cells_per_second: f64,
    pub stages: StageTimes,
    /// CPU time of building the reports (tables, plots, sheets, gallery), ms.
    pub report_ms: f64,
    /// Sum of the stage times (prepare, render, readback, encode, metrics, report), ms.
    pub stage_sum_ms: f64,
    /// wall ÷ (stage sum ÷ cores): 1 when the stages overlap perfectly on every core.
    pub overlap_ratio: f64,
    /// Process CPU time ÷ (wall × cores): how much of the machine the run used.
    pub utilisation: Maybe<f64>,
    pub peak_rss_bytes: Maybe<u64>,
    /// GPU time per pass by group, or why there is none (no timestamp queries).
    pub gpu_passes: Maybe<Vec<GpuPassRow>>,
}
