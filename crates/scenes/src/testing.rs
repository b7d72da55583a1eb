//! Checks shared by the scenes' unit tests, with every tolerance in one place and the reason
//! for its size. Failures print expected, got and residual.

use crate::{Params, Scene, SceneType, scene_of};
use lagrange::{Mechanism, Model, State};
use lagrange_testing::max_abs_diff;
pub(crate) use lagrange_testing::{assert_close, max_abs};

/// Engine `q̈` against the hand-coded closed form, relative to the largest `|q̈_i|`.
///
/// Both are exact formulas for the same `q̈`: they differ only by round-off. For the
/// well-conditioned states used (1 to 4 coordinates, mass matrices with condition numbers
/// below ~10³) that is O(10 ε) ≈ 2e-15 for the closed form and at most cond(M)·ε for the
/// engine's LDLᵀ solve; 1e-12 leaves a margin without hiding a wrong term (any missing or
/// wrong term changes `q̈` by O(1) relative at these generic states).
pub(crate) const ENGINE_VS_CLOSED_FORM: f64 = 1e-12;

/// An exact solution evaluated at its own start time against the initial state, relative to
/// the largest entry: evaluating the closed form at `τ = 0` is exact up to the round-off of a
/// few operations (Kepler: solving Kepler's equation to a few ε).
pub(crate) const EXACT_AT_START: f64 = 1e-13;

/// Step of the central differences that differentiate exact solutions (s): the solutions'
/// time scales are ≥ 0.3 s, so the O(h²) truncation error is ~1e-7 relative and the round-off
/// `~100 ε |q| / h` ~ 1e-11 relative; both are accounted for in the tolerance.
const FD_STEP: f64 = 1e-3;

/// Round-off in one evaluation of an exact solution, in units of ε·(largest entry): a few
/// dozen operations, or Newton's iteration on Kepler's equation converged to a few ε.
const EXACT_ROUND_OFF: f64 = 100.0;

/// The engine's `q̈` (built through [`Scene::build`]) equals the scene's closed form at every
/// state, to [`ENGINE_VS_CLOSED_FORM`] relative to the largest acceleration.
pub(crate) fn assert_engine_matches_closed_form(scene: &dyn Scene, params: &Params, states: &[State]) {
    let mut system = scene.build(params).unwrap_or_else(|e| panic!("{}: build failed: {e}", scene.id()));
    for (k, state) in states.iter().enumerate() {
        let got = system.accelerations(state.t, &state.q, &state.qdot).unwrap().to_vec();
        let expected = scene.closed_form_accelerations(params, state.t, &state.q, &state.qdot).unwrap();
        let expected = expected.unwrap_or_else(|| panic!("{}: no closed form", scene.id()));
        let what = format!("{}: engine q̈ vs closed form at state {k} {state:?}", scene.id());
        assert_close(&what, &expected, &got, ENGINE_VS_CLOSED_FORM * max_abs(&expected));
    }
}

/// Generic states `(t, q, q̇)` of the central forces (`r > 0`, both senses of rotation).
pub(crate) const POLAR_ROWS: [(f64, [f64; 2], [f64; 2]); 4] = [
    (0.5, [0.7, 1.1], [0.4, -2.0]),
    (1.0, [2.3, -3.0], [-0.6, 0.3]),
    (2.0, [0.4, 7.0], [1.5, 4.0]),
    (4.0, [5.0, 0.2], [0.1, 0.05]),
];

/// Generic states `(t, q, q̇)` of two coordinates, with no symmetry and no special value (the
/// pulleys, the wedge, the charge).
pub(crate) const PLANAR_ROWS: [(f64, [f64; 2], [f64; 2]); 4] = [
    (0.5, [-0.4, 0.3], [1.2, -0.5]),
    (1.0, [2.0, 1.9], [-3.0, 2.0]),
    (3.0, [4.5, -0.7], [0.7, 0.1]),
    (7.0, [-1.5, 2.5], [-0.2, -1.1]),
];

/// [`assert_engine_matches_closed_form`] for the scene `T` at its default state and the states
/// `rows` `(t, q, q̇)`: at the default parameters, then after each change of `changes` in turn
/// (each keeping the ones before).
pub(crate) fn assert_engine_matches_closed_form_along<T: SceneType, const N: usize>(
    rows: &[(f64, [f64; N], [f64; N])],
    changes: &[(&str, f64)],
) {
    let (scene, mut params) = (scene_of::<T>(), scene_of::<T>().default_params());
    let mut states = vec![scene.default_state(&params).unwrap()];
    states.extend(rows.iter().map(|&(t, q, qdot)| State::new(t, q, qdot)));
    assert_engine_matches_closed_form(scene, &params, &states);
    for &(key, value) in changes {
        params.set(key, value).unwrap();
        assert_engine_matches_closed_form(scene, &params, &states);
    }
}

/// The largest difference between the articulated-body algorithm on the mechanism's declared
/// tree and the generic assembly from its poses (`Model::new_generic`) over `states`, relative
/// to the largest `|q̈_i|` of the generic path (NaN kept); `None` without a declared tree.
pub(crate) fn tree_versus_generic<M: Mechanism + Clone>(mechanism: M, states: &[State]) -> Option<f64> {
    mechanism.tree()?;
    let tree = Model::new(mechanism.clone()).expect("the declared tree matches the poses");
    let generic = Model::new_generic(mechanism).expect("valid");
    assert!(tree.uses_tree_path() && !generic.uses_tree_path());
    let (mut wt, mut wg) = (tree.workspace(), generic.workspace());
    let relative = states.iter().map(|s| {
        let a = lagrange::accelerations(&tree, &mut wt, s.t, &s.q, &s.qdot).expect("valid").to_vec();
        let b = lagrange::accelerations(&generic, &mut wg, s.t, &s.q, &s.qdot).expect("valid").to_vec();
        max_abs_diff(&a, &b) / max_abs(&b)
    });
    Some(max_abs(&relative.collect::<Vec<_>>()))
}

/// `(q, q̇)` of the scene's exact solution at `t`, which must exist.
fn exact(scene: &dyn Scene, params: &Params, initial: &State, t: f64) -> (Vec<f64>, Vec<f64>) {
    let state = scene.exact_solution(params, initial, t).unwrap();
    let state = state.unwrap_or_else(|| panic!("{}: no exact solution from {initial:?}", scene.id()));
    assert_eq!(state.t, t, "{}: the exact state is at the requested time", scene.id());
    (state.q, state.qdot)
}

/// The scene's exact solution from `initial`:
/// * at `t₀` returns the initial state (to [`EXACT_AT_START`]);
/// * at each `t₀ + τ` has `dq/dt = q̇` and `dq̇/dt = q̈_closed(q, q̇)`, the derivatives taken by
///   central differences. The tolerance is the differences' own truncation error, estimated
///   by Richardson's comparison of steps `h` and `h/2` (the error of the `h/2` difference is
///   one third of their gap; the gap itself is allowed), plus the round-off `2·100 ε |q| / h`.
pub(crate) fn assert_exact_solution_consistent(scene: &dyn Scene, params: &Params, initial: &State, offsets: &[f64]) {
    let id = scene.id();
    let start = scene.exact_solution(params, initial, initial.t).unwrap();
    let start = start.unwrap_or_else(|| panic!("{id}: no exact solution from {initial:?}"));
    let scale = max_abs(&initial.q).max(max_abs(&initial.qdot)).max(1.0);
    let what = format!("{id}: exact solution at t₀ vs initial state");
    assert_close(&format!("{what} (q)"), &initial.q, &start.q, EXACT_AT_START * scale);
    assert_close(&format!("{what} (q̇)"), &initial.qdot, &start.qdot, EXACT_AT_START * scale);

    for &offset in offsets {
        let t = initial.t + offset;
        let (q, qdot) = exact(scene, params, initial, t);
        let qddot = scene.closed_form_accelerations(params, t, &q, &qdot).unwrap().unwrap();
        // Central differences of (q, q̇) with steps h and h/2.
        let central = |h: f64| {
            let (q_plus, qdot_plus) = exact(scene, params, initial, t + h);
            let (q_minus, qdot_minus) = exact(scene, params, initial, t - h);
            let dq: Vec<f64> = q_plus.iter().zip(&q_minus).map(|(p, m)| (p - m) / (2.0 * h)).collect();
            let dqdot: Vec<f64> = qdot_plus.iter().zip(&qdot_minus).map(|(p, m)| (p - m) / (2.0 * h)).collect();
            (dq, dqdot)
        };
        let (dq_h, dqdot_h) = central(FD_STEP);
        let (dq, dqdot) = central(FD_STEP / 2.0);
        let magnitude = max_abs(&q).max(max_abs(&qdot)).max(max_abs(&qddot)).max(1.0);
        let round_off = 2.0 * EXACT_ROUND_OFF * f64::EPSILON * magnitude / (FD_STEP / 2.0);
        let what = format!("{id}: derivative of the exact solution at t = {t}");
        assert_close(&format!("{what}: dq/dt vs q̇"), &qdot, &dq, max_abs_diff(&dq_h, &dq) + round_off);
        assert_close(
            &format!("{what}: dq̇/dt vs closed-form q̈"),
            &qddot,
            &dqdot,
            max_abs_diff(&dqdot_h, &dqdot) + round_off,
        );
    }
}
