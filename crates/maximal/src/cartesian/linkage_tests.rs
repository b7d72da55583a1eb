//! The Cartesian solve through rank loss and redundancy, and its independence of the world's
//! origin: parallelogram chains passing their flat position, a parallelogram with a redundant
//! third crank, a constraint pair that cannot hold, a constraint written twice.
//!
//! The chain of `N` windows: `N + 1` cranks (uniform rods, 1 kg, 1 m, `I = 1/12 kg m²`) pivoted
//! on the ground at `(k, 0)` by absolute revolute joints and `N` couplers (the same rods) pinned
//! to the tips of consecutive cranks. Started with every crank hanging at `θ = −π/2`, the
//! couplers horizontal and the cranks turning at 8 rad/s, it stays on the branch where every
//! crank has the same angle `θ(t)`, a pendulum `θ̈ = −Ω² cos θ` with
//! `Ω² = 3 g (3N + 1) / (2 (4N + 1))` (`T = θ̇² ((N + 1)/6 + N/2)`,
//! `V = g sin θ ((N + 1)/2 + N)`), and turns over the top: it lies flat (every link horizontal,
//! `J` short of `N` in rank) twice per turn.

use super::simulation::CartesianSimulation;
use super::system::CartesianSystem;
use crate::{BodyState, MaximalSimulation};
use lagrange::graph::{GROUND, GraphMechanism, JointGraph};
use lagrange::{Dynamics, Error};
use lagrange_scenes::{ParallelogramChain, RedundantParallelogram, SceneType};
use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

/// Gravity (m/s²).
const GRAVITY: f64 = 9.81;
/// The cranks' initial rate (rad/s).
const RATE: f64 = 8.0;

/// The Cartesian system of a joint graph and a simulation of it from `states` at `tolerance`.
fn simulate(graph: JointGraph, states: &[BodyState], tolerance: f64) -> CartesianSimulation {
    let mechanism = GraphMechanism::new(graph).unwrap();
    let system = CartesianSystem::from_graph("linkage", Arc::new(mechanism));
    CartesianSimulation::new(system, states, 0.0, tolerance).unwrap()
}

/// The chain of `windows` windows with every pivot and body moved by `shift`, and its body
/// states at crank angle `θ` and rate `θ̇` on the parallel branch (bodies: crank 0, coupler 0,
/// crank 1, …, crank N).
fn parallelogram_chain(windows: usize, shift: [f64; 2], theta: f64, rate: f64) -> (JointGraph, Vec<BodyState>) {
    let scene = ParallelogramChain::new(windows, GRAVITY, rate).unwrap();
    let graph = shifted(scene.joint_graph().unwrap(), shift);
    let mut states = Vec::new();
    let (sin, cos) = theta.sin_cos();
    for k in 0..=windows {
        let pivot = [k as f64 + shift[0], shift[1]];
        states.push(BodyState {
            pose: [pivot[0] + 0.5 * cos, pivot[1] + 0.5 * sin, theta],
            velocity: [-0.5 * rate * sin, 0.5 * rate * cos, rate],
        });
        if k < windows {
            states.push(BodyState {
                pose: [pivot[0] + cos + 0.5, pivot[1] + sin, 0.0],
                velocity: [-rate * sin, rate * cos, 0.0],
            });
        }
    }
    (graph, states)
}

/// `graph` with its ground anchors moved by `shift`.
fn shifted(mut graph: JointGraph, shift: [f64; 2]) -> JointGraph {
    for joint in &mut graph.joints {
        for (end, anchor) in [(&joint.parent, &mut joint.parent_anchor), (&joint.child, &mut joint.child_anchor)] {
            if end == GROUND {
                anchor[0] += shift[0];
                anchor[1] += shift[1];
            }
        }
    }
    graph
}

/// The crank angles of a chain's body states (bodies 0, 2, 4, …).
fn crank_angles(bodies: &[BodyState]) -> Vec<f64> {
    bodies.iter().step_by(2).map(|b| b.pose[2]).collect()
}

/// What a run of a chain measured.
#[derive(Debug)]
struct ChainRun {
    /// Largest angle between any two cranks over the samples (rad).
    spread: f64,
    /// Times a crank passed a flat position (`sin θ` changed sign between samples).
    flat_passes: usize,
    /// Largest `|E(t) − E(0)| / |E(0)|` over the samples.
    energy: f64,
    /// Crank 0's angle at every sample.
    angles: Vec<f64>,
    /// Accepted steps.
    steps: usize,
}

/// Run the chain of `windows` windows, moved by `shift`, for `horizon` s at `tolerance`,
/// sampling every `sample` s.
fn run_chain(windows: usize, shift: [f64; 2], horizon: f64, tolerance: f64, sample: f64) -> ChainRun {
    let (graph, states) = parallelogram_chain(windows, shift, -FRAC_PI_2, RATE);
    let mut simulation = simulate(graph, &states, tolerance);
    let energy = |simulation: &mut CartesianSimulation| {
        let (t, z, zdot) = (simulation.t(), simulation.z.clone(), simulation.zdot.clone());
        simulation.system.energy_function(&mut simulation.ws, t, &z, &zdot).unwrap()
    };
    let e0 = energy(&mut simulation);
    let mut run = ChainRun { spread: 0.0, flat_passes: 0, energy: 0.0, angles: Vec::new(), steps: 0 };
    let samples = (horizon / sample).round() as usize;
    let mut previous = -1.0;
    for k in 1..=samples {
        simulation
            .advance_to(k as f64 * sample)
            .unwrap_or_else(|e| panic!("N = {windows}, t = {}: {e}", k as f64 * sample));
        let angles = crank_angles(&simulation.bodies());
        let spread = angles.iter().fold(0.0_f64, |s, a| s.max((a - angles[0]).abs()));
        run.spread = run.spread.max(spread);
        if angles[0].sin() * previous < 0.0 {
            run.flat_passes += 1;
        }
        previous = angles[0].sin();
        run.angles.push(angles[0]);
        run.energy = run.energy.max((energy(&mut simulation) - e0).abs() / e0.abs());
    }
    run.steps = simulation.steps();
    run
}

/// Bound on the angle between two cranks. Off the flat position the projection holds `Φ = 0`
/// to round-off, and `Φ = 0` near the parallel branch means parallel cranks. Near the flat
/// position, where the parallel and the crossed branch meet, `Φ ≈ 2 θ δ` (θ the distance from
/// it) hardly sees the angle `δ` between cranks, which keeps what the steps there put into it:
/// an accepted step's local error, at most `tol · (1 + |z|) · √n` per coordinate (the
/// integrator's weighted RMS norm), with `|z|` up to the cranks' accumulated angle (≈ 40 rad
/// after 5 s): 1e-10 · 41 · √63 ≈ 3e-8 for N = 10. 1e-7 leaves a factor 3 above that worst case
/// (measured ≤ 2.2e-12); a crank that follows the crossed branch instead leaves the bound by O(1).
const SPREAD_TOL: f64 = 1e-7;

/// Bound on the relative energy change: each of a few thousand steps may change the energy by
/// about the tolerance 1e-10, relative — ≈ 4e-7 if they all added up, in practice a random
/// walk — and the projection is mass-orthogonal, removing energy only to second order in the
/// violation. 1e-8 is the target for this tolerance; measured ≤ 1.7e-10.
const ENERGY_TOL: f64 = 1e-8;

/// Least number of flat passes that makes a run a test of them: the cranks turn over about five
/// times in 5 s (mean rate ≈ 6.4 rad/s for N = 2), lying flat twice per turn — 9 passes for
/// N = 2, 10 for N = 10 (counted as sign changes of `sin θ` between samples).
const FLAT_PASSES: usize = 8;

/// The chain passes its flat position many times without an error, its cranks stay parallel
/// and its energy is conserved (N = 2 and 10, 5 s at tolerance 1e-10).
#[test]
fn parallelogram_chain_passes_its_flat_position() {
    for windows in [2, 10] {
        let run = run_chain(windows, [0.0, 0.0], 5.0, 1e-10, 0.01);
        eprintln!(
            "N = {windows}: {} flat passes, spread {:.1e} rad, energy {:.1e}, {} steps",
            run.flat_passes, run.spread, run.energy, run.steps
        );
        assert!(run.flat_passes >= FLAT_PASSES, "N = {windows}: {} flat passes", run.flat_passes);
        assert!(run.spread <= SPREAD_TOL, "N = {windows}: cranks {:e} rad apart", run.spread);
        assert!(run.energy <= ENERGY_TOL, "N = {windows}: energy changed by {:e}", run.energy);
    }
}

/// Bound on the crank angle of the translated run against the untranslated one. The simulation
/// runs in a frame at the bodies' initial centroid, so the two runs differ by the round-off of
/// the translation alone: ≈ 1e-13 in the initial positions, where they are built at 1e3 m
/// (measured 2e-16 in the angle after 0.05 s). A flat position amplifies any difference across
/// the branches (the constraints there do not see it), about doubling it per crossing: measured
/// 2.7e-11 after ten crossings in this run, and up to 1.7e-10 with other initial rates (7.3 and
/// 9.1 rad/s). 5e-10 bounds that; evaluating the equations 1e3 m from the origin instead (the
/// round-off of `Φ` then 1e3 times larger) moved the angles by 1e-8 … 1e-2.
const TRANSLATION_TOL: f64 = 5e-10;

/// Translating every body and ground anchor by (1e3, 1e3) m gives the same motion: the crank
/// angles agree to round-off at every sample.
#[test]
fn parallelogram_chain_does_not_depend_on_the_origin() {
    let here = run_chain(2, [0.0, 0.0], 5.0, 1e-10, 0.05);
    let there = run_chain(2, [1e3, 1e3], 5.0, 1e-10, 0.05);
    let difference = here.angles.iter().zip(&there.angles).fold(0.0_f64, |d, (a, b)| d.max((a - b).abs()));
    eprintln!(
        "translated by 1e3 m: crank angles differ by {difference:.1e} rad ({} and {} steps)",
        here.steps, there.steps
    );
    assert!(difference <= TRANSLATION_TOL, "translated chain differs by {difference:e} rad");
}

/// Bound on `z̈` against the branch's exact accelerations (relative to the largest) at distances
/// `δ ≥ 1e-3` rad from the flat position, where the rank-loss eigenvalue of the scaled `S`
/// (`σ ≈ 0.3 δ²` for N = 10) is at least 300 μ: the refined solve's error there is
/// `(μ/σ)^(k+1) ≤ 1e-10` of the loop tensions' share of `z̈` (below), plus the round-off the
/// conditioning `1/σ` lends any solve (≈ 4e-18/δ², measured with no shift: 8e-12 at 1e-3).
/// Measured 1.5e-10 at 1e-3 and ≤ 1e-13 from 1e-2 on; 1e-9 keeps a margin.
const BRANCH_RTOL: f64 = 1e-9;

/// Bound on `z̈` against the branch at the flat position itself (and so, below, everywhere):
/// the branch needs there the limit of the loop tensions' force (the end cranks carry half a
/// coupler, the inner ones a whole one, and only horizontal pin forces `T` with torques
/// `T sin θ` can make them turn alike: `T ~ 1/sin θ`), which no multiplier can give once `J`
/// has lost rank; the equations' own solution there misses it: 1.8e-2 of the largest
/// acceleration for N = 10. 5e-2 says that it is finite and of that size, where an unshifted
/// solve fails (at δ ≤ 1e-8).
const FLAT_RTOL: f64 = 5e-2;

/// `z̈` at crank angles `θ = δ` from the flat positions (`θ = 0` and `π`; δ from 1e-1 to 1e-8,
/// and 0) against the exact accelerations of the parallel branch, the pendulum
/// `θ̈ = −Ω² cos θ` carried to every body: exact to [`BRANCH_RTOL`] where the rows are
/// independent enough (δ ≥ 1e-3), and in between moving continuously to the flat position's own
/// solution, never beyond it ([`FLAT_RTOL`]). Measured (μ = 1e-9, 3 refinements):
/// δ = 1e-1: 4e-15, 1e-2: 1e-13, 1e-3: 1.5e-10, 1e-4: 4.0e-4, 1e-5: 1.4e-2, ≤ 1e-6: 1.8e-2.
#[test]
fn accelerations_through_the_flat_position_are_the_branch_accelerations() {
    let windows = 10;
    let omega2 = 3.0 * GRAVITY * (3 * windows + 1) as f64 / (2.0 * (4 * windows + 1) as f64);
    for flat in [0.0, std::f64::consts::PI] {
        let mut errors = Vec::new();
        for distance in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 0.0] {
            let theta = flat + distance;
            let (graph, states) = parallelogram_chain(windows, [0.0, 0.0], theta, RATE);
            let mut simulation = simulate(graph, &states, 1e-10);
            simulation.evaluate().unwrap();
            // The branch: θ̈ = −Ω² cos θ; crank centres at ½ (cos θ, sin θ), couplers at (cos θ, sin θ).
            let (sin, cos) = theta.sin_cos();
            let accel = -omega2 * cos;
            let tip = [-sin * accel - cos * RATE * RATE, cos * accel - sin * RATE * RATE];
            let expected: Vec<f64> = (0..2 * windows + 1)
                .flat_map(|b| if b % 2 == 0 { [0.5 * tip[0], 0.5 * tip[1], accel] } else { [tip[0], tip[1], 0.0] })
                .collect();
            let scale = expected.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            let zddot = &simulation.ws.zddot;
            let error = expected.iter().zip(zddot).fold(0.0_f64, |e, (a, b)| e.max((a - b).abs())) / scale;
            eprintln!("θ = {flat:.3} + {distance:.0e}: z̈ off the branch by {error:.1e} relative");
            errors.push((distance, error));
        }
        let at_flat = errors.last().unwrap().1;
        assert!(at_flat <= FLAT_RTOL, "θ = {flat}: z̈ off the branch by {at_flat:e} at the flat position");
        for &(distance, error) in &errors {
            let bound = if distance >= 1e-3 { BRANCH_RTOL } else { at_flat + BRANCH_RTOL };
            assert!(error <= bound, "θ = {flat} + {distance:e}: z̈ off the branch by {error:e} relative");
        }
    }
}

/// The redundant parallelogram: a crank (1 m) pivoted at the origin, a coupler (2 m), a rocker
/// (1 m) pivoted at (2, 0) and a third crank (1 m) pivoted at (1, 0) pinned to the coupler's
/// middle — one of its rows repeats the others' everywhere — with every crank at `θ` turning at
/// `θ̇` (bodies: crank, coupler, rocker, third crank).
fn redundant_parallelogram(theta: f64, rate: f64) -> (JointGraph, Vec<BodyState>) {
    let graph = RedundantParallelogram::new(GRAVITY, rate).unwrap().joint_graph().unwrap();
    let (sin, cos) = theta.sin_cos();
    let crank = |pivot: f64| BodyState {
        pose: [pivot + 0.5 * cos, 0.5 * sin, theta],
        velocity: [-0.5 * rate * sin, 0.5 * rate * cos, rate],
    };
    let coupler = BodyState { pose: [cos + 1.0, sin, 0.0], velocity: [-rate * sin, rate * cos, 0.0] };
    (graph, vec![crank(0.0), coupler, crank(2.0), crank(1.0)])
}

/// The redundant parallelogram runs 2 s (tolerance 1e-10) through its flat positions without an
/// error — the dense solve refused it at the start, its `Φ_z` rank-deficient — with its three
/// cranks parallel and its energy conserved (bounds [`SPREAD_TOL`], [`ENERGY_TOL`], for the
/// same reasons as the chain's).
#[test]
fn redundant_parallelogram_runs_with_a_row_too_many() {
    let (graph, states) = redundant_parallelogram(-FRAC_PI_2, RATE);
    let mut simulation = simulate(graph, &states, 1e-10);
    let energy = |simulation: &mut CartesianSimulation| {
        let (t, z, zdot) = (simulation.t(), simulation.z.clone(), simulation.zdot.clone());
        simulation.system.energy_function(&mut simulation.ws, t, &z, &zdot).unwrap()
    };
    let e0 = energy(&mut simulation);
    let (mut spread, mut drift, mut flat_passes, mut previous) = (0.0_f64, 0.0_f64, 0, -1.0);
    for k in 1..=200 {
        simulation.advance_to(0.01 * k as f64).unwrap();
        let bodies = simulation.bodies();
        let angles = [bodies[0].pose[2], bodies[2].pose[2], bodies[3].pose[2]];
        spread = spread.max((angles[1] - angles[0]).abs()).max((angles[2] - angles[0]).abs());
        drift = drift.max((energy(&mut simulation) - e0).abs() / e0.abs());
        if angles[0].sin() * previous < 0.0 {
            flat_passes += 1;
        }
        previous = angles[0].sin();
    }
    eprintln!("redundant parallelogram: {flat_passes} flat passes, spread {spread:.1e} rad, energy {drift:.1e}");
    // Two seconds at ≈ 6 rad/s: about two turns, four flat passes.
    assert!(flat_passes >= 2, "it passes its flat position ({flat_passes} times)");
    assert!(spread <= SPREAD_TOL, "cranks {spread:e} rad apart");
    assert!(drift <= ENERGY_TOL, "energy changed by {drift:e}");
}

/// A bob on a rod from the origin, and a floor `y = −l` tangent to its circle at the bottom:
/// passing the bottom at speed `v`, the rod asks for `ÿ = v²/l` and the floor for `ÿ = 0`. The
/// acceleration equations cannot hold together (their residual after refinement is `≈ v²/2l`,
/// against round-off), an error naming both constraints.
#[test]
fn constraints_that_cannot_hold_together_are_an_error_naming_them() {
    use super::constraints::{Y, linear};
    let params = lagrange_scenes::find("nonminimal_pendulum").unwrap().default_params();
    let length = params.get("length");
    let system = CartesianSystem::new(crate::scene("nonminimal_pendulum"), &params).unwrap();
    let mut constraints = system.constraints.clone();
    constraints.push(linear(&[(0, Y, 1.0)], length, "floor"));
    let system = system.with_constraints(constraints);
    let (z, zdot) = ([0.0, -length, 0.0], [1.5, 0.0, 0.0]);
    let mut ws = system.workspace();
    let error = system.evaluate(&mut ws, 0.0, &z, &zdot).unwrap_err();
    let Error::InconsistentConstraints { ref constraints, residual, .. } = error else {
        panic!("expected inconsistent constraints, got {error}");
    };
    assert!(constraints.iter().any(|c| c.contains("rod")) && constraints.iter().any(|c| c == "floor"), "{error}");
    assert!(residual > 0.1 * 1.5 * 1.5 / length, "{error}");
    // At rest at the bottom the two agree: no error.
    system.evaluate(&mut ws, 0.0, &z, &[0.0; 3]).unwrap();
}

/// Bound on the 40-window chain's energy change at tolerance 1e-6: each of its ~560 steps may
/// change the energy by about the tolerance, relative; as a random walk √560 · 1e-6 ≈ 2.4e-5,
/// with a factor 4 for coherent stretches. Measured 7.7e-7.
const ENERGY_TOL_FORTY: f64 = 1e-4;

/// Bound on the angle between the 40-window chain's cranks at tolerance 1e-6: a step's error,
/// about the tolerance, is what the flat positions let through (see [`SPREAD_TOL`]); a crank that
/// follows the crossed branch leaves it by O(1). Measured 7.2e-13.
const SPREAD_TOL_FORTY: f64 = 1e-6;

/// The 40-window chain (81 bodies, 242 constraint rows) for 20 s at tolerance 1e-6, the run the
/// dense KKT solve took 114 s for: through its ~40 flat positions with parallel cranks and its
/// energy kept. Prints the wall time (measured 0.26 s in a release build, 0.69 s in the test
/// profile); a benchmark's time is not asserted.
#[test]
fn parallelogram_chain_of_forty_windows_for_twenty_seconds() {
    let start = std::time::Instant::now();
    let run = run_chain(40, [0.0, 0.0], 20.0, 1e-6, 0.1);
    let elapsed = start.elapsed();
    eprintln!(
        "N = 40, 20 s at tol 1e-6: {:.2} s wall, {} steps, {} flat passes, spread {:.1e} rad, energy {:.1e}",
        elapsed.as_secs_f64(),
        run.steps,
        run.flat_passes,
        run.spread,
        run.energy
    );
    // Twenty seconds at ≈ 6 rad/s: about twenty turns, forty flat passes.
    assert!(run.flat_passes >= 30, "the run passes the flat position ({} times)", run.flat_passes);
    assert!(run.spread <= SPREAD_TOL_FORTY, "cranks {:e} rad apart", run.spread);
    assert!(run.energy <= ENERGY_TOL_FORTY, "energy changed by {:e}", run.energy);
}

/// Bound on the crank angle against the exact reduction: both runs integrate at 1e-12 per step
/// over 2 s and ~10³ steps (global errors ≲ 1e-10 each, measured 1.2e-9 apart — the change point
/// costs the Cartesian run a few digits), and a run that left the analytic branch at the change
/// point differs by O(1) (0.36 rad after 2 s).
const CHANGE_POINT_TOL: f64 = 1e-8;

/// The change-point four-bar (`a + b = c + d`) passes its flat position at `θ2 = 2π` and `4π`
/// (after ≈ 1.1 s and 1.9 s) on the analytic branch: its crank's angle follows the scene's exact one-coordinate
/// reduction through the change point (`ChangePointCrank`, no constraints at all). The Cartesian
/// angle is continuous, so whole turns are compared too.
#[test]
fn change_point_four_bar_follows_its_one_coordinate_reduction() {
    use crate::Settings;
    use lagrange::integrate::Tolerances;
    use lagrange::{Method, Model, Output, State};
    use lagrange_scenes::SceneType;
    let id = "change_point_four_bar";
    let params = lagrange_scenes::find(id).unwrap().default_params();
    let scene = lagrange_scenes::ChangePointFourBar::new(params.get("gravity"), params.get("crank_speed")).unwrap();
    let initial = scene.default_state();
    let settings = Settings { tolerance: 1e-12, ..Settings::default() };
    let mut simulation =
        crate::build(crate::Engine::Cartesian, crate::scene(id), &params, &initial, &settings).unwrap().simulation;
    let model = Model::new(scene.crank_model()).unwrap();
    let start = State::new(0.0, [initial.q[0]], [initial.qdot[0]]);
    let method = Method::Dopri5 { tol: Tolerances::uniform(1e-12) };
    let run = lagrange::simulate(&model, &start, 2.0, method, &Output::Ends).unwrap();
    let exact = run.last_state().unwrap().q[0];
    simulation.advance_to(2.0).unwrap();
    let crank = simulation.bodies()[0].pose[2];
    eprintln!("change point: θ2 = {exact} (reduction), {crank} (Cartesian), {:.1e} apart", (exact - crank).abs());
    assert!(exact > 2.0 * std::f64::consts::TAU, "the crank passes the change point");
    assert!((exact - crank).abs() <= CHANGE_POINT_TOL, "θ2 = {crank} against {exact}");
}
