//! Reading TOML input with errors that name the file, line and column, and the nearest valid
//! name for unknown keys and variants.

use serde::de::DeserializeOwned;
use std::path::Path;

use crate::error::{Error, InputError};
use crate::input::names::nearest;
use crate::input::read;

/// Parse `text` (from `origin`, a file name for messages) into `T`.
pub fn parse_toml<T: DeserializeOwned>(origin: &str, text: &str) -> Result<T, InputError> {
    toml::from_str::<T>(text).map_err(|e| {
        let location = e.span().map(|s| line_col(text, s.start));
        InputError { file: origin.to_string(), location, key: None, message: with_suggestion(e.message()) }
    })
}

/// Read and parse a TOML file; a missing or unreadable file is bad input.
pub fn read_toml<T: DeserializeOwned>(path: &Path) -> Result<T, Error> {
    let shown = path.display().to_string();
    let text = read_text(path)?;
    Ok(parse_toml(&shown, &text)?)
}

/// The text of the input file at `path` (`input::read`: a regular file, bounded), or bad input
/// naming the file.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    read::read_text(path, read::TEXT).map_err(|e| InputError::new(path.display().to_string(), e.to_string()))
}

/// The bytes of the regular file at `path` and its extension in lower case, refused past `limit`.
pub fn read_bounded(path: &Path, limit: read::Limit) -> Result<(Vec<u8>, String), String> {
    let bytes = read::read(path, limit).map_err(|e| e.to_string())?;
    Ok((bytes, path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase()))
}

/// A FIFO or a device would block or read without end: only regular files are input (an absent
/// file passes here, for the caller to say so with its key).
pub fn regular_file(path: &Path) -> Result<(), InputError> {
    match read::is_regular_file(path) {
        Err(read::ReadError::NotRegular) => {
            Err(InputError::new(path.display().to_string(), read::ReadError::NotRegular.to_string()))
        }
        _ => Ok(()),
    }
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map(|l| l.chars().count()).unwrap_or(0) + 1;
    (line, col)
}

/// serde reports "unknown field `x`, expected one of `a`, `b`"; add the nearest of those names.
fn with_suggestion(message: &str) -> String {
    let message = message.trim_end().to_string();
    let Some(rest) = message.strip_prefix("unknown field `").or_else(|| message.strip_prefix("unknown variant `"))
    else {
        return message;
    };
    let Some((given, expected)) = rest.split_once('`') else { return message };
    let valid: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
    match nearest(given, &valid) {
        Some(n) => format!("{message}; did you mean `{n}`?"),
        None => message,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Small {
        color: Option<[f64; 3]>,
        intensity: Option<f64>,
    }

    #[test]
    fn syntax_error_has_line_and_column() {
        let err = parse_toml::<Small>("x.toml", "intensity = 1.0\ncolor = [1, 2\n").unwrap_err();
        assert_eq!(err.file, "x.toml");
        let (line, _) = err.location.expect("location");
        assert_eq!(line, 2, "{err}");
    }

    #[test]
    fn unknown_key_suggests_nearest() {
        let err = parse_toml::<Small>("x.toml", "colr = [1, 1, 1]\n").unwrap_err();
        assert!(err.message.contains("did you mean `color`?"), "{err}");
        assert_eq!(err.location.map(|l| l.0), Some(1));
    }
}
