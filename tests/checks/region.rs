//! Admissible regions (docs/method.md#admissible-regions): a run that leaves the region where its
//! model holds ends in `Error::Inadmissible` with every integrator, at the first step outside;
//! the scenes declare theirs; tolerances that cannot give a meaningful result are refused.

use lagrange::integrate::MIN_RELATIVE_TOLERANCE;
use lagrange::{Bounds, Description, Error, Mechanism, Method, Model, Output, Pose, Scalar, State, Tolerances};
use lagrange_scenes::find;

/// A free particle in plane polar coordinates `q = (r, θ)`: `r > 0` is its region.
struct Polar {
    description: Description,
}

impl Mechanism for Polar {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0] * q[1].cos(), q[0] * q[1].sin());
    }

    fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        bounds.above("r", q[0], 0.0);
        true
    }
}

fn polar() -> Model<Polar> {
    Model::new(Polar { description: Description::new().length("r").angle("θ").point("particle", 1.0) }).expect("valid")
}

fn every_method() -> [Method; 5] {
    let (dt, tol) = (0.3, Tolerances::uniform(1e-8));
    [
        Method::Rk4 { dt },
        Method::Dopri5 { tol },
        Method::Variational { dt },
        Method::Sdirk4 { tol },
        Method::Gauss4 { dt },
    ]
}

/// Straight at the origin from r = 1 at 1 m/s (`r = 1 − t`, every method exact up to
/// round-off): each method stops at the first step that ends at r ≤ 0 — the fixed-step ones at
/// t = 1.2 (r = −0.2), the adaptive ones wherever their step lands past t = 1 — never later,
/// and brackets the crossing with the last state it found inside (t = 0.9 for the fixed steps).
#[test]
fn every_integrator_stops_at_the_first_step_outside_the_region() {
    let model = polar();
    assert!(model.has_admissible_region());
    let initial = State::new(0.0, [1.0, 0.0], [-1.0, 0.0]);
    for method in every_method() {
        let run = lagrange::simulate(&model, &initial, 3.0, method, &Output::Ends);
        let Err(Error::Inadmissible { t, inside_until: Some(inside), quantity, bound, value, limit }) = run else {
            panic!("{method:?}: {run:?}")
        };
        assert_eq!((quantity.as_str(), bound.as_str(), limit), ("r", "r > 0", 0.0), "{method:?}");
        // The state at the failing step is on the line r = 1 − t, at or past r = 0; the last
        // state found inside is before the crossing at t = 1.
        assert!(t >= 1.0 && value <= 0.0 && (value - (1.0 - t)).abs() <= 1e-9, "{method:?}: t = {t}, r = {value}");
        assert!(inside < 1.0, "{method:?}: inside until {inside}");
        match method {
            Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt } => {
                assert!((t - 4.0 * dt).abs() <= 1e-12 && (inside - 3.0 * dt).abs() <= 1e-12, "{method:?}: t = {t}")
            }
            _ => assert!(t < 3.0, "{method:?}: t = {t}"),
        }
    }
}

#[test]
fn an_initial_state_outside_the_region_is_refused_before_any_step() {
    let model = polar();
    let initial = State::new(0.5, [-0.25, 0.0], [1.0, 0.0]);
    for method in every_method() {
        let run = lagrange::simulate(&model, &initial, 1.0, method, &Output::Ends);
        assert_eq!(
            run,
            Err(Error::Inadmissible {
                t: 0.5,
                inside_until: None,
                quantity: "r".into(),
                bound: "r > 0".into(),
                value: -0.25,
                limit: 0.0
            }),
            "{method:?}"
        );
    }
    let message = Bounds::check(&model, 0.5, &[-0.25, 0.0], &[0.0, 0.0]).unwrap_err().to_string();
    assert_eq!(message, "r = -0.25 is outside the admissible region r > 0 at t = 0.5 s");
}

/// Without a declared region nothing is checked: the same motion runs through r = 0.
#[test]
fn without_a_region_nothing_is_checked() {
    struct Unbounded {
        description: Description,
    }
    impl Mechanism for Unbounded {
        fn description(&self) -> &Description {
            &self.description
        }
        fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
            p[0] = Pose::point(q[0] * q[1].cos(), q[0] * q[1].sin());
        }
    }
    let model =
        Model::new(Unbounded { description: Description::new().length("r").angle("θ").point("particle", 1.0) })
            .expect("valid");
    assert!(!model.has_admissible_region());
    assert_eq!(Bounds::check(&model, 0.0, &[-1.0, 0.0], &[0.0, 0.0]), Ok(false));
    let run = lagrange::simulate(
        &model,
        &State::new(0.0, [1.0, 0.0], [-1.0, 0.0]),
        3.0,
        Method::Rk4 { dt: 0.3 },
        &Output::Ends,
    )
    .expect("no region");
    assert!((run.q(1)[0] + 2.0).abs() < 1e-12, "r(3) = {}", run.q(1)[0]);
}

/// A run of a registered scene: `(id, parameter changes, initial state or the default, method,
/// horizon)` → its result.
fn scene_run(
    id: &str,
    changes: &[(&str, f64)],
    initial: Option<State>,
    method: Method,
    t_end: f64,
) -> Result<lagrange::Trajectory, Error> {
    let scene = find(id).expect("registered");
    let mut params = scene.default_params();
    for &(name, value) in changes {
        params.set(name, value).expect("valid");
    }
    let initial = initial.unwrap_or_else(|| scene.default_state(&params).expect("valid"));
    let system = scene.build(&params).expect("valid");
    system.simulate(&initial, t_end, method, &Output::Every(t_end / 200.0))
}

/// The run's `Inadmissible` for `quantity`: `(last time inside, time found outside)`.
fn expect_inadmissible(what: &str, run: Result<lagrange::Trajectory, Error>, quantity: &str) -> (Option<f64>, f64) {
    match run {
        Err(Error::Inadmissible { quantity: q, t, inside_until, .. }) if q == quantity => (inside_until, t),
        other => panic!("{what}: expected Inadmissible for {quantity}, got {other:?}"),
    }
}

/// The run left through `quantity` and brackets the exact crossing time `crossing`.
fn expect_crossing(what: &str, run: Result<lagrange::Trajectory, Error>, quantity: &str, crossing: f64) {
    let (inside, t) = expect_inadmissible(what, run, quantity);
    let inside = inside.unwrap_or_else(|| panic!("{what}: the initial state is inside"));
    // 1e-9: the adaptive runs' position error at tol 1e-10 over ≈ 11 s, far below a step.
    assert!(
        inside <= crossing + 1e-9 && crossing - 1e-9 <= t,
        "{what}: crossing at {crossing}, bracket [{inside}, {t}]"
    );
}

/// Kepler's radial infall from rest at r = 1 reaches r = 0 at t_c = (π/2)√(1/2) = 1.1107 s;
/// RK4 with dt = 1e-3 used to step over it and run on to r(2) = −19.9.
#[test]
fn kepler_stepped_through_r_0_by_rk4_ends_in_inadmissible() {
    let infall = Some(State::new(0.0, [1.0, 0.0], [0.0, 0.0]));
    let run = scene_run("kepler", &[], infall, Method::Rk4 { dt: 1e-3 }, 2.0);
    let (inside, t) = expect_inadmissible("kepler", run, "r");
    let collision = std::f64::consts::FRAC_PI_2 * 0.5_f64.sqrt();
    assert!((collision - 0.01..=collision + 0.01).contains(&t), "stopped at {t}, collision at {collision}");
    assert_eq!(inside.map(|inside| ((t - inside) * 1e3).round()), Some(1.0), "one step before");
}

/// The pulley machines and the wedge leave their regions from their defaults on runs longer
/// than the report's 10 s (masses pulled through pulleys, the block off the end of its incline),
/// and the error brackets the exact crossing time.
#[test]
fn scenes_leave_their_regions_with_a_typed_error() {
    let adaptive = Method::Dopri5 { tol: Tolerances::uniform(1e-10) };
    // Atwood: x = 6 − 2t + ẍ t²/2 with ẍ = 0.1 g/2.5 = 0.3924 m/s² reaches l − πa = 8.4292 m at
    // t = (2 + √(4 + 2ẍ · 2.4292))/ẍ = 11.2903 s.
    let run = scene_run("atwood", &[], None, adaptive, 100.0);
    expect_crossing("atwood", run, "rope to m2, l − πa − x", 11.290_305_967_762_47);
    // Wedge: x' = 9 − 3.2t + ẍ' t²/2 with ẍ' = 4g sin 0.05/(3 + sin² 0.05) = 0.653184 m/s²
    // reaches L = 10 m at t = 10.1013 s.
    let run = scene_run("wedge", &[], None, adaptive, 100.0);
    expect_crossing("wedge", run, "block on the incline x'", 10.101_285_335_807_05);
    // Double Atwood with l' = 0.001 < x' = 0.5: outside from the start.
    let (_, t) = expect_inadmissible(
        "double_atwood",
        scene_run("double_atwood", &[("lower_rope_length", 0.001)], None, adaptive, 10.0),
        "lower rope to m3, l' − x'",
    );
    assert_eq!(t, 0.0);
    // Polar scenes and the spring pendulum at r < 0.
    for (id, quantity) in [("isotropic_oscillator", "r"), ("spring_pendulum", "spring length r")] {
        let outside = Some(State::new(0.0, [-0.5, 0.0], [0.0, 0.0]));
        expect_inadmissible(id, scene_run(id, &[], outside, adaptive, 1.0), quantity);
    }
}

/// Every scene's default state lies inside its region, and the scenes without a coordinate
/// singularity or a physical limit declare none.
#[test]
fn default_states_are_admissible_and_unbounded_scenes_declare_no_region() {
    let bounded = [
        "kepler",
        "isotropic_oscillator",
        "atwood",
        "double_atwood",
        "double_double_atwood",
        "wedge",
        "spring_pendulum",
    ];
    for scene in lagrange_scenes::all() {
        let params = scene.default_params();
        let initial = scene.default_state(&params).expect("valid");
        let system = scene.build(&params).expect("valid");
        let region = system.check_admissible(initial.t, &initial.q, &initial.qdot);
        assert_eq!(region, Ok(bounded.contains(&scene.id())), "{}", scene.id());
    }
}

/// Every scene's default state stays inside its region over the report's full horizon: the
/// report, `simulate` and `compare` with their defaults never end in `Inadmissible`. Only a
/// scene that declares a region can end there (the test above: the others declare none), so
/// only those are run; the others' full-horizon runs are the full report's.
#[test]
fn default_states_stay_inside_over_the_full_horizon() {
    let horizon = lagrange_validation::plan::FULL_HORIZON;
    let mut bounded = 0;
    for scene in lagrange_scenes::all() {
        let params = scene.default_params();
        let initial = scene.default_state(&params).expect("valid");
        let system = scene.build(&params).expect("valid");
        if system.check_admissible(initial.t, &initial.q, &initial.qdot) != Ok(true) {
            continue;
        }
        bounded += 1;
        let method = Method::Dopri5 { tol: Tolerances::uniform(1e-8) };
        let run = system.simulate(&initial, horizon, method, &Output::Every(horizon / 1000.0));
        assert!(run.is_ok(), "{}: {:?}", scene.id(), run.err());
    }
    assert_eq!(bounded, 7, "the scenes that declare a region, as listed above");
}

/// `--tol 10` used to be accepted (a conservative oscillator's energy grew from 0.05 to 1e16),
/// and 1e-15 .. 1e-20 too close to f64 round-off: the relative tolerance must lie in [10 ε, 1).
#[test]
fn tolerances_outside_ten_epsilon_to_one_are_refused() {
    assert_eq!(MIN_RELATIVE_TOLERANCE, 10.0 * f64::EPSILON);
    let scene = find("harmonic_oscillator").expect("registered");
    let params = scene.default_params();
    let system = scene.build(&params).expect("valid");
    let initial = scene.default_state(&params).expect("valid");
    let run = |method| system.simulate(&initial, 1.0, method, &Output::Ends);
    for tol in [10.0, 1.0, 2e-15, 1e-20] {
        for method in
            [Method::Dopri5 { tol: Tolerances::uniform(tol) }, Method::Sdirk4 { tol: Tolerances::uniform(tol) }]
        {
            match run(method) {
                Err(Error::InvalidSetting { what: "tolerance", value, why }) => {
                    assert_eq!(value, tol);
                    assert!(why.contains("[2.2e-15, 1)"), "{why}");
                }
                other => panic!("{method:?}: {other:?}"),
            }
        }
    }
    for tol in [0.5, 1e-14] {
        for method in
            [Method::Dopri5 { tol: Tolerances::uniform(tol) }, Method::Sdirk4 { tol: Tolerances::uniform(tol) }]
        {
            assert!(run(method).is_ok(), "{method:?} refused");
        }
    }
}

/// The maximal engines are checked in their measurement loop: read back into the wedge's
/// coordinates, the block sent down from x' = 9 m at 1 m/s leaves the incline (x' = L = 10 m at
/// t = (−1 + √(1 + 2ẍ'))/ẍ' = 0.7941 s, ẍ' = 0.653184 m/s²) between the samples at 0.75 and
/// 0.80 s, and the pass ends there.
#[test]
fn maximal_engines_read_back_outside_the_region_end_in_inadmissible() {
    use lagrange_maximal::{Engine, Settings, build};
    use lagrange_validation::measure::track;
    let scene = find("wedge").expect("registered");
    let params = scene.default_params();
    let initial = State::new(0.0, [0.0, 9.0], [0.0, 1.0]);
    let times: Vec<f64> = (0..=40).map(|k| k as f64 * 0.05).collect();
    for engine in [Engine::Cartesian, Engine::RapierMultibody] {
        let mut built = build(engine, scene, &params, &initial, &Settings::default()).expect("buildable");
        let mut reduced = scene.build(&built.params).expect("the wedge builds");
        let result = track(&mut built, reduced.as_mut(), &initial, &times, |_, _| 0.0, |_| Ok(()));
        match result {
            Err(lagrange_validation::Error::Engine(Error::Inadmissible {
                quantity, t, inside_until, value, ..
            })) => {
                assert_eq!(quantity, "block on the incline x'", "{engine}");
                assert!((t - 0.80).abs() < 1e-9 && value > 10.0, "{engine}: t = {t}, x' = {value}");
                assert_eq!(inside_until, Some(times[15]), "{engine}");
            }
            other => panic!("{engine}: {:?}", other.map(|pass| pass.errors.len())),
        }
    }
}
