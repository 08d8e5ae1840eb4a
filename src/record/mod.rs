//! Records on disk: one `CellRecord` per cell (`cells/<id>/cell.json`) and one `RunRecord` per run
//! (`run.json`), typed and versioned. They are the only way those files are written and read —
//! by `run`, `report`, `check` and `list` — so a renamed field is a compile error, not a blank
//! column. A record of another schema version is refused with both versions named.

pub mod bench;
pub mod cell;
pub mod layout;
pub mod run;
mod versioned;

pub use cell::{CellRecord, CELL_SCHEMA};
pub use layout::{RunDir, RunLock, CELL_FILE, REFERENCE_PNG, RUN_FILE, TRUTH_NOISE_PNG};
pub use run::{RunRecord, RUN_SCHEMA};
pub use versioned::{read_record, RecordError};

use serde::{Deserialize, Serialize};

/// A value, or the reason it could not be had. Never a made-up value in its place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Maybe<T> {
    Value(T),
    Missing { missing: String },
}

impl<T> Maybe<T> {
    pub fn missing(why: impl Into<String>) -> Self {
        Maybe::Missing { missing: why.into() }
    }

    pub fn value(&self) -> Option<&T> {
        match self {
            Maybe::Value(v) => Some(v),
            Maybe::Missing { .. } => None,
        }
    }

    pub fn why_missing(&self) -> Option<&str> {
        match self {
            Maybe::Value(_) => None,
            Maybe::Missing { missing } => Some(missing),
        }
    }
}
