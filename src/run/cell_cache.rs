//! Finished cells kept across runs, content-addressed: a cell's folder (images, maps, study frames,
//! reference and record) is stored under its key (`run::cell_key`), and a later run — into any
//! folder — whose cell has the same key takes the folder instead of rendering it.
//!
//! Entries live in the verified store (`store`): copied in and out, never hard-linked (with links,
//! `cp other.png RUN/cells/X/image.png` rewrote the cache entry and every run that had taken it),
//! read-only, every file checked against the size and SHA-256 recorded when it was stored. An
//! entry whose own bytes fail is dropped and the cell renders; a failure to write the restored
//! folder (a full disk in the run folder) is the run's error and leaves the entry alone.

use std::path::{Path, PathBuf};

use crate::error::Error;
use crate::record::{CellRecord, CELL_FILE};
use crate::store::Store;

/// The default cache: beside the run folders (results/.cell-cache for results/<run>).
pub fn default_dir(results_root: &Path) -> PathBuf {
    results_root.join(".cell-cache")
}

pub struct CellCache {
    store: Store,
}

impl CellCache {
    pub fn new(dir: PathBuf) -> CellCache {
        CellCache { store: Store::new(dir, "cell cache", true) }
    }

    pub fn dir(&self) -> &Path {
        self.store.dir()
    }

    /// Whether an entry (its manifest) is stored under `key`; `take` verifies it.
    pub fn contains(&self, key: &str) -> bool {
        self.store.contains(key)
    }

    /// The verified record stored under `key`, and the entry it came from, without writing
    /// anything: what a caller checks (the truth it was compared with) before `write_entry`.
    pub fn take(&self, key: &str) -> Option<(CellRecord, crate::store::Entry)> {
        self.store.get_as(key, |entry| {
            let text = entry.file(CELL_FILE).ok_or_else(|| format!("it holds no {CELL_FILE}"))?;
            let record: CellRecord =
                serde_json::from_slice(text).map_err(|e| format!("its {CELL_FILE} does not parse: {e}"))?;
            match record.input_hash == key {
                true => Ok((record, entry)),
                false => Err(format!("its {CELL_FILE} is of key {}, not {key}", record.input_hash)),
            }
        })
    }

    /// Keep the finished cell in `cell_dir` under `key` (nothing when an entry is there already;
    /// `replacing`: in place of the one there). A cache that cannot be written warns once.
    pub fn store(&self, key: &str, cell_dir: &Path, replacing: bool) -> Result<(), Error> {
        if key.is_empty() || !cell_dir.join(CELL_FILE).is_file() || (!replacing && self.contains(key)) {
            return Ok(());
        }
        let mut files = Vec::new();
        read_tree(cell_dir, "", &mut files)?;
        files.retain(|(path, _)| path != crate::store::MANIFEST_FILE);
        let _ = self.store.keep(key, &files, replacing);
        Ok(())
    }
}

/// The verified `entry` (`CellCache::take`) written into `cell_dir` whole, its record's matrix
/// hash set to this run's: beside under a temporary name, then renamed. An error writing is the
/// run's, and leaves the cache entry alone: its bytes were good.
pub fn write_entry(
    entry: &crate::store::Entry,
    mut record: CellRecord,
    cell_dir: &Path,
    matrix_sha256: &str,
) -> Result<(), Error> {
    let parent = cell_dir.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| Error::io_path("creating folder", parent, e))?;
    let tmp = temp_name(cell_dir, CACHED_TAG);
    let _ = std::fs::remove_dir_all(&tmp);
    let written = (|| -> Result<(), Error> {
        for (path, bytes) in &entry.files {
            let to = tmp.join(path);
            let dir = to.parent().unwrap_or(&tmp);
            std::fs::create_dir_all(dir).map_err(|e| Error::io_path("creating folder", dir, e))?;
            if path == CELL_FILE && record.matrix_sha256 != matrix_sha256 {
                record.matrix_sha256 = matrix_sha256.to_string();
                crate::fsutil::write_json(&to, &record)?;
            } else {
                std::fs::write(&to, bytes).map_err(|e| Error::io_path("writing", &to, e))?;
            }
        }
        replace_dir(&tmp, cell_dir)
    })();
    if written.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    written
}

/// The tag of a cell folder being restored from the cache (`.NAME.cachedPID`).
pub const CACHED_TAG: &str = "cached";

pub use crate::store::temp_name;

/// `tmp` renamed to `to`, replacing what is there.
fn replace_dir(tmp: &Path, to: &Path) -> Result<(), Error> {
    if to.exists() {
        std::fs::remove_dir_all(to).map_err(|e| Error::io_path("replacing", to, e))?;
    }
    std::fs::rename(tmp, to).map_err(|e| Error::io_path("renaming into place", to, e))
}

/// The folder `from` copied (`read_tree`) into `to`, replacing what is there, whole or not at all:
/// built beside under a temporary name (`.name.<tag>PID`, which `--resume` clears), then renamed.
pub fn copy_into_place(from: &Path, to: &Path, tag: &str) -> Result<(), Error> {
    let parent = to.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| Error::io_path("creating folder", parent, e))?;
    let mut files = Vec::new();
    read_tree(from, "", &mut files)?;
    let tmp = temp_name(to, tag);
    let _ = std::fs::remove_dir_all(&tmp);
    let written = (|| -> Result<(), Error> {
        for (path, bytes) in &files {
            let dst = tmp.join(path);
            let dir = dst.parent().unwrap_or(&tmp);
            std::fs::create_dir_all(dir).map_err(|e| Error::io_path("creating folder", dir, e))?;
            std::fs::write(&dst, bytes).map_err(|e| Error::io_path("writing", &dst, e))?;
        }
        replace_dir(&tmp, to)
    })();
    if written.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    written
}

/// Every regular file under `from` (symbolic links, other kinds and hidden names such as an
/// unfinished write's `.name.tmpN` left out), read through the bounded reader, `/`-separated
/// paths relative to `from` after `prefix`.
fn read_tree(from: &Path, prefix: &str, files: &mut Vec<(String, Vec<u8>)>) -> Result<(), Error> {
    let entries = std::fs::read_dir(from).map_err(|e| Error::io_path("listing", from, e))?;
    let mut entries: Vec<_> = entries.filter_map(Result::ok).collect();
    entries.sort_by_key(|e| e.file_name());
    for e in entries {
        let name = e.file_name().to_string_lossy().to_string();
        if name.starts_with('.') {
            continue;
        }
        let rel = format!("{prefix}{name}");
        let kind = e.file_type().map_err(|err| Error::io_path("reading", &e.path(), err))?;
        if kind.is_dir() {
            read_tree(&e.path(), &format!("{rel}/"), files)?;
        } else if kind.is_file() {
            let bytes = crate::input::read::read(&e.path(), crate::input::read::OUTPUT)
                .map_err(|err| Error::Other(format!("reading {}: {err}", e.path().display())))?;
            files.push((rel, bytes));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unfinished_cell_is_not_stored_and_unknown_keys_do_not_restore() {
        let tmp = tempfile::tempdir().unwrap();
        let cache = CellCache::new(tmp.path().join("cache"));
        let cell = tmp.path().join("run/cells/a");
        std::fs::create_dir_all(cell.join("study")).unwrap();
        std::fs::write(cell.join("image.png"), b"png").unwrap();
        std::fs::write(cell.join("study/x.png"), b"x").unwrap();
        std::fs::write(cell.join(".image.exr.tmp1"), b"half").unwrap();
        // Without a record the folder is not a finished cell: nothing is stored.
        cache.store("abcd", &cell, false).unwrap();
        let out = tmp.path().join("other/cells/a");
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
        assert!(cache.take("abcd").is_none() && cache.take("ffff").is_none());
        assert!(!out.exists());
        assert!(!cache.contains("abcd") && !tmp.path().join("cache/ab").exists(), "an unfinished cell was stored");
    }
}
