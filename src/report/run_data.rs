//! Reading a run folder back: its run record and every finished cell's record, typed.

use std::path::{Path, PathBuf};

use crate::error::{Error, InputError};
use crate::record::{CellRecord, RecordError, RunRecord, CELL_FILE};

pub struct RunData {
    pub dir: PathBuf,
    pub run: RunRecord,
    /// Sorted by id.
    pub cells: Vec<CellRecord>,
}

impl RunData {
    pub fn load(dir: &Path) -> Result<RunData, Error> {
        let shown = dir.display().to_string();
        if !dir.join(crate::record::RUN_FILE).is_file() {
            return Err(InputError::new(&shown, "not a run folder (no run.json)").into());
        }
        let run = RunRecord::load(dir)?;
        let mut cells = Vec::new();
        let entries = std::fs::read_dir(dir.join("cells"))
            .map_err(|e| InputError::new(&shown, format!("no cells folder: {e}")))?;
        for entry in entries.filter_map(|e| e.ok()) {
            let path = entry.path().join(CELL_FILE);
            match CellRecord::read(&path) {
                Ok(c) => cells.push(c),
                // A cell without its record never finished: it is not part of the run.
                Err(RecordError::Absent) => {}
                Err(e) => return Err(e.into_error(&path, "cell record")),
            }
        }
        cells.sort_by(|a, b| a.id.cmp(&b.id));
        Ok(RunData { dir: dir.to_path_buf(), run, cells })
    }

    pub fn cell_dir(&self, id: &str) -> PathBuf {
        self.dir.join("cells").join(id)
    }

    pub fn adapter(&self) -> String {
        self.run.adapter_label()
    }

    pub fn has_cell(&self, id: &str) -> bool {
        self.cells.binary_search_by(|c| c.id.0.as_str().cmp(id)).is_ok()
    }
}
