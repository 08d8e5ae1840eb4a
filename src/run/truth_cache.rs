//! Truths kept across cells and runs: a truth is keyed by exactly what it reads (`key`), so that
//! every cell whose truth reads the same shares one — the three shaders of one preset and
//! pipeline share a physical truth — and stored in a folder per key: truth.exr (mean RGB, standard
//! error in A), roles.png (the first surface's role in R) and truth.json (what it reached).
//! Entries live in the verified store (`store`): whole or not at all, read-only, every file's
//! size and SHA-256 checked when read; a broken entry is dropped and traced again.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::cells::Cell;
use crate::declarations::matrix::Matrix;
use crate::error::Error;
use crate::images::encode;
use crate::render::truth::Truth;
use crate::store::{Entry, Store};

/// 3: entries in the verified store (`store`), every file checked when read.
pub const TRUTH_CACHE_SCHEMA: u32 = 3;

/// The default cache: beside the run folders (results/.truth-cache for results/<run>).
pub fn default_dir(run_dir: &Path) -> PathBuf {
    run_dir.parent().unwrap_or(Path::new(".")).join(".truth-cache")
}

/// A `--no-cache` run's truths: a private folder inside the run (`.truth-cache.tmpPID`, a
/// temporary name `--resume` clears), so a killed run leaves nothing behind outside its folder.
pub fn private_dir(run_dir: &Path) -> PathBuf {
    crate::store::temp_name(&run_dir.join("truth-cache"), "tmp")
}

const EXR_FILE: &str = "truth.exr";
const ROLES_FILE: &str = "roles.png";
const RECORD_FILE: &str = "truth.json";

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TruthCacheRecord {
    pub schema: u32,
    pub key: String,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub bounces: u32,
    pub subject_noise: Option<f64>,
    pub seconds: f64,
    pub adapter: String,
}

pub struct TruthCache {
    store: Store,
    /// A folder of this run's own, removed when the run ends (`--no-cache`).
    ephemeral: bool,
}

impl TruthCache {
    pub fn new(dir: PathBuf) -> TruthCache {
        TruthCache { store: Store::new(dir, "truth cache", false), ephemeral: false }
    }

    /// A cache that holds this run's truths only (so that cells whose truths read the same still
    /// share one) in `dir` (`private_dir`), removed with it: what `--no-cache` runs use.
    pub fn ephemeral(dir: PathBuf) -> TruthCache {
        let _ = std::fs::remove_dir_all(&dir);
        TruthCache { store: Store::new(dir, "truth cache", false), ephemeral: true }
    }

    /// The key of `cell`'s truth: what its tracer reads (`Renderer::truth_reads`: the cell's
    /// camera, lights, materials and settings as traced), the composition as parsed with the
    /// bytes of its mesh files, the models' sources where it reads them, the tool, and the adapter
    /// when the GPU traces it. Cells whose truths read the same get the same key and share it.
    pub fn key(matrix: &Matrix, cell: &Cell, reads: &serde_json::Value, adapter: &str) -> String {
        let on_gpu = reads.get("backend").and_then(|b| b.as_str()) != Some("cpu");
        let models = reads.get("models").is_some_and(|m| !m.is_null());
        let text = serde_json::json!({
            "schema": TRUTH_CACHE_SCHEMA,
            "tool": super::cell_key::tool_fingerprint(),
            "scene": matrix.compositions[cell.composition_index],
            "mesh_files": super::cell_key::mesh_digests(matrix, cell),
            "models": models.then(|| super::cell_key::model_sources(matrix, cell)),
            "reads": reads,
            "adapter": on_gpu.then_some(adapter),
        });
        crate::declarations::matrix::hex(&Sha256::digest(text.to_string().as_bytes()))
    }

    /// The digest of the entry under `key`, from its manifest: what a cached cell's record is
    /// checked against (the files are verified when a cell traces with them).
    pub fn digest(&self, key: &str) -> Option<String> {
        self.store.digest(key)
    }

    /// The truth stored under `key`, if a whole one is (`kind`: which truth the key was made for).
    /// An entry whose files verify but do not decode into the truth its record describes is
    /// dropped, so it is traced and stored again rather than skipped on every run.
    pub fn load(&self, key: &str, kind: crate::render::truth::TruthKind) -> Option<Truth> {
        self.store.get_as(key, |entry| decode(&entry, key, kind))
    }

    /// Keep `truth` under `key` (a cache that cannot be written warns once); the digest of the
    /// entry under `key`, when there is one.
    pub fn store(&self, key: &str, truth: &Truth, adapter: &str) -> Result<Option<String>, Error> {
        let px: Vec<f32> =
            truth.mean.iter().zip(&truth.std_error).flat_map(|(m, &se)| [m[0], m[1], m[2], se]).collect();
        let roles: Vec<u8> = truth.roles.iter().flat_map(|&r| [r, 0, 0, 255]).collect();
        let record = TruthCacheRecord {
            schema: TRUTH_CACHE_SCHEMA,
            key: key.to_string(),
            width: truth.width,
            height: truth.height,
            spp: truth.spp,
            bounces: truth.bounces,
            subject_noise: truth.subject_noise,
            seconds: truth.seconds,
            adapter: adapter.to_string(),
        };
        let record = serde_json::to_vec_pretty(&record).map_err(|e| Error::encode("encoding truth.json", e))?;
        let files = vec![
            (EXR_FILE.to_string(), encode::exr_bytes(truth.width, truth.height, &px)?),
            (ROLES_FILE.to_string(), encode::png_bytes(truth.width, truth.height, &roles)?),
            (RECORD_FILE.to_string(), record),
        ];
        Ok(self.store.keep(key, &files, false))
    }
}

/// The truth in a verified entry, checked against its record.
fn decode(entry: &Entry, key: &str, kind: crate::render::truth::TruthKind) -> Result<Truth, String> {
    let file = |name: &str| entry.file(name).ok_or_else(|| format!("it holds no {name}"));
    let record: TruthCacheRecord =
        serde_json::from_slice(file(RECORD_FILE)?).map_err(|e| format!("its {RECORD_FILE} does not parse: {e}"))?;
    if record.schema != TRUTH_CACHE_SCHEMA || record.key != key {
        return Err(format!("its {RECORD_FILE} is of schema {} and key {}", record.schema, record.key));
    }
    let (w, h, px) = encode::exr_from_bytes(file(EXR_FILE)?).map_err(|e| format!("{EXR_FILE}: {e}"))?;
    let roles = image::load_from_memory_with_format(file(ROLES_FILE)?, image::ImageFormat::Png)
        .map_err(|e| format!("{ROLES_FILE}: {e}"))?
        .to_rgba8();
    if (w, h) != (record.width, record.height) || roles.dimensions() != (w, h) {
        return Err(format!("its images are not the {}×{} its record says", record.width, record.height));
    }
    Ok(Truth {
        kind,
        width: w,
        height: h,
        mean: px.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect(),
        std_error: px.chunks_exact(4).map(|p| p[3]).collect(),
        roles: roles.pixels().map(|p| p[0]).collect(),
        spp: record.spp,
        bounces: record.bounces,
        subject_noise: record.subject_noise,
        seconds: record.seconds,
        cached: true,
        stored: Some((key.to_string(), entry.digest.clone())),
    })
}

impl Drop for TruthCache {
    fn drop(&mut self) {
        if self.ephemeral {
            let _ = std::fs::remove_dir_all(self.store.dir());
        }
    }
}
