//! A panic caught by `tress_hair::panic_guard::quietly` prints nothing, even with
//! `RUST_BACKTRACE=1`, while a panic outside it still reaches the hook that was there before.
//!
//! Panic messages go to the process's stderr, which a test cannot capture in-process, so this
//! test (`harness = false`) runs itself again as a child process that does the panicking, and
//! reads the child's stderr.

use std::process::Command;

const CHILD: &str = "TRESS_PANIC_GUARD_CHILD";

/// In the child: a guarded panic, then (for `"outside"`) an unguarded one, caught.
fn child(what: &str) {
    let r = tress_hair::panic_guard::quietly(|| -> u8 { panic!("a reader tripped") });
    assert_eq!(r, None);
    eprintln!("guarded call returned");
    if what == "outside" {
        let r = std::panic::catch_unwind(|| -> u8 { panic!("outside the guard") });
        assert!(r.is_err());
    }
}

/// Run this binary as a child doing `what`, with `RUST_BACKTRACE=1`; its stderr.
fn run_child(what: &str) -> String {
    let out = Command::new(std::env::current_exe().unwrap())
        .env(CHILD, what)
        .env("RUST_BACKTRACE", "1")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "the child failed: {stderr}");
    assert!(
        stderr.contains("guarded call returned"),
        "the child did not run: {stderr}"
    );
    stderr
}

fn main() {
    if let Ok(what) = std::env::var(CHILD) {
        child(&what);
        return;
    }
    // A guarded panic prints nothing, with RUST_BACKTRACE set.
    let stderr = run_child("guarded");
    for printed in ["panicked", "a reader tripped", "stack backtrace"] {
        assert!(
            !stderr.contains(printed),
            "a guarded panic printed {printed:?}: {stderr}"
        );
    }
    // A panic outside the guard still reaches the previous (default) hook, after a guarded one.
    let stderr = run_child("outside");
    assert!(stderr.contains("outside the guard"), "{stderr}");
    assert!(stderr.contains("stack backtrace"), "{stderr}");
    assert!(!stderr.contains("a reader tripped"), "{stderr}");
    println!("panic_guard: 2 checks passed");
}
