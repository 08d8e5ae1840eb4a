//! A backstop for third-party parsers that panic on malformed input instead of returning an error
//! (fuzzing found gltf-json 1.4 indexing out of bounds while validating a primitive whose attribute
//! names a missing accessor). The panic becomes bad input naming the file; its message is kept
//! and the default hook's report is silenced for that call on that thread only, so a user sees one
//! clear error, never a backtrace. Written by hand: `std::panic::catch_unwind` is the mechanism, and
//! no crate adds a per-thread quiet hook.

use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    static QUIET: Cell<bool> = const { Cell::new(false) };
}

fn install_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(Cell::get) {
                previous(info)
            }
        }));
    });
}

/// Run `f`; a panic inside it comes back as `Err` with the panic's message.
pub fn without_panics<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    install_hook();
    let was = QUIET.with(|q| q.replace(true));
    let result = catch_unwind(AssertUnwindSafe(f));
    QUIET.with(|q| q.set(was));
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".into())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_its_message_and_values_pass_through() {
        assert_eq!(without_panics(|| 7), Ok(7));
        let v: Vec<u32> = vec![1, 2, 3];
        let i = v.len() + 65533;
        let err = without_panics(|| v[i]).unwrap_err();
        assert!(err.contains("index out of bounds"), "{err}");
    }
}
