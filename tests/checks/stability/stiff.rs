//! Stiff springs and strong damping at fixed steps: the observed stability limits of RK4 and of
//! rapier against the stability functions of the methods, the explicit adaptive method pinned
//! at its own stability boundary, and the implicit methods unconditionally stable.
//!
//! Which RK4 constant applies: RK4 multiplies the amplitude of a mode `y' = λ y` by
//! `R(z) = 1 + z + z²/2 + z³/6 + z⁴/24`, `z = λ dt`, per step. An undamped oscillator has
//! `λ = ±iω`, on the imaginary axis, where `|R(iy)|² = 1 − y⁶/72 + y⁸/576` exceeds 1 beyond
//! `y = 2√2 = 2.828`: that is its limit, `ω dt ≤ 2√2`. The often-quoted 2.785 is the boundary on
//! the negative real axis (`R(−x) = 1`, `x³ − 4x² + 12x − 24 = 0`), which is the limit of a
//! strongly over-damped oscillator, whose fast mode has a real `λ ≈ −c/m`: `|λ| dt ≤ 2.785`
//! (not `2/ω`, which is explicit Euler's). Both are measured below by bisection on `dt`.

use super::{build, params, relative_energy_error};
use lagrange::integrate::stability::{damped_roots, dopri5_real_axis_limit};
use lagrange::{Method, Output, State, Tolerances};
use lagrange_maximal::{Engine, Settings, maps};
use lagrange_scenes::SceneType;
use lagrange_tests::tolerance::{STABILITY_LIMIT, gauss_energy_per_step};

/// `k/m` of the stiff springs: 1e2 … 1e12 (m = 1).
const STIFFNESSES: [f64; 6] = [1e2, 1e4, 1e6, 1e8, 1e10, 1e12];

fn assert_limit(what: &str, measured: f64, theory: f64, tolerance: f64) {
    let residual = measured / theory - 1.0;
    assert!(
        residual.abs() <= tolerance,
        "{what}: expected ω dt = {theory:.12}, got {measured:.12}, residual {residual:e} (bound {tolerance:e})"
    );
}

/// Strong damping: `k/m = 1e6`, `c/m = 1e6`, roots ≈ −1e6 and −1.
const DAMPED: (f64, f64) = (1e6, 1e6);

#[test]
fn explicit_adaptive_steps_sit_on_their_stability_boundary_when_stiff() {
    let (k, c) = DAMPED;
    let p = params("harmonic_oscillator", &[("stiffness", k), ("damping", c)]);
    let system = build("harmonic_oscillator", &p);
    let oscillator = lagrange_scenes::harmonic_oscillator::HarmonicOscillator::from_params(&p).expect("valid");
    let (fast, _) = damped_roots(k, c);
    let initial = State::new(0.0, [0.1], [0.0]);
    for tol in [1e-3, 1e-6, 1e-9] {
        let t_end = 1.0;
        let run = system
            .simulate(&initial, t_end, Method::Adaptive { tol: Tolerances::uniform(tol) }, &Output::Ends)
            .expect("integrates");
        // Whatever the tolerance, the mean step is the Dormand–Prince real-axis boundary
        // 3.3066/|λ_fast|: the step is set by stability, not accuracy (the signature of
        // stiffness). 1 % covers the initial transient, where the steps are accuracy-bound.
        let mean_step = -fast * t_end / run.stats.steps as f64;
        assert_limit(&format!("DOPRI5 at tol {tol:e}"), mean_step, dopri5_real_axis_limit(), STABILITY_LIMIT);
        // And accurate nevertheless: the global error stays at the tolerance's scale.
        let (x, v) = oscillator.motion(0.1, 0.0, t_end);
        let error = (run.q[1] - x).abs().max((run.qdot[1] - v).abs());
        assert!(error <= 10.0 * tol, "tol {tol:e}: expected x = {x}, got {}, residual {error:e}", run.q[1]);
    }
}

#[test]
fn rapier_energy_error_on_the_oscillator_is_bounded_by_symplectic_eulers() {
    // Symplectic Euler (`v ← v − h ω² x`, `x ← x + h v`) conserves `I = v² + ω² x² − h ω² x v`
    // exactly, and `|h ω² x v| ≤ (h ω/2)(v² + ω² x²)`, so the energy stays within
    // `E/I ∈ [1/(1 + hω/2), 1/(1 − hω/2)]`: from a turning point (`E₀ = I`) its relative error
    // is at most `(hω/2)/(1 − hω/2)`, for ever — bounded, no drift.
    let p = params("harmonic_oscillator", &[]);
    let initial = State::new(0.0, [0.1], [0.0]);
    let (dt, omega) = (0.01, 10f64.sqrt());
    let settings = Settings { dt, substeps: 1, tolerance: 1e-12 };
    let mut built = lagrange_maximal::build(Engine::RapierImpulse, "harmonic_oscillator", &p, &initial, &settings)
        .expect("buildable");
    let mut energy = vec![maps::energy("harmonic_oscillator", &built.params, 0.0, &built.simulation.bodies()).unwrap()];
    for k in 1..=2000 {
        let t = k as f64 * 50.0 * dt;
        built.simulation.advance_to(t).expect("stable");
        energy.push(maps::energy("harmonic_oscillator", &built.params, t, &built.simulation.bodies()).unwrap());
    }
    let error = relative_energy_error(&energy);
    let half = omega * dt / 2.0;
    let bound = half / (1.0 - half);
    // 1e5 steps; the bound is reached only at some steps, sampled every 50th: ≤ it, up to round-off.
    assert!(error <= bound * (1.0 + 1e-9), "expected ≤ (hω/2)/(1 − hω/2) = {bound:e}, got {error:e}");
    assert!(error >= 0.9 * bound, "the band is reached: expected ≈ {bound:e}, got {error:e}");
}

#[test]
fn gauss_conserves_the_linear_oscillators_energy_at_any_step() {
    // A-stable with |R(iy)| = 1, and quadratic invariants are conserved exactly: the energy of
    // the oscillator to round-off, whatever ω dt (here 0.1 to 1e4).
    let (dt, steps) = (0.01, 1000);
    for k in STIFFNESSES {
        let system = build("harmonic_oscillator", &params("harmonic_oscillator", &[("stiffness", k)]));
        let initial = State::new(0.0, [0.1], [0.0]);
        let run = system
            .simulate(&initial, steps as f64 * dt, Method::Gauss { dt }, &Output::Every(dt))
            .expect("A-stable: no step is too large");
        let error = relative_energy_error(&run.energy);
        let bound = steps as f64 * gauss_energy_per_step(k.sqrt() * dt);
        assert!(error <= bound, "k/m = {k:e}: expected 0, got {error:e} (bound {bound:e})");
    }
}

#[test]
fn sdirk_steps_over_the_stiff_spring_at_the_pendulums_pace() {
    // Released from its static stretch, the stiff spring pendulum swings like a rigid one; the
    // radial mode (ω = √(k/m)) is barely excited and, unresolved, is damped by the L-stable
    // method (R(∞) = 0): its steps follow the swing whatever k, and the energy never grows
    // beyond its error control (10 tol relative to the swing's energy).
    let tol = 1e-6;
    let (theta0, horizon) = (1.0_f64, 2.0);
    let rigid = build("driven_pendulum", &params("driven_pendulum", &[("amplitude", 0.0)]));
    let reference = rigid
        .simulate(
            &State::new(0.0, [theta0], [0.0]),
            horizon,
            Method::Adaptive { tol: Tolerances::uniform(1e-12) },
            &Output::Ends,
        )
        .expect("integrates");
    let mut steps = Vec::new();
    for k in STIFFNESSES {
        let p = params("spring_pendulum", &[("stiffness", k)]);
        let mut system = build("spring_pendulum", &p);
        let initial = State::new(0.0, [1.0 + 9.81 * theta0.cos() / k, theta0], [0.0, 0.0]);
        let e_eq = system.energy_function(0.0, &[1.0 + 9.81 / k, 0.0], &[0.0, 0.0]).expect("valid");
        let swing = system.energy_function(0.0, &initial.q, &initial.qdot).expect("valid") - e_eq;
        let method = Method::Implicit { tol: Tolerances::uniform(tol) };
        let run = system.simulate(&initial, horizon, method, &Output::Every(0.1)).expect("integrates");
        let growth = run.energy.iter().map(|e| e - run.energy[0]).fold(0.0, f64::max) / swing;
        assert!(growth <= 10.0 * tol, "k/m = {k:e}: the energy grew by {growth:e} of the swing's");
        steps.push(run.stats.steps);
        // Stiff enough to be rigid (the stretch m g/k ≤ 1e-7): the rigid pendulum's swing, to
        // the global error of tol 1e-6 over 2 s (≤ 100 tol).
        if k >= 1e8 {
            let theta = run.last_state().expect("recorded").q[1];
            let residual = (theta - reference.q(1)[0]).abs();
            assert!(
                residual <= 100.0 * tol,
                "k/m = {k:e}: θ(2 s) expected {}, got {theta}, residual {residual:e}",
                reference.q(1)[0]
            );
        }
    }
    // The cost does not grow with the stiffness (the explicit method's grows like ω).
    assert!(steps.iter().all(|&s| s <= 2 * steps[0]), "SDIRK4 steps at k/m = 1e2 … 1e12: {steps:?}");
}

#[test]
fn sdirk_follows_the_slow_mode_of_the_strongly_damped_oscillator() {
    let (k, c) = DAMPED;
    let p = params("harmonic_oscillator", &[("stiffness", k), ("damping", c)]);
    let system = build("harmonic_oscillator", &p);
    let oscillator = lagrange_scenes::harmonic_oscillator::HarmonicOscillator::from_params(&p).expect("valid");
    let (fast, _) = damped_roots(k, c);
    let initial = State::new(0.0, [0.1], [0.0]);
    let (x, v) = oscillator.motion(0.1, 0.0, 1.0);
    for tol in [1e-3, 1e-6, 1e-9] {
        let tol = Tolerances::uniform(tol);
        let implicit = system.simulate(&initial, 1.0, Method::Implicit { tol }, &Output::Ends).expect("integrates");
        let explicit = system.simulate(&initial, 1.0, Method::Adaptive { tol }, &Output::Ends).expect("integrates");
        let error = (implicit.q[1] - x).abs().max((implicit.qdot[1] - v).abs());
        assert!(
            error <= 10.0 * tol.rtol,
            "tol {:e}: expected x = {x}, got {}, residual {error:e}",
            tol.rtol,
            implicit.q[1]
        );
        // L-stable: steps set by the slow mode, ≥ 10 times the explicit boundary 3.3/|λ_fast| on
        // average — the explicit method needs at least 1/3.3 of |λ_fast| steps per second, and
        // says the problem is stiff.
        let mean = -fast / implicit.stats.steps as f64;
        assert!(mean >= 10.0 * dopri5_real_axis_limit(), "tol {:e}: mean |λ| h = {mean}", tol.rtol);
        assert!(explicit.stats.steps as f64 >= 0.99 * -fast / dopri5_real_axis_limit(), "{:?}", explicit.stats);
        assert!(explicit.stats.stiffness.is_some_and(|t| t < 1e-3), "stiffness not detected: {:?}", explicit.stats);
    }
}

#[test]
fn variational_integrator_converges_under_strong_damping() {
    // m = 1, k = 10, c = 150: c h/m = 1.5 at h = 0.01. The damping force depends on the unknown
    // increment, so Newton needs ∂Q/∂Δq in its matrix; without it Newton contracted only by
    // c h/(2m) per iteration and failed at t = 0 (regression). Check convergence and the order:
    // the forced midpoint scheme is second order, so halving h divides the error against the
    // closed-form overdamped solution by 4 (±25 %).
    let scene = lagrange_scenes::find("harmonic_oscillator").expect("registered");
    let p = params("harmonic_oscillator", &[("damping", 150.0)]);
    let system = build("harmonic_oscillator", &p);
    let initial = State::new(0.0, [0.1], [0.0]);
    let exact = scene.exact_solution(&p, &initial, 1.0).expect("valid").expect("closed form");
    let errors: Vec<f64> = [0.01, 0.005, 0.0025]
        .iter()
        .map(|&dt| {
            let run = system.simulate(&initial, 1.0, Method::Variational { dt }, &Output::Ends);
            let last = run.unwrap_or_else(|e| panic!("dt = {dt}: {e}")).last_state().expect("recorded");
            (last.q[0] - exact.q[0]).abs()
        })
        .collect();
    for w in errors.windows(2) {
        assert!((3.0..=5.0).contains(&(w[0] / w[1])), "errors {errors:?} are not second order");
    }
}

#[test]
fn gauss_starts_from_rest_at_the_static_stretch() {
    // The spring pendulum (k/m = 100, ω dt = 0.1) released at rest at θ = 1 from its static
    // stretch r = L0 + g cos θ/ω²: ṙ = 0 and r̈ = 0, so the radial velocity grows from zero and
    // the scaled Newton update of that component rose once before converging (regression: that
    // single rise was declared a failure at t = 0). Check the run and its order: fourth order,
    // so halving h divides the error against a tol-1e-13 adaptive reference by 16 (±25 %).
    let system = build("spring_pendulum", &params("spring_pendulum", &[]));
    let initial = State::new(0.0, [1.0 + 9.81 * 1f64.cos() / 100.0, 1.0], [0.0, 0.0]);
    let reference = system
        .simulate(&initial, 1.0, Method::Adaptive { tol: Tolerances::uniform(1e-13) }, &Output::Ends)
        .expect("integrates")
        .last_state()
        .expect("recorded");
    let errors: Vec<f64> = [0.02, 0.01, 0.005]
        .iter()
        .map(|&dt| {
            let run = system.simulate(&initial, 1.0, Method::Gauss { dt }, &Output::Ends);
            let last = run.unwrap_or_else(|e| panic!("dt = {dt}: {e}")).last_state().expect("recorded");
            last.q.iter().zip(&reference.q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
        })
        .collect();
    for w in errors.windows(2) {
        assert!((12.0..=20.0).contains(&(w[0] / w[1])), "errors {errors:?} are not fourth order");
    }
}

#[test]
fn gauss_follows_the_slow_swing_of_a_stiff_spring_pendulum_at_any_omega_dt() {
    // Released at rest from the static stretch at θ = 1, k/m = 1e4 … 1e12 at dt = 0.01 (ω dt =
    // 1 … 1e4): the stiff radial mode is not excited and Gauss (A-stable) steps over it. Its
    // stage velocity ṙ stays near zero with round-off of order ε ω² h, which the Newton test
    // used to take for non-convergence (regression: NewtonFailed at t = 0 for k/m ≥ 1e6).
    // Measured: relative energy error 6.7e-10 … 6.9e-10 at every k/m (the slow swing's
    // O((Ω dt)⁴) error, Ω² = g), |θ − θ_ref| ≤ 3.3e-9 against SDIRK4 at tol 1e-10; bounds 1e-8
    // for both (≥ 3× margin).
    for k in [1e4, 1e6, 1e8, 1e10, 1e12] {
        let system = build("spring_pendulum", &params("spring_pendulum", &[("stiffness", k)]));
        let released = State::new(0.0, [1.0 + 9.81 * 1f64.cos() / k, 1.0], [0.0, 0.0]);
        let run = system.simulate(&released, 2.0, Method::Gauss { dt: 0.01 }, &Output::Every(0.1));
        let run = run.unwrap_or_else(|e| panic!("k/m = {k:e}: {e}"));
        let energy = relative_energy_error(&run.energy);
        assert!(energy <= 1e-8, "k/m = {k:e}: relative energy error {energy:e}");
        let reference = system
            .simulate(&released, 2.0, Method::Implicit { tol: Tolerances::uniform(1e-10) }, &Output::Ends)
            .expect("integrates")
            .last_state()
            .expect("recorded");
        let theta = (run.last_state().expect("recorded").q[1] - reference.q[1]).abs();
        assert!(theta <= 1e-8, "k/m = {k:e}: |θ − θ_ref| = {theta:e}");
    }
}
