//! Constraint (reaction) forces from the reduced solution against their closed forms: Atwood
//! rope tensions, the wedge's normal force, the cart pendulum's rod tension; and no reaction
//! where nothing constrains the body (the Kepler particle).

use lagrange_scenes::SceneType;
use lagrange_scenes::{atwood::Atwood, cart_pendulum::CartPendulum, double_atwood::DoubleAtwood, wedge::Wedge};
use lagrange_tests::{max_abs, rng, sampling, tolerance};

use lagrange_tests::scene;

/// Check the engine's reaction on each body against `expected` (F_x, F_y, τ), where given,
/// at random states.
fn check(id: &str, seed: u64, expected: impl Fn(&lagrange_scenes::Params, &lagrange::State) -> Vec<Option<[f64; 3]>>) {
    let s = scene(id);
    let mut rng = rng(seed);
    for set in 0..10 {
        let mut params = if set == 0 { s.default_params() } else { sampling::regular_params(s, &mut rng) };
        // The lecture's point bob: the closed forms below are for it.
        if let Some(spec) = s.params().iter().find(|p| p.name == "bob_inertia") {
            params.set(spec.name, 0.0).expect("zero is allowed");
        }
        let state = sampling::state(s, &params, &mut rng, set);
        let mut system = s.build(&params).expect("valid");
        let reaction =
            system.reaction_forces(state.t, &state.q, &state.qdot).expect("valid").expect("a body model").to_vec();
        for (b, want) in expected(&params, &state).iter().enumerate() {
            let Some(want) = want else { continue };
            let got = &reaction[3 * b..3 * b + 3];
            let scale = max_abs(want).max(max_abs(got)).max(1e-300);
            for c in 0..3 {
                // Both sides are exact formulas: round-off only.
                assert!(
                    (got[c] - want[c]).abs() <= tolerance::ROUNDOFF * scale,
                    "{id} body {b}: expected {want:?}, got {got:?}"
                );
            }
        }
    }
}

#[test]
fn atwood_rope_tensions() {
    // T₁ = m₁(g − ẍ), T₂ = m₂(g + ẍ) (docs/scenes.md#atwood): the rope pulls each mass straight up.
    check("atwood", 7001, |params, state| {
        let atwood = Atwood::from_params(params).expect("valid");
        let (t1, t2) = atwood.tensions(&state.q, &state.qdot);
        vec![Some([0.0, t1, 0.0]), Some([0.0, t2, 0.0])]
    });
}

#[test]
fn double_atwood_rope_tensions() {
    check("double_atwood", 7002, |params, state| {
        let machine = DoubleAtwood::from_params(params).expect("valid");
        let (upper, lower) = machine.tensions(&state.q, &state.qdot);
        vec![Some([0.0, upper, 0.0]), Some([0.0, lower, 0.0]), Some([0.0, lower, 0.0])]
    });
}

#[test]
fn wedge_normal_force_on_the_block() {
    // N = M m g cos α / (M + m sin²α) (docs/scenes.md#wedge), along the slope's outward normal
    // (sin α, cos α); body 1 is the block.
    // The bound is round-off of max(|want|∞, |got|∞) ≈ |N| max(sin α, cos α) ≤ |N|.
    check("wedge", 7003, |params, _| {
        let (alpha, n) = (params.get("angle"), Wedge::from_params(params).expect("valid").normal_force());
        vec![None, Some([n * alpha.sin(), n * alpha.cos(), 0.0])]
    });
}

#[test]
fn cart_pendulum_rod_tension() {
    // The rod pulls the (point) bob towards the pivot, along (−sin θ, cos θ), with
    // T = m (g cos θ + r θ̇² − Ẍ sin θ). A compound bob (I_b > 0) also feels a transverse pin
    // force and a torque from the rod, which this closed form does not cover.
    check("cart_pendulum", 7004, |params, state| {
        let cart = CartPendulum::from_params(params).expect("valid");
        let tension = cart.rod_tension(&state.q, &state.qdot);
        let theta = state.q[1];
        // The cart's reaction (rail normal force plus the rod's pull) is not checked here.
        vec![None, Some([-tension * theta.sin(), tension * theta.cos(), 0.0])]
    });
}

#[test]
fn a_free_particle_in_a_central_field_feels_no_constraint_force() {
    let s = scene("kepler");
    let mut rng = rng(7005);
    for k in 0..10 {
        let params = sampling::regular_params(s, &mut rng);
        let state = sampling::state(s, &params, &mut rng, k);
        let mut system = s.build(&params).expect("valid");
        let qddot = system.accelerations(state.t, &state.q, &state.qdot).expect("valid").to_vec();
        let reaction = system.reaction_forces(state.t, &state.q, &state.qdot).expect("valid").expect("bodies").to_vec();
        // m p̈ = −∂V/∂p exactly: the reaction is round-off of the size of m|p̈| ~ m |q̈| r.
        let scale = params.get("mass") * max_abs(&qddot) * state.q[0].abs().max(1.0);
        assert!(max_abs(&reaction) <= tolerance::ROUNDOFF * scale, "reaction {reaction:?} (scale {scale})");
    }
}
