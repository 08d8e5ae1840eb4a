//! The results layout of DESIGN.md: `results/<run>/run.json`, `cells/<cell-id>/{image.exr,
//! image.png, cell.json}`. cell.json is written last, so its presence (with a matching input
//! hash) marks a finished cell and lets `--resume` skip it.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use crate::error::{Error, InputError};
use crate::gpu::AdapterRecord;

pub const RUN_FILE: &str = "run.json";
pub const CELL_FILE: &str = "cell.json";

pub struct RunDir {
    pub root: PathBuf,
}

impl RunDir {
    /// Choose the run folder. A new run never writes into a folder that already holds a run;
    /// `resume` continues one: the given `out`, or the newest run of this matrix under `results_root`.
    pub fn open(results_root: &Path, out: Option<&Path>, matrix_name: &str, resume: bool) -> Result<RunDir, Error> {
        let root = match (out, resume) {
            (Some(o), _) => o.to_path_buf(),
            (None, false) => {
                let stamp = chrono::Local::now().format("%Y%m%d-%H%M%S");
                let mut candidate = results_root.join(format!("{matrix_name}-{stamp}"));
                let mut n = 2;
                while candidate.exists() {
                    candidate = results_root.join(format!("{matrix_name}-{stamp}-{n}"));
                    n += 1;
                }
                candidate
            }
            (None, true) => newest_run(results_root, matrix_name).ok_or_else(|| {
                InputError::new(
                    results_root.display().to_string(),
                    format!("--resume: no earlier run of matrix `{matrix_name}` found here; give --out DIR"),
                )
            })?,
        };
        if !resume && root.join(RUN_FILE).exists() {
            return Err(InputError::new(
                root.display().to_string(),
                "this folder already holds a run; pass --resume to continue it, or choose another --out",
            )
            .into());
        }
        std::fs::create_dir_all(root.join("cells")).map_err(|e| Error::io_path("creating run folder", &root, e))?;
        Ok(RunDir { root })
    }

    pub fn cell_dir(&self, id: &str) -> PathBuf {
        self.root.join("cells").join(id)
    }

    /// A cell is done when its cell.json exists, parses, has this input hash, and its images exist.
    pub fn cell_done(&self, id: &str, input_hash: &str) -> bool {
        let dir = self.cell_dir(id);
        let Ok(text) = std::fs::read_to_string(dir.join(CELL_FILE)) else { return false };
        let Ok(rec) = serde_json::from_str::<CellRecordHead>(&text) else { return false };
        rec.input_hash == input_hash && dir.join("image.exr").is_file() && dir.join("image.png").is_file()
    }
}

fn newest_run(results_root: &Path, matrix_name: &str) -> Option<PathBuf> {
    let prefix = format!("{matrix_name}-");
    let mut runs: Vec<PathBuf> = std::fs::read_dir(results_root)
        .ok()?
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with(&prefix) && e.path().join(RUN_FILE).is_file())
        .map(|e| e.path())
        .collect();
    runs.sort();
    runs.pop()
}

/// The part of cell.json that resume reads.
#[derive(Deserialize)]
struct CellRecordHead {
    input_hash: String,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunRecord {
    pub shadematrix_version: String,
    pub status: RunStatus,
    pub matrix: MatrixRecord,
    pub adapter: AdapterRecord,
    pub started: String,
    pub finished: Option<String>,
    pub wall_seconds: Option<f64>,
    pub counts: RunCounts,
    pub compositions: Vec<CompositionRecord>,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    Running,
    Complete,
    Failed,
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
    /// The contact sheets `report` draws.
    #[serde(default)]
    pub sheets: Vec<crate::report::sheets::SheetSpec>,
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
    pub pruned: usize,
    pub filtered_out: usize,
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
