//! Bad input gets a typed error naming what is wrong — never a panic, never a NaN.

use lagrange::error::Stage;
use lagrange::{Description, Error, Mechanism, Method, Model, Output, Pose, Scalar, State, Tolerances};
use lagrange_scenes::{Domain, all, find};

#[test]
fn non_finite_negative_and_zero_parameters_are_rejected_by_name() {
    for scene in all() {
        for spec in scene.params() {
            let mut params = scene.default_params();
            let mut bad = vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
            match spec.domain {
                Domain::Positive => bad.extend([0.0, -1.0]),
                Domain::NonNegative => bad.push(-1e-3),
                Domain::OpenInterval(lo, hi) => bad.extend([lo, hi]),
                Domain::Integer { min, max } => bad.extend([min as f64 - 1.0, max as f64 + 1.0, min as f64 + 0.5]),
                Domain::Finite => {}
            }
            for value in bad {
                match params.set(spec.name, value) {
                    Err(Error::InvalidParameter { name, .. }) => {
                        assert_eq!(name, spec.name, "{}: wrong name", scene.id())
                    }
                    other => panic!("{}: {} = {value} gave {other:?}", scene.id(), spec.name),
                }
            }
        }
    }
}

#[test]
fn unknown_parameters_are_rejected_with_the_accepted_names() {
    let scene = find("cart_pendulum").expect("registered");
    let mut params = scene.default_params();
    match params.set("mass", 1.0) {
        Err(Error::InvalidParameter { name, why, .. }) => {
            assert_eq!(name, "mass");
            assert!(why.contains("cart_mass") && why.contains("bob_mass"), "{why}");
        }
        other => panic!("{other:?}"),
    }
    // By symbol as well as by name.
    params.set("M", 3.0).expect("symbol of cart_mass");
    assert_eq!(params.get("cart_mass"), 3.0);
}

/// Two coordinates that move one body the same way: `M` is singular everywhere.
struct Redundant {
    description: Description,
}

impl Mechanism for Redundant {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0] + q[1], S::zero());
    }
}

/// The description of the redundant coordinates `a`, `b` under gravity, before its one body is
/// added.
fn redundant() -> Description {
    Description::new().length("a").length("b").gravity(9.81)
}

#[test]
fn dependent_coordinates_give_a_singular_mass_matrix_error() {
    let model = Model::new(Redundant { description: redundant().point("block", 1.0) }).expect("valid bodies");
    let mut ws = model.workspace();
    match lagrange::accelerations(&model, &mut ws, 0.0, &[0.1, 0.2], &[0.0, 0.0]) {
        Err(Error::SingularMassMatrix { coordinate, q, .. }) => {
            assert_eq!(coordinate, "b");
            assert_eq!(q, vec![0.1, 0.2]);
        }
        other => panic!("{other:?}"),
    }
    // The integrators pass the error on instead of producing NaN.
    let result = lagrange::simulate(
        &model,
        &State::new(0.0, [0.1, 0.2], [0.0, 0.0]),
        1.0,
        Method::Rk4 { dt: 0.1 },
        &Output::Ends,
    );
    assert!(matches!(result, Err(Error::SingularMassMatrix { .. })), "{result:?}");
}

#[test]
fn invalid_bodies_are_rejected() {
    for (mass, inertia) in [(f64::NAN, 0.0), (-1.0, 0.0), (1.0, -1.0), (1.0, f64::INFINITY)] {
        let m = Redundant { description: redundant().rigid("block", mass, inertia) };
        assert!(matches!(Model::new(m), Err(Error::InvalidParameter { .. })), "m = {mass}, I = {inertia}");
    }
}

#[test]
fn zero_length_rods_are_rejected() {
    for (id, name) in [("cart_pendulum", "rod_length"), ("double_pendulum", "length_2"), ("chain", "link_length")] {
        let scene = find(id).expect("registered");
        let mut params = scene.default_params();
        assert!(matches!(params.set(name, 0.0), Err(Error::InvalidParameter { .. })), "{id}.{name} = 0 accepted");
    }
}

#[test]
fn non_positive_steps_and_tolerances_are_rejected() {
    let scene = find("cart_pendulum").expect("registered");
    let params = scene.default_params();
    let system = scene.build(&params).expect("valid");
    let initial = scene.default_state(&params).expect("valid");
    for dt in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        for method in [Method::Rk4 { dt }, Method::Variational { dt }] {
            let result = system.simulate(&initial, 1.0, method, &Output::Ends);
            assert!(matches!(result, Err(Error::InvalidSetting { what: "step", .. })), "{method:?}: {result:?}");
        }
    }
    for tol in [0.0, -1e-6, f64::NAN, 1e-18] {
        let result = system.simulate(&initial, 1.0, Method::Dopri5 { tol: Tolerances::uniform(tol) }, &Output::Ends);
        assert!(matches!(result, Err(Error::InvalidSetting { what: "tolerance", .. })), "tol {tol}: {result:?}");
    }
    let result = system.simulate(&initial, 1.0, Method::Rk4 { dt: 0.3 }, &Output::Every(0.5));
    assert!(matches!(result, Err(Error::InvalidSetting { .. })), "off-grid output accepted: {result:?}");
}

#[test]
fn non_finite_and_misshapen_states_are_rejected() {
    let scene = find("double_pendulum").expect("registered");
    let mut system = scene.build(&scene.default_params()).expect("valid");
    assert!(matches!(
        system.accelerations(0.0, &[f64::NAN, 0.0], &[0.0, 0.0]),
        Err(Error::NonFinite { stage: Stage::State, .. })
    ));
    assert!(matches!(system.accelerations(0.0, &[0.0], &[0.0, 0.0]), Err(Error::DimensionMismatch { .. })));
    assert!(matches!(system.accelerations(f64::INFINITY, &[0.0, 0.0], &[0.0, 0.0]), Err(Error::NonFinite { .. })));
}

#[test]
fn a_diverging_integration_is_an_error_not_nan() {
    // RK4 on a stiff oscillator with ω dt = 10, far beyond its stability limit ω dt ≈ 2.785:
    // the amplitude grows without bound until it overflows.
    let scene = find("harmonic_oscillator").expect("registered");
    let mut params = scene.default_params();
    params.set("stiffness", 1e6).expect("positive");
    let system = scene.build(&params).expect("valid");
    let initial = scene.default_state(&params).expect("valid");
    let result = system.simulate(&initial, 100.0, Method::Rk4 { dt: 1e-2 }, &Output::Ends);
    assert!(matches!(result, Err(Error::Diverged { .. })), "{result:?}");
}
