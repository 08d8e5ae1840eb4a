//! Finished cells kept across runs, content-addressed: a cell's folder (images, maps, study frames,
//! reference and record) is stored under its key (`run::cell_key`), and a later run — into any
//! folder — whose cell has the same key takes the folder instead of rendering it.
//!
//! Files are hard-linked where the cache and the run share a file system (no second copy on
//! disk), else copied. That is safe because every file of a run is written whole under a
//! temporary name and renamed into place (`fsutil`): a re-rendered cell replaces its files and
//! never writes through a link. An entry appears whole or not at all (built beside, then renamed).

use std::path::{Path, PathBuf};

use crate::error::Error;
use crate::record::{CellRecord, CELL_FILE};

/// The default cache: beside the run folders (results/.cell-cache for results/<run>).
pub fn default_dir(results_root: &Path) -> PathBuf {
    results_root.join(".cell-cache")
}

pub struct CellCache {
    dir: PathBuf,
}

impl CellCache {
    pub fn new(dir: PathBuf) -> CellCache {
        CellCache { dir }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn entry(&self, key: &str) -> PathBuf {
        self.dir.join(&key[..2.min(key.len())]).join(key)
    }

    /// Whether a whole entry is stored under `key`.
    pub fn contains(&self, key: &str) -> bool {
        !key.is_empty() && self.entry(key).join(CELL_FILE).is_file()
    }

    /// Put the entry under `key` in `cell_dir` (replacing what is there), with its record's
    /// matrix hash set to this run's. False when there is no such entry.
    pub fn restore(&self, key: &str, cell_dir: &Path, matrix_sha256: &str) -> Result<bool, Error> {
        let from = self.entry(key);
        let Ok(mut record) = CellRecord::load(&from.join(CELL_FILE)) else { return Ok(false) };
        if record.input_hash != key {
            return Ok(false);
        }
        link_into_place(&from, cell_dir, "cached", |tmp| {
            if record.matrix_sha256 == matrix_sha256 {
                return Ok(());
            }
            record.matrix_sha256 = matrix_sha256.to_string();
            crate::fsutil::write_json(&tmp.join(CELL_FILE), &record)
        })?;
        Ok(true)
    }

    /// Keep the finished cell in `cell_dir` under `key` (nothing when an entry is there already).
    pub fn store(&self, key: &str, cell_dir: &Path) -> Result<(), Error> {
        if key.is_empty() || self.contains(key) {
            return Ok(());
        }
        let entry = self.entry(key);
        let parent = entry.parent().unwrap_or(&self.dir);
        std::fs::create_dir_all(parent).map_err(|e| Error::io_path("creating folder", parent, e))?;
        let tmp = parent.join(format!(".{key}.tmp{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        link_tree(cell_dir, &tmp)?;
        match std::fs::rename(&tmp, &entry) {
            Ok(()) => Ok(()),
            // Another run stored the same key first: theirs is the same cell.
            Err(_) if self.contains(key) => {
                let _ = std::fs::remove_dir_all(&tmp);
                Ok(())
            }
            Err(e) => {
                let _ = std::fs::remove_dir_all(&tmp);
                Err(Error::io_path("renaming into place", &entry, e))
            }
        }
    }
}

/// The folder `from` linked (`link_tree`) into `to`, replacing what is there, whole or not at all:
/// built beside under a temporary name (`.name.<tag>PID`, which `--resume` clears), `edit`ed
/// there, then renamed into place.
pub fn link_into_place(
    from: &Path,
    to: &Path,
    tag: &str,
    edit: impl FnOnce(&Path) -> Result<(), Error>,
) -> Result<(), Error> {
    let parent = to.parent().unwrap_or(Path::new("."));
    let name = to.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let tmp = parent.join(format!(".{name}.{tag}{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    link_tree(from, &tmp)?;
    edit(&tmp)?;
    if to.exists() {
        std::fs::remove_dir_all(to).map_err(|e| Error::io_path("replacing", to, e))?;
    }
    std::fs::rename(&tmp, to).map_err(|e| Error::io_path("renaming into place", to, e))
}

/// `to` made a copy of the folder `from`: files hard-linked, or copied where linking fails;
/// temporary files (`.name.tmpN`) of an unfinished write are left out.
fn link_tree(from: &Path, to: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(to).map_err(|e| Error::io_path("creating folder", to, e))?;
    let entries = std::fs::read_dir(from).map_err(|e| Error::io_path("reading folder", from, e))?;
    for e in entries {
        let e = e.map_err(|e| Error::io_path("reading folder", from, e))?;
        let name = e.file_name();
        if name.to_string_lossy().starts_with('.') {
            continue;
        }
        let (src, dst) = (e.path(), to.join(&name));
        if src.is_dir() {
            link_tree(&src, &dst)?;
        } else if std::fs::hard_link(&src, &dst).is_err() {
            std::fs::copy(&src, &dst).map_err(|e| Error::io_path("copying", &src, e))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stored_folder_comes_back_whole_and_unknown_keys_do_not() {
        let tmp = tempfile::tempdir().unwrap();
        let cache = CellCache::new(tmp.path().join("cache"));
        let cell = tmp.path().join("run/cells/a");
        std::fs::create_dir_all(cell.join("study")).unwrap();
        std::fs::write(cell.join("image.png"), b"png").unwrap();
        std::fs::write(cell.join("study/x.png"), b"x").unwrap();
        std::fs::write(cell.join(".image.exr.tmp1"), b"half").unwrap();
        // Without a record the folder is not a finished cell: nothing is restored.
        cache.store("abcd", &cell).unwrap();
        let out = tmp.path().join("other/cells/a");
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
        assert!(!cache.restore("abcd", &out, "m").unwrap());
        assert!(!cache.restore("ffff", &out, "m").unwrap());
        assert!(!out.exists());
        assert!(std::fs::read_dir(tmp.path().join("cache/ab")).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .contains("tmp")));
    }
}
