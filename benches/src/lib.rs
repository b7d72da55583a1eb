//! Shared by the benches: where criterion writes its estimates, and reading them back so that
//! each bench prints its ratios from the same run.
//!
//! Benches: `cargo bench -p lagrange-benches --bench eom` (engine vs hand-coded EOM, RK4 step),
//! `--bench rapier` (one rapier step of every scene), `--bench scaling` (chains of 2 … 64 links:
//! our step against rapier's), `--bench implicit` (Gauss4 step and AD Jacobian beside RK4; whole
//! stiff runs of SDIRK4 against Dormand–Prince).

use criterion::measurement::WallTime;
use criterion::{BatchSize, BenchmarkGroup, Criterion};
use lagrange::{Error, State};
use lagrange_maximal::MaximalSimulation;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Criterion as every bench runs it: 0.3 s warm-up, 1 s of measurement, `samples` samples,
/// then the options of the command line.
pub fn criterion(samples: usize) -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(samples)
        .configure_from_args()
}

/// Bench one integrator step as `name`: every timed call advances a fresh copy of `state`, made
/// outside the timing.
pub fn bench_step(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    state: &State,
    mut step: impl FnMut(&mut State) -> Result<(), Error>,
) {
    group.bench_function(name, |b| {
        b.iter_batched_ref(|| state.clone(), |s| step(s).map(|_| s.q[0]), BatchSize::SmallInput)
    });
}

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

/// Bench one step `dt` of a maximal-coordinate simulation as `name`: every timed call advances it
/// by `dt` from where the last one stopped.
pub fn bench_advance(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    mut simulation: Box<dyn MaximalSimulation>,
    dt: f64,
) {
    let mut t = 0.0;
    group.bench_function(name, |b| {
        b.iter(|| {
            t += dt;
            simulation.advance_to(black_box(t)).expect("steps");
        })
    });
}
