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

/// The columns of every table the benches print, which the README's performance section
/// reproduces: one definition, read by the benches when they print and by the test that checks
/// the README's tables against them (the numbers come from a run: `benches/run-all`).
pub mod tables {
    /// `--bench eom`: the engine's `q̈` beside the hand-coded one.
    pub const EOM: &[&str] = &["scene", "n", "engine q̈", "hand-coded q̈", "ratio", "raw-Lagrangian q̈", "RK4 step"];
    /// `--bench constraints`: the constrained `q̈` with its multipliers.
    pub const CONSTRAINTS: &[&str] = &[
        "scene",
        "q̈ + λ (engine)",
        "hand-coded KKT",
        "engine / hand-coded",
        "RK4 step + projection",
        "adaptive step + projection",
    ];
    /// `--bench rapier`: one step of every scene, ours and rapier's.
    pub const RAPIER: &[&str] =
        &["scene", "reduced RK4 step", "rapier impulse", "rapier multibody", "impulse f32", "multibody f32"];
    /// `--bench files`: a scene file's `q̈` against the built-in scene's.
    pub const FILES: &[&str] =
        &["scene", "built-in q̈", "built-in q̈, generic path", "file q̈", "file / built-in", "file / generic path"];
    /// `--bench implicit`, first table: one Gauss4 step and the AD Jacobian beside RK4.
    pub const IMPLICIT_STEP: &[&str] = &["scene", "RK4 step", "Gauss4 step", "Gauss4 / RK4", "AD Jacobian ∂q̈/∂(q, q̇)"];
    /// `--bench implicit`, second table: whole stiff runs.
    pub const IMPLICIT_STIFF: &[&str] = &["stiff run", "SDIRK4", "Dormand–Prince 5(4)", "Dormand–Prince / SDIRK4"];
    /// `--bench scaling`: chains of `N` links.
    pub const SCALING: &[&str] = &[
        "N",
        "reduced q̈",
        "graph q̈",
        "reduced RK4 step",
        "graph RK4 step",
        "rapier multibody step",
        "rapier impulse step",
        "RK4 / impulse",
        "graph / hand RK4",
    ];
    /// `--bench singular`: the tolerance of the simulated second of its first table.
    pub const SINGULAR_TOLERANCE: f64 = 1e-9;
    /// `--bench singular`, first table: the parallelogram chain against `N`.
    pub fn singular() -> Vec<String> {
        let run = format!("1 s at tol {SINGULAR_TOLERANCE:.0e}");
        [
            "N",
            "q̈",
            "ratio to N = 8",
            "Model::new",
            "ratio to N = 8",
            &run,
            "evaluations (steps, rejected)",
            "crank-tip error",
        ]
        .iter()
        .map(|c| c.to_string())
        .collect()
    }
    /// `--bench singular`, second table: `q̈` near the flat position.
    pub const SINGULAR_FLAT: &[&str] = &[
        "δ (rad from flat)",
        "q̈ error on the branch",
        "q̈ error after 1e-12 off and projected",
        "on the branch, 80 windows",
    ];

    /// The header and separator lines of a markdown table with `columns`.
    pub fn header<S: AsRef<str>>(columns: &[S]) -> String {
        let names: Vec<&str> = columns.iter().map(AsRef::as_ref).collect();
        format!("| {} |\n|{}", names.join(" | "), "---|".repeat(names.len()))
    }

    /// Print a table's header and separator, after a blank line.
    pub fn print_header<S: AsRef<str>>(columns: &[S]) {
        println!("\n{}", header(columns));
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        /// Every table of the README's performance section has the columns of a table a bench
        /// prints (so a number pasted from a run lands under the right heading), and each of
        /// its rows has as many cells.
        #[test]
        fn the_readme_tables_have_the_benches_columns() {
            let readme = include_str!("../../README.md");
            let start = readme.find("\n## Performance\n").expect("the README has a performance section");
            let end = readme[start + 1..].find("\n## ").map_or(readme.len(), |i| start + 1 + i);
            let section = &readme[start..end];
            let known: Vec<String> =
                [EOM, CONSTRAINTS, RAPIER, IMPLICIT_STEP, IMPLICIT_STIFF, SCALING, SINGULAR_FLAT, FILES]
                    .iter()
                    .map(|columns| header(columns))
                    .chain([header(&singular())])
                    .collect();
            let lines: Vec<&str> = section.lines().collect();
            let mut tables = 0;
            let mut i = 0;
            while i < lines.len() {
                if !lines[i].starts_with('|') {
                    i += 1;
                    continue;
                }
                let head = format!("{}\n{}", lines[i], lines.get(i + 1).copied().unwrap_or(""));
                assert!(known.contains(&head), "a README table with columns no bench prints:\n{head}");
                let cells = lines[i].matches('|').count();
                i += 2;
                while i < lines.len() && lines[i].starts_with('|') {
                    assert_eq!(lines[i].matches('|').count(), cells, "row of the wrong width: {}", lines[i]);
                    i += 1;
                }
                tables += 1;
            }
            // eom, constraints, rapier, implicit (two), scaling, singular.
            assert!(tables >= 7, "{tables} tables in the performance section");
        }
    }
}
