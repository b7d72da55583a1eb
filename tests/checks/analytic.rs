//! Engine accelerations against the hand-coded closed forms of every scene
//! (docs/scenes.md; the lecture (docs/scenes.md#the-lecture)), at random and extreme parameters and states.

use lagrange_scenes::{Params, Scene, all};
use lagrange_tests::{condition_number, max_abs, max_abs_diff, rng, sampling, tolerance};

/// Compare engine and closed form at one state; returns the relative error and its bound.
fn compare(scene: &dyn Scene, label: &str, params: &Params, state: &lagrange::State) -> Option<(f64, f64)> {
    let expected = scene.closed_form_accelerations(params, state.t, &state.q, &state.qdot).expect("valid input")?;
    let mut system = scene.build(params).expect("valid parameters");
    let got = system
        .accelerations(state.t, &state.q, &state.qdot)
        .unwrap_or_else(|e| panic!("{} [{label}]: {e}", scene.id()))
        .to_vec();
    let n = got.len();
    // A constrained scene's solve goes through S = G M⁻¹ Gᵀ: κ(S) ≤ κ(M) κ(G)².
    let kappa = condition_number(n, system.mass_matrix(state.t, &state.q, &state.qdot).expect("valid state"))
        * sampling::constraint_condition(system.as_mut(), state);
    let bound = tolerance::conditioned(kappa);
    let scale = max_abs(&expected);
    let residual = max_abs_diff(&got, &expected);
    let relative = if scale == 0.0 { residual } else { residual / scale };
    assert!(
        relative <= bound,
        "{} [{label}] at q = {:?}, q̇ = {:?}: expected {expected:?}, got {got:?}, relative residual {relative:e} > {bound:e} (κ(M) κ(G)² = {kappa:e})",
        scene.id(),
        state.q,
        state.qdot
    );
    Some((relative, bound))
}

#[test]
fn accelerations_match_closed_forms_at_random_states_and_parameters() {
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(1000 + index as u64);
        let mut checked = 0;
        // 8 parameter sets × 4 states (a quarter of them at angles 1e-8, another at π/2 − 1e-8).
        for set in 0..8 {
            let params = if set == 0 { scene.default_params() } else { sampling::regular_params(*scene, &mut rng) };
            for k in 0..4 {
                let state = sampling::state(*scene, &params, &mut rng, k);
                if compare(*scene, &format!("set {set}"), &params, &state).is_some() {
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 32, "{}: states compared", scene.id());
    }
}

#[test]
fn accelerations_match_closed_forms_at_extreme_parameters() {
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(2000 + index as u64);
        for (label, params) in sampling::extreme_params(*scene) {
            for k in 0..4 {
                let state = sampling::state(*scene, &params, &mut rng, k);
                compare(*scene, &label, &params, &state);
            }
        }
    }
}

#[test]
fn every_scene_has_a_closed_form() {
    for scene in all() {
        let params = scene.default_params();
        let state = scene.default_state(&params).expect("defaults are valid");
        assert!(
            scene.closed_form_accelerations(&params, state.t, &state.q, &state.qdot).expect("valid").is_some(),
            "{} has no closed-form accelerations",
            scene.id()
        );
    }
}

#[test]
fn equal_atwood_masses_do_not_accelerate_at_all() {
    let scene = lagrange_scenes::find("atwood").expect("registered");
    let mut rng = rng(3);
    for _ in 0..20 {
        let mut params = sampling::regular_params(scene, &mut rng);
        let m = params.get("mass_1");
        params.set("mass_2", m).expect("positive");
        let state = sampling::state(scene, &params, &mut rng, 0);
        let mut system = scene.build(&params).expect("valid");
        let qddot = system.accelerations(state.t, &state.q, &state.qdot).expect("valid");
        // (m1 − m2) g is formed from identical numbers: the acceleration is exactly zero.
        assert_eq!(qddot[0], 0.0, "m1 = m2 = {m}: ẍ = {}", qddot[0]);
    }
}
