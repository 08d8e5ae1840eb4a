//! Nearest-name suggestions for unknown names ("did you mean `lambert`?").

use crate::error::InputError;

/// The candidate closest to `name` by edit distance, if it is close enough to be a plausible typo.
pub fn nearest<'a>(name: &str, candidates: &[&'a str]) -> Option<&'a str> {
    let name = name.to_ascii_lowercase();
    candidates
        .iter()
        .map(|c| (strsim::damerau_levenshtein(&name, c), *c))
        .filter(|(d, c)| *d <= (c.len().max(name.len()) / 2).max(2))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// "unknown shader `lambret`; valid: a, b, c; did you mean `lambert`?"
pub fn unknown_name(file: &str, key: &str, what: &str, value: &str, valid: &[&str]) -> InputError {
    let mut message = format!("unknown {what} `{value}`; valid: {}", valid.join(", "));
    if let Some(n) = nearest(value, valid) {
        message.push_str(&format!("; did you mean `{n}`?"));
    }
    InputError::at_key(file, key, message)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names_only() {
        let valid = ["lambert", "standard", "half_lambert"];
        assert_eq!(nearest("lambret", &valid), Some("lambert"));
        assert_eq!(nearest("Standrd", &valid), Some("standard"));
        assert_eq!(nearest("zzzzzzzzzz", &valid), None);
    }
}
