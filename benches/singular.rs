//! Cost against the size of a mechanism with many loops: the parallelogram chain of `N`
//! windows (`2N + 1` coordinates, `2N` loop rows), written as it is read, for
//! `N = 2, 8, 20, 40, 80` — one constrained `q̈` at a state off the flat position, building the
//! model (`Model::new`: structure, probes, sparsity), and one simulated second with
//! Dormand–Prince at tolerance 1e-9 from the scene's default state, whose error against the
//! exact solution (Jacobi elliptic functions) is printed beside it.
//!
//! `cargo bench -p lagrange-benches --bench singular` measures, then prints the table of this
//! run's times and their ratios to `N = 8` (the target: `q̈` at `N = 80` within 10× of
//! `N = 8`), and the whole run: `N = 40` for 20 s (about twenty flat positions) with
//! DOP853 at tolerance 1e-9, read at 400 output times, with the largest crank-tip error
//! against the exact solution over them (the target: 1e-6 in 0.5 s). Last, no timing: how
//! exact `q̈` is at a distance `δ` from the flat position (10 windows, cranks turning at
//! 6 rad/s) — at the exact state on the parallelogram branch, and after the state is moved by
//! 1e-12 in every coordinate and rate and projected back, as an integrator's step leaves it —
//! and at the exact state of 80 windows.

use criterion::BatchSize;
use lagrange::{Method, Model, Output, Tolerances};
use lagrange_benches::{criterion, format_ns, mean_ns};
use lagrange_scenes::{ParallelogramChain, SceneType};
use std::hint::black_box;

const SIZES: [usize; 5] = [2, 8, 20, 40, 80];

/// Tolerance of the simulated second.
const TOLERANCE: f64 = lagrange_benches::tables::SINGULAR_TOLERANCE;

/// The whole run: windows, length (s), output times, DOP853's tolerance.
const WHOLE: (usize, f64, usize, f64) = (40, 20.0, 400, 1e-9);

/// The crank tip's distance from the exact solution's (m, unit cranks) at `theta`, time `t`.
fn tip_error(scene: &ParallelogramChain, start: &lagrange::State, t: f64, theta: f64) -> f64 {
    let exact = scene.exact_solution(start, t).expect("on the branch").q[0];
    ((theta.cos() - exact.cos()).powi(2) + (theta.sin() - exact.sin()).powi(2)).sqrt()
}

/// The variational integrator's run: length (s), step (s).
const VARIATIONAL: (f64, f64) = (20.0, 0.05);

/// The chains the variational run is timed on.
const VARIATIONAL_SIZES: [usize; 3] = [2, 10, 40];

/// The variational integrator over [`VARIATIONAL`]'s length at its step on each of
/// [`VARIATIONAL_SIZES`], read every 0.05 s: timed (ten samples), and each run's largest
/// crank-tip error against the exact solution with its counts.
fn variational_runs(criterion: &mut criterion::Criterion) -> Vec<(f64, lagrange::integrate::Stats)> {
    let (length, dt) = VARIATIONAL;
    let method = Method::Variational { dt };
    let output = Output::Every(0.05);
    VARIATIONAL_SIZES
        .into_iter()
        .map(|windows| {
            let scene = chain(windows);
            let start = scene.default_state();
            let model = Model::new(scene.clone()).expect("valid");
            let mut group = criterion.benchmark_group(format!("parallelogram_chain_{windows}"));
            group.sample_size(10);
            group.bench_function("variational_run", |b| {
                b.iter(|| black_box(lagrange::simulate(&model, &start, length, method, &output).map(|r| r.len())))
            });
            group.finish();
            let run = lagrange::simulate(&model, &start, length, method, &output).expect("runs");
            let error = (0..run.len()).map(|i| tip_error(&scene, &start, run.t[i], run.q(i)[0])).fold(0.0, f64::max);
            (error, run.stats)
        })
        .collect()
}

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
        // Model::new consumes its mechanism: the copy it is given is made outside the timing.
        group.bench_function("model_new", |b| {
            b.iter_batched(
                || scene.clone(),
                |mechanism| black_box(Model::new(mechanism).map(|m| m.dof())),
                BatchSize::SmallInput,
            )
        });
        let method = Method::Dopri5 { tol: Tolerances::uniform(TOLERANCE) };
        group.bench_function("one_simulated_second", |b| {
            b.iter(|| black_box(lagrange::simulate(&model, &start, 1.0, method, &Output::Ends).map(|r| r.len())))
        });
        group.finish();
        let run = lagrange::simulate(&model, &start, 1.0, method, &Output::Ends).expect("runs");
        errors.push((tip_error(&scene, &start, 1.0, run.q(run.len() - 1)[0]), run.stats));
    }
    let (windows, length, samples, tol) = WHOLE;
    let scene = chain(windows);
    let start = scene.default_state();
    let model = Model::new(scene.clone()).expect("valid");
    let times: Vec<f64> = (1..=samples).map(|k| length * k as f64 / samples as f64).collect();
    let method = Method::Dop853 { tol: Tolerances::uniform(tol) };
    let mut group = criterion.benchmark_group(format!("parallelogram_chain_{windows}"));
    group.sample_size(10);
    group.bench_function("whole_run", |b| {
        b.iter(|| {
            black_box(
                lagrange::simulate(&model, &start, length, method, &Output::Times(times.clone())).map(|r| r.len()),
            )
        })
    });
    group.finish();
    let run = lagrange::simulate(&model, &start, length, method, &Output::Times(times.clone())).expect("runs");
    let whole_error = (0..run.len()).map(|i| tip_error(&scene, &start, run.t[i], run.q(i)[0])).fold(0.0, f64::max);
    let variational = variational_runs(&mut criterion);
    criterion.final_summary();
    lagrange_benches::tables::print_header(&lagrange_benches::tables::singular());
    let get = |windows: usize, bench: &str| mean_ns(&format!("parallelogram_chain_{windows}"), bench);
    let ratio = |windows: usize, bench: &str| match (get(windows, bench), get(8, bench)) {
        (Some(a), Some(b)) => format!("{:.1}×", a / b),
        _ => "—".into(),
    };
    let cell = |v: Option<f64>| v.map_or("—".to_string(), format_ns);
    for (windows, (error, stats)) in SIZES.into_iter().zip(errors) {
        println!(
            "| {windows} | {} | {} | {} | {} | {} | {} ({}, {}) | {error:.1e} m |",
            cell(get(windows, "qddot")),
            ratio(windows, "qddot"),
            cell(get(windows, "model_new")),
            ratio(windows, "model_new"),
            cell(get(windows, "one_simulated_second")),
            stats.evaluations,
            stats.steps,
            stats.rejected,
        );
    }
    conditioning();
    println!(
        "\nN = {windows}, {length} s, {samples} output times, DOP853 at tol {tol:.0e}: {} per run, largest crank-tip \
         error {whole_error:.1e} m",
        cell(get(windows, "whole_run"))
    );
    let (length, dt) = VARIATIONAL;
    for (n, (error, stats)) in VARIATIONAL_SIZES.into_iter().zip(variational) {
        println!(
            "N = {n}, {length} s, variational at dt = {dt}: {} per run, largest crank-tip error {error:.1e} m \
             ({} Newton iterations, {} Newton matrices built)",
            cell(mean_ns(&format!("parallelogram_chain_{n}"), "variational_run")),
            stats.newton_iterations,
            stats.jacobians,
        );
    }
}

/// The largest distance of the accelerations `a` from the branch's: `θ̈` for the cranks (even
/// coordinates), `−θ̈` for the couplers.
fn branch_error(a: &[f64], theta_ddot: f64) -> f64 {
    a.iter().enumerate().map(|(i, x)| (x - if i % 2 == 0 { theta_ddot } else { -theta_ddot }).abs()).fold(0.0, f64::max)
}

/// The error of `q̈` near the flat position against the branch's exact `θ̈ = −ω² cos θ`
/// (couplers `−θ̈`) on 10 windows, at the exact state and after a disturbance of 1e-12 and a
/// projection; and at the exact state of the longest chain, where the window around the flat
/// position that the solve's filter leaves inexact is wider.
fn conditioning() {
    let scene = chain(10);
    let model = Model::new(scene.clone()).expect("valid");
    let mut ws = model.workspace();
    let w2 = scene.omega_squared();
    let long = chain(SIZES[SIZES.len() - 1]);
    let long_model = Model::new(long.clone()).expect("valid");
    let mut long_ws = long_model.workspace();
    let mut seed: u64 = 12_345;
    let mut next = move || {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    lagrange_benches::tables::print_header(lagrange_benches::tables::SINGULAR_FLAT);
    for e in 1..=6 {
        let delta = 10f64.powi(-e);
        let state = scene.state_at(0.0, delta, 6.0);
        let exact = -w2 * delta.cos();
        let error = |a: &[f64]| branch_error(a, exact);
        let on = lagrange::accelerations(&model, &mut ws, 0.0, &state.q, &state.qdot).map(&error);
        let mut q: Vec<f64> = state.q.iter().map(|x| x + 1e-12 * next()).collect();
        let mut qdot: Vec<f64> = state.qdot.iter().map(|x| x + 1e-12 * next()).collect();
        let off = lagrange::project(&model, &mut ws, 0.0, &mut q, &mut qdot)
            .and_then(|()| lagrange::accelerations(&model, &mut ws, 0.0, &q, &qdot).map(&error));
        // The same exact state of the longest chain (its branch's ω² is its own).
        let long_state = long.state_at(0.0, delta, 6.0);
        let long_exact = -long.omega_squared() * delta.cos();
        let long_on = lagrange::accelerations(&long_model, &mut long_ws, 0.0, &long_state.q, &long_state.qdot)
            .map(|a| branch_error(a, long_exact));
        let show = |r: Result<f64, lagrange::Error>| r.map_or_else(|e| e.to_string(), |v| format!("{v:.1e}"));
        println!("| {delta:.0e} | {} | {} | {} |", show(on), show(off), show(long_on));
    }
}
