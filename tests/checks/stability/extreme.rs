//! Extreme parameters, simulated: mass ratios 1e-6 and 1e6 (cart pendulum, wedge, Atwood),
//! wedge angles 1e-6 and π/2 − 1e-6, an Atwood pulley with `I/a²` = 1e8 and balanced masses,
//! and chains whose link masses span 1e6 — against closed forms (constant accelerations, the
//! small-oscillation frequency) and conservation laws (horizontal momentum, energy). The
//! accelerations alone at extreme parameters are checked in `analytic.rs`.

use super::{build, params, phase, relative_energy_error, scene};
use lagrange::tree::Tree;
use lagrange::{Error, Method, Model, Output, Simulation, State, System, Tolerances};
use lagrange_scenes::SceneType;
use lagrange_tests::tolerance::{EPS, conditioned};
use lagrange_tests::{condition_number, max_abs, max_abs_diff};
use std::f64::consts::{FRAC_PI_2, PI};

/// Four rods of length 1 hanging from the origin with these masses, top first.
fn chain(masses: &[f64]) -> Tree {
    lagrange_scenes::chain::hanging_rods(masses, 1.0, 9.81).expect("valid chain")
}

/// Mass ratios of docs/validation.md#extreme_parameters.
const RATIOS: [f64; 2] = [1e-6, 1e6];

/// Round-off bound of `steps` fixed steps on a constant-acceleration motion, relative to the
/// largest `|q|, |q̇|`: RK4 and the midpoint rule reproduce `q₀ + v₀ t + a t²/2` exactly in exact
/// arithmetic, so only the acceleration's round-off (`conditioned(κ)`) and a few roundings per
/// step (≤ 4ε each, accumulating at worst linearly) remain.
fn constant_acceleration_bound(kappa: f64, steps: usize) -> f64 {
    conditioned(kappa) + 4.0 * EPS * steps as f64
}

#[test]
fn wedge_at_extreme_masses_and_angles_follows_its_constant_accelerations() {
    let s = scene("wedge");
    let mut cases: Vec<(f64, f64)> = RATIOS.iter().map(|&r| (r, FRAC_PI_2 / 3.0)).collect();
    for angle in [1e-6, FRAC_PI_2 - 1e-6] {
        cases.extend([(1.0, angle), (1e-6, angle), (1e6, angle)]);
    }
    for (ratio, angle) in cases {
        let p = params("wedge", &[("wedge_mass", 1.0), ("block_mass", ratio), ("angle", angle)]);
        let mut system = build("wedge", &p);
        let initial = State::new(0.0, [0.0, 0.0], [0.0, 0.0]);
        let kappa = condition_number(2, system.mass_matrix(0.0, &initial.q, &initial.qdot).expect("valid"));
        let steps = 100;
        for method in [Method::Rk4 { dt: 0.01 }, Method::Variational { dt: 0.01 }] {
            let run = system.simulate(&initial, 1.0, method, &Output::Ends).expect("integrates");
            let got = run.last_state().expect("recorded");
            let exact = s.exact_solution(&p, &initial, 1.0).expect("valid").expect("closed form");
            let (got, exact) = (phase(&got), phase(&exact));
            let residual = max_abs_diff(&got, &exact) / max_abs(&exact);
            let bound = constant_acceleration_bound(kappa, steps);
            assert!(
                residual <= bound,
                "m/M = {ratio:e}, α = {angle}, {}: expected {exact:?}, got {got:?}, relative residual {residual:e} > {bound:e}",
                method.name()
            );
            // x is cyclic and starts with p_x = 0: it stays 0, to the round-off of the momenta
            // (M + m) ẋ and m cosα ẋ' that cancel in it.
            let p_x = system.momenta(1.0, run.q(1), run.qdot(1)).expect("valid")[0];
            let scale = (1.0 + ratio) * max_abs(&got[2..]);
            assert!(p_x.abs() <= bound * scale, "m/M = {ratio:e}, α = {angle}: p_x = {p_x:e}, scale {scale:e}");
        }
    }
}

#[test]
fn atwood_with_balanced_masses_does_not_move_at_all() {
    // m1 = m2: the generalized gravity force m1 g − m2 g is exactly 0 in floating point, so
    // q̈ = 0 exactly and every method keeps the machine at rest, bit for bit.
    for inertia in [0.1, 1e8 * 0.25] {
        let p = params("atwood", &[("mass_1", 1.0), ("mass_2", 1.0), ("pulley_inertia", inertia)]);
        let system = build("atwood", &p);
        let initial = scene("atwood").default_state(&p).expect("valid");
        for method in [
            Method::Rk4 { dt: 0.01 },
            Method::Adaptive { tol: Tolerances::uniform(1e-10) },
            Method::Variational { dt: 0.01 },
        ] {
            let run = system.simulate(&initial, 100.0, method, &Output::Every(1.0)).expect("integrates");
            for k in 0..run.len() {
                assert_eq!(
                    (run.q(k), run.qdot(k)),
                    (initial.q.as_slice(), initial.qdot.as_slice()),
                    "I = {inertia}, {} at t = {}: drifted",
                    method.name(),
                    run.t[k]
                );
            }
        }
    }
}

#[test]
fn atwood_with_a_huge_pulley_or_extreme_masses_follows_its_constant_acceleration() {
    // a = 0.5: I = 1e8 a² makes the acceleration (m1 − m2) g / (m1 + m2 + 1e8) ≈ 1e-7 g.
    let cases = [(2.0, 1.0, 1e8 * 0.25), (1e-6, 1.0, 0.1), (1e6, 1.0, 0.1), (1.0, 1e6, 0.1)];
    let s = scene("atwood");
    for (m1, m2, inertia) in cases {
        let p = params("atwood", &[("mass_1", m1), ("mass_2", m2), ("pulley_inertia", inertia)]);
        let system = build("atwood", &p);
        let initial = State::new(0.0, [1.0], [0.5]);
        let exact = s.exact_solution(&p, &initial, 1.0).expect("valid").expect("closed form");
        for method in [Method::Rk4 { dt: 0.01 }, Method::Variational { dt: 0.01 }] {
            let run = system.simulate(&initial, 1.0, method, &Output::Ends).expect("integrates");
            let got = phase(&run.last_state().expect("recorded"));
            let residual = max_abs_diff(&got, &phase(&exact)) / max_abs(&phase(&exact));
            // M = m1 + m2 + I/a² is 1 × 1: κ = 1.
            let bound = constant_acceleration_bound(1.0, 100);
            assert!(
                residual <= bound,
                "m1 = {m1:e}, m2 = {m2:e}, I = {inertia:e}, {}: expected {:?}, got {got:?}, relative residual {residual:e}",
                method.name(),
                phase(&exact)
            );
        }
    }
}

#[test]
fn cart_pendulum_at_extreme_mass_ratios_keeps_its_frequency_and_momentum() {
    let s = scene("cart_pendulum");
    for ratio in RATIOS {
        let p = params("cart_pendulum", &[("cart_mass", 1.0), ("bob_mass", ratio)]);
        let cart = lagrange_scenes::cart_pendulum::CartPendulum::from_params(&p).expect("valid");
        let system = s.build(&p).expect("valid");
        // ω² = g (M + m)/(M r) (docs/scenes.md#cart_pendulum). The swing changes the inertia M + m sin²θ by
        // m θ₀², so the amplitude correction to the period is ≈ θ₀² (1/16 + m/(4M)) (measured
        // 2.5e-3 at θ₀ = 1e-4, m/M = 1e6): θ₀ = 1e-9 puts it below 1e-12.
        let omega = cart.small_oscillation_frequency();
        let period = 2.0 * PI / omega;
        let theta0 = 1e-9;
        let initial = State::new(0.0, [0.0, theta0], [0.0, 0.0]);
        let dt = period / 2000.0;
        let tol = Tolerances { rtol: 1e-12, atol: 1e-12 * theta0 };
        let run =
            system.simulate(&initial, 10.5 * period, Method::Adaptive { tol }, &Output::Every(dt)).expect("integrates");
        let mut crossings = Vec::new();
        for k in 1..run.len() {
            let (a, b) = (run.q(k - 1)[1], run.q(k)[1]);
            if a > 0.0 && b <= 0.0 {
                crossings.push(run.t[k - 1] + dt * a / (a - b));
            }
        }
        assert!(crossings.len() >= 10, "m/M = {ratio:e}: {} crossings", crossings.len());
        let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
        // Linear interpolation of the crossings (θ is linear there to O(dt³)) and the integration
        // error at relative tolerance 1e-12 stay below 1e-9; 1e-8 leaves a margin of 10.
        let residual = measured / period - 1.0;
        assert!(
            residual.abs() <= 1e-8,
            "m/M = {ratio:e}: expected P = {period:e}, got {measured:e}, residual {residual:e}"
        );

        // Horizontal momentum with the variational integrator (discrete Noether): conserved to
        // its Newton residual, a few ε|p| per step.
        let moving = State::new(0.0, [0.0, 0.5], [0.3, -1.0]);
        let steps = 20_000;
        let mut system = system;
        let p0 = system.momenta(0.0, &moving.q, &moving.qdot).expect("valid")[0];
        let run = system
            .simulate(&moving, steps as f64 * dt, Method::Variational { dt }, &Output::Every(100.0 * dt))
            .expect("integrates");
        // |p_X| is a sum of (M + m) Ẋ and m r cosθ θ̇, which can cancel: the scale is the larger.
        let scale = (1.0 + ratio) * 0.3 + ratio * cart.rod_length * 1.0;
        for k in 0..run.len() {
            let p = system.momenta(run.t[k], run.q(k), run.qdot(k)).expect("valid")[0];
            let bound = 4.0 * EPS * steps as f64 * scale;
            assert!((p - p0).abs() <= bound, "m/M = {ratio:e}, t = {}: p_X = {p} vs {p0}, bound {bound:e}", run.t[k]);
        }
    }
}

#[test]
fn chains_with_link_masses_spanning_a_million_conserve_energy() {
    for masses in [[1.0, 1e2, 1e4, 1e6], [1e6, 1e4, 1e2, 1.0], [1.0, 1e6, 1.0, 1e6]] {
        let tree = chain(&masses);
        let mut fast = Simulation::new(Model::new(tree.clone()).expect("valid"));
        let mut generic = Simulation::new(Model::new_generic(tree).expect("valid"));
        let (q, qdot) = ([0.5, 1.0, -0.3, 2.0], [0.3, -1.0, 2.0, 0.5]);
        // The articulated-body algorithm against the assembled and factored M.
        let kappa = condition_number(4, generic.mass_matrix(0.0, &q, &qdot).expect("valid"));
        let a = fast.accelerations(0.0, &q, &qdot).expect("valid").to_vec();
        let b = generic.accelerations(0.0, &q, &qdot).expect("valid").to_vec();
        let residual = max_abs_diff(&a, &b) / max_abs(&b);
        assert!(
            residual <= conditioned(kappa),
            "{masses:?}: tree {a:?}, generic {b:?}, residual {residual:e}, κ {kappa:e}"
        );
        // Energy over 10 s: the adaptive method's global error is C tol with C measured ≤ 250
        // (integrators.rs); 1e3 tol bounds it with margin.
        let tol = 1e-12;
        let initial = State::new(0.0, q, qdot);
        let run = fast
            .simulate(&initial, 10.0, Method::Adaptive { tol: Tolerances::uniform(tol) }, &Output::Every(0.1))
            .expect("integrates");
        let error = relative_energy_error(&run.energy);
        assert!(error <= 1e3 * tol, "{masses:?}: relative energy error {error:e} > {:e}", 1e3 * tol);
    }
}

#[test]
fn gauss_integrates_a_chain_with_link_masses_spanning_a_million() {
    // Heavy links at the root, light at the tip: Gauss converges at fourth order against a
    // tol-1e-13 adaptive reference (measured errors 6.1e-6, 3.8e-7, 2.4e-8 at dt = 1e-2 …
    // 2.5e-3: ratios 16 ± 25 %) with the energy error falling alike. Before the round-off
    // plateau rule this ordering's mirror failed at a plateau of 1.2e-12 (regression).
    let initial = State::new(0.0, [0.5, 1.0, -0.3, 2.0], [0.3, -1.0, 2.0, 0.5]);
    let system = Simulation::new(Model::new(chain(&[1e6, 1e4, 1e2, 1.0])).expect("valid"));
    let reference = system
        .simulate(&initial, 2.0, Method::Adaptive { tol: Tolerances::uniform(1e-13) }, &Output::Ends)
        .expect("integrates")
        .last_state()
        .expect("recorded");
    let (mut errors, mut energy) = (Vec::new(), Vec::new());
    for dt in [1e-2, 5e-3, 2.5e-3] {
        let run = system.simulate(&initial, 2.0, Method::Gauss { dt }, &Output::Every(0.01));
        let run = run.unwrap_or_else(|e| panic!("dt = {dt}: {e}"));
        errors.push(max_abs_diff(&run.last_state().expect("recorded").q, &reference.q));
        energy.push(relative_energy_error(&run.energy));
    }
    for (what, values) in [("error", &errors), ("energy error", &energy)] {
        for w in values.windows(2) {
            assert!((12.0..=20.0).contains(&(w[0] / w[1])), "{what} {values:?} is not fourth order");
        }
    }
    // Light link at the root, heavy at the tip: the root link is whipped (the reference's
    // velocities jump to 18 rad/s within milliseconds near t = 0.09 and 0.15, where its steps
    // collapse to ~1e-5). A fixed step of 1e-3 cannot follow that; Gauss must say so with a
    // typed error inside that window, not return a wrong trajectory or NaN.
    let system = Simulation::new(Model::new(chain(&[1.0, 1e2, 1e4, 1e6])).expect("valid"));
    match system.simulate(&initial, 2.0, Method::Gauss { dt: 1e-3 }, &Output::Ends) {
        Err(Error::NewtonFailed { t, .. }) => assert!((0.08..=0.17).contains(&t), "failed at t = {t}"),
        other => panic!("expected NewtonFailed in the whip, got {other:?}"),
    }
}
