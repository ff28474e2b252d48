//! The last line of defence around third-party readers: a panic inside them becomes an error,
//! and prints nothing.
//!
//! tress checks what `openusd` and `gltf` would trip on before calling them, so no input is
//! known to panic inside them. Should one still do, [`quietly`] catches it, and the user sees the
//! reader's one error line only: not Rust's `thread 'main' panicked at …` message, nor a
//! backtrace when `RUST_BACKTRACE` is set.
//!
//! A panic hook is process-wide, so [`install`] (called by [`quietly`] on first use) wraps the
//! hook in place at that moment: inside a [`quietly`] call on the same thread the wrapper stays
//! silent; everywhere else it hands the panic to the hook it replaced, so an application's own hook
//! keeps working. An application that sets its own hook after tress's first read replaces the
//! wrapper, and a guarded panic then reaches that hook as any panic would. Every panic the wrapper
//! silenced is counted ([`silenced`]), so tests and fuzzers can tell a caught panic from none.
//!
//! ```
//! let r = tress_hair::panic_guard::quietly(|| -> u32 { panic!("inside a reader") });
//! assert_eq!(r, None);
//! assert!(tress_hair::panic_guard::silenced() >= 1);
//! ```

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;
use std::sync::atomic::{AtomicUsize, Ordering};

thread_local! {
    /// How many [`quietly`] calls are running on this thread.
    static DEPTH: Cell<usize> = const { Cell::new(0) };
}

static INSTALL: Once = Once::new();
static SILENCED: AtomicUsize = AtomicUsize::new(0);

/// Wrap the current panic hook (once per process) so panics inside [`quietly`] print nothing.
/// [`quietly`] calls this itself; call it earlier to put a hook of your own outside the wrapper
/// (one that then sees every panic, silenced or not).
pub fn install() {
    INSTALL.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if DEPTH.with(Cell::get) > 0 {
                SILENCED.fetch_add(1, Ordering::Relaxed);
            } else {
                previous(info);
            }
        }));
    });
}

/// How many panics [`quietly`] has silenced in this process.
pub fn silenced() -> usize {
    SILENCED.load(Ordering::Relaxed)
}

/// Run `f`; a panic inside it gives `None` and prints nothing.
pub fn quietly<T>(f: impl FnOnce() -> T) -> Option<T> {
    install();
    DEPTH.with(|d| d.set(d.get() + 1));
    let result = panic::catch_unwind(AssertUnwindSafe(f));
    DEPTH.with(|d| d.set(d.get() - 1));
    result.ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_inside_is_none_and_counted_and_outside_values_pass() {
        let before = silenced();
        assert_eq!(quietly(|| 7), Some(7));
        assert_eq!(quietly(|| -> i32 { panic!("boom") }), None);
        // Nested guards unwind to the innermost.
        assert_eq!(
            quietly(|| quietly(|| -> i32 { panic!("inner") }).unwrap_or(3)),
            Some(3)
        );
        assert!(silenced() >= before + 2);
        // The depth is back to zero afterwards.
        assert_eq!(DEPTH.with(Cell::get), 0);
    }
}
