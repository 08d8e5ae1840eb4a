//! Bakes kept across runs (`<results>/.truth-cache/bakes/<key>/`), as truths are: a bake is keyed
//! by exactly what it reads — the composed tracer's source, the scene as parsed, the static
//! geometry as the lightmap's texels and the probes' positions give it, the static objects'
//! materials, the lights' values and shares, the frame's environment scale, the Lighting
//! Settings and the adapter — and stored as its raw sums (sums.bin) with a record (bake.json).
//! Entries live in the verified store (`store`): whole or not at all, read-only, every file's
//! size and SHA-256 checked when read; a broken entry is dropped and baked again.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::Error;
use crate::render::truth::bake::{BakeSums, BAKE_STRIDE};
use crate::store::{Entry, Store};

/// 3: entries in the verified store (`store`), every file checked when read.
pub const BAKE_CACHE_SCHEMA: u32 = 3;

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
    store: Store,
}

const SUMS_FILE: &str = "sums.bin";
const RECORD_FILE: &str = "bake.json";

impl BakeCache {
    pub fn new(dir: PathBuf) -> BakeCache {
        BakeCache { store: Store::new(dir, "bake cache", false) }
    }

    /// The sums and record stored under `key`, if a whole bake with `points` points is. An entry
    /// whose files verify but do not hold such a bake is dropped, so it is baked and stored again.
    pub fn load(&self, key: &str, points: usize) -> Option<(BakeSums, BakeCacheRecord)> {
        self.store.get_as(key, |entry| decode(&entry, key, points))
    }

    /// Keep `sums` under `record.key` (a cache that cannot be written warns once).
    pub fn store(&self, record: &BakeCacheRecord, sums: &BakeSums) -> Result<(), Error> {
        let bytes: Vec<u8> = sums.iter().flatten().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let json = serde_json::to_vec_pretty(record).map_err(|e| Error::encode("encoding bake.json", e))?;
        let _ = self.store.keep(&record.key, &[(SUMS_FILE.to_string(), bytes), (RECORD_FILE.to_string(), json)], false);
        Ok(())
    }
}

/// The bake in a verified entry, checked against its record and the points asked for.
fn decode(entry: &Entry, key: &str, points: usize) -> Result<(BakeSums, BakeCacheRecord), String> {
    let file = |name: &str| entry.file(name).ok_or_else(|| format!("it holds no {name}"));
    let record: BakeCacheRecord =
        serde_json::from_slice(file(RECORD_FILE)?).map_err(|e| format!("its {RECORD_FILE} does not parse: {e}"))?;
    if record.schema != BAKE_CACHE_SCHEMA || record.key != key || record.points != points {
        return Err(format!(
            "its {RECORD_FILE} is of schema {}, key {} and {} points ({points} asked for)",
            record.schema, record.key, record.points
        ));
    }
    let bytes = file(SUMS_FILE)?;
    if bytes.len() != points * BAKE_STRIDE * 16 {
        return Err(format!("{SUMS_FILE} is {} bytes, not {}", bytes.len(), points * BAKE_STRIDE * 16));
    }
    let floats: Vec<f32> = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    let sums = floats
        .chunks_exact(BAKE_STRIDE * 4)
        .map(|p| std::array::from_fn(|k| [p[4 * k], p[4 * k + 1], p[4 * k + 2], p[4 * k + 3]]))
        .collect();
    Ok((sums, record))
}
