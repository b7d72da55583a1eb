//! The animation pages in a real browser: `scripts/browser-check` (headless Chromium driven by
//! Playwright from Python, tests/browser/test_animation.py) against this build of `lagrange`.
//! The script installs what it needs the first time (Debian's chromium, a `.venv`); a machine
//! where it cannot fails here with the script's message, never skips.

use std::path::Path;
use std::process::Command;

#[test]
fn animation_pages_play_in_headless_chromium() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let output = Command::new(root.join("scripts/browser-check"))
        .env("LAGRANGE_BIN", env!("CARGO_BIN_EXE_lagrange"))
        .output()
        .expect("scripts/browser-check runs");
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "the browser check failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("9 passed"), "every page checked:\n{stdout}");
}
