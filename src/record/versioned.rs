//! Reading a versioned record: the schema number is checked before the body is parsed, so a file
//! of another version gets a message naming both versions rather than a field-level parse error.

use serde::de::DeserializeOwned;
use serde::Deserialize;
use std::path::Path;

use crate::error::{Error, InputError};

#[derive(Deserialize)]
struct Head {
    /// Records written before versioning (shadematrix ≤ 0.1 without a `schema` key) are version 1.
    #[serde(default = "first_version")]
    schema: u32,
}

fn first_version() -> u32 {
    1
}

/// Why a record could not be read.
#[derive(Debug)]
pub enum RecordError {
    /// No such file: the cell or run never finished writing it.
    Absent,
    OtherVersion {
        found: u32,
        expected: u32,
    },
    Invalid(String),
}

impl RecordError {
    pub fn into_error(self, path: &Path, what: &str) -> Error {
        let shown = path.display().to_string();
        match self {
            RecordError::Absent => InputError::new(shown, format!("no {what} here")).into(),
            RecordError::OtherVersion { found, expected } => InputError::new(
                shown,
                format!(
                    "{what} schema version {found}; this shadematrix {} reads version {expected}: re-run the \
                     matrix (or `run --resume`, which re-renders cells whose records are stale)",
                    env!("CARGO_PKG_VERSION")
                ),
            )
            .into(),
            RecordError::Invalid(e) => InputError::new(shown, format!("invalid {what}: {e}")).into(),
        }
    }
}

/// The text of the record at `path` (`input::read`: a regular file, bounded).
pub fn record_text(path: &Path) -> Result<String, RecordError> {
    match crate::input::read::read_text(path, crate::input::read::RECORD) {
        Ok(t) => Ok(t),
        Err(crate::input::read::ReadError::NotFound) => Err(RecordError::Absent),
        Err(e) => Err(RecordError::Invalid(e.to_string())),
    }
}

/// Read a record of schema `expected` from `path`.
pub fn read_record<T: DeserializeOwned>(path: &Path, expected: u32) -> Result<T, RecordError> {
    let text = record_text(path)?;
    let head: Head = serde_json::from_str(&text).map_err(|e| RecordError::Invalid(e.to_string()))?;
    if head.schema != expected {
        return Err(RecordError::OtherVersion { found: head.schema, expected });
    }
    serde_json::from_str(&text).map_err(|e| RecordError::Invalid(e.to_string()))
}
