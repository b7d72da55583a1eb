//! The implicit integrators (Gauss4, Sdirk4), stiffness detection in Dopri5, and divergence
//! reports of every integrator.

use super::{assert_order, final_state};
use crate::integrate::*;
use crate::ode::tests::WithoutJacobian;
use crate::test_support::{Spring, cart};
use crate::{Error, Model, State};
use lagrange_testing::max_abs_diff;

#[test]
fn gauss4_is_fourth_order_on_the_cart_pendulum() {
    // Order 4: ratio 2⁴ = 16 per halving, ±25 % for the asymptotic regime (measured 16.0).
    assert_order(&State::new(0.0, [0.0, 0.5], [0.0, 0.0]), [0.04, 0.02, 0.01], |dt| Method::Gauss4 { dt }, 12.0..20.0);
}

/// Gauss methods conserve quadratic invariants exactly; with Newton solved to round-off, the
/// energy of the linear oscillator moves only by round-off.
#[test]
fn gauss4_conserves_the_linear_oscillator_energy_to_round_off() {
    let model = Model::new(Spring::new(1.0, 10.0, 0.0)).unwrap();
    let initial = State::new(0.0, [0.1], [0.0]);
    let (dt, steps) = (0.01, 100_000);
    let t_end = steps as f64 * dt;
    let relative_drift = |method| {
        let traj = simulate(&model, &initial, t_end, method, &Output::Every(100.0 * dt)).unwrap();
        traj.energy.iter().map(|e| (e - traj.energy[0]).abs() / traj.energy[0]).fold(0.0, f64::max)
    };
    let gauss = relative_drift(Method::Gauss4 { dt });
    // Each step changes h by O(ε) with a random sign: after N = 1e5 steps ~ε√N ≈ 7e-14
    // (measured 3.1e-14); 1e-12 leaves a factor 14.
    assert!(gauss <= 1e-12, "Gauss4 energy error {gauss:e} over {steps} steps");
    // RK4 at the same step is dissipative at (ωh)⁶/72 per unit of ωt: ~1e-6 here.
    let rk4 = relative_drift(Method::Rk4 { dt });
    assert!(rk4 > 1e4 * gauss, "RK4 energy error {rk4:e} is not far above Gauss4's {gauss:e}");
}

#[test]
fn sdirk4_error_tracks_tolerance_on_a_smooth_problem() {
    // Cart pendulum over 2 s against a 1e-13 reference.
    let model = Model::new(cart(2.0, 1.0, 1.0)).unwrap();
    let initial = State::new(0.0, [0.0, 0.5], [0.0, 0.0]);
    let reference = final_state(&model, &initial, 2.0, Method::Dopri5 { tol: Tolerances::uniform(1e-13) });
    let mut previous = f64::INFINITY;
    for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let err = max_abs_diff(
            &final_state(&model, &initial, 2.0, Method::Sdirk4 { tol: Tolerances::uniform(tol) }),
            &reference,
        );
        // Proportional to the tolerance: within [tol/100, 10 tol] (measured 1.0–1.3 tol), and
        // decreasing with it.
        assert!(err <= 10.0 * tol && err >= 0.01 * tol, "tol {tol}: error {err:e}");
        assert!(err < previous, "tol {tol}: error {err:e} not below {previous:e}");
        previous = err;
    }
    // The oscillator at requested output times (the steps land on them).
    let spring = Model::new(Spring::new(1.0, 10.0, 0.0)).unwrap();
    let omega = 10.0_f64.sqrt();
    let times: Vec<f64> = (0..=50).map(|k| k as f64 * 0.2).collect();
    for tol in [1e-4, 1e-7, 1e-10] {
        let method = Method::Sdirk4 { tol: Tolerances::uniform(tol) };
        let traj =
            simulate(&spring, &State::new(0.0, [0.1], [0.0]), 10.0, method, &Output::Times(times.clone())).unwrap();
        assert_eq!(traj.t, times);
        let err = (0..traj.len()).map(|k| (traj.q(k)[0] - 0.1 * (omega * traj.t[k]).cos()).abs()).fold(0.0, f64::max);
        // Global error within 100 tol, as for Dopri5 (local control, 5 periods of accumulation).
        assert!(err < 100.0 * tol, "tol {tol}: error {err:e}");
    }
}

/// `m ẍ = −k (x − A sin t)` with `k/m = 1e8` (`ω = 1e4`) from the slow solution: the L-stable
/// method takes steps with `ω h ≈ 20` and keeps to the slow solution; RK4 with the same mean
/// step blows up.
#[test]
fn sdirk4_is_stable_and_accurate_on_a_stiff_oscillator() {
    let spring = Spring::driven(1.0, 1e8, 0.1);
    let (omega, amplitude) = (1e4, spring.slow_amplitude());
    let model = Model::new(spring).unwrap();
    let initial = State::new(0.0, [0.0], [amplitude]);
    let tol = 1e-4;
    let method = Method::Sdirk4 { tol: Tolerances::uniform(tol) };
    let traj = simulate(&model, &initial, 10.0, method, &Output::Every(0.5)).unwrap();
    let mean_step = 10.0 / traj.stats.steps as f64;
    assert!(omega * mean_step >= 10.0, "ω h = {} ({:?})", omega * mean_step, traj.stats);
    for k in 0..traj.len() {
        let t = traj.t[k];
        let (x, v) = (traj.q(k)[0], traj.qdot(k)[0]);
        let (x_exact, v_exact) = (amplitude * t.sin(), amplitude * t.cos());
        // Position: within tol × amplitude (measured 1.2e-8). Velocity: the fast mode carries ω
        // times the position deviation into q̇, within 10 tol (measured 1.1e-4).
        assert!((x - x_exact).abs() <= tol * amplitude, "t = {t}: x = {x}, expected {x_exact}");
        assert!((v - v_exact).abs() <= 10.0 * tol, "t = {t}: v = {v}, expected {v_exact}");
    }
    // Far outside the explicit stability region (RK4: ω h ≤ 2.8).
    let explicit = simulate(&model, &initial, 10.0, Method::Rk4 { dt: mean_step }, &Output::Ends);
    assert!(matches!(explicit, Err(Error::Diverged { .. })), "{explicit:?}");
}

/// `ẍ = −c ẋ − k x` with `c = 1e4`, `k = 1`: eigenvalues `≈ −1e4` (the velocity relaxes at
/// once) and `≈ −1e-4` (slow creep). The exact solution is the sum of the two exponentials.
#[test]
fn sdirk4_damps_a_strongly_damped_oscillator() {
    let model = Model::new(Spring::new(1.0, 1.0, 1e4)).unwrap();
    let (c, k) = (1e4_f64, 1.0_f64);
    let root = (c * c - 4.0 * k).sqrt();
    let (slow, fast) = ((-c + root) / 2.0, (-c - root) / 2.0);
    let exact = |t: f64| {
        let x = (fast * (slow * t).exp() - slow * (fast * t).exp()) / (fast - slow);
        let v = slow * fast * ((slow * t).exp() - (fast * t).exp()) / (fast - slow);
        (x, v)
    };
    let tol = 1e-6;
    let method = Method::Sdirk4 { tol: Tolerances::uniform(tol) };
    let traj = simulate(&model, &State::new(0.0, [1.0], [0.0]), 10.0, method, &Output::Every(0.5)).unwrap();
    for i in 0..traj.len() {
        let (x, v) = exact(traj.t[i]);
        // Within the tolerance (measured 1e-12).
        assert!((traj.q(i)[0] - x).abs() <= tol && (traj.qdot(i)[0] - v).abs() <= tol, "t = {}", traj.t[i]);
        if i > 0 {
            assert!(traj.energy[i] < traj.energy[i - 1], "energy grows at t = {}: {:?}", traj.t[i], traj.energy);
        }
    }
    // Steps for the slow time scale, not the fast one (Dopri5 needs ~3e4 here; measured 18).
    assert!(traj.stats.steps <= 100, "{:?}", traj.stats);
}

#[test]
fn dopri5_flags_stiffness_on_a_stiff_damped_problem() {
    let damped = Model::new(Spring::new(1.0, 1.0, 1e4)).unwrap();
    let method = Method::Dopri5 { tol: Tolerances::uniform(1e-6) };
    let traj = simulate(&damped, &State::new(0.0, [1.0], [0.0]), 1.0, method, &Output::Ends).unwrap();
    // The stability limit h |λ| ≈ 3.3 binds from the first steps on (λ ≈ −1e4).
    let flagged = traj.stats.stiffness.expect("stiffness detected");
    assert!(flagged < 0.05, "flagged at t = {flagged}");
    // Not on a smooth non-stiff problem.
    let cart = Model::new(cart(2.0, 1.0, 1.0)).unwrap();
    let traj = simulate(&cart, &State::new(0.0, [0.0, 0.5], [0.0, 0.0]), 5.0, method, &Output::Ends).unwrap();
    assert_eq!(traj.stats.stiffness, None);
    // A collapse after the test fired says so and points to the implicit integrator.
    let mut dopri = Dopri5::new(1, Tolerances::uniform(1e-6)).unwrap();
    let mut ws = damped.workspace();
    dopri.start(&damped, &mut ws, 0.0, &[1.0], &[0.0], 1.0).unwrap();
    while dopri.stats().stiffness.is_none() {
        dopri.step(&damped, &mut ws, 1.0).unwrap();
    }
    let t = dopri.t();
    let error = dopri.step(&damped, &mut ws, t * (1.0 + f64::EPSILON)).unwrap_err();
    assert!(matches!(error, Error::Stiff { .. }), "{error:?}");
    let message = error.to_string();
    assert!(message.contains("looks stiff") && message.contains("--integrator sdirk4"), "{message}");
}

/// `ẍ = 1e4 x` grows like `cosh(100 t)` and overflows near `t = 7.1`: every integrator reports a
/// divergence that names the quantity.
#[test]
fn divergence_messages_name_the_quantity() {
    let inverted = Model::new(Spring::new(1.0, -1e4, 0.0)).unwrap();
    let initial = State::new(0.0, [1.0], [0.0]);
    for method in [
        Method::Rk4 { dt: 1e-3 },
        Method::Gauss4 { dt: 1e-3 },
        Method::Variational { dt: 1e-3 },
        Method::Dopri5 { tol: Tolerances::uniform(1e-6) },
        Method::Sdirk4 { tol: Tolerances::uniform(1e-6) },
    ] {
        match simulate(&inverted, &initial, 10.0, method, &Output::Ends) {
            Err(Error::Diverged { t, quantity, .. }) => {
                assert!((6.5..7.5).contains(&t), "{}: diverged at t = {t}", method.name());
                // `q[x] = inf`, `q̇[x] = NaN`, or the stage that overflowed, with the state.
                let named = quantity.contains("[x] = ") || quantity.contains("q = [") || quantity.contains("q̇");
                assert!(named, "{}: `{quantity}` names no quantity", method.name());
                if matches!(method, Method::Gauss4 { .. } | Method::Sdirk4 { .. }) {
                    assert!(quantity.starts_with("Newton did not converge"), "{}: {quantity}", method.name());
                }
            }
            other => panic!("{}: {other:?}", method.name()),
        }
    }
    // A Gauss step far too large for the motion: Newton fails, and says so.
    let cart = Model::new(cart(2.0, 1.0, 1.0)).unwrap();
    let result =
        simulate(&cart, &State::new(0.0, [0.0, 3.0], [0.0, 5.0]), 20.0, Method::Gauss4 { dt: 2.0 }, &Output::Ends);
    assert!(matches!(result, Err(Error::NewtonFailed { t: 0.0, .. })), "{result:?}");
}

#[test]
fn implicit_methods_report_their_work_and_run_on_finite_difference_jacobians() {
    let model = Model::new(cart(2.0, 1.0, 1.0)).unwrap();
    let initial = State::new(0.0, [0.0, 0.5], [0.3, 0.0]);
    let tol = Tolerances::uniform(1e-8);
    let exact = simulate(&model, &initial, 2.0, Method::Sdirk4 { tol }, &Output::Ends).unwrap();
    let stats = exact.stats;
    assert!(stats.steps > 0 && stats.jacobians > 0 && stats.factorizations > 0 && stats.newton_iterations > 0);
    assert!(stats.evaluations >= stats.newton_iterations && stats.stiffness.is_none(), "{stats:?}");
    let gauss = simulate(&model, &initial, 2.0, Method::Gauss4 { dt: 0.01 }, &Output::Ends).unwrap();
    assert_eq!(gauss.stats.steps, 200);
    assert!(gauss.stats.jacobians > 0 && gauss.stats.newton_iterations >= 200, "{:?}", gauss.stats);
    // A system without AD derivatives gets the default finite-difference Jacobian: Newton
    // converges as well, to the same results (simplified Newton tolerates an inexact matrix).
    let fallback = WithoutJacobian(Model::new(cart(2.0, 1.0, 1.0)).unwrap());
    let approximate = simulate(&fallback, &initial, 2.0, Method::Sdirk4 { tol }, &Output::Ends).unwrap();
    assert!(max_abs_diff(exact.q(1), approximate.q(1)) <= 1e-8, "{:?} vs {:?}", exact.q(1), approximate.q(1));
    let approximate = simulate(&fallback, &initial, 2.0, Method::Gauss4 { dt: 0.01 }, &Output::Ends).unwrap();
    assert!(max_abs_diff(gauss.q(1), approximate.q(1)) <= 1e-13, "{:?} vs {:?}", gauss.q(1), approximate.q(1));
    assert_eq!([Method::Sdirk4 { tol }.name(), Method::Gauss4 { dt: 0.1 }.name()], ["sdirk4", "gauss4"]);
}
