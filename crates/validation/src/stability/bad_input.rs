//! Bad input on every scene: every call under `catch_unwind`, counting panics, non-finite values
//! returned as values, and invalid parameters or settings not rejected by name.

use super::{CaseBuilder, CaseSpec, Check, Cost, Effort, ErrorKind, Measurement, timed_simulate};
use lagrange::{Error, Method, Output, State, System, Tolerances};
use lagrange_maximal::{BuildError, Engine, Settings};
use lagrange_scenes::{Domain, Params, Scene};
use lagrange_testing::{Rng, rng};
use rand::Rng as _;
use std::collections::BTreeSet;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

pub const BAD_INPUT: CaseSpec = CaseSpec {
    id: "bad_input",
    title: "Bad input on every scene: random, extreme, overflowing, non-finite and misshapen",
    // Every registered scene.
    scenes: &[],
    theory: "User input never reaches a panic, and the engine checks finiteness after every stage \
             (docs/method.md#typed-failures): every call returns finite values or a typed error; a \
             non-finite, negative or zero mass, length or step is rejected with the parameter named. A \
             relative tolerance outside [10 ε, 1) is refused (InvalidSetting): at 1 and above no digit is \
             correct, below 10 ε the error estimate is rounding noise. A run that leaves its scene's \
             admissible region (docs/method.md#admissible-regions) ends in Inadmissible, whatever the \
             method: Kepler's radial infall stepped over r = 0 by RK4, the Atwood machines pulling a mass \
             through a pulley, the wedge's block sliding off its incline. A start off the constraints is \
             refused (InvalidSetting). A run that does not resolve its motion fails its own check \
             (lagrange_validation::health): a declared constant of the motion drifts beyond the error its \
             method and setting allow.",
    run: bad_input,
};

/// What the calls of one scene did.
#[derive(Default)]
struct Tally {
    calls: usize,
    panics: Vec<String>,
    non_finite: BTreeSet<String>,
    not_named: Vec<String>,
}

impl Tally {
    /// Run `f` under `catch_unwind`; `None` (and a recorded panic) if it panicked.
    fn call<T>(&mut self, what: &str, f: impl FnOnce() -> T) -> Option<T> {
        self.calls += 1;
        match catch_unwind(AssertUnwindSafe(f)) {
            Ok(value) => Some(value),
            Err(_) => {
                self.panics.push(what.to_string());
                None
            }
        }
    }

    /// Record a value that should be finite.
    fn finite(&mut self, what: &str, values: &[f64]) {
        if !values.iter().all(|v| v.is_finite()) {
            self.non_finite.insert(what.to_string());
        }
    }
}

/// Parameter sets: defaults, and each mass scaled by 1e-6 and 1e6.
fn parameter_sets(scene: &dyn Scene) -> Vec<(String, Params)> {
    let mut sets = vec![("defaults".to_string(), scene.default_params())];
    for spec in scene.params().iter().filter(|s| s.unit == "kg" && s.domain == Domain::Positive) {
        for factor in [1e-6, 1e6] {
            let mut params = scene.default_params();
            if params.set(spec.name, spec.default * factor).is_ok() {
                sets.push((format!("{} × {factor:.0e}", spec.name), params));
            }
        }
    }
    sets
}

/// Regular states around the default, then overflowing ones (whose values may not be finite:
/// `overflowing` = true).
fn states(default: &State, random: &mut Rng) -> Vec<(String, State, bool)> {
    let mut states = Vec::new();
    for k in 0..3 {
        let mut s = default.clone();
        for q in &mut s.q {
            *q = *q * random.random_range(0.5..1.5) + random.random_range(-0.3..0.3);
        }
        for v in &mut s.qdot {
            *v = random.random_range(-3.0..3.0);
        }
        states.push((format!("random {k}"), s, false));
    }
    let with = |f: &dyn Fn(&mut State)| {
        let mut s = default.clone();
        f(&mut s);
        s
    };
    states.push(("q = 1e300".into(), with(&|s| s.q.fill(1e300)), true));
    states.push(("q̇ = 1e200".into(), with(&|s| s.qdot.fill(1e200)), true));
    states.push(("q = 0".into(), with(&|s| s.q.fill(0.0)), true));
    states
}

/// Malformed states: every call must be an error (or ignore the malformed part).
fn malformed(default: &State) -> Vec<(String, State)> {
    let n = default.q.len();
    let with = |f: &dyn Fn(&mut State)| {
        let mut s = default.clone();
        f(&mut s);
        s
    };
    vec![
        ("NaN q".into(), with(&|s| s.q[n - 1] = f64::NAN)),
        ("∞ q̇".into(), with(&|s| s.qdot[0] = f64::INFINITY)),
        ("NaN t".into(), with(&|s| s.t = f64::NAN)),
        ("short q".into(), with(&|s| s.q.truncate(n - 1))),
    ]
}

fn evaluate(tally: &mut Tally, system: &mut dyn System, state: &State, overflowing: bool, label: &str) {
    let (t, q, v) = (state.t, state.q.as_slice(), state.qdot.as_slice());
    let what = |call: &str| format!("{call} at {label}");
    if let Some(Ok(a)) = tally.call(&what("accelerations"), || system.accelerations(t, q, v).map(<[f64]>::to_vec)) {
        tally.finite(&what("accelerations"), &a);
    }
    if let Some(Ok(r)) =
        tally.call(&what("reactions"), || system.reaction_forces(t, q, v).map(|r| r.map(<[f64]>::to_vec)))
    {
        tally.finite(&what("reaction forces"), &r.unwrap_or_default());
    }
    if let Some(Ok(m)) = tally.call(&what("mass matrix"), || system.mass_matrix(t, q, v).map(<[f64]>::to_vec)) {
        tally.finite(&what("mass matrix"), &m);
    }
    if let Some(Ok(p)) = tally.call(&what("momenta"), || system.momenta(t, q, v).map(<[f64]>::to_vec)) {
        tally.finite(&if overflowing { what("momenta") } else { what("momenta (regular state)") }, &p);
    }
    if let Some(Ok(e)) = tally.call(&what("energy"), || system.energy_function(t, q, v)) {
        tally.finite(&if overflowing { what("energy") } else { what("energy (regular state)") }, &[e]);
    }
}

fn simulate(tally: &mut Tally, system: &dyn System, state: &State) {
    let (dt, tol) = (0.005, 1e-6);
    let horizon = state.t + 0.1;
    let methods = [
        Method::Rk4 { dt },
        Method::Dopri5 { tol: Tolerances::uniform(tol) },
        Method::Variational { dt },
        Method::Sdirk4 { tol: Tolerances::uniform(tol) },
        Method::Gauss4 { dt },
    ];
    for method in methods {
        let what = format!("simulate {}", method.name());
        if let Some(Ok(run)) = tally.call(&what, || system.simulate(state, horizon, method, &Output::Every(0.05))) {
            tally.finite(&what, &[run.q, run.qdot, run.energy].concat());
        }
    }
    for bad in [0.0, -dt, f64::NAN, f64::INFINITY] {
        for method in [Method::Rk4 { dt: bad }, Method::Variational { dt: bad }, Method::Gauss4 { dt: bad }] {
            let what = format!("simulate {} with dt = {bad}", method.name());
            let result = tally.call(&what, || system.simulate(state, horizon, method, &Output::Ends));
            if !matches!(result, Some(Err(Error::InvalidSetting { what: "step", .. })) | None) {
                tally.not_named.push(what);
            }
        }
    }
    for bad in [0.0, -tol, f64::NAN, 1e-18, 1e-20, 1.0, 10.0] {
        for method in
            [Method::Dopri5 { tol: Tolerances::uniform(bad) }, Method::Sdirk4 { tol: Tolerances::uniform(bad) }]
        {
            let what = format!("simulate {} with tol = {bad}", method.name());
            let result = tally.call(&what, || system.simulate(state, horizon, method, &Output::Ends));
            if !matches!(result, Some(Err(Error::InvalidSetting { what: "tolerance", .. })) | None) {
                tally.not_named.push(what);
            }
        }
    }
}

fn maximal(tally: &mut Tally, scene: &dyn Scene, params: &Params, state: &State) {
    for engine in Engine::ALL {
        let settings = Settings { dt: 1.0 / 240.0, substeps: 2, tolerance: 1e-8 };
        let what = format!("{engine} build");
        match tally.call(&what, || lagrange_maximal::build(engine, scene, params, state, &settings)) {
            Some(Ok(mut built)) => {
                let sim = &mut built.simulation;
                if let Some(Ok(())) = tally.call(&format!("{engine} advance"), || sim.advance_to(state.t + 0.05)) {
                    let bodies = tally.call(&format!("{engine} bodies"), || sim.bodies()).unwrap_or_default();
                    let values: Vec<f64> = bodies.iter().flat_map(|b| b.pose.into_iter().chain(b.velocity)).collect();
                    tally.finite(&format!("{engine} bodies"), &values);
                }
            }
            Some(Err(BuildError::Invalid(error))) => {
                tally.not_named.push(format!("{what}: valid input rejected: {error}"))
            }
            _ => {}
        }
        for (bad, setting) in [
            (Settings { dt: f64::NAN, ..settings }, "step"),
            (Settings { substeps: 0, ..settings }, "substeps"),
            (Settings { tolerance: -1.0, ..settings }, "tolerance"),
        ] {
            let used = engine.is_rapier() == (setting != "tolerance");
            let what = format!("{engine} build with a bad {setting}");
            let result = tally.call(&what, || lagrange_maximal::build(engine, scene, params, state, &bad));
            let named =
                matches!(result, Some(Err(BuildError::Invalid(Error::InvalidSetting { what, .. }))) if what == setting);
            if used && !named && !matches!(result, Some(Err(BuildError::Unbuildable { .. }))) {
                tally.not_named.push(what);
            }
        }
    }
}

fn invalid_parameters(tally: &mut Tally, scene: &dyn Scene) {
    for spec in scene.params() {
        let mut bad = vec![f64::NAN, f64::INFINITY];
        match spec.domain {
            Domain::Positive => bad.extend([0.0, -1.0]),
            Domain::NonNegative => bad.push(-1e-3),
            Domain::OpenInterval(low, high) => bad.extend([low, high]),
            Domain::Integer { min, max } => bad.extend([f64::from(min) - 1.0, f64::from(max) + 1.0, 1.5]),
            Domain::Finite => {}
        }
        for value in bad {
            let mut params = scene.default_params();
            let what = format!("{} = {value}", spec.name);
            let result = tally.call(&what, || params.set(spec.name, value));
            if !matches!(result, Some(Err(Error::InvalidParameter { ref name, .. })) if name == spec.name) {
                tally.not_named.push(what);
            }
        }
    }
}

fn bad_input(case: &mut CaseBuilder, _effort: Effort) -> Result<(), crate::Error> {
    case.setup = "Per scene: the defaults and every mass scaled by 1e-6 and 1e6; at three random states (fixed seed) \
                  and at q = 1e300, q̇ = 1e200, q = 0: accelerations, reaction forces, mass matrix, momenta, energy; \
                  at NaN q, ∞ q̇, NaN t and a short q: the same, which must be errors; 0.1 s runs with every method \
                  and with bad steps and tolerances; builds in every maximal engine (advanced 0.05 s) and with bad \
                  settings; every parameter set to NaN, ∞ and values outside its domain. Runs that leave the \
                  admissible region: Kepler from r = 1 at rest with RK4 (dt = 1e-3) for 2 s; the Atwood machine and \
                  the wedge from their defaults for 100 s and the double Atwood machine with l' = 0.001 for 10 s \
                  (adaptive, tol 1e-10). The harmonic oscillator with tolerances 10, 1 and 1e-20 (adaptive, \
                  implicit). Starts off the constraints: the non-minimal pendulum at q = (2, 0), the four-bar at \
                  q = 0, the sleigh at q̇ = (1, 1, 0). Runs that do not resolve their motion, checked against \
                  their scene's constants: the four-bar with τ = 1 at tol 1e-3 for 8.98 s and by RK4 at \
                  dt = 0.05 for 10 s, Andrews' squeezer by RK4 and Gauss at dt = 1e-3 for 0.03 s."
        .into();
    // Panics are caught and counted here: keep their messages off the terminal.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = run_scenes(case);
    std::panic::set_hook(hook);
    result?;
    leaving_the_region(case)?;
    refused_tolerances(case)?;
    inconsistent_starts(case)?;
    runs_that_fail_their_check(case)
}

/// A run that must fail its own check (`health::check`): `(label, scene, parameter changes,
/// method, horizon)`.
type Drifting<'a> = (&'a str, &'a str, &'a [(&'a str, f64)], Method, f64);

/// Runs that do not resolve their motion — each exited 0 with a wrong answer before runs
/// checked themselves — fail their check: the largest drift of a declared constant of the
/// motion over its bound is above 1.
fn runs_that_fail_their_check(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let runs: [Drifting<'_>; 4] = [
        ("τ = 1 at tol 1e-3", "four_bar", &[("torque", 1.0)], Method::Dopri5 { tol: Tolerances::uniform(1e-3) }, 8.98),
        ("RK4 at the default step", "andrews_squeezer", &[], Method::Rk4 { dt: 1e-3 }, 0.03),
        ("Gauss at the default step", "andrews_squeezer", &[], Method::Gauss4 { dt: 1e-3 }, 0.03),
        ("RK4 at dt = 0.05", "four_bar", &[], Method::Rk4 { dt: 0.05 }, 10.0),
    ];
    for (label, id, changes, method, horizon) in runs {
        let scene = crate::error::scene(id)?;
        let params = super::scene_params(scene, changes)?;
        let mut system = scene.build(&params)?;
        let initial = scene.default_state(&params)?;
        // A hundred samples, on the step grid for the fixed-step methods.
        let every = horizon / 100.0;
        let output = Output::Every(match method {
            Method::Rk4 { dt } | Method::Gauss4 { dt } | Method::Variational { dt } => {
                dt * (every / dt).round().max(1.0)
            }
            Method::Dopri5 { .. } | Method::Dop853 { .. } | Method::Sdirk4 { .. } => every,
        });
        let (run, wall) = timed_simulate(system.as_ref(), &initial, horizon, method, &output);
        let m = Measurement::new(label, id, method.name(), "largest drift of a declared constant over its bound")
            .params(changes)
            .method_settings(method, horizon);
        let m = match run {
            Ok(t) => {
                let health = crate::health::check(scene, &params, system.as_mut(), method, &t)?;
                let ratio = health.findings.iter().map(|f| f.drift / f.bound).fold(0.0, f64::max);
                m.value(ratio).cost(Cost::of(&t.stats, wall))
            }
            Err(e) => m.failed(e),
        };
        case.push(m.check(Check::AtLeast, None, Some(1.0)));
    }
    Ok(())
}

/// A start off the constraints is refused by every run (`InvalidSetting`), the inconsistency
/// named: a bob 2 m out on a 1 m rod, a four-bar open by 0.2 m, a sleigh sliding sideways.
fn inconsistent_starts(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let starts = [
        ("bob 2 m out on a 1 m rod", "nonminimal_pendulum", State::new(0.0, [2.0, 0.0], [0.0, 0.0])),
        ("loop open by 0.2 m", "four_bar", State::new(0.0, [0.0, 0.0, 0.0], [0.0; 3])),
        ("sliding sideways", "chaplygin_sleigh", State::new(0.0, [0.0, 0.0, 0.0], [1.0, 1.0, 0.0])),
    ];
    let method = Method::Dopri5 { tol: Tolerances::uniform(1e-10) };
    for (label, id, initial) in starts {
        let scene = crate::error::scene(id)?;
        let system = scene.build(&scene.default_params())?;
        let (run, wall) = timed_simulate(system.as_ref(), &initial, 1.0, method, &Output::Ends);
        let m = Measurement::new(label, id, method.name(), "the inconsistent start is refused")
            .method_settings(method, 1.0);
        let m = m.ended(run, wall);
        case.push(m.expect_error(ErrorKind::InvalidSetting));
    }
    Ok(())
}

/// A run that must leave its scene's admissible region: `(label, scene, parameter changes,
/// initial state or the default, method, horizon)`.
type Leaving<'a> = (&'a str, &'a str, &'a [(&'a str, f64)], Option<State>, Method, f64);

/// Runs that leave their scene's admissible region end in [`Error::Inadmissible`], checked for
/// the exact variant.
fn leaving_the_region(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let adaptive = Method::Dopri5 { tol: Tolerances::uniform(1e-10) };
    let runs: [Leaving<'_>; 4] = [
        (
            "radial infall through r = 0",
            "kepler",
            &[],
            Some(State::new(0.0, [1.0, 0.0], [0.0, 0.0])),
            Method::Rk4 { dt: 1e-3 },
            2.0,
        ),
        ("default state for 100 s", "atwood", &[], None, adaptive, 100.0),
        ("default state for 100 s", "wedge", &[], None, adaptive, 100.0),
        ("l' = 0.001", "double_atwood", &[("lower_rope_length", 0.001)], None, adaptive, 10.0),
    ];
    for (label, id, changes, initial, method, horizon) in runs {
        let scene = crate::error::scene(id)?;
        let params = super::scene_params(scene, changes)?;
        let system = scene.build(&params)?;
        let initial = match initial {
            Some(state) => state,
            None => scene.default_state(&params)?,
        };
        let (run, wall) = timed_simulate(system.as_ref(), &initial, horizon, method, &Output::Every(horizon / 200.0));
        let m = Measurement::new(label, id, method.name(), "the run ends in Inadmissible")
            .params(changes)
            .method_settings(method, horizon);
        let m = m.ended(run, wall);
        case.push(m.expect_error(ErrorKind::Inadmissible));
    }
    Ok(())
}

/// Relative tolerances outside `[10 ε, 1)` are refused with [`Error::InvalidSetting`] by both
/// error-controlled methods, checked for the exact variant.
fn refused_tolerances(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let scene = crate::error::scene("harmonic_oscillator")?;
    let params = scene.default_params();
    let system = scene.build(&params)?;
    let initial = scene.default_state(&params)?;
    for tol in [10.0, 1.0, 1e-20] {
        for method in
            [Method::Dopri5 { tol: Tolerances::uniform(tol) }, Method::Sdirk4 { tol: Tolerances::uniform(tol) }]
        {
            let (run, wall) = timed_simulate(system.as_ref(), &initial, 10.0, method, &Output::Ends);
            let m = Measurement::new(format!("tol = {tol:e}"), scene.id(), method.name(), "the tolerance is refused")
                .method_settings(method, 10.0);
            let m = m.ended(run, wall);
            case.push(m.expect_error(ErrorKind::InvalidSetting));
        }
    }
    Ok(())
}

fn run_scenes(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    for (index, scene) in lagrange_scenes::all().iter().enumerate() {
        let start = Instant::now();
        let mut tally = Tally::default();
        let mut random = rng(0x9E37_79B9_7F4A_7C15 ^ (index as u64 + 1));
        for (label, params) in parameter_sets(*scene) {
            let Some(Ok(mut system)) = tally.call("build", || scene.build(&params)) else {
                tally.not_named.push(format!("build [{label}]: valid parameters rejected"));
                continue;
            };
            let default = scene.default_state(&params)?;
            for (state_label, state, overflowing) in states(&default, &mut random) {
                evaluate(&mut tally, system.as_mut(), &state, overflowing, &state_label);
            }
            for (state_label, state) in malformed(&default) {
                let what = format!("accelerations at {state_label}");
                let result =
                    tally.call(&what, || system.accelerations(state.t, &state.q, &state.qdot).map(<[f64]>::to_vec));
                if !matches!(result, Some(Err(Error::NonFinite { .. } | Error::DimensionMismatch { .. })) | None) {
                    tally.not_named.push(format!("{what}: accepted"));
                }
                evaluate(&mut tally, system.as_mut(), &state, true, &state_label);
            }
            simulate(&mut tally, system.as_ref(), &default);
            if label == "defaults" {
                maximal(&mut tally, *scene, &params, &default);
            }
        }
        invalid_parameters(&mut tally, *scene);
        let id = scene.id();
        let cost = Cost { wall_time_s: start.elapsed().as_secs_f64(), ..Cost::default() };
        let calls = tally.calls;
        let list = |items: &mut dyn Iterator<Item = &String>| items.take(6).cloned().collect::<Vec<_>>().join("; ");
        case.push(
            Measurement::new("every call", id, "engine", "panics")
                .value(tally.panics.len() as f64)
                .cost(cost)
                .note(format!(
                    "{calls} calls under catch_unwind{}",
                    if tally.panics.is_empty() {
                        String::new()
                    } else {
                        format!(": {}", list(&mut tally.panics.iter()))
                    }
                ))
                .check(Check::Exact, Some(0.0), None),
        );
        let m = Measurement::new("every call", id, "engine", "non-finite values returned as values (call kinds)")
            .value(tally.non_finite.len() as f64)
            .cost(cost);
        let m = if tally.non_finite.is_empty() { m } else { m.note(list(&mut tally.non_finite.iter())) };
        case.push(m.check(Check::Exact, Some(0.0), None));
        let m = Measurement::new(
            "invalid input",
            id,
            "engine",
            "invalid parameters, settings or states not rejected by name",
        )
        .value(tally.not_named.len() as f64)
        .cost(cost);
        let m = if tally.not_named.is_empty() { m } else { m.note(list(&mut tally.not_named.iter())) };
        case.push(m.check(Check::Exact, Some(0.0), None));
    }
    Ok(())
}
