//! The Cartesian + multiplier formulation against the reduced solver, scene by scene: body
//! accelerations, trajectories, constraint forces and energy; then the error paths.
//!
//! Tolerances, each with its origin:
//! * [`ACCELERATION_RTOL`]: `z̈` and the reduced `p̈_b = J_b q̈ + γ_b` are two exact formulas
//!   for the same accelerations, so they differ by round-off only: the KKT solve loses
//!   `cond(KKT)·ε ≲ 1e3 · 2e-16` at these well-conditioned states; 1e-10 leaves a wide margin
//!   while any wrong or missing term (a sign in `γ_Φ`, a missing force) changes `z̈` at O(1).
//! * [`TRAJECTORY_TOL`]: both runs integrate at [`TOLERANCE`] = 1e-12 per step; over 2 s and
//!   O(10³) steps the global errors of either run stay ≲ 1e-10 for these non-chaotic horizons
//!   (measured: see the printed reports), so 1e-8 bounds their difference with margin.
//! * [`VIOLATION_TOL`]: the projection leaves every `|Φ_i| ≤ 4 ε · size_i` after every step
//!   (`size_i` the magnitude of the positions and lever arms in the equation); 1e-10 of the size
//!   is the largest violation it accepts when Gauss–Newton stalls at round-off.
//! * [`FORCE_RTOL`]: at the same state the constraint forces are again two exact formulas
//!   (round-off only); 1e-8 relative to the largest force (floored at 1 N) as the brief asks.
//! * [`ENERGY_RTOL`]: with local errors ≤ 1e-12 the energy drifts by O(steps · 1e-12) relative
//!   to the energy's own magnitude (floored at 1 J); 1e-10 allows ~100 steps' worth of error
//!   accumulating coherently.

use super::constraints::Constraint;
use super::simulation::CartesianSimulation;
use super::system::CartesianSystem;
use crate::maps::ReadBack;
use crate::{BodyState, BuildError, Engine, MaximalSimulation, Settings};
use lagrange::integrate::Tolerances;
use lagrange::num_dual::Dual2_64;
use lagrange::{Dynamics, Error, Mechanism, Method, Output, Pose, State};
use lagrange_scenes::SceneType;
use lagrange_scenes::{ClosedForm, MechanismVisitor, Params, SINGULAR_DEFAULT_MOTION, Scene, visit_mechanism};
use lagrange_testing::{assert_close, max_abs, max_abs_diff};

/// `z̈` against the reduced body accelerations, relative to the largest (floored at 1 m/s²).
const ACCELERATION_RTOL: f64 = 1e-10;
/// Integrator tolerance of both the Cartesian and the reduced run.
const TOLERANCE: f64 = 1e-12;
/// Length of the compared runs (s).
const HORIZON: f64 = 2.0;
/// Read-back `(q, q̇)` against the reduced solution after [`HORIZON`] (m, rad, m/s, rad/s).
const TRAJECTORY_TOL: f64 = 1e-8;
/// [`TRAJECTORY_TOL`] for the scenes whose default motion passes singular configurations
/// ([`SINGULAR_DEFAULT_MOTION`]): there the reduced run is the less accurate of the two — its
/// regularized multiplier solve drops part of the vanishing rows' force within about 1e-5 of
/// the flat position (docs/method.md#constraints; measured against the reduced run at 2 s:
/// 1.5e-8 for the parallelogram chain, whose reduced run is 1.5e-8 off its exact solution,
/// and 7.1e-6 for the change-point four-bar). The Cartesian runs themselves meet
/// [`TRAJECTORY_TOL`] against the exact solutions (`cartesian_runs_follow_the_exact_solutions`).
const SINGULAR_TRAJECTORY_TOL: f64 = 3e-5;
/// [`ENERGY_RTOL`] for [`SINGULAR_DEFAULT_MOTION`]: the Cartesian solve is regularized the
/// same way (its shift `μ = 1e-9`) and each pass through a flat position costs energy at the
/// same level (measured 8.2e-10 relative for the change-point four-bar over 2 s, two passes).
const SINGULAR_ENERGY_RTOL: f64 = 5e-9;
/// Constraint violation after [`HORIZON`] (m, rad).
const VIOLATION_TOL: f64 = 1e-10;
/// Constraint forces against the reduced reaction forces, relative to the largest (floored at 1 N).
const FORCE_RTOL: f64 = 1e-8;
/// Energy change over [`HORIZON`], relative to `max(|E₀|, 1 J)`.
const ENERGY_RTOL: f64 = 1e-10;
/// Split of a redundant pair's multipliers against equal halves, relative to the largest
/// multiplier: the shift `μ = 1e-9` of the Schur complement lets the round-off of the right-hand
/// side into the redundant direction amplified by `1/μ`, once per solve and refinement:
/// `(k + 1) ε / μ ≈ 9e-7` (measured 9e-8); 1e-5 keeps a margin, while a split decided by the
/// order of the rows (the whole force on one copy) is off by 1/2.
const REDUNDANT_RTOL: f64 = 1e-5;

/// The scene and its parameters with `overrides` set.
fn scene_and_params(id: &str, overrides: &[(&str, f64)]) -> (&'static dyn Scene, Params) {
    let scene = lagrange_scenes::find(id).unwrap_or_else(|| panic!("unknown scene {id}"));
    let mut params = scene.default_params();
    for &(key, value) in overrides {
        params.set(key, value).unwrap();
    }
    (scene, params)
}

/// A Cartesian simulation of `id` started from the reduced `state`.
fn cartesian(id: &str, params: &Params, state: &State) -> CartesianSimulation {
    let system = CartesianSystem::new(crate::scene(id), params).unwrap();
    let states = ReadBack::new(crate::scene(id), params).unwrap().body_states(state).unwrap();
    CartesianSimulation::new(system, &states, state.t, TOLERANCE).unwrap()
}

/// The reduced model's body accelerations `p̈_b = J_b q̈ + γ_b` (3B), computed independently of
/// the reduced engine's own assembly: one second-order dual pass of the scene's poses along
/// `q(s) = q + s q̇ + ½ s² q̈`, `t + s`.
struct BodyAccelerations<'a> {
    state: &'a State,
    qddot: &'a [f64],
}

impl MechanismVisitor for BodyAccelerations<'_> {
    type Output = Vec<f64>;

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) -> Vec<f64> {
        let s = self.state;
        let q: Vec<Dual2_64> =
            s.q.iter().zip(&s.qdot).zip(self.qddot).map(|((&q, &v), &a)| Dual2_64::new(q, v, a)).collect();
        let mut poses = vec![Pose::<Dual2_64>::default(); mechanism.description().bodies.len()];
        mechanism.poses(Dual2_64::new(s.t, 1.0, 0.0), &q, &mut poses);
        poses.iter().flat_map(|p| [p.x.v2, p.y.v2, p.angle.v2]).collect()
    }
}

fn reduced_body_accelerations(id: &str, params: &Params, state: &State, qddot: &[f64]) -> Vec<f64> {
    match visit_mechanism(id, params, BodyAccelerations { state, qddot }).unwrap() {
        Some(accelerations) => accelerations,
        // The charged particle: its coordinates are the particle's position.
        None => vec![qddot[0], qddot[1], 0.0],
    }
}

/// The non-conservative forces the reduced reaction forces keep (they act along coordinates,
/// not through poses) but the Cartesian formulation applies: the oscillator's damping
/// `−c ẋ` on body 0 (its coordinate is the body's `x`). Added to the Cartesian constraint
/// forces before comparing.
fn reduced_keeps(id: &str, params: &Params, zdot: &[f64]) -> Vec<f64> {
    let mut kept = vec![0.0; zdot.len()];
    if id == "harmonic_oscillator" {
        kept[0] = -params.get("damping") * zdot[0];
    }
    kept
}

/// What one scene's comparison measured.
#[derive(Debug, Default)]
struct Report {
    acceleration: f64,
    force_start: f64,
    trajectory_q: f64,
    trajectory_qdot: f64,
    violation: f64,
    force_end: f64,
    energy: Option<f64>,
    steps: usize,
}

/// Accelerations and constraint forces of the Cartesian system at `state` against the reduced
/// engine's; returns the two relative errors.
fn compare_at(id: &str, params: &Params, state: &State) -> (f64, f64) {
    let scene = lagrange_scenes::find(id).unwrap();
    let mut reduced = scene.build(params).unwrap();
    let mut simulation = cartesian(id, params, state);
    simulation.evaluate().unwrap();
    // (1) z̈ against J_b q̈ + γ_b.
    let qddot = reduced.accelerations(state.t, &state.q, &state.qdot).unwrap().to_vec();
    let expected = reduced_body_accelerations(id, params, state, &qddot);
    let scale = max_abs(&expected).max(1.0);
    let what = format!("{id}: z̈ vs reduced body accelerations at {state:?}");
    let acceleration = assert_close(&what, &expected, &simulation.ws.zddot, ACCELERATION_RTOL * scale) / scale;
    // (3) −Φ_zᵀλ against the reduced reaction forces.
    let n = simulation.system.n();
    let mut forces = vec![0.0; n];
    simulation.system.constraint_forces(&simulation.ws, &mut forces);
    let kept = reduced_keeps(id, params, &simulation.zdot);
    let got: Vec<f64> = forces.iter().zip(&kept).map(|(f, k)| f + k).collect();
    let expected =
        reduced.reaction_forces(state.t, &state.q, &state.qdot).unwrap().map_or(vec![0.0; n], <[f64]>::to_vec);
    let scale = max_abs(&expected).max(1.0);
    let what = format!("{id}: constraint forces vs reduced reaction forces at {state:?}");
    let force = assert_close(&what, &expected, &got, FORCE_RTOL * scale) / scale;
    (acceleration, force)
}

/// `state` moved onto the scene's constraints among its coordinates (closed loops), the first
/// coordinate and its rate held ([`lagrange::assemble`]); unchanged for a scene without them.
struct Assembled<'a>(&'a State);

impl MechanismVisitor for Assembled<'_> {
    type Output = State;

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) -> State {
        let model = lagrange::Model::new(mechanism).unwrap();
        let held: Vec<bool> = (0..self.0.q.len()).map(|i| i == 0).collect();
        lagrange::assemble(&model, self.0, &held).unwrap()
    }
}

/// How long the runs of a scene are compared (s): [`HORIZON`], or the scene's own span where it
/// has one (Andrews' squeezer: the test problem's 0.03 s; its crank turns at ~1000 rad/s by then).
fn horizon(id: &str) -> f64 {
    lagrange_scenes::find(id).and_then(|s| s.horizon()).unwrap_or(HORIZON)
}

/// The four comparisons of the brief for one scene with `overrides`.
fn check(id: &str, overrides: &[(&str, f64)]) -> Report {
    let horizon = horizon(id);
    let (scene, params) = scene_and_params(id, overrides);
    let initial = scene.default_state(&params).unwrap();
    let mut report = Report::default();
    // (1), (3) at the start, and at a moving state later in time (exercises γ_Φ, Φ_t, Φ_tt).
    let (acceleration, force) = compare_at(id, &params, &initial);
    let moving = State::new(
        0.7,
        initial.q.iter().map(|q| q + 0.1).collect::<Vec<_>>(),
        initial.qdot.iter().map(|v| v + 0.3).collect::<Vec<_>>(),
    );
    let moving = visit_mechanism(id, &params, Assembled(&moving)).unwrap().unwrap_or(moving);
    let (acceleration_moving, force_moving) = compare_at(id, &params, &moving);
    report.acceleration = acceleration.max(acceleration_moving);
    report.force_start = force.max(force_moving);

    // (2) after the horizon at tolerance 1e-12, against the reduced solution.
    let settings = Settings { tolerance: TOLERANCE, ..Settings::default() };
    let built = super::build(crate::scene(id), &params, &initial, &settings).unwrap();
    assert_eq!((built.params.clone(), built.deviations.len()), (params.clone(), 0), "{id}: no deviations");
    let mut simulation = built.simulation;
    assert_eq!(simulation.engine(), Engine::Cartesian);
    simulation.advance_to(horizon).unwrap();
    assert_eq!(simulation.t(), horizon, "{id}: advance_to reaches the time exactly");
    let bodies = simulation.bodies();
    let reduced = scene.build(&params).unwrap();
    let method = Method::Dopri5 { tol: Tolerances::uniform(TOLERANCE) };
    let trajectory = reduced.simulate(&initial, horizon, method, &Output::Ends).unwrap();
    let end = trajectory.last_state().unwrap();
    // Angles are read back on the branch nearest the reduced solution (a crank turns many
    // times; its angle is compared modulo 2π).
    let (q, qdot) = ReadBack::new(crate::scene(id), &params).unwrap().generalized(horizon, &bodies, &end.q);
    let bound = if SINGULAR_DEFAULT_MOTION.contains(&id) { SINGULAR_TRAJECTORY_TOL } else { TRAJECTORY_TOL };
    report.trajectory_q = assert_close(&format!("{id}: q after {horizon} s"), &end.q, &q, bound);
    report.trajectory_qdot = assert_close(&format!("{id}: q̇ after {horizon} s"), &end.qdot, &qdot, bound);
    report.violation = simulation.constraint_violation().unwrap();
    assert!(report.violation <= VIOLATION_TOL, "{id}: constraint violation {:e}", report.violation);
    report.steps = simulation.steps();

    // (3) at the end: the reduced reaction forces at the read-back state.
    let forces = simulation.constraint_forces().unwrap();
    let zdot: Vec<f64> = bodies.iter().flat_map(|b| b.velocity).collect();
    let kept = reduced_keeps(id, &params, &zdot);
    let got: Vec<f64> = forces.iter().zip(&kept).map(|(f, k)| f + k).collect();
    let mut reduced = scene.build(&params).unwrap();
    let expected = reduced.reaction_forces(horizon, &q, &qdot).unwrap().map_or(vec![0.0; got.len()], <[f64]>::to_vec);
    let scale = max_abs(&expected).max(1.0);
    let what = format!("{id}: constraint forces after {horizon} s");
    report.force_end = assert_close(&what, &expected, &got, FORCE_RTOL * scale) / scale;

    // (4) energy, where the scene conserves it (both formulations must agree on that).
    let system = CartesianSystem::new(crate::scene(id), &params).unwrap();
    assert_eq!(system.conserves_energy(), reduced.conserves_energy(), "{id}: energy conservation");
    if system.conserves_energy() {
        let mut ws = system.workspace();
        let start = ReadBack::new(crate::scene(id), &params).unwrap().body_states(&initial).unwrap();
        let (z0, zdot0) = flatten(&start);
        let e0 = system.energy_function(&mut ws, initial.t, &z0, &zdot0).unwrap();
        let (z1, zdot1) = flatten(&bodies);
        let e1 = system.energy_function(&mut ws, horizon, &z1, &zdot1).unwrap();
        let drift = (e1 - e0).abs() / e0.abs().max(1.0);
        let bound = if SINGULAR_DEFAULT_MOTION.contains(&id) { SINGULAR_ENERGY_RTOL } else { ENERGY_RTOL };
        assert!(drift <= bound, "{id}: energy {e0} → {e1}, relative change {drift:e}");
        report.energy = Some(drift);
    }
    eprintln!("cartesian {id} {overrides:?}: {report:?}");
    report
}

/// `(z, ż)` of body states.
fn flatten(states: &[BodyState]) -> (Vec<f64>, Vec<f64>) {
    (states.iter().flat_map(|b| b.pose).collect(), states.iter().flat_map(|b| b.velocity).collect())
}

/// The rolling disc's rotation read from its body angle without unwrapping: the Cartesian
/// angle is continuous, so whole turns are compared too (bound [`TRAJECTORY_TOL`]).
#[test]
fn rolling_disc_turns_as_far_as_the_reduced_disc() {
    let (scene, params) = scene_and_params("rolling_disc", &[]);
    let initial = scene.default_state(&params).unwrap();
    let settings = Settings { tolerance: TOLERANCE, ..Settings::default() };
    let mut simulation = super::build(crate::scene("rolling_disc"), &params, &initial, &settings).unwrap().simulation;
    simulation.advance_to(HORIZON).unwrap();
    let exact = scene.exact_solution(&params, &initial, HORIZON).unwrap().unwrap();
    assert!(exact.q[1] > 30.0, "several turns: φ = {}", exact.q[1]);
    assert_close("φ after 2 s", &[exact.q[1]], &[simulation.bodies()[0].pose[2]], TRAJECTORY_TOL);
}

/// The knife edge holds in the Cartesian run: after 3 s the velocity row `v_P · n` is at
/// round-off (the projection after every step), and the multiplier is the reduced one.
#[test]
fn the_knife_edge_holds_in_cartesian_coordinates() {
    let (scene, params) = scene_and_params("chaplygin_sleigh", &[]);
    let initial = scene.default_state(&params).unwrap();
    let mut simulation = cartesian("chaplygin_sleigh", &params, &initial);
    simulation.advance_to(3.0).unwrap();
    let (z, zdot) = (simulation.z.clone(), simulation.zdot.clone());
    simulation.system.constraint_rate(&mut simulation.ws, 3.0, &z, &zdot);
    assert!(simulation.ws.rate[0].abs() <= 1e-15, "v_P · n = {:e}", simulation.ws.rate[0]);
    simulation.evaluate().unwrap();
    let (q, qdot) = ReadBack::new(crate::scene("chaplygin_sleigh"), &params).unwrap().generalized(
        3.0,
        &simulation.bodies(),
        &initial.q,
    );
    let mut reduced = scene.build(&params).unwrap();
    let lambda = reduced.constraint_multipliers(3.0, &q, &qdot).unwrap().unwrap().to_vec();
    // The same row in both: A = (−sinφ, cosφ, a) is v_P · n in body poses.
    assert_close("knife-edge multiplier", &lambda, &simulation.ws.multipliers, FORCE_RTOL * max_abs(&lambda).max(1.0));
}

/// The loops' multipliers are the Cartesian pin forces: each closing constraint of the reduced
/// model is the same point coincidence as one Cartesian pin (the four-bar's `B_coupler −
/// B_rocker`, the slider-crank's rod end on the slider, the squeezer's `E` through K2 against
/// `E` through K3, K4 and K6), so with the same sign convention (`M q̈ + Gᵀ λ = f` and
/// `M z̈ + Φ_zᵀ λ = F`) the two multipliers are one force. Compared along a Cartesian run, at
/// the state read back from it, to [`FORCE_RTOL`] of the largest: both solve the same
/// equations at the same state, so only round-off separates them.
#[test]
fn loop_multipliers_are_the_cartesian_pin_forces() {
    /// A scene, its parameter overrides, the time compared and the Cartesian rows of each
    /// reduced row (the graph's joints in order, two rows per pin or slide: the loop-closing
    /// pins come after the tree's joints).
    type Case = (&'static str, &'static [(&'static str, f64)], f64, &'static [usize]);
    let cases: [Case; 4] = [
        ("four_bar", &[], 0.7, &[6, 7]),
        ("four_bar", &[("torque", 2.5)], 0.7, &[6, 7]),
        ("slider_crank", &[], 0.2, &[6, 7]),
        ("andrews_squeezer", &[], 0.01, &[14, 15, 16, 17, 18, 19]),
    ];
    for (id, overrides, t, rows) in cases {
        let (scene, params) = scene_and_params(id, overrides);
        let initial = scene.default_state(&params).unwrap();
        let mut simulation = cartesian(id, &params, &initial);
        simulation.advance_to(t).unwrap();
        simulation.evaluate().unwrap();
        let (q, qdot) =
            ReadBack::new(crate::scene(id), &params).unwrap().generalized(t, &simulation.bodies(), &initial.q);
        let mut reduced = scene.build(&params).unwrap();
        let lambda = reduced.constraint_multipliers(t, &q, &qdot).unwrap().unwrap().to_vec();
        let pins: Vec<f64> = rows.iter().map(|&r| simulation.ws.multipliers[r]).collect();
        let scale = max_abs(&lambda);
        eprintln!("{id} {overrides:?}: λ differs by {:.1e} relative", max_abs_diff(&lambda, &pins) / scale);
        assert_close(&format!("{id}: pin forces"), &lambda, &pins, FORCE_RTOL * scale);
    }
}

/// One test per scene (and variant), and the list of covered scenes.
macro_rules! scene_tests {
    ($($name:ident: $scene:literal $(, $key:literal = $value:expr)*;)*) => {
        $(
            #[test]
            fn $name() {
                check($scene, &[$(($key, $value)),*]);
            }
        )*
        /// Every scene id some test above compares.
        const COVERED: &[&str] = &[$($scene),*];
    };
}

scene_tests! {
    cart_pendulum: "cart_pendulum";
    cart_pendulum_compound_bob: "cart_pendulum", "bob_inertia" = 0.2;
    harmonic_oscillator: "harmonic_oscillator";
    harmonic_oscillator_damped: "harmonic_oscillator", "damping" = 0.5;
    kepler: "kepler";
    isotropic_oscillator: "isotropic_oscillator";
    atwood: "atwood";
    atwood_massless_pulley: "atwood", "pulley_inertia" = 0.0;
    double_atwood: "double_atwood";
    double_atwood_massive_pulley: "double_atwood", "lower_pulley_mass" = 0.4;
    double_double_atwood: "double_double_atwood";
    double_double_atwood_massive_pulleys: "double_double_atwood", "pulley_a_mass" = 0.3, "pulley_b_mass" = 0.6;
    wedge: "wedge";
    double_pendulum: "double_pendulum";
    double_pendulum_compound_bobs: "double_pendulum", "inertia_1" = 0.1, "inertia_2" = 0.05;
    chain: "chain";
    chain_of_three: "chain", "links" = 3.0;
    spring_pendulum: "spring_pendulum";
    driven_pendulum: "driven_pendulum";
    charged_particle: "charged_particle";
    nonminimal_pendulum: "nonminimal_pendulum";
    chaplygin_sleigh: "chaplygin_sleigh";
    chaplygin_sleigh_edge_behind: "chaplygin_sleigh", "offset" = -0.3;
    rolling_disc: "rolling_disc";
    rolling_disc_steep: "rolling_disc", "incline" = 1.1, "radius" = 0.4;
    four_bar: "four_bar";
    four_bar_driven: "four_bar", "torque" = 2.5;
    slider_crank: "slider_crank";
    slider_crank_driven: "slider_crank", "torque" = -1.5;
    andrews_squeezer: "andrews_squeezer";
    parallelogram_chain: "parallelogram_chain";
    change_point_four_bar: "change_point_four_bar";
    redundant_parallelogram: "redundant_parallelogram";
}

#[test]
fn every_scene_is_compared() {
    for id in lagrange_scenes::ids() {
        assert!(COVERED.contains(&id), "{id} has no Cartesian comparison test");
    }
}

/// Every scene with an exact solution (closed forms, Kepler's equation, Jacobi elliptic
/// functions through a parallelogram's flat positions), run in Cartesian coordinates for
/// [`HORIZON`] at [`TOLERANCE`], against that solution, to [`TRAJECTORY_TOL`]: the same bound as
/// against the reduced run, with the reduced solver out of the comparison.
#[test]
fn cartesian_runs_follow_the_exact_solutions() {
    let settings = Settings { tolerance: TOLERANCE, ..Settings::default() };
    let mut compared = 0;
    for scene in lagrange_scenes::all() {
        let (id, params) = (scene.id(), scene.default_params());
        let initial = scene.default_state(&params).unwrap();
        let horizon = horizon(id);
        let Some(exact) = scene.exact_solution(&params, &initial, horizon).unwrap() else {
            continue;
        };
        let mut simulation = super::build(crate::scene(id), &params, &initial, &settings).unwrap().simulation;
        simulation.advance_to(horizon).unwrap();
        let (q, qdot) =
            ReadBack::new(crate::scene(id), &params).unwrap().generalized(horizon, &simulation.bodies(), &exact.q);
        let (error_q, error_qdot) = (max_abs_diff(&exact.q, &q), max_abs_diff(&exact.qdot, &qdot));
        eprintln!(
            "{id}: Cartesian against the exact solution after {horizon} s: {error_q:.1e} in q, {error_qdot:.1e} in q̇"
        );
        assert_close(&format!("{id}: q against the exact solution"), &exact.q, &q, TRAJECTORY_TOL);
        assert_close(&format!("{id}: q̇ against the exact solution"), &exact.qdot, &qdot, TRAJECTORY_TOL);
        compared += 1;
    }
    assert!(compared >= 10, "{compared} scenes have exact solutions");
}

/// The constraint forces are the closed-form forces the lecture's systems name: the Atwood
/// rope tensions (docs/scenes.md#atwood), the wedge's normal force (docs/scenes.md#wedge), the cart pendulum's rod
/// tension (§1), at generic states.
#[test]
fn constraint_forces_are_the_closed_form_tensions_and_normal_force() {
    let tolerance = |scale: f64| FORCE_RTOL * scale.max(1.0);
    // Atwood: the rope pulls m1 and m2 up with T1 and T2.
    let (_, params) = scene_and_params("atwood", &[]);
    let state = State::new(0.0, [1.3], [0.4]);
    let mut simulation = cartesian("atwood", &params, &state);
    let forces = simulation.constraint_forces().unwrap();
    let (t1, t2) = lagrange_scenes::Atwood::from_params(&params).unwrap().tensions(&state.q, &state.qdot);
    assert_close("Atwood tensions", &[t1, t2], &[forces[1], forces[4]], tolerance(t1.max(t2)));
    // Wedge: the incline pushes the block along its normal (sin α, cos α) with N.
    let (_, params) = scene_and_params("wedge", &[]);
    let state = State::new(0.0, [0.2, 0.5], [-0.1, 0.6]);
    let mut simulation = cartesian("wedge", &params, &state);
    let forces = simulation.constraint_forces().unwrap();
    let normal = lagrange_scenes::Wedge::from_params(&params).unwrap().normal_force();
    let (sin, cos) = params.get("angle").sin_cos();
    assert_close("wedge normal force", &[normal * sin, normal * cos, 0.0], &forces[3..6], tolerance(normal));
    // Cart pendulum: the rod pulls the bob towards the cart along (−sin θ, cos θ) with T.
    let (_, params) = scene_and_params("cart_pendulum", &[]);
    let state = State::new(0.0, [0.3, -0.7], [0.4, 1.3]);
    let mut simulation = cartesian("cart_pendulum", &params, &state);
    let forces = simulation.constraint_forces().unwrap();
    let tension = lagrange_scenes::CartPendulum::from_params(&params).unwrap().rod_tension(&state.q, &state.qdot);
    let (sin, cos) = state.q[1].sin_cos();
    assert_close("cart rod tension", &[-tension * sin, tension * cos, 0.0], &forces[3..6], tolerance(tension));
}

/// `advance_to` reaches every requested time exactly, in any sequence; going back in time
/// or to a non-finite time is an error, and a repeated time does nothing.
#[test]
fn advance_to_reaches_each_requested_time_exactly() {
    let (scene, params) = scene_and_params("double_pendulum", &[]);
    let initial = scene.default_state(&params).unwrap();
    let settings = Settings { tolerance: 1e-10, ..Settings::default() };
    let mut simulation = crate::build(Engine::Cartesian, crate::scene("double_pendulum"), &params, &initial, &settings)
        .unwrap()
        .simulation;
    for t in [0.1, 0.25, 0.25, 1.0 / 3.0] {
        simulation.advance_to(t).unwrap();
        assert_eq!(simulation.t(), t);
    }
    let steps = simulation.steps();
    assert!(steps > 0);
    simulation.advance_to(1.0 / 3.0).unwrap();
    assert_eq!(simulation.steps(), steps, "a repeated time takes no step");
    for bad in [0.2, f64::NAN, f64::INFINITY] {
        let error = simulation.advance_to(bad).unwrap_err();
        assert!(matches!(error, Error::InvalidSetting { what: "time", .. }), "{bad}: {error}");
    }
    assert!(simulation.constraint_violation().unwrap() <= VIOLATION_TOL);
}

/// A scene of one's own that is not a joint graph: the cart pendulum's model and data under
/// another id, without its graph.
struct Opaque(&'static dyn Scene);

impl Scene for Opaque {
    fn id(&self) -> &'static str {
        "opaque_cart_pendulum"
    }
    fn title(&self) -> &'static str {
        self.0.title()
    }
    fn reference(&self) -> &'static str {
        self.0.reference()
    }
    fn horizon(&self) -> Option<f64> {
        self.0.horizon()
    }
    fn params(&self) -> &'static [lagrange_scenes::ParamSpec] {
        self.0.params()
    }
    fn coordinates(&self, params: &Params) -> Result<Vec<lagrange::Coordinate>, Error> {
        self.0.coordinates(params)
    }
    fn default_state(&self, params: &Params) -> Result<State, Error> {
        self.0.default_state(params)
    }
    fn build(&self, params: &Params) -> Result<Box<dyn lagrange::System>, Error> {
        self.0.build(params)
    }
    fn closed_form_accelerations(
        &self,
        params: &Params,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<Vec<f64>>, Error> {
        self.0.closed_form_accelerations(params, t, q, qdot)
    }
    fn exact_solution(&self, params: &Params, initial: &State, t: f64) -> Result<Option<State>, Error> {
        self.0.exact_solution(params, initial, t)
    }
    fn conserved_quantities(&self, params: &Params) -> Result<Vec<lagrange_scenes::Conserved>, Error> {
        self.0.conserved_quantities(params)
    }
    fn joint_graph(&self, _: &Params) -> Result<Option<lagrange::graph::JointGraph>, Error> {
        Ok(None)
    }
    fn rapier_deviations(&self, multibody: bool) -> &'static [lagrange_scenes::RapierDeviation] {
        self.0.rapier_deviations(multibody)
    }
}

/// A scene with no maximal description (neither a joint graph nor a hand-written one) is
/// unbuildable in every engine, saying why; invalid parameters are still named as such.
#[test]
fn a_scene_without_a_maximal_description_is_unbuildable() {
    let scene = Opaque(crate::scene("cart_pendulum"));
    let params = scene.default_params();
    let initial = scene.default_state(&params).unwrap();
    for engine in Engine::ALL {
        match crate::build(engine, &scene, &params, &initial, &Settings::default()) {
            Err(BuildError::Unbuildable { engine: e, scene: id, reason }) => {
                assert_eq!((e, id.as_str()), (engine, "opaque_cart_pendulum"));
                assert!(reason.contains("no maximal description"), "{reason}");
            }
            other => panic!("{engine}: expected unbuildable, got {:?}", other.err()),
        }
    }
}

#[test]
fn invalid_inputs_are_errors_not_panics() {
    let (scene, params) = scene_and_params("cart_pendulum", &[]);
    let initial = scene.default_state(&params).unwrap();
    let settings = Settings::default();
    let invalid = |result: Result<crate::Built, BuildError>| match result {
        Err(BuildError::Invalid(error)) => error,
        Err(other) => panic!("expected an invalid-input error, got {other}"),
        Ok(_) => panic!("expected an error"),
    };
    let foreign = lagrange_scenes::find("charged_particle").unwrap().default_params();
    let error = invalid(super::build(crate::scene("cart_pendulum"), &foreign, &initial, &settings));
    assert!(matches!(error, Error::InvalidParameter { .. }), "{error}");
    let short = State::new(0.0, [0.0], [0.0]);
    let error = invalid(super::build(crate::scene("cart_pendulum"), &params, &short, &settings));
    assert!(matches!(error, Error::DimensionMismatch { .. }), "{error}");
    for tolerance in [0.0, -1.0, f64::NAN] {
        let error = invalid(super::build(
            crate::scene("cart_pendulum"),
            &params,
            &initial,
            &Settings { tolerance, ..settings },
        ));
        assert!(matches!(error, Error::InvalidSetting { what: "tolerance", .. }), "{error}");
    }
    let nan = State::new(0.0, [f64::NAN, 0.5], [0.0, 0.0]);
    let error = invalid(super::build(crate::scene("cart_pendulum"), &params, &nan, &settings));
    assert!(matches!(error, Error::NonFinite { .. }), "{error}");
}

/// Body states that violate a constraint (here: the bob moved off the rod) are rejected at the
/// start, naming the constraint.
#[test]
fn initial_states_off_the_constraints_are_rejected() {
    let (scene, params) = scene_and_params("cart_pendulum", &[]);
    let mut states = ReadBack::new(crate::scene("cart_pendulum"), &params)
        .unwrap()
        .body_states(&scene.default_state(&params).unwrap())
        .unwrap();
    states[1].pose[0] += 1e-6;
    let system = CartesianSystem::new(crate::scene("cart_pendulum"), &params).unwrap();
    let error = CartesianSimulation::new(system, &states, 0.0, TOLERANCE).err().unwrap();
    // The bob's joint `θ` on the cart, its x row.
    assert!(matches!(error, Error::Inconsistent { ref what } if what.contains("`θ (x)`")), "{error}");
}

/// A massless pulley without its joint (the pin and the rope's no-slip coupling) has nothing
/// fixing it: its augmented mass matrix is singular, reported as `SingularMassMatrix` naming the
/// coordinate, never a panic or NaN.
#[test]
fn singular_kkt_matrices_are_errors_naming_the_culprit() {
    let (scene, params) = scene_and_params("atwood", &[("pulley_inertia", 0.0)]);
    let initial = scene.default_state(&params).unwrap();
    let states = ReadBack::new(crate::scene("atwood"), &params).unwrap().body_states(&initial).unwrap();
    let system = CartesianSystem::new(crate::scene("atwood"), &params).unwrap();
    let no_slip = |c: &Constraint| c.name == "pulley turn";
    // Without the pulley's joint.
    let slipping: Vec<Constraint> = system.constraints.iter().filter(|c| !no_slip(c)).cloned().collect();
    let slipping = system.clone().with_constraints(slipping);
    let (z, zdot) = flatten(&states);
    let mut ws = slipping.workspace();
    let error = slipping.evaluate(&mut ws, 0.0, &z, &zdot).unwrap_err();
    assert!(
        matches!(error, Error::SingularMassMatrix { ref coordinate, .. } if coordinate.contains("[pulley]")),
        "{error}"
    );
    let error = CartesianSimulation::new(slipping, &states, 0.0, TOLERANCE).err().unwrap();
    assert!(matches!(error, Error::SingularMassMatrix { .. }), "{error}");
}

/// A constraint written twice (the Atwood rope's joint, three rows) is redundant, not singular:
/// the accelerations are those of the rope written once (to [`FORCE_RTOL`]: round-off), and the
/// rope's multipliers are shared equally between the copies — the least `Σ S_ii λ_i²` among the
/// multipliers that hold the rope — to [`REDUNDANT_RTOL`].
#[test]
fn a_constraint_written_twice_shares_its_force() {
    let (scene, params) = scene_and_params("atwood", &[]);
    let initial = scene.default_state(&params).unwrap();
    let (z, zdot) = flatten(&ReadBack::new(crate::scene("atwood"), &params).unwrap().body_states(&initial).unwrap());
    let system = CartesianSystem::new(crate::scene("atwood"), &params).unwrap();
    let mut ws = system.workspace();
    system.evaluate(&mut ws, 0.0, &z, &zdot).unwrap();
    // The rope's rows in the single system, and the copy's rows (appended last).
    let mut first = 0;
    let rope = system.constraints.iter().position(|c| c.name == "rope to m2").unwrap();
    for constraint in &system.constraints[..rope] {
        first += constraint.equations();
    }
    let rows = system.constraints[rope].equations();
    let mut doubled = system.constraints.clone();
    doubled.push(Constraint { name: "rope again".into(), joint: system.constraints[rope].joint.clone() });
    let doubled = system.clone().with_constraints(doubled);
    let mut twice = doubled.workspace();
    doubled.evaluate(&mut twice, 0.0, &z, &zdot).unwrap();
    let scale = max_abs(&ws.multipliers);
    assert_close("z̈ with the rope twice", &ws.zddot, &twice.zddot, FORCE_RTOL * max_abs(&ws.zddot));
    let half: Vec<f64> = ws.multipliers[first..first + rows].iter().map(|l| 0.5 * l).collect();
    let copy = system.m();
    assert_close("the rope's share", &half, &twice.multipliers[first..first + rows], REDUNDANT_RTOL * scale);
    assert_close("the copy's share", &half, &twice.multipliers[copy..copy + rows], REDUNDANT_RTOL * scale);
}

/// The projection takes a state perturbed off both manifolds back onto `Φ = 0` to
/// `1e-14 · scale` and onto `Φ̇ = 0` to round-off.
#[test]
fn projection_restores_positions_and_velocities() {
    for (id, overrides) in [
        ("chain", &[][..]),
        ("driven_pendulum", &[][..]),
        ("wedge", &[][..]),
        ("chaplygin_sleigh", &[][..]),
        ("rolling_disc", &[][..]),
    ] {
        let (scene, params) = scene_and_params(id, overrides);
        let state = scene.default_state(&params).unwrap();
        let system = CartesianSystem::new(crate::scene(id), &params).unwrap();
        let (mut z, mut zdot) =
            flatten(&ReadBack::new(crate::scene(id), &params).unwrap().body_states(&state).unwrap());
        for (k, (p, v)) in z.iter_mut().zip(zdot.iter_mut()).enumerate() {
            *p += 1e-7 * (k as f64 + 1.0).sin();
            *v += 1e-5 * (k as f64 + 2.0).cos();
        }
        let t = 0.3;
        let mut ws = system.workspace();
        system.project(&mut ws, t, &mut z, &mut zdot).unwrap();
        let scale = max_abs(&z).max(1.0);
        assert!(system.violation(t, &z) <= 1e-14 * scale, "{id}: Φ = {:e}", system.violation(t, &z));
        system.constraint_rate(&mut ws, t, &z, &zdot);
        assert!(max_abs(&ws.rate) <= 1e-14 * scale, "{id}: Φ̇ = {:?}", ws.rate);
    }
}

/// The `Dynamics` interface: `3B` named coordinates, `M = diag(m_b, m_b, I_b)`, momenta `M ż`,
/// and the energy equals the maps' independent `Σ ½ m v² + ½ I ω² + m g y + V`.
#[test]
fn dynamics_interface_matches_the_bodies() {
    for scene in lagrange_scenes::all() {
        let id = scene.id();
        let params = scene.default_params();
        let state = scene.default_state(&params).unwrap();
        let system = CartesianSystem::new(crate::scene(id), &params).unwrap();
        let bodies = ReadBack::new(crate::scene(id), &params).unwrap().bodies().to_vec();
        let n = 3 * bodies.len();
        assert_eq!((system.dof(), system.bodies().len()), (n, bodies.len()), "{id}");
        let states = ReadBack::new(crate::scene(id), &params).unwrap().body_states(&state).unwrap();
        let (z, zdot) = flatten(&states);
        let mut ws = system.workspace();
        let mut mass = vec![f64::NAN; n * n];
        system.mass_matrix(&mut ws, 0.0, &z, &zdot, &mut mass).unwrap();
        let mut momenta = vec![0.0; n];
        system.momenta(&mut ws, 0.0, &z, &zdot, &mut momenta).unwrap();
        for (b, body) in bodies.iter().enumerate() {
            for c in 0..3 {
                let j = 3 * b + c;
                let m = if c == 2 { body.inertia } else { body.mass };
                assert_eq!(mass[j * n + j], m, "{id}: M[{j}][{j}]");
                assert_eq!(momenta[j], m * zdot[j], "{id}: p[{j}]");
            }
        }
        let energy = system.energy_function(&mut ws, state.t, &z, &zdot).unwrap();
        let expected = ReadBack::new(crate::scene(id), &params).unwrap().energy(state.t, &states);
        assert!((energy - expected).abs() <= 1e-14 * expected.abs().max(1.0), "{id}: energy {energy} vs {expected}");
        let mut reaction = vec![0.0; n];
        assert!(system.reaction_forces(&mut ws, state.t, &z, &zdot, &mut reaction).unwrap());
    }
}
