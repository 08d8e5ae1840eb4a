//! The results layout of DESIGN.md: `results/<run>/run.json`, `cells/<cell-id>/{image.exr,
//! image.png, cell.json}`. cell.json is written last, so its presence (with a matching input
//! hash) marks a finished cell and lets `--resume` skip it.

use std::path::{Path, PathBuf};

use super::cell::{CellRecord, CELL_SCHEMA};
use crate::error::{Error, InputError};

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
        if resume {
            remove_unfinished_writes(&root);
        }
        Ok(RunDir { root })
    }

    pub fn cell_dir(&self, id: &str) -> PathBuf {
        self.root.join("cells").join(id)
    }

    /// A cell is done when its cell.json exists, parses, has this input hash, and its images exist.
    pub fn cell_done(&self, id: &str, input_hash: &str) -> bool {
        let dir = self.cell_dir(id);
        // A record of another schema version is stale: the cell is rendered again.
        let Ok(rec) = super::read_record::<CellRecord>(&dir.join(CELL_FILE), CELL_SCHEMA) else { return false };
        rec.input_hash == input_hash && dir.join("image.exr").is_file() && dir.join("image.png").is_file()
    }
}

/// Temporary files (`.name.tmpPID`, `fsutil::write_atomic`) and folders of a process that was
/// killed mid-write: never part of a finished cell, so a resumed run leaves none behind.
fn remove_unfinished_writes(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.filter_map(|e| e.ok()) {
        let (name, path) = (e.file_name().to_string_lossy().to_string(), e.path());
        let unfinished =
            name.starts_with('.') && (name.contains(".tmp") || name.contains(".cached") || name.contains(".merge"));
        match (path.is_dir(), unfinished) {
            (true, true) => drop(std::fs::remove_dir_all(&path)),
            (false, true) => drop(std::fs::remove_file(&path)),
            (true, false) => remove_unfinished_writes(&path),
            (false, false) => {}
        }
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
