//! Near-singular configurations: what the engine does there — a regular value, or a typed
//! error — never a NaN.

use super::{
    CaseBuilder, CaseSpec, Check, Cost, Effort, ErrorKind, Measurement, find, relative_energy_error, scene_params,
    timed_simulate,
};
use crate::tolerance::conditioned;
use lagrange::{Error, Method, Output, State, Tolerances};
use lagrange_scenes::SceneType;
use lagrange_scenes::kepler::Kepler;
use lagrange_testing::{condition_number, max_abs};

pub const SINGULAR: CaseSpec = CaseSpec {
    id: "near_singular",
    title: "Near-singular configurations: the stretched double pendulum, polar coordinates at r → 0",
    scenes: &["double_pendulum", "kepler", "isotropic_oscillator", "spring_pendulum"],
    theory: "The double pendulum's det M = l₁²l₂² m₂ (m₁ + m₂ sin²(θ₁ − θ₂)) is l₁²l₂² m₁m₂ > 0 when fully \
             stretched: a regular configuration, the accelerations are the closed form's. With a nearly \
             massless elbow (m₁ = 1e-12 m₂) M is singular to working precision there, and the engine refuses \
             with SingularMassMatrix naming θ1 (its pivot threshold is 1e-12 of the diagonal) instead of \
             dividing. In polar coordinates M = diag(m, m r²) loses rank at r = 0 (SingularMassMatrix for θ, \
             also wherever r² underflows), unless the potential is singular first (−k/r, |x| at the origin: \
             NonFinite at the potential stage); for small finite r the accelerations are finite, with round-off \
             amplified by κ(M) = 1/r². A radial infall from rest at r₀ = 1 reaches r = 0 at \
             t_c = (π/2)√(r₀³/2μ) = 1.1107 s; the scene's admissible region is r > 0, so a fixed-step run that \
             steps over the collision stops there with Inadmissible instead of running on at r < 0.",
    run: singular,
};

/// How an evaluation ended: `value` (finite), `non-finite value` (a defect), or the error.
fn outcome(result: Result<Vec<f64>, Error>) -> (Option<f64>, &'static str, String, Option<ErrorKind>) {
    match result {
        Ok(values) if values.iter().all(|v| v.is_finite()) => {
            (Some(max_abs(&values)), "ok", "finite".to_string(), None)
        }
        Ok(values) => (None, "ok", format!("non-finite value returned: {values:?}"), None),
        Err(error) => (None, "failed", error.to_string(), Some(ErrorKind::of(&error))),
    }
}

fn singular(case: &mut CaseBuilder, _effort: Effort) -> Result<(), crate::Error> {
    case.setup =
        "Double pendulum (l = 1, m₂ = 1) at θ₁ = θ₂ ∈ {0, 0.7, π} with q̇ = (1, −2), m₁ ∈ {1, 1e-6}; m₁ = 1e-12 \
                  at θ = (0.7, 0.7) and (0.7, 0.7 + 1e-8). Kepler, isotropic oscillator and spring pendulum at \
                  r ∈ {0, 1e-300, 1e-160, 1e-10}, θ = 0.3, q̇ = (1, 0.5): accelerations and energy. Kepler radial \
                  infall from r = 1 at rest for 2 s with every method."
            .into();
    stretched_double_pendulum(case)?;
    massless_elbow(case)?;
    polar_origin(case)?;
    radial_infall(case)
}

/// The fully stretched double pendulum, a regular configuration: q̈ against the closed form to
/// the round-off bound at the measured κ(M).
fn stretched_double_pendulum(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let scene = find("double_pendulum")?;
    for m1 in [1.0, 1e-6] {
        let params = scene_params(scene, &[("mass_1", m1)])?;
        let mut system = scene.build(&params)?;
        for angle in [0.0, 0.7, std::f64::consts::PI] {
            let (q, qdot) = ([angle, angle], [1.0, -2.0]);
            let expected = scene
                .closed_form_accelerations(&params, 0.0, &q, &qdot)?
                .ok_or(crate::Error::Missing("no closed form"))?;
            let m = Measurement::new(
                format!("m₁ = {m1:.0e}, θ₁ = θ₂ = {angle:.3}"),
                "double_pendulum",
                "engine",
                "relative error of q̈ vs the closed form",
            )
            .params(&[("mass_1", m1)]);
            let m = match system.accelerations(0.0, &q, &qdot) {
                Ok(got) => {
                    let residual = got.iter().zip(&expected).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                    let scale = expected.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
                    // `crate::tolerance::conditioned` at the measured κ(M) (tighter than the
                    // upper bound (m₁ + 2m₂)²/(m₁ m₂) the report used before).
                    let kappa = condition_number(2, system.mass_matrix(0.0, &q, &qdot)?);
                    m.value(residual / scale).note(format!("κ(M) = {kappa:.2e}")).check(
                        Check::AtMost,
                        Some(0.0),
                        Some(conditioned(kappa)),
                    )
                }
                Err(e) => m.failed(e).check(Check::AtMost, Some(0.0), Some(0.0)),
            };
            case.push(m);
        }
    }
    Ok(())
}

/// The double pendulum with a nearly massless elbow (m₁ = 1e-12 m₂), whose M is singular to
/// working precision: the typed error naming θ1, at once, also for a simulation.
fn massless_elbow(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let scene = find("double_pendulum")?;
    let params = scene_params(scene, &[("mass_1", 1e-12)])?;
    let mut system = scene.build(&params)?;
    for q in [[0.7, 0.7], [0.7, 0.7 + 1e-8]] {
        let (value, status, note, error) = outcome(system.accelerations(0.0, &q, &[1.0, -2.0]).map(<[f64]>::to_vec));
        let mut m = Measurement::new(
            format!("m₁ = 1e-12, θ = ({}, {})", q[0], q[1]),
            "double_pendulum",
            "engine",
            "q̈ (largest |component|)",
        )
        .params(&[("mass_1", 1e-12)])
        .note(note);
        m.value = value;
        m.status = status;
        m.error = error;
        case.push(m.expect_error(ErrorKind::SingularMassMatrix));
        // The error names the coordinate whose pivot vanished.
        let named = match system.accelerations(0.0, &q, &[1.0, -2.0]) {
            Err(Error::SingularMassMatrix { coordinate, .. }) => coordinate,
            _ => String::new(),
        };
        let m = Measurement::new(
            format!("m₁ = 1e-12, θ = ({}, {})", q[0], q[1]),
            "double_pendulum",
            "engine",
            "the singular-matrix error names θ1 (1 = yes)",
        )
        .params(&[("mass_1", 1e-12)])
        .note(format!("named: {named:?}"));
        case.push(m.value(f64::from(u8::from(named == "θ1"))).check(Check::Exact, Some(1.0), None));
        // A simulation from there stops with the same typed error, at once.
        let method = Method::Rk4 { dt: 0.01 };
        let (run, wall) = timed_simulate(system.as_ref(), &State::new(0.0, q, [1.0, -2.0]), 1.0, method, &Output::Ends);
        let mut m = Measurement::new(
            format!("m₁ = 1e-12, θ = ({}, {})", q[0], q[1]),
            "double_pendulum",
            "rk4",
            "simulation from the singular configuration",
        )
        .params(&[("mass_1", 1e-12)])
        .method_settings(method, 1.0);
        m = m.ended(run, wall);
        case.push(m.expect_error(ErrorKind::SingularMassMatrix));
    }
    Ok(())
}

/// Polar coordinates at and near the origin, where M = diag(m, m r²) loses rank: finite values
/// or typed errors from every evaluation, never a NaN.
fn polar_origin(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    for id in ["kepler", "isotropic_oscillator", "spring_pendulum"] {
        let scene = find(id)?;
        let mut system = scene.build(&scene.default_params())?;
        for (r, qdot) in [0.0, 1e-300, 1e-160, 1e-10]
            .map(|r| (r, [1.0, 0.5]))
            .into_iter()
            .chain([0.0, 1e-300, 1e-160, 1e-100, 1e-10, -1e-10].map(|r| (r, [0.0, 0.0])))
            .chain([(1e-100, [1.0, 0.5]), (-1e-10, [1.0, 0.5])])
        {
            let q = [r, 0.3];
            let label = if qdot == [1.0, 0.5] { format!("r = {r:.0e}") } else { format!("r = {r:.0e}, at rest") };
            let label = label.as_str();
            let (value, status, note, error) = outcome(system.accelerations(0.0, &q, &qdot).map(<[f64]>::to_vec));
            let mut m = Measurement::new(label, id, "engine", "q̈ (largest |component|)").note(note);
            m.value = value;
            m.status = status;
            m.error = error;
            // At the origin itself, the singular mass matrix (θ's entry m r² vanishes); at
            // r = 1e-10, a finite value.
            case.push(match r {
                0.0 => m.expect_error(ErrorKind::SingularMassMatrix),
                1e-10 => m.check(Check::Finite, None, None),
                _ => m.check(Check::FiniteOrTypedError, None, None),
            });
            let (value, status, note, error) = outcome(system.energy_function(0.0, &q, &qdot).map(|e| vec![e]));
            let mut m = Measurement::new(label, id, "engine", "energy (|value|)").note(note);
            m.value = value;
            m.status = status;
            m.error = error;
            // A value must be finite or an error (never ±∞/NaN as a value); Kepler's potential
            // −k/r is −∞ at (or, r² underflowing aside, next to) the origin: NonFinite, not a
            // value (regression: the energy once returned −∞).
            case.push(if id == "kepler" && (r == 0.0 || r == 1e-300) {
                m.expect_error(ErrorKind::NonFinite)
            } else {
                m.check(Check::FiniteOrTypedError, None, None)
            });
            // The other evaluations (M, p, reaction forces): finite values or typed errors.
            let mut results = vec![
                system.mass_matrix(0.0, &q, &qdot).map(<[f64]>::to_vec),
                system.momenta(0.0, &q, &qdot).map(<[f64]>::to_vec),
            ];
            if let Some(r) = system.reaction_forces(0.0, &q, &qdot).transpose() {
                results.push(r.map(<[f64]>::to_vec));
            }
            let nonfinite = results.iter().any(|r| r.as_ref().is_ok_and(|v| v.iter().any(|x| !x.is_finite())));
            let values: Vec<f64> = results.iter().filter_map(|r| r.as_ref().ok()).flatten().copied().collect();
            let errors: Vec<String> =
                results.iter().filter_map(|r| r.as_ref().err()).map(ToString::to_string).collect();
            let mut m = Measurement::new(label, id, "engine", "M, p and reaction forces (largest |component|)");
            if !errors.is_empty() {
                m = m.note(errors.join("; "));
            }
            m = match (nonfinite, values.is_empty()) {
                (true, _) => m.note("non-finite value returned"),
                (false, false) => m.value(max_abs(&values)),
                (false, true) => {
                    let note = m.note.take().unwrap_or_default();
                    m.failed(note)
                }
            };
            case.push(m.check(Check::FiniteOrTypedError, None, None));
        }
    }
    Ok(())
}

/// Kepler's radial infall from rest: the collision time against its closed form, and where
/// each method's run stops.
fn radial_infall(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let scene = find("kepler")?;
    let params = scene.default_params();
    let system = scene.build(&params)?;
    let initial = State::new(0.0, [1.0, 0.0], [0.0, 0.0]);
    let collision = Kepler::from_params(&params)?.radial_infall_time(1.0);
    // m = k = 1, r₀ = 1: t_c = (π/2) √(1/2).
    case.push(Measurement::new("radial infall", "kepler", "engine", "collision time t_c (s)").value(collision).check(
        Check::AbsoluteToTheory,
        Some(std::f64::consts::FRAC_PI_2 * 0.5f64.sqrt()),
        Some(1e-15),
    ));
    let methods = [
        Method::Rk4 { dt: 0.01 },
        Method::Dopri5 { tol: Tolerances::uniform(1e-8) },
        Method::Variational { dt: 0.01 },
        Method::Sdirk4 { tol: Tolerances::uniform(1e-8) },
        Method::Gauss4 { dt: 0.01 },
    ];
    for method in methods {
        let (run, wall) = timed_simulate(system.as_ref(), &initial, 2.0, method, &Output::Every(0.01));
        let m = Measurement::new("radial infall", "kepler", method.name(), "time the run stops (s)")
            .method_settings(method, 2.0);
        case.push(match run {
            Ok(t) => {
                let finite = t.q.iter().chain(&t.qdot).chain(&t.energy).all(|v| v.is_finite());
                let m = m.cost(Cost::of(&t.stats, wall)).note(format!(
                    "ran through r = 0 to the end, {}: relative energy error {:.1e}, r(2 s) = {:.3}",
                    if finite { "finite values" } else { "NON-FINITE values" },
                    relative_energy_error(&t.energy),
                    t.q[t.q.len() - 2]
                ));
                if finite {
                    m.value(2.0).check(Check::None, Some(collision), None)
                } else {
                    m.check(Check::Finite, None, None)
                }
            }
            Err(error) => {
                let t = match error {
                    Error::StepSizeUnderflow { t, .. }
                    | Error::Stiff { t, .. }
                    | Error::NewtonFailed { t, .. }
                    | Error::Diverged { t, .. }
                    | Error::Inadmissible { t, .. } => Some(t),
                    _ => None,
                };
                let mut m = m.failed(&error);
                m.value = t;
                // The adaptive methods stop at the collision (to its step): |t − t_c| ≤ 1e-6.
                // The fixed-step ones at the step that reaches it: no earlier than 2 steps before
                // t_c and no later than one step after, t ∈ [t_c − 0.02, t_c + 0.01], written as
                // |t − (t_c − 0.005)| ≤ 0.015.
                let adaptive = matches!(method, Method::Dopri5 { .. } | Method::Sdirk4 { .. });
                let (centre, bound) = if adaptive { (collision, 1e-6) } else { (collision - 0.005, 0.015) };
                let mut m = m.check(Check::AbsoluteToTheory, Some(centre), Some(bound));
                m.status = "failed";
                m
            }
        });
    }
    Ok(())
}
