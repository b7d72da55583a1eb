//! Cost against the size of a mechanism with many loops: the parallelogram chain of `N`
//! windows (`2N + 1` coordinates, `2N` loop rows), written as it is read, for
//! `N = 2, 8, 20, 40, 80` — one constrained `q̈` at a state off the flat position, building the
//! model (`Model::new`: structure, probes, sparsity), and one simulated second with
//! Dormand–Prince at tolerance 1e-9 from the scene's default state, whose error against the
//! exact solution (Jacobi elliptic functions) is printed beside it.
//!
//! `cargo bench -p lagrange-benches --bench singular` measures, then prints the table of this
//! run's times and their ratios to `N = 8` (the target: `q̈` at `N = 80` within 10× of
//! `N = 8`).

use lagrange::{Method, Model, Output, Tolerances};
use lagrange_benches::{criterion, format_ns, mean_ns};
use lagrange_scenes::{ParallelogramChain, SceneType};
use std::hint::black_box;

const SIZES: [usize; 5] = [2, 8, 20, 40, 80];

/// Tolerance of the simulated second.
const TOLERANCE: f64 = 1e-9;

fn chain(windows: usize) -> ParallelogramChain {
    ParallelogramChain::new(windows, 9.81, 8.0).expect("valid")
}

fn main() {
    let mut criterion = criterion(20);
    let mut errors = Vec::new();
    for windows in SIZES {
        let scene = chain(windows);
        let state = scene.state_at(0.0, -1.2, 8.0);
        let start = scene.default_state();
        let model = Model::new(scene.clone()).expect("valid");
        let mut group = criterion.benchmark_group(format!("parallelogram_chain_{windows}"));
        let mut ws = model.workspace();
        group.bench_function("qddot", |b| {
            b.iter(|| {
                black_box(
                    lagrange::accelerations(&model, &mut ws, 0.0, black_box(&state.q), black_box(&state.qdot))
                        .map(|a| a[0]),
                )
            })
        });
        group.bench_function("model_new", |b| {
            b.iter(|| black_box(Model::new(black_box(scene.clone())).map(|m| m.dof())))
        });
        let method = Method::Adaptive { tol: Tolerances::uniform(TOLERANCE) };
        group.bench_function("one_simulated_second", |b| {
            b.iter(|| black_box(lagrange::simulate(&model, &start, 1.0, method, &Output::Ends).map(|r| r.len())))
        });
        group.finish();
        let run = lagrange::simulate(&model, &start, 1.0, method, &Output::Ends).expect("runs");
        let exact = scene.exact_solution(&start, 1.0).expect("on the branch");
        let end = run.q(run.len() - 1)[0];
        let tip = ((end.cos() - exact.q[0].cos()).powi(2) + (end.sin() - exact.q[0].sin()).powi(2)).sqrt();
        errors.push(tip);
    }
    criterion.final_summary();
    println!(
        "\n| N | q̈ | ratio to N = 8 | Model::new | ratio to N = 8 | 1 s at tol {TOLERANCE:.0e} | crank-tip error |"
    );
    println!("|---|---|---|---|---|---|---|");
    let get = |windows: usize, bench: &str| mean_ns(&format!("parallelogram_chain_{windows}"), bench);
    let ratio = |windows: usize, bench: &str| match (get(windows, bench), get(8, bench)) {
        (Some(a), Some(b)) => format!("{:.1}×", a / b),
        _ => "—".into(),
    };
    let cell = |v: Option<f64>| v.map_or("—".to_string(), format_ns);
    for (windows, error) in SIZES.into_iter().zip(errors) {
        println!(
            "| {windows} | {} | {} | {} | {} | {} | {error:.1e} m |",
            cell(get(windows, "qddot")),
            ratio(windows, "qddot"),
            cell(get(windows, "model_new")),
            ratio(windows, "model_new"),
            cell(get(windows, "one_simulated_second")),
        );
    }
}
