//! Shared by the benches: where criterion writes its estimates, and reading them back so that
//! each bench prints its ratios from the same run.
//!
//! Benches: `cargo bench -p lagrange-benches --bench eom` (engine vs hand-coded EOM, RK4 step),
//! `--bench rapier` (one rapier step of every scene), `--bench scaling` (chains of 2 … 64 links:
//! our step against rapier's), `--bench implicit` (Gauss4 step and AD Jacobian beside RK4; whole
//! stiff runs of SDIRK4 against Dormand–Prince).

use std::path::{Path, PathBuf};

/// Mean time (ns) of a finished benchmark `group/bench`, from criterion's `estimates.json`.
pub fn mean_ns(group: &str, bench: &str) -> Option<f64> {
    read_mean(&criterion_root(), group, bench)
}

fn read_mean(root: &Path, group: &str, bench: &str) -> Option<f64> {
    let text = std::fs::read_to_string(root.join(group).join(bench).join("new").join("estimates.json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    json["mean"]["point_estimate"].as_f64()
}

/// Criterion writes to `$CARGO_TARGET_DIR/criterion`, else `target/criterion` of the workspace.
pub fn criterion_root() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join("target"));
    target.join("criterion")
}

/// `1234.5 ns` as `1.23 µs`, etc.
pub fn format_ns(ns: f64) -> String {
    if ns >= 1e6 {
        format!("{:.2} ms", ns / 1e6)
    } else if ns >= 1e3 {
        format!("{:.2} µs", ns / 1e3)
    } else {
        format!("{ns:.1} ns")
    }
}
