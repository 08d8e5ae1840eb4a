//! The verified store every cache of the tool goes through: finished cells (`run::cell_cache`),
//! path-traced truths (`run::truth_cache`) and bakes (`render::gi::cache`). As Bazel's and git's
//! object stores do, an entry is content-addressed, immutable and verified:
//! - An entry is a folder under its key holding files and a manifest (`entry.json`, `Manifest`):
//!   every file's path, size and SHA-256, recorded when it was stored. It appears whole or not at
//!   all: built beside under a temporary name, then renamed. Stored files are read-only.
//! - Reading an entry reads every file through the bounded reader (`input::read`, at most the
//!   recorded size) and checks its size and digest. An entry with a missing, truncated or edited
//!   file, or a manifest that does not parse or names another key, is **dropped** (renamed aside,
//!   then removed) with a warning, and the caller builds it again: a broken entry is replaced,
//!   never served and never skipped forever.
//! - An entry is dropped only when *its own* bytes fail. What the caller does with verified bytes
//!   (writing them into a run folder on a full disk) is the caller's error, and leaves the entry.
//! - A cache is an optimisation: a store that cannot be written (a full or read-only folder) warns
//!   once and the run goes on without keeping entries there (`Store::keep`).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::Error;
use crate::input::read::{self, Limit};

/// An entry's manifest, inside the entry folder.
pub const MANIFEST_FILE: &str = "entry.json";
pub const MANIFEST_SCHEMA: u32 = 1;

/// What an entry holds, recorded when it was stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub schema: u32,
    /// The key the entry is stored under.
    pub key: String,
    pub files: Vec<StoredFile>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredFile {
    /// Relative to the entry, `/`-separated.
    pub path: String,
    pub bytes: u64,
    pub sha256: String,
}

/// A verified entry: every file's bytes, checked against the manifest.
#[derive(Debug, Clone)]
pub struct Entry {
    pub key: String,
    pub files: Vec<(String, Vec<u8>)>,
    /// The SHA-256 of the manifest's file list: what a record that used this entry keeps, so that
    /// a later reader can tell the same bytes from a rebuilt entry.
    pub digest: String,
}

impl Entry {
    /// The bytes of the file at `path` (relative to the entry).
    pub fn file(&self, path: &str) -> Option<&[u8]> {
        self.files.iter().find(|(p, _)| p == path).map(|(_, b)| b.as_slice())
    }
}

/// What a lookup found.
#[derive(Debug)]
pub enum Lookup {
    Absent,
    Found(Entry),
    /// The entry failed its check and was dropped (the warning said why).
    Dropped(String),
}

impl Lookup {
    pub fn found(self) -> Option<Entry> {
        match self {
            Lookup::Found(e) => Some(e),
            _ => None,
        }
    }
}

pub struct Store {
    dir: PathBuf,
    /// The cache's name in warnings ("cell cache").
    name: &'static str,
    /// Entries under a two-character folder of their key (`ab/abcd…`), for caches of many entries.
    fan_out: bool,
    /// Whether the warning that the store cannot be written was given.
    warned: AtomicBool,
}

impl Store {
    pub fn new(dir: PathBuf, name: &'static str, fan_out: bool) -> Store {
        Store { dir, name, fan_out, warned: AtomicBool::new(false) }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The entry folder of `key`; None for a key that is not one path component of the key
    /// alphabet (lower-case letters and digits), so no key can name a path outside the store.
    fn entry_dir(&self, key: &str) -> Option<PathBuf> {
        if key.is_empty() || key.len() > 128 || !key.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit()) {
            return None;
        }
        Some(match self.fan_out {
            true => self.dir.join(&key[..2.min(key.len())]).join(key),
            false => self.dir.join(key),
        })
    }

    /// Whether an entry (its manifest) is stored under `key`; `get` verifies it.
    pub fn contains(&self, key: &str) -> bool {
        self.entry_dir(key).is_some_and(|d| d.join(MANIFEST_FILE).is_file())
    }

    /// The entry under `key`, every file verified; a broken entry is dropped with a warning.
    pub fn get(&self, key: &str) -> Lookup {
        let Some(dir) = self.entry_dir(key) else { return Lookup::Absent };
        if !dir.join(MANIFEST_FILE).exists() {
            return Lookup::Absent;
        }
        match verified(&dir, key) {
            Ok(entry) => Lookup::Found(entry),
            Err(why) => {
                eprintln!("warning: {} entry {} dropped: {why}; it is built again", self.name, dir.display());
                self.drop_entry(key);
                Lookup::Dropped(why)
            }
        }
    }

    /// The digest of the entry stored under `key`, from its manifest alone (None: no entry, or a
    /// manifest that does not parse or names another key). What a record that used an entry is
    /// checked against: the same digest is the same files, whose bytes `get` verifies when they
    /// are read — a warm run need not read every truth its cached cells were compared with.
    pub fn digest(&self, key: &str) -> Option<String> {
        let dir = self.entry_dir(key)?;
        let bytes = read::read(&dir.join(MANIFEST_FILE), read::RECORD).ok()?;
        let manifest: Manifest = serde_json::from_slice(&bytes).ok()?;
        (manifest.schema == MANIFEST_SCHEMA && manifest.key == key).then(|| list_digest(&manifest.files))
    }

    /// The entry under `key` read as `T` by `decode`. An entry whose bytes verify but do not
    /// decode (a record naming another key, images of another size than it says) is dropped with
    /// a warning as a broken one is, so it is built again rather than skipped on every run.
    pub fn get_as<T>(&self, key: &str, decode: impl FnOnce(Entry) -> Result<T, String>) -> Option<T> {
        let entry = self.get(key).found()?;
        match decode(entry) {
            Ok(value) => Some(value),
            Err(why) => {
                eprintln!("warning: {} entry {key} dropped: {why}; it is built again", self.name);
                self.drop_entry(key);
                None
            }
        }
    }

    /// Remove the entry under `key`: renamed aside first, so no reader sees it half-removed.
    pub fn drop_entry(&self, key: &str) {
        let Some(entry) = self.entry_dir(key) else { return };
        let aside = temp_name(&entry, "dropped");
        if std::fs::rename(&entry, &aside).is_ok() {
            let _ = std::fs::remove_dir_all(&aside);
        }
    }

    /// Store `files` under `key`, unless an entry is there already; the digest of the entry now
    /// under `key`.
    pub fn put(&self, key: &str, files: &[(String, Vec<u8>)]) -> Result<String, Error> {
        self.write(key, files, false)
    }

    /// Store `files` under `key`, replacing the entry there (one whose bytes verify but that no
    /// longer fits what its user checks, such as a cell compared with a truth since rebuilt).
    pub fn replace(&self, key: &str, files: &[(String, Vec<u8>)]) -> Result<String, Error> {
        self.write(key, files, true)
    }

    /// `put`, or `replace`; a failure is a warning given once, and the run goes on: a cache is an
    /// optimisation, and a full or read-only cache folder is no reason to lose a run.
    /// The digest of the entry now under `key`, None when it could not be stored.
    pub fn keep(&self, key: &str, files: &[(String, Vec<u8>)], replacing: bool) -> Option<String> {
        match self.write(key, files, replacing) {
            Ok(digest) => Some(digest),
            Err(e) => {
                if !self.warned.swap(true, Ordering::Relaxed) {
                    eprintln!(
                        "warning: the {} at {} cannot be written ({e}); the run goes on without keeping entries \
                         there",
                        self.name,
                        self.dir.display()
                    );
                }
                None
            }
        }
    }

    fn write(&self, key: &str, files: &[(String, Vec<u8>)], replacing: bool) -> Result<String, Error> {
        let entry = self
            .entry_dir(key)
            .ok_or_else(|| Error::Other(format!("`{key}` is not a key of the {} (letters and digits)", self.name)))?;
        let existing = || {
            self.get(key)
                .found()
                .map(|e| e.digest)
                .ok_or_else(|| Error::Other(format!("the {} entry {key} was dropped as it was stored", self.name)))
        };
        if !replacing && self.contains(key) {
            return existing();
        }
        for (path, _) in files {
            if !inside(path) || path == MANIFEST_FILE {
                return Err(Error::Other(format!("`{path}` is not a file name inside a {} entry", self.name)));
            }
        }
        let parent = entry.parent().unwrap_or(&self.dir);
        std::fs::create_dir_all(parent).map_err(|e| Error::io_path("creating folder", parent, e))?;
        let tmp = temp_name(&entry, "tmp");
        let _ = std::fs::remove_dir_all(&tmp);
        let result = (|| {
            let mut stored = Vec::new();
            for (path, bytes) in files {
                let to = tmp.join(path);
                std::fs::create_dir_all(to.parent().unwrap_or(&tmp))?;
                std::fs::write(&to, bytes)?;
                read_only(&to);
                stored.push(StoredFile {
                    path: path.clone(),
                    bytes: bytes.len() as u64,
                    sha256: hex(&Sha256::digest(bytes)),
                });
            }
            stored.sort_by(|a, b| a.path.cmp(&b.path));
            let digest = list_digest(&stored);
            let manifest = Manifest { schema: MANIFEST_SCHEMA, key: key.to_string(), files: stored };
            let bytes = serde_json::to_vec_pretty(&manifest).map_err(std::io::Error::other)?;
            std::fs::write(tmp.join(MANIFEST_FILE), bytes)?;
            read_only(&tmp.join(MANIFEST_FILE));
            // An entry being replaced, or a folder without a manifest (an older tool's), gives way.
            if entry.exists() && (replacing || !self.contains(key)) {
                self.drop_entry(key);
            }
            std::fs::rename(&tmp, &entry).map(|()| digest)
        })();
        match result {
            Ok(digest) => Ok(digest),
            // Another run stored the same key first: its entry is the one there.
            Err(_) if !replacing && self.contains(key) => {
                let _ = std::fs::remove_dir_all(&tmp);
                existing()
            }
            Err(e) => {
                let _ = std::fs::remove_dir_all(&tmp);
                Err(Error::io_path(&format!("storing in the {}", self.name), &entry, e))
            }
        }
    }
}

/// The entry in `dir`, every file read through the bounded reader and checked.
fn verified(dir: &Path, key: &str) -> Result<Entry, String> {
    let manifest_bytes =
        read::read(&dir.join(MANIFEST_FILE), read::RECORD).map_err(|e| format!("its manifest cannot be read: {e}"))?;
    let manifest: Manifest =
        serde_json::from_slice(&manifest_bytes).map_err(|e| format!("its manifest does not parse: {e}"))?;
    if manifest.schema != MANIFEST_SCHEMA {
        return Err(format!("its manifest is of schema {}, this tool writes {MANIFEST_SCHEMA}", manifest.schema));
    }
    if manifest.key != key {
        return Err(format!("its manifest names key {}", manifest.key));
    }
    let mut files = Vec::with_capacity(manifest.files.len());
    for f in &manifest.files {
        if !inside(&f.path) {
            return Err(format!("its manifest names `{}`, not a path inside the entry", f.path));
        }
        let limit = Limit { bytes: f.bytes, what: "a stored file (its recorded size)" };
        let bytes = read::read(&dir.join(&f.path), limit).map_err(|e| match e {
            read::ReadError::TooLarge { bytes, .. } => format!("{} is {bytes} bytes, {} when stored", f.path, f.bytes),
            e => format!("{}: {e}", f.path),
        })?;
        if bytes.len() as u64 != f.bytes {
            return Err(format!("{} is {} bytes, {} when stored", f.path, bytes.len(), f.bytes));
        }
        let digest = hex(&Sha256::digest(&bytes));
        if digest != f.sha256 {
            return Err(format!("{} has changed since it was stored (SHA-256 {digest}, stored {})", f.path, f.sha256));
        }
        files.push((f.path.clone(), bytes));
    }
    Ok(Entry { key: key.to_string(), files, digest: list_digest(&manifest.files) })
}

/// An entry's digest: the SHA-256 of its files' paths, sizes and digests, in the manifest's order.
fn list_digest(files: &[StoredFile]) -> String {
    let mut list = Sha256::new();
    for f in files {
        list.update(format!("{} {} {}\n", f.path, f.bytes, f.sha256));
    }
    hex(&list.finalize())
}

fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// A relative, `/`-separated path that stays inside its folder.
fn inside(path: &str) -> bool {
    !path.is_empty() && !path.starts_with('/') && path.split('/').all(|c| !c.is_empty() && c != "." && c != "..")
}

/// `.NAME.TAGPID` beside `path`: a temporary name `--resume` recognises exactly (`record::layout`).
pub fn temp_name(path: &Path, tag: &str) -> PathBuf {
    let parent = path.parent().unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    parent.join(format!(".{name}.{tag}{}", std::process::id()))
}

/// Stored files are read-only: a tool or a person writing through a path into the store is
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

    fn files(pairs: &[(&str, &[u8])]) -> Vec<(String, Vec<u8>)> {
        pairs.iter().map(|(p, b)| (p.to_string(), b.to_vec())).collect()
    }

    #[test]
    fn an_entry_comes_back_whole_and_verified() {
        let tmp = tempfile::tempdir().unwrap();
        let store = Store::new(tmp.path().join("s"), "test store", true);
        store.put("abcd", &files(&[("a.bin", b"aaa"), ("sub/b.bin", b"b")])).unwrap();
        let e = store.get("abcd").found().expect("stored");
        assert_eq!(store.digest("abcd").as_deref(), Some(e.digest.as_str()), "the manifest's digest is the entry's");
        assert_eq!(e.file("a.bin"), Some(&b"aaa"[..]));
        assert_eq!(e.file("sub/b.bin"), Some(&b"b"[..]));
        assert!(matches!(store.get("abce"), Lookup::Absent));
    }

    #[test]
    fn a_changed_file_drops_the_entry_and_it_can_be_stored_again() {
        let tmp = tempfile::tempdir().unwrap();
        let store = Store::new(tmp.path().join("s"), "test store", false);
        store.put("k1", &files(&[("a.bin", b"aaa")])).unwrap();
        let f = tmp.path().join("s/k1/a.bin");
        let mut p = std::fs::metadata(&f).unwrap().permissions();
        #[allow(clippy::permissions_set_readonly_false)]
        p.set_readonly(false);
        std::fs::set_permissions(&f, p).unwrap();
        std::fs::write(&f, b"aab").unwrap();
        assert!(matches!(store.get("k1"), Lookup::Dropped(why) if why.contains("changed since it was stored")));
        assert!(!store.contains("k1"));
        store.put("k1", &files(&[("a.bin", b"aaa")])).unwrap();
        assert!(store.get("k1").found().is_some());
    }

    #[test]
    fn keys_and_file_names_stay_inside_the_store() {
        let tmp = tempfile::tempdir().unwrap();
        let store = Store::new(tmp.path().join("s"), "test store", false);
        assert!(store.put("../x", &files(&[("a", b"a")])).is_err());
        assert!(store.put("k", &files(&[("../a", b"a")])).is_err());
        assert!(matches!(store.get("../x"), Lookup::Absent));
        assert!(!tmp.path().join("x").exists() && !tmp.path().join("a").exists());
    }

    #[test]
    fn replace_takes_the_place_of_a_verified_entry() {
        let tmp = tempfile::tempdir().unwrap();
        let store = Store::new(tmp.path().join("s"), "test store", false);
        store.put("k", &files(&[("a", b"old")])).unwrap();
        store.put("k", &files(&[("a", b"new")])).unwrap();
        assert_eq!(store.get("k").found().unwrap().file("a"), Some(&b"old"[..]));
        store.replace("k", &files(&[("a", b"new")])).unwrap();
        assert_eq!(store.get("k").found().unwrap().file("a"), Some(&b"new"[..]));
    }
}
