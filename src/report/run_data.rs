//! Reading a run folder back: run.json and every cell's cell.json.

use std::path::{Path, PathBuf};

use crate::error::{Error, InputError};
use crate::run::store::{CELL_FILE, RUN_FILE};

pub struct RunData {
    pub dir: PathBuf,
    pub run: serde_json::Value,
    /// (cell id, cell.json), sorted by id.
    pub cells: Vec<(String, serde_json::Value)>,
}

impl RunData {
    pub fn load(dir: &Path) -> Result<RunData, Error> {
        let shown = dir.display().to_string();
        let run_text = std::fs::read_to_string(dir.join(RUN_FILE))
            .map_err(|e| InputError::new(&shown, format!("not a run folder (no readable {RUN_FILE}): {e}")))?;
        let run: serde_json::Value = serde_json::from_str(&run_text)
            .map_err(|e| InputError::new(dir.join(RUN_FILE).display().to_string(), format!("invalid JSON: {e}")))?;
        let mut cells = Vec::new();
        let entries = std::fs::read_dir(dir.join("cells"))
            .map_err(|e| InputError::new(&shown, format!("no cells folder: {e}")))?;
        for entry in entries.filter_map(|e| e.ok()) {
            let path = entry.path().join(CELL_FILE);
            // A cell without its record never finished: it is not part of the run.
            let Ok(text) = std::fs::read_to_string(&path) else { continue };
            let v: serde_json::Value = serde_json::from_str(&text)
                .map_err(|e| InputError::new(path.display().to_string(), format!("invalid JSON: {e}")))?;
            cells.push((entry.file_name().to_string_lossy().to_string(), v));
        }
        cells.sort_by(|a, b| a.0.cmp(&b.0));
        Ok(RunData { dir: dir.to_path_buf(), run, cells })
    }

    pub fn cell_dir(&self, id: &str) -> PathBuf {
        self.dir.join("cells").join(id)
    }

    pub fn adapter(&self) -> String {
        let a = &self.run["adapter"];
        format!(
            "{} ({}, {})",
            a["name"].as_str().unwrap_or("?"),
            a["backend"].as_str().unwrap_or("?"),
            a["driver_info"].as_str().unwrap_or("")
        )
    }
}
