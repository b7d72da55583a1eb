//! Integrators: observed order, error against tolerance, structure preservation over 10⁶
//! steps, and the closed-form periods of the lecture's systems.

use lagrange::{Method, Output, State, Tolerances};
use lagrange_scenes::SceneType;
use lagrange_tests::max_abs_diff;
use std::f64::consts::PI;
use std::ops::Range;

use lagrange_tests::scene;

/// Final `(q, q̇)` of a run of the default scene.
fn final_state(id: &str, initial: &State, t_end: f64, method: Method) -> Vec<f64> {
    let s = scene(id);
    let system = s.build(&s.default_params()).expect("defaults are valid");
    let trajectory = system.simulate(initial, t_end, method, &Output::Ends).expect("integrates");
    let last = trajectory.last_state().expect("recorded");
    [last.q, last.qdot].concat()
}

/// On each scene over 3 s, every halving of the step divides the error of `method(dt)` against
/// a 1e-14 reference by a ratio in `ratios`.
fn assert_order(ids: &[&str], steps: [f64; 3], method: fn(f64) -> Method, ratios: Range<f64>) {
    for id in ids {
        let s = scene(id);
        let initial = s.default_state(&s.default_params()).expect("valid");
        let reference = final_state(id, &initial, 3.0, Method::Dopri5 { tol: Tolerances::uniform(1e-14) });
        let errors: Vec<f64> =
            steps.iter().map(|&dt| max_abs_diff(&final_state(id, &initial, 3.0, method(dt)), &reference)).collect();
        let observed: Vec<f64> = errors.windows(2).map(|w| w[0] / w[1]).collect();
        assert!(observed.iter().all(|r| ratios.contains(r)), "{id}: errors {errors:?}, ratios {observed:?}");
    }
}

#[test]
fn rk4_error_falls_sixteenfold_per_halving() {
    // Order 4: 2⁴ = 16 per halving; ±25 % for pre-asymptotic terms at these steps.
    let ids = ["cart_pendulum", "double_pendulum", "kepler"];
    assert_order(&ids, [0.02, 0.01, 0.005], |dt| Method::Rk4 { dt }, 12.0..20.0);
}

#[test]
fn variational_error_falls_fourfold_per_halving() {
    // Order 2: 2² = 4 per halving, ±25 %.
    let ids = ["cart_pendulum", "double_pendulum", "spring_pendulum", "driven_pendulum"];
    assert_order(&ids, [0.01, 0.005, 0.0025], |dt| Method::Variational { dt }, 3.0..5.0);
}

#[test]
fn adaptive_error_tracks_its_tolerance() {
    // Kepler from the default orbit (e ≈ 0.44), against Kepler's equation, over two periods.
    let s = scene("kepler");
    let params = s.default_params();
    let initial = s.default_state(&params).expect("valid");
    let system = s.build(&params).expect("valid");
    let times: Vec<f64> = (0..=60).map(|k| k as f64 * 0.5).collect();
    let tolerances = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13];
    let mut ratios = Vec::new();
    for tol in tolerances {
        let method = Method::Dopri5 { tol: Tolerances::uniform(tol) };
        let trajectory = system.simulate(&initial, 30.0, method, &Output::Times(times.clone())).expect("integrates");
        let mut error: f64 = 0.0;
        for k in 0..trajectory.len() {
            let exact = s.exact_solution(&params, &initial, trajectory.t[k]).expect("valid").expect("elliptic orbit");
            error = error.max(max_abs_diff(trajectory.q(k), &exact.q));
        }
        ratios.push(error / tol);
    }
    // DOPRI5 propagates the 5th-order solution while controlling the 4th-order estimate, so the
    // global error is proportional to the tolerance: error = C tol. C depends on the problem
    // and horizon (measured ≈ 250 here: the Kepler phase error grows linearly over two
    // revolutions). Proportionality means C stays within a factor 1.5 of its geometric mean
    // over these seven decades (measured spread: 240–310).
    let mean = (ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64).exp();
    for (tol, ratio) in tolerances.iter().zip(&ratios) {
        assert!(
            ratio / mean < 1.5 && mean / ratio < 1.5,
            "tol {tol:e}: error/tol = {ratio:.1}, mean {mean:.1}; all {ratios:?}"
        );
    }
}

#[test]
fn variational_conserves_cart_momentum_and_energy_over_a_million_steps() {
    let s = scene("cart_pendulum");
    let params = s.default_params();
    let mut initial = s.default_state(&params).expect("valid");
    initial.qdot[0] = 0.3; // a moving cart: p_X ≠ 0
    let mut system = s.build(&params).expect("valid");
    let p0 = system.momenta(initial.t, &initial.q, &initial.qdot).expect("valid")[0];
    let e0 = system.energy_function(initial.t, &initial.q, &initial.qdot).expect("valid");
    let dt = 0.01;
    let steps = 1_000_000;
    let trajectory = system
        .simulate(&initial, steps as f64 * dt, Method::Variational { dt }, &Output::Every(1000.0 * dt))
        .expect("integrates");
    assert_eq!(trajectory.stats.steps, steps);
    let mut energy_error = Vec::with_capacity(trajectory.len());
    for k in 0..trajectory.len() {
        let p = system.momenta(trajectory.t[k], trajectory.q(k), trajectory.qdot(k)).expect("valid")[0];
        // Discrete Noether: each step conserves p_X up to its final Newton residual, a few ε|p|;
        // 10⁶ steps accumulate at most 4ε|p| each: 1e6 × 4 × 2.2e-16 ≈ 1e-9 relative.
        assert!((p - p0).abs() <= 1e-9 * p0.abs(), "t = {}: p_X = {p} vs {p0}", trajectory.t[k]);
        energy_error.push((trajectory.energy[k] - e0).abs());
    }
    // Bounded energy error, no drift: the largest error of the last tenth of the run is no
    // larger than that of the first tenth (within 50 %: both windows sample the same bounded
    // oscillation), and both are O(h²).
    let tenth = energy_error.len() / 10;
    let first = energy_error[..tenth].iter().cloned().fold(0.0, f64::max);
    let last = energy_error[energy_error.len() - tenth..].iter().cloned().fold(0.0, f64::max);
    assert!(last <= 1.5 * first, "energy error grows: first tenth {first:e}, last tenth {last:e}");
    assert!(first <= 1e-3 * e0.abs(), "energy error {first:e} not O(h²) of |E| = {}", e0.abs());
}

#[test]
fn kepler_orbit_closes_after_its_period() {
    let s = scene("kepler");
    let params = s.default_params();
    let initial = s.default_state(&params).expect("valid");
    let kepler = lagrange_scenes::kepler::Kepler::from_params(&params).expect("valid");
    let orbit = kepler.orbit(&initial.q, &initial.qdot);
    let period = orbit.period.expect("bound orbit");
    // docs/scenes.md#kepler: P = 2π sqrt(m a³/k); the default orbit starts at an apsis (ṙ = 0), so
    // after exactly one period it is back at the same point with θ advanced by 2π.
    let system = s.build(&params).expect("valid");
    let trajectory = system
        .simulate(&initial, period, Method::Dopri5 { tol: Tolerances::uniform(1e-13) }, &Output::Ends)
        .expect("integrates");
    let last = trajectory.last_state().expect("recorded");
    let expected = [initial.q[0], initial.q[1] + 2.0 * PI, initial.qdot[0], initial.qdot[1]];
    let got = [last.q[0], last.q[1], last.qdot[0], last.qdot[1]];
    // Tolerance 1e-13 per step, ~1e3 steps: global error ≲ 1e-10; 1e-9 leaves a margin of 10.
    assert!(max_abs_diff(&got, &expected) <= 1e-9, "after P = {period}: {got:?} vs {expected:?}");
}

#[test]
fn cart_pendulum_oscillates_at_the_small_oscillation_frequency() {
    let s = scene("cart_pendulum");
    let params = s.default_params();
    let cart = lagrange_scenes::cart_pendulum::CartPendulum::from_params(&params).expect("valid");
    // ω² = g (M + m)/(M r) (docs/scenes.md#cart_pendulum): released at rest, the centre of mass stays put and
    // θ(t) = θ₀ cos ωt up to O(θ₀²) corrections of the frequency.
    let omega = cart.small_oscillation_frequency();
    let theta0 = 1e-4;
    let initial = State::new(0.0, [0.0, theta0], [0.0, 0.0]);
    let period = 2.0 * PI / omega;
    let system = s.build(&params).expect("valid");
    let dt = period / 2000.0;
    let trajectory = system
        .simulate(&initial, 10.5 * period, Method::Dopri5 { tol: Tolerances::uniform(1e-13) }, &Output::Every(dt))
        .expect("integrates");
    // Downward zero crossings of θ, located by linear interpolation between samples (θ is
    // linear there to O(dt³)).
    let mut crossings = Vec::new();
    for k in 1..trajectory.len() {
        let (a, b) = (trajectory.q(k - 1)[1], trajectory.q(k)[1]);
        if a > 0.0 && b <= 0.0 {
            crossings.push(trajectory.t[k - 1] + dt * a / (a - b));
        }
    }
    assert!(crossings.len() >= 10, "only {} crossings", crossings.len());
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    // Amplitude correction ≈ θ₀²/16 = 6e-10; interpolation and integration errors below 1e-9.
    let relative = (measured - period).abs() / period;
    assert!(relative <= 1e-8, "measured period {measured}, 2π/ω = {period}, relative {relative:e}");
}

#[test]
fn fixed_step_methods_land_on_the_requested_times() {
    let s = scene("harmonic_oscillator");
    let params = s.default_params();
    let initial = s.default_state(&params).expect("valid");
    let system = s.build(&params).expect("valid");
    for method in [Method::Rk4 { dt: 0.001 }, Method::Variational { dt: 0.001 }] {
        let trajectory = system.simulate(&initial, 1.0005, method, &Output::Every(0.25)).expect("integrates");
        assert_eq!(trajectory.t, vec![0.0, 0.25, 0.5, 0.75, 1.0, 1.0005]);
        for k in 0..trajectory.len() {
            let exact = s.exact_solution(&params, &initial, trajectory.t[k]).expect("valid").expect("closed form");
            // RK4 error O(dt⁴) ≈ 1e-12, variational O(dt²) ω² x ≈ 1e-6 × 0.1: bound 1e-6.
            assert!(max_abs_diff(trajectory.q(k), &exact.q) <= 1e-6, "{method:?} at t = {}", trajectory.t[k]);
        }
    }
}

/// A sink that asks the run to stop (`Sink::keep_going`) stops it at the first step past its
/// mark with `Error::Stopped`, for every method, and keeps the samples recorded before.
#[test]
fn a_sink_stops_a_run_and_keeps_its_samples() {
    use lagrange::Trajectory;
    use lagrange::integrate::{MethodKind, Sample, Sink, Stats};
    struct Until(Trajectory, f64);
    impl Sink for Until {
        fn record(&mut self, sample: Sample<'_>) {
            self.0.record(sample);
        }
        fn finish(&mut self, stats: Stats) {
            self.0.finish(stats);
        }
        fn keep_going(&mut self, t: f64) -> bool {
            t < self.1
        }
    }
    let s = scene("double_pendulum");
    let params = s.default_params();
    let initial = s.default_state(&params).expect("valid");
    let system = s.build(&params).expect("valid");
    for kind in MethodKind::ALL {
        let mut sink = Until(Trajectory::with_capacity(2, 0), 1.0);
        let result = system.simulate_into(&initial, 3.0, kind.default_method(), &Output::Every(0.1), &mut sink);
        match result {
            Err(lagrange::Error::Stopped { t, steps }) => {
                assert!((1.0..1.2).contains(&t) && steps > 0, "{kind:?}: stopped at t = {t} after {steps} steps");
            }
            other => panic!("{kind:?}: {other:?}"),
        }
        // Samples at 0, 0.1, …, up to the last one before the stop.
        assert!((10..=12).contains(&sink.0.len()), "{kind:?}: {} samples", sink.0.len());
    }
}
