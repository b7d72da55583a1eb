//! Bad input, as property tests: random (fixed-seed) parameters — regular, extreme and invalid —
//! and random states — regular, extreme, non-finite and misshapen — across every scene. Every
//! call (build, accelerations, energy, momenta, mass matrix, reaction forces, simulate with
//! every method, maximal builds in every engine) returns a value or a typed error, never a
//! panic (each runs under `catch_unwind`) and never a non-finite value; non-finite, negative or
//! zero masses, lengths and steps are rejected with the parameter named.

use lagrange::tree::{Joint, Parent, Tree};
use lagrange::{Body, Error, Method, Model, Output, State, System, Tolerances};
use lagrange_maximal::{BuildError, Engine, Settings};
use lagrange_scenes::{Domain, Params, Scene, all};
use lagrange_tests::{rng, sampling};
use rand::Rng;
use std::panic::{AssertUnwindSafe, catch_unwind};

/// Run `f`, failing the test (with `what`) if it panics.
fn no_panic<T>(what: &str, f: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(value) => value,
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            panic!("{what}: panicked: {message}")
        }
    }
}

fn all_finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// A result that is either finite values or an error (every error of the engine is typed).
fn assert_finite_or_error(what: &str, result: Result<&[f64], &Error>) {
    if let Ok(values) = result {
        assert!(all_finite(values), "{what}: returned non-finite values {values:?}");
    }
}

/// Parameter sets of a scene: defaults, random regular ones, and the extreme ones (mass ratios
/// 1e±6, `I/a²` = 1e8, angles at the ends of their interval).
fn parameter_sets(scene: &dyn Scene, rng: &mut impl Rng) -> Vec<(String, Params)> {
    let mut sets = vec![("defaults".to_string(), scene.default_params())];
    for k in 0..3 {
        sets.push((format!("random {k}"), sampling::regular_params(scene, rng)));
    }
    sets.extend(sampling::extreme_params(scene));
    sets
}

/// How a state is formed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// Finite, the right size, moderate values.
    Regular,
    /// Finite and the right size, but overflowing (1e300) or at a singular point (`q = 0`):
    /// finite values or a typed error all the same.
    Overflowing,
    /// Non-finite or misshapen: the accelerations must be an error.
    Malformed,
}

/// States at which to evaluate: random regular ones (a quarter at angles 1e-8, another at
/// π/2 − 1e-8), then huge, non-finite and misshapen ones.
fn states(scene: &dyn Scene, params: &Params, rng: &mut impl Rng) -> Vec<(String, State, Kind)> {
    let mut states: Vec<(String, State, Kind)> =
        (0..4).map(|k| (format!("random {k}"), sampling::state(scene, params, rng, k), Kind::Regular)).collect();
    let base = states[0].1.clone();
    let n = base.q.len();
    let with = |f: &dyn Fn(&mut State)| {
        let mut s = base.clone();
        f(&mut s);
        s
    };
    states.push(("q = 1e300".into(), with(&|s| s.q.fill(1e300)), Kind::Overflowing));
    states.push(("q̇ = 1e200".into(), with(&|s| s.qdot.fill(1e200)), Kind::Overflowing));
    states.push(("q = 0".into(), with(&|s| s.q.fill(0.0)), Kind::Overflowing));
    states.push(("NaN q".into(), with(&|s| s.q[n - 1] = f64::NAN), Kind::Malformed));
    states.push(("∞ q̇".into(), with(&|s| s.qdot[0] = f64::INFINITY), Kind::Malformed));
    states.push(("NaN t".into(), with(&|s| s.t = f64::NAN), Kind::Malformed));
    states.push(("short q".into(), with(&|s| s.q.truncate(n - 1)), Kind::Malformed));
    states.push(("long q̇".into(), with(&|s| s.qdot.push(0.0)), Kind::Malformed));
    states
}

/// Every evaluation at one state: finite values or a typed error; at a malformed state the
/// accelerations are always an error (the mass matrix, say, may ignore a malformed `q̇`).
fn evaluate(what: &str, system: &mut dyn System, state: &State, kind: Kind) {
    let (t, q, qdot) = (state.t, state.q.as_slice(), state.qdot.as_slice());
    let results = [
        ("accelerations", no_panic(what, || system.accelerations(t, q, qdot).map(<[f64]>::to_vec))),
        ("mass matrix", no_panic(what, || system.mass_matrix(t, q, qdot).map(<[f64]>::to_vec))),
        ("momenta", no_panic(what, || system.momenta(t, q, qdot).map(<[f64]>::to_vec))),
        ("reactions", no_panic(what, || system.reaction_forces(t, q, qdot).map(|r| r.unwrap_or(&[]).to_vec()))),
        ("energy", no_panic(what, || system.energy_function(t, q, qdot).map(|e| vec![e]))),
    ];
    for (call, result) in &results {
        let what = format!("{what}: {call}");
        if kind == Kind::Malformed && *call == "accelerations" {
            assert!(
                matches!(result, Err(Error::NonFinite { .. } | Error::DimensionMismatch { .. })),
                "{what}: a malformed state gave {result:?}"
            );
        } else {
            assert_finite_or_error(&what, result.as_deref());
        }
    }
}

/// A short run with every method: well-formed settings give finite trajectories or typed
/// errors; bad steps and tolerances are rejected naming them.
fn simulate_every_method(what: &str, system: &dyn System, state: &State, rng: &mut impl Rng) {
    let dt = 10f64.powf(rng.random_range(-3.0..-1.5));
    let tol = 10f64.powf(rng.random_range(-10.0..-3.0));
    let horizon = state.t + 20.0 * dt;
    let good = [
        Method::Rk4 { dt },
        Method::Dopri5 { tol: Tolerances::uniform(tol) },
        Method::Variational { dt },
        Method::Sdirk4 { tol: Tolerances::uniform(tol) },
        Method::Gauss4 { dt },
    ];
    for method in good {
        let what = format!("{what}: {method:?}");
        let result = no_panic(&what, || system.simulate(state, horizon, method, &Output::Every(5.0 * dt)));
        if let Ok(run) = result {
            for values in [&run.q, &run.qdot, &run.energy] {
                assert!(all_finite(values), "{what}: non-finite trajectory");
            }
        }
    }
    for bad in [0.0, -dt, f64::NAN, f64::INFINITY] {
        for method in [Method::Rk4 { dt: bad }, Method::Variational { dt: bad }, Method::Gauss4 { dt: bad }] {
            let result = no_panic(what, || system.simulate(state, horizon, method, &Output::Ends));
            assert!(
                matches!(result, Err(Error::InvalidSetting { what: "step", .. })),
                "{what}: {method:?}: {result:?}"
            );
        }
    }
    for bad in [0.0, -tol, f64::NAN, f64::INFINITY, 1e-18] {
        for method in
            [Method::Dopri5 { tol: Tolerances::uniform(bad) }, Method::Sdirk4 { tol: Tolerances::uniform(bad) }]
        {
            let result = no_panic(what, || system.simulate(state, horizon, method, &Output::Ends));
            assert!(
                matches!(result, Err(Error::InvalidSetting { what: "tolerance", .. })),
                "{what}: {method:?}: {result:?}"
            );
        }
    }
    for bad in [f64::NAN, state.t - 1.0, f64::INFINITY] {
        let result = no_panic(what, || system.simulate(state, bad, Method::Rk4 { dt }, &Output::Ends));
        assert!(
            matches!(result, Err(Error::InvalidSetting { what: "horizon", .. })),
            "{what}: t_end {bad}: {result:?}"
        );
    }
}

#[test]
fn every_call_on_every_scene_returns_a_value_or_a_typed_error() {
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(7000 + index as u64);
        for (label, params) in parameter_sets(*scene, &mut rng) {
            let what = format!("{} [{label}]", scene.id());
            let built = no_panic(&what, || scene.build(&params));
            let mut system = built.unwrap_or_else(|e| panic!("{what}: valid parameters rejected: {e}"));
            let states = states(*scene, &params, &mut rng);
            for (state_label, state, kind) in &states {
                evaluate(&format!("{what} at {state_label}"), system.as_mut(), state, *kind);
            }
            // Short runs from the regular states (integrating from 1e300 only tests overflow).
            for (state_label, state, _) in states.iter().take(2) {
                simulate_every_method(&format!("{what} from {state_label}"), system.as_ref(), state, &mut rng);
            }
        }
    }
}

/// Regression: the energy once returned `∞ − ∞ = NaN` for an overflowing kinetic energy.
#[test]
fn energy_of_an_overflowing_state_is_an_error_not_nan() {
    let scene = lagrange_scenes::find("cart_pendulum").expect("registered");
    let mut system = scene.build(&scene.default_params()).expect("valid");
    let energy = system.energy_function(0.0, &[0.0, 0.3], &[1e200, 1e200]);
    assert!(matches!(energy, Err(Error::NonFinite { .. })), "{energy:?}");
}

/// Regression: an RK4 run growing past 1e117 was once `Ok` with NaN energies recorded.
#[test]
fn a_run_that_overflows_is_an_error_not_a_nan_energy() {
    // The charged particle's cyclotron frequency e B/m = 1e6 rad/s: RK4 at ω dt = 1900 grows
    // by ~1e58 per step.
    let scene = lagrange_scenes::find("charged_particle").expect("registered");
    let mut params = scene.default_params();
    params.set("mass", 1e-6).expect("positive");
    let system = scene.build(&params).expect("valid");
    let initial = scene.default_state(&params).expect("valid");
    let run = system.simulate(&initial, 20.0 * 2e-3, Method::Rk4 { dt: 2e-3 }, &Output::Every(1e-2));
    match run {
        Ok(run) => assert!(all_finite(&run.energy), "Ok with energies {:?}", run.energy),
        Err(error) => assert!(matches!(error, Error::Diverged { .. } | Error::NonFinite { .. }), "{error}"),
    }
}

#[test]
fn invalid_parameters_are_rejected_by_name_at_random() {
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(7100 + index as u64);
        for _ in 0..20 {
            let spec = &scene.params()[rng.random_range(0..scene.params().len())];
            let mut bad = vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
            match spec.domain {
                Domain::Positive => bad.extend([0.0, -0.0, -rng.random_range(1e-300..1e300)]),
                Domain::NonNegative => bad.push(-rng.random_range(1e-300..1e300)),
                Domain::OpenInterval(low, high) => bad.extend([low, high, low - 1.0, high + 1.0]),
                Domain::Integer { min, max } => bad.extend([f64::from(min) - 1.0, f64::from(max) + 1.0, 1.5]),
                Domain::Finite => {}
            }
            let value = bad[rng.random_range(0..bad.len())];
            let mut params = scene.default_params();
            let result = no_panic(scene.id(), || params.set(spec.name, value));
            match result {
                Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, spec.name, "{}", scene.id()),
                other => panic!("{}: {} = {value} gave {other:?}", scene.id(), spec.name),
            }
            assert_eq!(params, scene.default_params(), "{}: a rejected value changed the set", scene.id());
        }
    }
}

#[test]
fn bodies_and_trees_with_bad_masses_or_lengths_are_rejected_by_name() {
    let mut rng = rng(7200);
    for _ in 0..50 {
        let bad = [f64::NAN, f64::INFINITY, -rng.random_range(1e-300..1e300)][rng.random_range(0..3)];
        let (mass, inertia, anchor) = match rng.random_range(0..3) {
            0 => (bad, 0.1, 1.0),
            1 => (1.0, bad, 1.0),
            _ => (1.0, 0.1, if bad.is_finite() { f64::NAN } else { bad }),
        };
        let joints = vec![Joint::absolute_revolute("θ", Parent::Ground, [0.0, 0.0], [0.0, anchor])];
        let bodies = vec![Body::rigid("rod", mass, inertia)];
        let tree = no_panic("tree", || Tree::new(joints, bodies.clone(), 9.81));
        match tree {
            Err(Error::InvalidParameter { name, .. }) => {
                let expected = if !mass.is_finite() || mass < 0.0 {
                    "mass of rod"
                } else if !inertia.is_finite() || inertia < 0.0 {
                    "inertia of rod"
                } else {
                    "child_anchor of joint `θ`"
                };
                assert_eq!(name, expected, "m = {mass}, I = {inertia}, anchor = {anchor}");
            }
            other => panic!("m = {mass}, I = {inertia}, anchor = {anchor}: {other:?}"),
        }
        // The same body through a mechanism of its own: Model::new names it too.
        if anchor.is_finite() {
            let tree = Tree::new(
                vec![Joint::absolute_revolute("θ", Parent::Ground, [0.0, 0.0], [0.0, 1.0])],
                vec![Body::rigid("rod", 1.0, 0.1)],
                9.81,
            )
            .expect("valid");
            let model = no_panic("model", || Model::new(BadBodies::new(tree, bodies.clone())));
            assert!(
                matches!(model, Err(Error::InvalidParameter { ref name, .. }) if name.ends_with("of rod")),
                "m = {mass}, I = {inertia}: {:?}",
                model.err()
            );
        }
    }
}

/// A pendulum whose mechanism reports other (bad) bodies than its tree.
struct BadBodies {
    tree: Tree,
    description: lagrange::Description,
}

impl BadBodies {
    /// The tree's coordinates with `bodies` instead of the tree's, under gravity 9.81.
    fn new(tree: Tree, bodies: Vec<Body>) -> Self {
        let coordinates = lagrange::Mechanism::description(&tree).coordinates.clone();
        let description = lagrange::Description { coordinates, bodies, gravity: 9.81, ..Default::default() };
        Self { tree, description }
    }
}

impl lagrange::Mechanism for BadBodies {
    fn description(&self) -> &lagrange::Description {
        &self.description
    }
    fn poses<S: lagrange::Scalar>(&self, t: S, q: &[S], world_from_body: &mut [lagrange::Pose<S>]) {
        self.tree.poses(t, q, world_from_body);
    }
}

#[test]
fn maximal_builds_return_a_simulation_or_a_typed_error() {
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(7300 + index as u64);
        for (label, params) in parameter_sets(*scene, &mut rng).into_iter().take(3) {
            let state = sampling::state(*scene, &params, &mut rng, 0);
            for engine in Engine::ALL {
                let what = format!("{} [{label}] in {engine}", scene.id());
                let dt = [1.0 / 60.0, 1.0 / 240.0][rng.random_range(0..2)];
                let settings = Settings { dt, substeps: rng.random_range(1..5), tolerance: 1e-8 };
                match no_panic(&what, || lagrange_maximal::build(engine, *scene, &params, &state, &settings)) {
                    Ok(mut built) => {
                        let sim = &mut built.simulation;
                        let advanced = no_panic(&what, || sim.advance_to(state.t + 10.0 * dt));
                        if advanced.is_ok() {
                            let bodies = no_panic(&what, || sim.bodies());
                            let values: Vec<f64> =
                                bodies.iter().flat_map(|b| b.pose.into_iter().chain(b.velocity)).collect();
                            assert!(all_finite(&values), "{what}: non-finite bodies");
                            let _ = no_panic(&what, || (sim.constraint_violation(), sim.constraint_forces()));
                        }
                    }
                    Err(BuildError::Unbuildable { reason, .. }) => assert!(!reason.is_empty(), "{what}"),
                    Err(BuildError::Invalid(error)) => panic!("{what}: valid input rejected: {error}"),
                }
                // Bad settings and states: typed errors naming them.
                let bad_settings = [
                    Settings { dt: f64::NAN, ..settings },
                    Settings { dt: -dt, ..settings },
                    Settings { substeps: 0, ..settings },
                    Settings { tolerance: 0.0, ..settings },
                    Settings { tolerance: f64::INFINITY, ..settings },
                ];
                for bad in bad_settings {
                    let result = no_panic(&what, || lagrange_maximal::build(engine, *scene, &params, &state, &bad));
                    let uses = |what: &str| match what {
                        "step" | "substeps" => engine.is_rapier(),
                        _ => !engine.is_rapier(),
                    };
                    match result {
                        Err(BuildError::Invalid(Error::InvalidSetting { what: setting, .. })) => {
                            assert!(uses(setting), "{what}: {bad:?} rejected for {setting}")
                        }
                        Ok(_) | Err(BuildError::Unbuildable { .. }) => {}
                        Err(other) => panic!("{what}: {bad:?}: {other}"),
                    }
                }
                let mut nan_state = state.clone();
                nan_state.q[0] = f64::NAN;
                let result =
                    no_panic(&what, || lagrange_maximal::build(engine, *scene, &params, &nan_state, &settings));
                assert!(result.is_err(), "{what}: a NaN state was accepted");
            }
        }
    }
}
