//! `run.json`: what a run was (matrix, adapter, pass plans), how far it got, and what its stages
//! cost.

use serde::{Deserialize, Serialize};
use std::path::Path;

use super::{read_record, Maybe};
use crate::adapter::AdapterRecord;
use crate::declarations::sheets::SheetSpec;
use crate::error::Error;

/// Version of the `run.json` layout. 2: `schema`, `stages`.
pub const RUN_SCHEMA: u32 = 2;

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunRecord {
    pub schema: u32,
    pub shadematrix_version: String,
    pub status: RunStatus,
    pub matrix: MatrixRecord,
    pub adapter: AdapterRecord,
    pub started: String,
    pub finished: Option<String>,
    pub wall_seconds: Option<f64>,
    pub counts: RunCounts,
    pub compositions: Vec<CompositionRecord>,
    /// Time spent in each stage, summed over cells (absent while running).
    #[serde(default)]
    pub stages: Option<StageTimes>,
    /// A shard's cells of other shards, rendered because its own are compared with them or copy
    /// them (`run::shard`); `merge` keeps the owning shard's copy.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub support: Vec<crate::cells::CellId>,
    /// The shard folders `merge` joined into this run.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub merged_from: Vec<String>,
    /// The combinations the matrix names that cannot exist, and why (the viewer says so).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pruned: Vec<crate::cells::PrunedCell>,
    /// Every cell of the run's expansion (a shard's own and support cells): what `merge` checks a
    /// shard folder against, so a deleted cell folder is found rather than merged around.
    #[serde(default)]
    pub cells: Vec<crate::cells::CellId>,
}

impl RunRecord {
    /// Mark the run complete once its reports exist (`run`, `merge` and `report` call it last).
    pub fn mark_complete(dir: &Path) -> Result<(), Error> {
        let mut r = RunRecord::load(dir)?;
        if r.status == RunStatus::Reporting {
            r.status = RunStatus::Complete;
            crate::fsutil::write_json(&dir.join(super::RUN_FILE), &r)?;
        }
        Ok(())
    }
}

impl RunRecord {
    pub fn load(dir: &Path) -> Result<RunRecord, Error> {
        let path = dir.join(super::RUN_FILE);
        read_record(&path, RUN_SCHEMA).map_err(|e| e.into_error(&path, "run record"))
    }

    /// "name (backend, driver)": how reports name the adapter.
    pub fn adapter_label(&self) -> String {
        let a = &self.adapter;
        format!("{} ({}, {})", a.name, a.backend, a.driver_info)
    }
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    Running,
    /// Every cell is finished; the reports are being written (`complete` once they exist).
    Reporting,
    Complete,
    Failed,
}

impl RunStatus {
    pub fn name(self) -> &'static str {
        match self {
            RunStatus::Running => "running",
            RunStatus::Reporting => "reporting",
            RunStatus::Complete => "complete",
            RunStatus::Failed => "failed",
        }
    }

    /// The status a report states: the reports are written while the run is `reporting`, and the
    /// run is `complete` exactly when they exist, so a page that exists to be read says so.
    pub fn in_reports(self) -> RunStatus {
        match self {
            RunStatus::Reporting => RunStatus::Complete,
            other => other,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MatrixRecord {
    pub name: String,
    pub origin: String,
    pub sha256: String,
    pub image: [u32; 2],
    pub frames: u32,
    pub warmup: u32,
    pub shard: Option<String>,
    /// The `--only` filter the run was given: `merge` recomputes the same expansion.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub only: Option<crate::declarations::filter::Filter>,
    /// The contact sheets `report` draws.
    #[serde(default)]
    pub sheets: Vec<SheetSpec>,
    /// The matrix's `[[assert]]` invariants, which `report` checks.
    #[serde(default)]
    pub asserts: Vec<crate::declarations::asserts::InvariantSpec>,
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct RunCounts {
    /// Cells of the matrix after filters (this shard's share when sharded).
    pub cells: usize,
    pub rendered: usize,
    /// Cells equal to an earlier cell because the shader ignores the axes they differ in.
    pub twins: usize,
    /// Cells found finished by --resume.
    pub resumed: usize,
    /// Cells taken from the cell cache (`--cache`): rendered by an earlier run with the same key.
    #[serde(default)]
    pub cached: usize,
    pub pruned: usize,
    pub filtered_out: usize,
    /// Of `cells`, the other shards' cells this shard rendered as support (`run::shard`).
    #[serde(default)]
    pub support: usize,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CompositionRecord {
    pub name: String,
    pub origin: String,
    pub passes: Vec<String>,
    pub left_out: Vec<(String, String)>,
    pub triangles: usize,
    pub prepare_seconds: f64,
}

/// Time spent in each stage, summed over its jobs (ms): wall time for the render thread (submit and
/// wait for the device), CPU time of the worker threads for the CPU stages, so that contention for
/// the cores does not inflate them. Stages overlap; the sum can exceed the run's wall time.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct StageTimes {
    /// Scene upload, probe prefiltering and pipeline creation.
    pub prepare_ms: f64,
    /// Queue submit to device idle, every frame of every rendered cell (supersampled references included).
    pub render_ms: f64,
    /// Mapping the frame back to the CPU.
    pub readback_ms: f64,
    /// Tonemapping, pixel statistics, EXR and PNG encoding and writing (twins' copies included).
    pub encode_ms: f64,
    /// FLIP, SSIM, maps, and the cell record.
    pub metrics_ms: f64,
    /// Time the render thread waited for room in the encode queue (back-pressure).
    pub render_blocked_ms: f64,
    /// Threads per CPU stage and queue depths.
    pub encode_workers: usize,
    pub metrics_workers: usize,
    pub queue_depth: usize,
    /// Process CPU time (user + system) over the whole run, where the OS reports it.
    pub process_cpu: Maybe<f64>,
    /// Peak resident set size of the process, bytes, where the OS reports it.
    pub peak_rss_bytes: Maybe<u64>,
}
