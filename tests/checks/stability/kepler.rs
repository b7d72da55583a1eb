//! A nearly parabolic Kepler orbit, `e = 0.99`, over 100 periods: the adaptive method keeps the
//! energy and the period; fixed-step methods given the same work fail at the first perihelion.

use super::{build, params, relative_energy_error, scene};
use lagrange::{Method, Output, State, Tolerances};
use lagrange_scenes::SceneType;
use lagrange_scenes::kepler::Kepler;

const ECCENTRICITY: f64 = 0.99;
const ORBITS: f64 = 100.0;

/// `m = k = 1`, starting at aphelion `r = a (1 + e)` with `a = 100` (perihelion `r = 1`), so that
/// a fixed-step method has half an orbit of easy going before its first perihelion passage.
fn orbit() -> (Kepler, State, f64) {
    let kepler = Kepler::from_params(&params("kepler", &[])).expect("valid");
    let (a, e) = (100.0, ECCENTRICITY);
    let r = a * (1.0 + e);
    // Vis-viva at aphelion: v² = μ (1 − e)/r_a.
    let theta_dot = ((1.0 - e) / r).sqrt() / r;
    let initial = State::new(0.0, [r, 0.0], [0.0, theta_dot]);
    let period = kepler.orbit(&initial.q, &initial.qdot).period.expect("bound");
    (kepler, initial, period)
}

#[test]
fn adaptive_keeps_energy_and_period_over_a_hundred_orbits_at_e_099() {
    let (kepler, initial, period) = orbit();
    let elements = kepler.orbit(&initial.q, &initial.qdot);
    assert!((elements.eccentricity - ECCENTRICITY).abs() < 1e-12, "e = {}", elements.eccentricity);
    let system = build("kepler", &params("kepler", &[]));
    // Saved at every aphelion and perihelion (k/2 periods).
    let times: Vec<f64> = (0..=(2.0 * ORBITS) as usize).map(|k| k as f64 * period / 2.0).collect();
    let t_end = ORBITS * period;
    let run = system
        .simulate(&initial, t_end, Method::Adaptive { tol: Tolerances::uniform(1e-13) }, &Output::Times(times))
        .expect("integrates");
    // The bound on the energy (measured 4.8e-9 at tol 1e-13; tol 1e-12 gives 5e-8).
    let energy_error = relative_energy_error(&run.energy);
    assert!(energy_error <= 1e-8, "relative energy error over 100 orbits: {energy_error:e} > 1e-8");
    // The period, from the time of the 100th perihelion passage: at t = 99.5 P the exact orbit
    // is at perihelion (ṙ = 0, r̈ = r θ̇² − 1/r² = e = 0.99 at r = 1), so the integrated ṙ there
    // says how early or late it arrives: δt = ṙ / r̈. Kepler's third law P ∝ |E|^{-3/2} turns
    // the energy bound into |δP/P| ≤ 1.5 · 1e-8.
    let k = run.len() - 2;
    assert!((run.t[k] - 99.5 * period).abs() < 1e-6 * period);
    let late = -run.qdot(k)[0] / ECCENTRICITY;
    let period_error = late / run.t[k];
    assert!(period_error.abs() <= 1.5e-8, "period: {:.3e} s late after 99.5 P, relative {period_error:e}", late);
    // Against Kepler's equation at the last aphelion: r to the same relative accuracy.
    let exact =
        scene("kepler").exact_solution(&params("kepler", &[]), &initial, t_end).expect("valid").expect("ellipse");
    let got = run.last_state().expect("recorded");
    assert!((got.q[0] / exact.q[0] - 1.0).abs() <= 1e-8, "r at 100 P: expected {}, got {}", exact.q[0], got.q[0]);
}

#[test]
fn fixed_steps_at_the_same_cost_fail_at_the_first_perihelion() {
    let (_, initial, period) = orbit();
    let system = build("kepler", &params("kepler", &[]));
    let t_end = ORBITS * period;
    let adaptive = system
        .simulate(&initial, t_end, Method::Adaptive { tol: Tolerances::uniform(1e-13) }, &Output::Ends)
        .expect("integrates");
    // RK4 with the adaptive run's evaluations (4 per step): dt ≈ 2.3 s, fine at aphelion where
    // the orbit turns in ~1e4 s, far too long at perihelion where it turns in ~1 s. Gauss with
    // the adaptive run's steps (each costs it more evaluations): dt ≈ 3.4 s.
    let rk4 = t_end / (adaptive.stats.evaluations / 4) as f64;
    let gauss = t_end / adaptive.stats.steps as f64;
    for method in [Method::Rk4 { dt: rk4 }, Method::Gauss { dt: gauss }] {
        let dt = if let Method::Rk4 { dt } | Method::Gauss { dt } = method { dt } else { unreachable!() };
        let every = (0.45 * period / dt).round() * dt;
        match system.simulate(&initial, t_end, method, &Output::Every(every)) {
            Ok(run) => {
                // Finite to the end, but the energy is lost at the perihelion passage.
                let good = relative_energy_error(&run.energy[..2]);
                let bad = relative_energy_error(&run.energy);
                assert!(good <= 1e-6 && bad >= 1e-2, "{method:?}: energy error {good:e} before, {bad:e} after");
            }
            Err(lagrange::Error::Diverged { t, .. } | lagrange::Error::NewtonFailed { t, .. }) => {
                // Failed at the first perihelion passage, t = P/2.
                assert!((t / period - 0.5).abs() < 0.01, "{method:?} failed at t = {t}, not at P/2 = {}", period / 2.0);
            }
            Err(other) => panic!("{method:?}: {other}"),
        }
    }
}
