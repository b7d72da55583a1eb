//! The Python package (crates/python) from Python: `scripts/python-check` builds its extension
//! module in the test profile, puts it in place in the package and runs the package's pytest
//! suite (crates/python/tests) in the project's `.venv`, which checks every
//! binding against this build of the `lagrange` command line (`LAGRANGE_BIN`) on the same runs.
//! The script installs what it needs the first time; a machine where it cannot fails here with
//! the script's message, never skips.

use std::path::Path;
use std::process::Command;

#[test]
fn python_package_passes_its_tests() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let output = Command::new(root.join("scripts/python-check"))
        .env("LAGRANGE_BIN", env!("CARGO_BIN_EXE_lagrange"))
        .output()
        .expect("scripts/python-check runs");
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "the Python tests failed:\n{stdout}\n{stderr}");
    let summary = stdout.lines().rev().find(|l| l.contains(" passed")).unwrap_or_default();
    assert!(!summary.contains("skipped") && !summary.contains("failed"), "every Python test ran and passed:\n{stdout}");
}
