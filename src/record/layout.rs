//! The results layout of DESIGN.md: `results/<run>/run.json`, `cells/<cell-id>/{image.exr,
//! image.png, cell.json}`. cell.json is written last, so its presence (with a matching input
//! hash) marks a finished cell and lets `--resume` skip it.

use std::path::{Path, PathBuf};

use super::cell::{CellRecord, CELL_SCHEMA};
use crate::error::{Error, InputError};

pub const RUN_FILE: &str = "run.json";
pub const CELL_FILE: &str = "cell.json";

/// A cell's own reference as a picture (a truth, a supersampled render), and its truth's noise
/// as one (`run::encode`): what the viewer shows as B and over it.
pub const REFERENCE_PNG: &str = "reference.png";
pub const TRUTH_NOISE_PNG: &str = "truth_noise.png";

/// The advisory lock of a run folder (`flock` on this file, as cargo locks its target dir).
pub const LOCK_FILE: &str = ".shadematrix.lock";

/// The temporary names this tool writes in a run folder, `.NAME.TAGPID`: `tmp` for a file being
/// written (`fsutil::write_atomic`), `cached` and `merge` for a cell folder being placed
/// (`run::cell_cache`). `--resume` removes these and nothing else.
const TEMP_TAGS: [&str; 3] = ["tmp", "cached", "merge"];

pub struct RunDir {
    pub root: PathBuf,
    /// Held while this process writes the folder; released when the RunDir is dropped.
    pub lock: RunLock,
}

/// An exclusive advisory lock on a run folder: a second writer (a run, a `--resume`, a `merge`
/// or a `report` into the same folder) is refused instead of mixing its files with ours.
#[derive(Debug)]
pub struct RunLock {
    _file: std::fs::File,
}

impl RunLock {
    /// Lock `dir` (which must exist), or say that another process holds it.
    pub fn acquire(dir: &Path) -> Result<RunLock, Error> {
        let path = dir.join(LOCK_FILE);
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .read(true)
            .write(true)
            .open(&path)
            .map_err(|e| Error::io_path("opening the run folder's lock", &path, e))?;
        match file.try_lock() {
            Ok(()) => Ok(RunLock { _file: file }),
            Err(std::fs::TryLockError::WouldBlock) => Err(InputError::new(
                dir.display().to_string(),
                "another shadematrix process is writing this run folder (it holds .shadematrix.lock); \
                 wait for it to finish, or choose another --out",
            )
            .into()),
            Err(std::fs::TryLockError::Error(e)) => Err(Error::io_path("locking the run folder", &path, e)),
        }
    }
}

impl RunDir {
    /// Choose the run folder and lock it before anything in it is read or written. A new run
    /// never writes into a folder that holds a run, nor into a non-empty folder this tool did not
    /// make; `resume` continues one: the given `out`, or the newest run of this matrix under
    /// `results_root`.
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
        if root.exists() && !root.is_dir() {
            return Err(InputError::new(root.display().to_string(), "--out: this is a file, not a folder").into());
        }
        std::fs::create_dir_all(&root).map_err(|e| Error::io_path("creating run folder", &root, e))?;
        let had_lock = root.join(LOCK_FILE).exists();
        let lock = RunLock::acquire(&root)?;
        // A refused folder is left as it was found: no lock file of ours in it.
        let refuse = |e: Error| -> Result<RunDir, Error> {
            if !had_lock {
                let _ = std::fs::remove_file(root.join(LOCK_FILE));
            }
            Err(e)
        };
        let holds_run = root.join(RUN_FILE).exists();
        if !resume && holds_run {
            return refuse(
                InputError::new(
                    root.display().to_string(),
                    "this folder already holds a run; pass --resume to continue it, or choose another --out",
                )
                .into(),
            );
        }
        if !holds_run {
            if let Some(name) = foreign_entry(&root) {
                return refuse(
                    InputError::new(
                        root.display().to_string(),
                        format!(
                            "--out: the folder is not empty and holds no run (it has `{name}`); a run writes \
                             index.html, tables/ and more here, so choose an empty or new folder"
                        ),
                    )
                    .into(),
                );
            }
        }
        if let Err(e) = check_own_tree(&root) {
            return refuse(e);
        }
        std::fs::create_dir_all(root.join("cells")).map_err(|e| Error::io_path("creating run folder", &root, e))?;
        if resume {
            remove_unfinished_writes(&root);
        }
        Ok(RunDir { root, lock })
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

/// An entry of `dir` this tool would not have made before its run.json: anything but its lock
/// and an empty `cells/` (what a run killed before its first record leaves).
fn foreign_entry(dir: &Path) -> Option<String> {
    let entries = std::fs::read_dir(dir).ok()?;
    for e in entries.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().to_string();
        let empty_cells = name == "cells"
            && e.file_type().is_ok_and(|t| t.is_dir())
            && std::fs::read_dir(e.path()).is_ok_and(|mut d| d.next().is_none());
        if name != LOCK_FILE && !empty_cells {
            return Some(name);
        }
    }
    None
}

/// The folders and files a run writes (`tables/`, `sheets/`, `plots/`, `cells/`, each cell's
/// folder, the reports) are the run's own, not symbolic links: `report` and `--resume` wrote
/// through a linked `tables/` or `cells/<id>` and overwrote a file outside the run.
pub fn check_own_tree(root: &Path) -> Result<(), Error> {
    let link = |p: &Path| std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_symlink());
    let mut paths: Vec<PathBuf> =
        ["tables", "sheets", "plots", "cells", "index.html", "gallery.html", "viewer-data.js"]
            .iter()
            .chain(&[RUN_FILE, "junit.xml", "summary.md"])
            .map(|n| root.join(n))
            .collect();
    if let Ok(entries) = std::fs::read_dir(root.join("cells")) {
        // Each cell's folder (hidden names are temporary ones, which the clean-up never follows).
        let cells = entries.filter_map(|e| e.ok()).filter(|e| !e.file_name().to_string_lossy().starts_with('.'));
        paths.extend(cells.map(|e| e.path()));
    }
    match paths.iter().find(|p| link(p)) {
        Some(p) => Err(InputError::new(
            p.display().to_string(),
            "is a symbolic link: a run writes its own files and folders, never through a link out of the run \
             (replace the link with the folder's contents, or run into a new folder)",
        )
        .into()),
        None => Ok(()),
    }
}

/// `path` (to be written or replaced) lies inside the run folder `root`: its parent canonicalises
/// under `root`'s canonical path and it is not itself a symbolic link, so nothing is written or
/// removed through a link out of the run (a linked `tables/` or `cells/<id>`).
pub fn check_inside(root: &Path, path: &Path) -> Result<(), Error> {
    let outside = |why: String| Error::from(InputError::new(path.display().to_string(), why));
    let root = root.canonicalize().map_err(|e| outside(format!("the run folder cannot be resolved: {e}")))?;
    let parent = path.parent().unwrap_or(Path::new("."));
    let parent = parent.canonicalize().map_err(|e| outside(format!("its folder cannot be resolved: {e}")))?;
    if !parent.starts_with(&root) {
        return Err(outside(format!(
            "leads out of the run folder {} (to {}): a symbolic link in the run is not followed",
            root.display(),
            parent.display()
        )));
    }
    if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        return Err(outside("is a symbolic link: the run writes its own files, not through links".into()));
    }
    Ok(())
}

/// Whether `name` is one of this tool's temporary names (`.NAME.TAGPID`) with one of `tags`.
pub fn is_temp_name(name: &str, tags: &[&str]) -> bool {
    let Some(rest) = name.strip_prefix('.') else { return false };
    tags.iter().any(|tag| {
        rest.rsplit_once(&format!(".{tag}"))
            .is_some_and(|(stem, pid)| !stem.is_empty() && !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// Temporary files and folders of a process that was killed mid-write: never part of a finished
/// cell, so a resumed run leaves none behind. Only the exact temporary names this tool writes
/// (`TEMP_TAGS`), only in the folders a run writes (the root, `cells/`, each cell's folder and
/// its subfolders, `tables/`, `sheets/`, `plots/`), and never through a symbolic link: the
/// clean-up once walked the whole tree, followed links out of it, and removed users' files.
pub fn remove_unfinished_writes(root: &Path) {
    let mut dirs = vec![root.to_path_buf(), root.join("tables"), root.join("sheets"), root.join("plots")];
    let cells = root.join("cells");
    dirs.push(cells.clone());
    for cell in real_subdirs(&cells) {
        dirs.extend(real_subdirs(&cell));
        dirs.push(cell);
    }
    for dir in dirs {
        // A folder of the list that is itself a link is not the run's: leave it.
        if std::fs::symlink_metadata(&dir).map(|m| m.is_dir()).unwrap_or(false) {
            remove_temp_entries(&dir);
        }
    }
}

/// The folders in `dir` (not links to folders), temporary ones left out.
fn real_subdirs(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    entries
        .filter_map(|e| e.ok())
        .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
        .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
        .map(|e| e.path())
        .collect()
}

fn remove_temp_entries(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().to_string();
        if !is_temp_name(&name, &TEMP_TAGS) {
            continue;
        }
        // `file_type` does not follow links; `remove_dir_all` does not either.
        match e.file_type() {
            Ok(t) if t.is_dir() => drop(std::fs::remove_dir_all(e.path())),
            Ok(t) if t.is_file() => drop(std::fs::remove_file(e.path())),
            _ => {}
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_tools_exact_temporary_names_are_temporary() {
        for name in [".image.exr.tmp123", ".cell__a_s0.5.cached9", ".x.merge1", ".run.json.tmp4"] {
            assert!(is_temp_name(name, &TEMP_TAGS), "{name}");
        }
        for name in ["image.tmp1", ".tmp", ".a.tmp", ".a.tmpx", ".notes.tmp1x", ".a.temp1", "..tmp1", ".a.cache1"] {
            assert!(!is_temp_name(name, &TEMP_TAGS), "{name}");
        }
    }
}
