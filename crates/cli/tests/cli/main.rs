//! The `lagrange` command line as a user runs it, one module per surface; with the browser check
//! of the animation pages and the Python package's pytest suite, which run against this build of
//! the command. One test binary (`cargo test -p lagrange-cli --test cli -- MODULE::` runs one
//! module).

mod browser;
mod commands;
mod files;
mod outputs;
mod python;
mod report;
mod robustness;

use std::process::{Command, Output};

/// Run this build's `lagrange` with `args`.
fn lagrange(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lagrange")).args(args).output().expect("the binary runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A failing command: non-zero exit, one line on stderr that mentions `needle`.
fn assert_one_line_error(args: &[&str], needle: &str) {
    let output = lagrange(args);
    let err = stderr(&output);
    assert!(!output.status.success(), "{args:?} succeeded");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: not one line: {err}");
    assert!(err.contains(needle), "{args:?}: `{err}` does not mention `{needle}`");
}
