//! Truths kept across cells and runs: a truth is keyed by exactly what it reads (`key`), so that
//! every cell whose truth reads the same shares one — the three shaders of one preset and
//! pipeline share a physical truth — and stored in a folder per key: truth.exr (mean RGB, standard
//! error in A), roles.png (the first surface's role in R) and truth.json (what it reached).
//! A folder appears whole or not at all (written beside, then renamed).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::cells::Cell;
use crate::error::Error;
use crate::images::encode;
use crate::render::truth::Truth;
use crate::spec::matrix::Matrix;

pub const TRUTH_CACHE_SCHEMA: u32 = 2;

/// The default cache: beside the run folders (results/.truth-cache for results/<run>).
pub fn default_dir(run_dir: &Path) -> PathBuf {
    run_dir.parent().unwrap_or(Path::new(".")).join(".truth-cache")
}

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
    dir: PathBuf,
    /// A folder of this run's own, removed when the run ends (`--no-cache`).
    ephemeral: bool,
}

impl TruthCache {
    pub fn new(dir: PathBuf) -> TruthCache {
        TruthCache { dir, ephemeral: false }
    }

    /// A cache that holds this run's truths only (so that cells whose truths read the same still
    /// share one) in a temporary folder removed with it: what `--no-cache` runs use.
    pub fn ephemeral() -> TruthCache {
        static RUNS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("shadematrix-truths-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        TruthCache { dir, ephemeral: true }
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
        crate::spec::matrix::hex(&Sha256::digest(text.to_string().as_bytes()))
    }

    /// The truth stored under `key`, if a whole one is (`kind`: which truth the key was made for).
    pub fn load(&self, key: &str, kind: crate::render::truth::TruthKind) -> Option<Truth> {
        let dir = self.dir.join(key);
        let record: TruthCacheRecord = serde_json::from_slice(&std::fs::read(dir.join("truth.json")).ok()?).ok()?;
        if record.schema != TRUTH_CACHE_SCHEMA || record.key != key {
            return None;
        }
        let (w, h, px) = encode::read_exr(&dir.join("truth.exr")).ok()?;
        let roles = image::open(dir.join("roles.png")).ok()?.to_rgba8();
        if (w, h) != (record.width, record.height) || roles.dimensions() != (w, h) {
            return None;
        }
        Some(Truth {
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
        })
    }

    /// Keep `truth` under `key`: written into a temporary folder, then renamed into place.
    pub fn store(&self, key: &str, truth: &Truth, adapter: &str) -> Result<(), Error> {
        let final_dir = self.dir.join(key);
        if final_dir.join("truth.json").is_file() {
            return Ok(());
        }
        let tmp = self.dir.join(format!(".{key}.tmp{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        std::fs::create_dir_all(&tmp).map_err(|e| Error::io_path("creating folder", &tmp, e))?;
        let px: Vec<f32> =
            truth.mean.iter().zip(&truth.std_error).flat_map(|(m, &se)| [m[0], m[1], m[2], se]).collect();
        std::fs::write(tmp.join("truth.exr"), encode::exr_bytes(truth.width, truth.height, &px)?)
            .map_err(|e| Error::io_path("writing", &tmp.join("truth.exr"), e))?;
        let roles: Vec<u8> = truth.roles.iter().flat_map(|&r| [r, 0, 0, 255]).collect();
        std::fs::write(tmp.join("roles.png"), encode::png_bytes(truth.width, truth.height, &roles)?)
            .map_err(|e| Error::io_path("writing", &tmp.join("roles.png"), e))?;
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
        crate::fsutil::write_json(&tmp.join("truth.json"), &record)?;
        match std::fs::rename(&tmp, &final_dir) {
            Ok(()) => Ok(()),
            // Another worker or run stored the same key first: theirs is as good.
            Err(_) if final_dir.join("truth.json").is_file() => {
                let _ = std::fs::remove_dir_all(&tmp);
                Ok(())
            }
            Err(e) => Err(Error::io_path("renaming into place", &final_dir, e)),
        }
    }
}

impl Drop for TruthCache {
    fn drop(&mut self) {
        if self.ephemeral {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}
