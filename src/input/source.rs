//! Reading TOML input with errors that name the file, line and column, and the nearest valid
//! name for unknown keys and variants.

use serde::de::DeserializeOwned;
use std::path::Path;

use crate::error::{Error, InputError};
use crate::input::names::nearest;

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
    regular_file(path)?;
    let text = std::fs::read_to_string(path).map_err(|e| InputError::new(&shown, format!("cannot read file: {e}")))?;
    Ok(parse_toml(&shown, &text)?)
}

/// A FIFO or a device would block or read without end: only regular files are input.
/// The bytes of the regular file at `path` and its extension in lower case, refused when over
/// `max` bytes (`what` names the kind of file in the message).
pub fn read_bounded(path: &Path, max: u64, what: &str) -> Result<(Vec<u8>, String), String> {
    regular_file(path).map_err(|e| e.message)?;
    let size = std::fs::metadata(path).map_err(|e| format!("cannot read: {e}"))?.len();
    if size > max {
        return Err(format!("{size} bytes: {what} may have at most {max}"));
    }
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read: {e}"))?;
    Ok((bytes, path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase()))
}

pub fn regular_file(path: &Path) -> Result<(), InputError> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(InputError::new(
            path.display().to_string(),
            "not a regular file (a folder, FIFO or device is not read)",
        )),
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
