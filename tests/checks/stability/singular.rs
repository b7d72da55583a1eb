//! Near-singular configurations: a typed error or a regular value, never a NaN.
//!
//! What the engine does, as measured and asserted here:
//! - the fully stretched double pendulum (`θ₁ = θ₂`) is a regular configuration in these
//!   coordinates: `det M = l₁² l₂² m₂ (m₁ + m₂ sin²(θ₁ − θ₂))` is `l₁² l₂² m₁ m₂ > 0` there, so the
//!   accelerations are the closed form's. Only with a (nearly) massless elbow does `M` become
//!   singular there; the engine then refuses with `SingularMassMatrix` naming `θ1` once the
//!   pivot falls below 1e-12 of its diagonal (its documented threshold), rather than dividing;
//! - polar coordinates at `r → 0`: `M = diag(m, m r²)` loses rank, so `r = 0` (and any `r` whose
//!   square underflows) is `SingularMassMatrix` for `θ`; where the potential itself is singular
//!   first (`−k/r` or `|x|` at the origin) it is `NonFinite` at the potential stage. For small
//!   finite `r` the accelerations are finite, with round-off amplified by `κ(M) = 1/r²`;
//! - a radial Kepler infall reaches `r = 0` at `t_c = (π/2) √(r₀³/2μ)`: the adaptive method stops
//!   there with a typed error; fixed steps either jump over the singularity (finite values,
//!   wrong energy) or fail with a typed error.

use super::{build, params, scene};
use lagrange::{Error, Method, Output, Stage, State, System, Tolerances};
use lagrange_scenes::SceneType;
use lagrange_tests::tolerance::conditioned;
use lagrange_tests::{condition_number, max_abs, max_abs_diff};

/// Every engine call at `(q, q̇)`: each returns finite values or a typed error.
fn assert_finite_or_error(what: &str, system: &mut dyn System, q: &[f64], qdot: &[f64]) {
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if let Ok(e) = system.energy_function(0.0, q, qdot) {
        assert!(e.is_finite(), "{what}: energy {e}");
    }
    if let Ok(a) = system.accelerations(0.0, q, qdot) {
        assert!(finite(a), "{what}: accelerations {a:?}");
    }
    if let Ok(m) = system.mass_matrix(0.0, q, qdot) {
        assert!(finite(m), "{what}: mass matrix {m:?}");
    }
    if let Ok(p) = system.momenta(0.0, q, qdot) {
        assert!(finite(p), "{what}: momenta {p:?}");
    }
    if let Ok(Some(r)) = system.reaction_forces(0.0, q, qdot) {
        assert!(finite(r), "{what}: reaction forces {r:?}");
    }
}

#[test]
fn fully_stretched_double_pendulum_is_regular_unless_the_elbow_is_massless() {
    let s = scene("double_pendulum");
    for m1 in [1.0, 1e-6] {
        let p = params("double_pendulum", &[("mass_1", m1)]);
        let mut system = build("double_pendulum", &p);
        for angle in [0.0, 0.7, std::f64::consts::PI] {
            let (q, qdot) = ([angle, angle], [1.0, -2.0]);
            let expected = s.closed_form_accelerations(&p, 0.0, &q, &qdot).expect("valid").expect("closed form");
            let got = system.accelerations(0.0, &q, &qdot).expect("regular").to_vec();
            let kappa = condition_number(2, system.mass_matrix(0.0, &q, &qdot).expect("valid"));
            let residual = max_abs_diff(&got, &expected) / max_abs(&expected).max(1.0);
            assert!(
                residual <= conditioned(kappa),
                "m1 = {m1:e}, θ = {angle}: expected {expected:?}, got {got:?}, residual {residual:e}, κ {kappa:e}"
            );
        }
    }
    // A massless elbow (m1 = 1e-12 m2): det M / (M11 M22) = m1/(m1 + m2) = 1e-12 at the
    // stretched configuration, below the engine's pivot threshold: a typed error naming θ1.
    let p = params("double_pendulum", &[("mass_1", 1e-12)]);
    let mut system = build("double_pendulum", &p);
    for q in [[0.7, 0.7], [0.7, 0.7 + 1e-8]] {
        match system.accelerations(0.0, &q, &[1.0, -2.0]) {
            Err(Error::SingularMassMatrix { coordinate, .. }) => assert_eq!(coordinate, "θ1"),
            other => panic!("q = {q:?}: expected SingularMassMatrix, got {other:?}"),
        }
        let run = system.simulate(&State::new(0.0, q, [1.0, -2.0]), 1.0, Method::Rk4 { dt: 0.01 }, &Output::Ends);
        assert!(matches!(run, Err(Error::SingularMassMatrix { .. })), "q = {q:?}: {run:?}");
    }
}

#[test]
fn polar_coordinates_at_the_origin_give_typed_errors() {
    for id in ["kepler", "isotropic_oscillator", "spring_pendulum"] {
        let mut system = build(id, &params(id, &[]));
        for r in [0.0, 1e-300, 1e-160, 1e-100, 1e-10, -1e-10] {
            for qdot in [[0.0, 0.0], [1.0, 0.5]] {
                let q = [r, 0.3];
                let what = format!("{id} at r = {r:e}, q̇ = {qdot:?}");
                assert_finite_or_error(&what, system.as_mut(), &q, &qdot);
                let result = system.accelerations(0.0, &q, &qdot).map(<[f64]>::to_vec);
                if r == 0.0 {
                    // At the origin itself the answer is always an error.
                    assert!(
                        matches!(
                            result,
                            Err(Error::SingularMassMatrix { ref coordinate, .. }) if coordinate == "θ"
                        ) || matches!(result, Err(Error::NonFinite { stage: Stage::Potential, .. })),
                        "{what}: {result:?}"
                    );
                }
            }
        }
    }
}

/// Regression: the energy once returned the potential's `−∞` at the origin as a value.
#[test]
fn energy_at_the_kepler_origin_is_an_error_not_infinity() {
    let mut system = build("kepler", &params("kepler", &[]));
    for r in [0.0, 1e-300] {
        let energy = system.energy_function(0.0, &[r, 0.3], &[0.0, 0.0]);
        assert!(matches!(energy, Err(Error::NonFinite { .. })), "r = {r:e}: {energy:?}");
    }
}

#[test]
fn radial_infall_stops_at_the_collision_with_a_typed_error() {
    let system = build("kepler", &params("kepler", &[]));
    let initial = State::new(0.0, [1.0, 0.0], [0.0, 0.0]);
    // Free fall from rest at r₀ = 1 under k/r² (m = k = 1): t_c = (π/2) √(1/2).
    let kepler = lagrange_scenes::kepler::Kepler::from_params(&params("kepler", &[])).expect("valid");
    let collision = kepler.radial_infall_time(1.0);
    assert!((collision - std::f64::consts::FRAC_PI_2 * 0.5f64.sqrt()).abs() <= 1e-15);
    let methods = [
        Method::Rk4 { dt: 0.01 },
        Method::Adaptive { tol: Tolerances::uniform(1e-8) },
        Method::Variational { dt: 0.01 },
    ];
    for method in methods {
        match system.simulate(&initial, 2.0, method, &Output::Every(0.01)) {
            Ok(run) => {
                let values = run.q.iter().chain(&run.qdot).chain(&run.energy);
                assert!(values.into_iter().all(|v| v.is_finite()), "{}: non-finite values returned", method.name());
            }
            Err(Error::StepSizeUnderflow { t, .. }) | Err(Error::Stiff { t, .. }) => {
                // The adaptive method runs into the singularity and stops there (to its step).
                assert!(
                    (t - collision).abs() < 1e-6,
                    "{}: stopped at t = {t}, collision at {collision}",
                    method.name()
                );
            }
            Err(Error::NewtonFailed { t, .. }) | Err(Error::Diverged { t, .. }) => {
                assert!(t <= collision + 0.01, "{}: failed at t = {t}, after the collision {collision}", method.name());
            }
            Err(other) => panic!("{}: unexpected error {other}", method.name()),
        }
    }
}
