//! Bakes kept across runs (`<results>/.truth-cache/bakes/<key>/`), as truths are: a bake is keyed
//! by exactly what it reads — the composed tracer's source, the scene as parsed, the static
//! geometry as the lightmap's texels and the probes' positions give it, the static objects'
//! materials, the lights' values and shares, the frame's environment scale, the Lighting
//! Settings and the adapter — and stored as its raw sums (sums.bin) with a record (bake.json).
//! A folder appears whole or not at all (written beside, then renamed).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::Error;
use crate::render::truth::bake::{BakeSums, BAKE_STRIDE};

pub const BAKE_CACHE_SCHEMA: u32 = 2;

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BakeCacheRecord {
    pub schema: u32,
    pub key: String,
    pub points: usize,
    pub samples: u32,
    /// The samples the texels took (a converging bake stops at its noise target).
    pub texel_samples: u32,
    pub bounces: u32,
    /// Wall time of the bake when it was made, s.
    pub seconds: f64,
    pub adapter: String,
}

/// The hex SHA-256 of what a bake reads, given as byte strings in a fixed order.
pub fn key(parts: &[&[u8]]) -> String {
    let mut h = Sha256::new();
    h.update(BAKE_CACHE_SCHEMA.to_le_bytes());
    for p in parts {
        h.update((p.len() as u64).to_le_bytes());
        h.update(p);
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

pub struct BakeCache {
    pub dir: PathBuf,
}

impl BakeCache {
    /// The sums and record stored under `key`, if a whole bake with `points` points is.
    pub fn load(&self, key: &str, points: usize) -> Option<(BakeSums, BakeCacheRecord)> {
        let dir = self.dir.join(key);
        let record: BakeCacheRecord = serde_json::from_slice(&std::fs::read(dir.join("bake.json")).ok()?).ok()?;
        if record.schema != BAKE_CACHE_SCHEMA || record.key != key || record.points != points {
            return None;
        }
        let bytes = std::fs::read(dir.join("sums.bin")).ok()?;
        if bytes.len() != points * BAKE_STRIDE * 16 {
            return None;
        }
        let floats: Vec<f32> = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
        let sums = floats
            .chunks_exact(BAKE_STRIDE * 4)
            .map(|p| std::array::from_fn(|k| [p[4 * k], p[4 * k + 1], p[4 * k + 2], p[4 * k + 3]]))
            .collect();
        Some((sums, record))
    }

    /// Keep `sums` under `record.key`: written into a temporary folder, then renamed into place.
    pub fn store(&self, record: &BakeCacheRecord, sums: &BakeSums) -> Result<(), Error> {
        let final_dir = self.dir.join(&record.key);
        if final_dir.join("bake.json").is_file() {
            return Ok(());
        }
        let tmp = self.dir.join(format!(".{}.tmp{}", record.key, std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        std::fs::create_dir_all(&tmp).map_err(|e| Error::io_path("creating folder", &tmp, e))?;
        let bytes: Vec<u8> = sums.iter().flatten().flatten().flat_map(|v| v.to_le_bytes()).collect();
        write(&tmp.join("sums.bin"), &bytes)?;
        crate::fsutil::write_json(&tmp.join("bake.json"), record)?;
        match std::fs::rename(&tmp, &final_dir) {
            Ok(()) => Ok(()),
            // Another worker or run stored the same key first: theirs is as good.
            Err(_) if final_dir.join("bake.json").is_file() => {
                let _ = std::fs::remove_dir_all(&tmp);
                Ok(())
            }
            Err(e) => Err(Error::io_path("renaming into place", &final_dir, e)),
        }
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    std::fs::write(path, bytes).map_err(|e| Error::io_path("writing", path, e))
}
