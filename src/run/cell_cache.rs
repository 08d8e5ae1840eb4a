//! Finished cells kept across runs, content-addressed: a cell's folder (images, maps, study frames,
//! reference and record) is stored under its key (`run::cell_key`), and a later run — into any
//! folder — whose cell has the same key takes the folder instead of rendering it.
//!
//! As Bazel's and git's object stores do, an entry is immutable and verified:
//! - Files are **copied** in and out (read once, digested and written), never hard-linked: with
//!   links, `cp other.png RUN/cells/X/image.png` rewrote the cache entry and every run that had
//!   taken it. Stored files are read-only besides.
//! - Each entry carries a manifest (`entry.json`, `CacheEntry`): every file's path, size and
//!   SHA-256, recorded when it was stored. Restoring checks each file against it while copying; an
//!   entry with a missing, truncated or edited file is dropped with a warning and the cell renders.
//! - An entry appears whole or not at all: built beside under a temporary name, then renamed.

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

use crate::error::Error;
use crate::record::{CellRecord, CELL_FILE};
use crate::spec::matrix::hex;

/// The default cache: beside the run folders (results/.cell-cache for results/<run>).
pub fn default_dir(results_root: &Path) -> PathBuf {
    results_root.join(".cell-cache")
}

/// An entry's manifest, inside the entry folder.
pub const ENTRY_FILE: &str = "entry.json";
pub const ENTRY_SCHEMA: u32 = 1;

/// What an entry holds, recorded when it was stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CacheEntry {
    pub schema: u32,
    /// The cell key the entry is stored under.
    pub key: String,
    pub files: Vec<StoredFile>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredFile {
    /// Relative to the entry (and the cell's folder), `/`-separated.
    pub path: String,
    pub bytes: u64,
    pub sha256: String,
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

    /// Whether an entry (its manifest) is stored under `key`; `restore` verifies it.
    pub fn contains(&self, key: &str) -> bool {
        !key.is_empty() && self.entry(key).join(ENTRY_FILE).is_file()
    }

    /// Put the entry under `key` in `cell_dir` (replacing what is there), with its record's
    /// matrix hash set to this run's. False when there is no such entry, or when it failed its
    /// check (then it is dropped, with a warning on stderr, and the cell renders again).
    pub fn restore(&self, key: &str, cell_dir: &Path, matrix_sha256: &str) -> Result<bool, Error> {
        if !self.contains(key) {
            return Ok(false);
        }
        let from = self.entry(key);
        let verified = self.verified_entry(key).and_then(|manifest| {
            let parent = cell_dir.parent().unwrap_or(Path::new("."));
            std::fs::create_dir_all(parent).map_err(|e| format!("creating {}: {e}", parent.display()))?;
            let tmp = temp_name(cell_dir, CACHED_TAG);
            let _ = std::fs::remove_dir_all(&tmp);
            let copied = copy_verified(&from, &tmp, &manifest).and_then(|()| {
                let record = CellRecord::load(&tmp.join(CELL_FILE)).map_err(|e| {
                    format!("its {CELL_FILE} cannot be read: {}", e.into_error(&from.join(CELL_FILE), "cell record"))
                })?;
                if record.input_hash != key {
                    return Err(format!("its {CELL_FILE} is of key {}, not {key}", record.input_hash));
                }
                Ok(record)
            });
            match copied {
                Ok(record) => Ok((tmp, record)),
                Err(e) => {
                    let _ = std::fs::remove_dir_all(&tmp);
                    Err(e)
                }
            }
        });
        let (tmp, mut record) = match verified {
            Ok(v) => v,
            Err(why) => {
                eprintln!("warning: cell cache entry {} dropped: {why}; the cell renders again", from.display());
                self.drop_entry(key);
                return Ok(false);
            }
        };
        if record.matrix_sha256 != matrix_sha256 {
            record.matrix_sha256 = matrix_sha256.to_string();
            crate::fsutil::write_json(&tmp.join(CELL_FILE), &record)?;
        }
        replace_dir(&tmp, cell_dir)?;
        Ok(true)
    }

    /// The entry's manifest, when it parses and is of this key.
    fn verified_entry(&self, key: &str) -> Result<CacheEntry, String> {
        let path = self.entry(key).join(ENTRY_FILE);
        let bytes = std::fs::read(&path).map_err(|e| format!("its manifest cannot be read: {e}"))?;
        let manifest: CacheEntry =
            serde_json::from_slice(&bytes).map_err(|e| format!("its manifest does not parse: {e}"))?;
        if manifest.schema != ENTRY_SCHEMA {
            return Err(format!("its manifest is of schema {}, this tool writes {ENTRY_SCHEMA}", manifest.schema));
        }
        if manifest.key != key {
            return Err(format!("its manifest names key {}", manifest.key));
        }
        if !manifest.files.iter().any(|f| f.path == CELL_FILE) {
            return Err(format!("it holds no {CELL_FILE}"));
        }
        Ok(manifest)
    }

    /// Remove a bad entry: renamed aside first, so no reader sees it half-removed.
    fn drop_entry(&self, key: &str) {
        let entry = self.entry(key);
        let aside = temp_name(&entry, "dropped");
        if std::fs::rename(&entry, &aside).is_ok() {
            let _ = std::fs::remove_dir_all(&aside);
        }
    }

    /// Keep the finished cell in `cell_dir` under `key` (nothing when an entry is there already).
    pub fn store(&self, key: &str, cell_dir: &Path) -> Result<(), Error> {
        if key.is_empty() || self.contains(key) || !cell_dir.join(CELL_FILE).is_file() {
            return Ok(());
        }
        let entry = self.entry(key);
        let parent = entry.parent().unwrap_or(&self.dir);
        std::fs::create_dir_all(parent).map_err(|e| Error::io_path("creating folder", parent, e))?;
        let tmp = temp_name(&entry, "tmp");
        let _ = std::fs::remove_dir_all(&tmp);
        let result = (|| {
            let mut files = Vec::new();
            copy_tree(cell_dir, &tmp, "", &mut files, true)?;
            files.sort_by(|a, b| a.path.cmp(&b.path));
            let manifest = CacheEntry { schema: ENTRY_SCHEMA, key: key.to_string(), files };
            let bytes = serde_json::to_vec_pretty(&manifest).map_err(std::io::Error::other)?;
            std::fs::write(tmp.join(ENTRY_FILE), bytes)?;
            read_only(&tmp.join(ENTRY_FILE));
            // A stale folder without a manifest (a store killed between rename and manifest
            // cannot happen, but an older tool's entry can) gives way.
            if entry.exists() && !self.contains(key) {
                let _ = std::fs::remove_dir_all(&entry);
            }
            std::fs::rename(&tmp, &entry)
        })();
        match result {
            Ok(()) => Ok(()),
            // Another run stored the same key first: theirs is the same cell.
            Err(_) if self.contains(key) => {
                let _ = std::fs::remove_dir_all(&tmp);
                Ok(())
            }
            Err(e) => {
                let _ = std::fs::remove_dir_all(&tmp);
                Err(Error::io_path("storing in the cell cache", &entry, e))
            }
        }
    }
}

/// The tag of a cell folder being restored from the cache (`.NAME.cachedPID`).
pub const CACHED_TAG: &str = "cached";

/// `.NAME.TAGPID` beside `path`: a temporary name `--resume` recognises exactly (`record::layout`).
pub fn temp_name(path: &Path, tag: &str) -> PathBuf {
    let parent = path.parent().unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    parent.join(format!(".{name}.{tag}{}", std::process::id()))
}

/// `tmp` renamed to `to`, replacing what is there.
fn replace_dir(tmp: &Path, to: &Path) -> Result<(), Error> {
    if to.exists() {
        std::fs::remove_dir_all(to).map_err(|e| Error::io_path("replacing", to, e))?;
    }
    std::fs::rename(tmp, to).map_err(|e| Error::io_path("renaming into place", to, e))
}

/// The folder `from` copied (`copy_tree`) into `to`, replacing what is there, whole or not at all:
/// built beside under a temporary name (`.name.<tag>PID`, which `--resume` clears), then renamed.
pub fn copy_into_place(from: &Path, to: &Path, tag: &str) -> Result<(), Error> {
    let parent = to.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| Error::io_path("creating folder", parent, e))?;
    let tmp = temp_name(to, tag);
    let _ = std::fs::remove_dir_all(&tmp);
    if let Err(e) = copy_tree(from, &tmp, "", &mut Vec::new(), false) {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(Error::io_path("copying", from, e));
    }
    replace_dir(&tmp, to)
}

/// `to` made a copy of the folder `from` (symbolic links and temporary files `.name.tmpN` of an
/// unfinished write left out), each file's size and digest pushed to `files`.
fn copy_tree(from: &Path, to: &Path, prefix: &str, files: &mut Vec<StoredFile>, readonly: bool) -> std::io::Result<()> {
    std::fs::create_dir_all(to)?;
    for e in std::fs::read_dir(from)? {
        let e = e?;
        let name = e.file_name().to_string_lossy().to_string();
        if name.starts_with('.') || (prefix.is_empty() && name == ENTRY_FILE) {
            continue;
        }
        let (src, dst) = (e.path(), to.join(&name));
        let rel = format!("{prefix}{name}");
        let kind = e.file_type()?;
        if kind.is_dir() {
            copy_tree(&src, &dst, &format!("{rel}/"), files, readonly)?;
        } else if kind.is_file() {
            let bytes = std::fs::read(&src)?;
            std::fs::write(&dst, &bytes)?;
            if readonly {
                read_only(&dst);
            }
            files.push(StoredFile { path: rel, bytes: bytes.len() as u64, sha256: hex(&Sha256::digest(&bytes)) });
        }
    }
    Ok(())
}

/// The files of `manifest` copied from the entry `from` into `to`, each checked against its
/// recorded size and digest; an error says which file and how it differs.
fn copy_verified(from: &Path, to: &Path, manifest: &CacheEntry) -> Result<(), String> {
    for f in &manifest.files {
        if f.path.split('/').any(|c| c.is_empty() || c == "." || c == "..") {
            return Err(format!("its manifest names `{}`, not a path inside the entry", f.path));
        }
        let src = from.join(&f.path);
        let bytes = std::fs::read(&src).map_err(|e| format!("{} cannot be read: {e}", f.path))?;
        if bytes.len() as u64 != f.bytes {
            return Err(format!("{} is {} bytes, {} when stored", f.path, bytes.len(), f.bytes));
        }
        let digest = hex(&Sha256::digest(&bytes));
        if digest != f.sha256 {
            return Err(format!("{} has changed since it was stored (SHA-256 {digest}, stored {})", f.path, f.sha256));
        }
        let dst = to.join(&f.path);
        if let Some(p) = dst.parent() {
            std::fs::create_dir_all(p).map_err(|e| format!("creating {}: {e}", p.display()))?;
        }
        std::fs::write(&dst, &bytes).map_err(|e| format!("writing {}: {e}", dst.display()))?;
    }
    Ok(())
}

/// Stored files are read-only: a tool or a person writing through a path into the cache is
/// refused (except as root, which the digests catch).
fn read_only(path: &Path) {
    if let Ok(m) = std::fs::metadata(path) {
        let mut p = m.permissions();
        p.set_readonly(true);
        let _ = std::fs::set_permissions(path, p);
    }
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
        assert!(!cache.contains("abcd") && !tmp.path().join("cache/ab").exists(), "an unfinished cell was stored");
    }

    #[test]
    fn a_manifest_names_only_paths_inside_its_entry() {
        let tmp = tempfile::tempdir().unwrap();
        let manifest = CacheEntry {
            schema: ENTRY_SCHEMA,
            key: "k".into(),
            files: vec![StoredFile { path: "../outside".into(), bytes: 0, sha256: String::new() }],
        };
        let err = copy_verified(tmp.path(), &tmp.path().join("to"), &manifest).unwrap_err();
        assert!(err.contains("not a path inside the entry"), "{err}");
    }
}
