//! The exact motion under constant generalized accelerations (Atwood machines, the wedge).

use lagrange::State;

/// `q(t) = q₀ + q̇₀ τ + ½ q̈ τ²`, `q̇(t) = q̇₀ + q̈ τ` with `τ = t − t₀`: the exact solution of
/// `q̈ = const` (docs/scenes.md#constant-accelerations: every pulley and wedge system there has constant `q̈`).
pub(crate) fn uniformly_accelerated(initial: &State, qddot: &[f64], t: f64) -> State {
    debug_assert!(initial.q.len() == qddot.len() && initial.qdot.len() == qddot.len());
    let tau = t - initial.t;
    let q = initial.q.iter().zip(&initial.qdot).zip(qddot).map(|((q0, v0), a)| q0 + tau * (v0 + 0.5 * a * tau));
    let qdot = initial.qdot.iter().zip(qddot).map(|(v0, a)| v0 + a * tau);
    State::new(t, q.collect::<Vec<_>>(), qdot.collect::<Vec<_>>())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_fall_from_a_later_start_time() {
        let initial = State::new(1.0, [2.0], [3.0]);
        let state = uniformly_accelerated(&initial, &[-10.0], 3.0);
        // τ = 2: q = 2 + 3·2 − 5·4, q̇ = 3 − 20.
        assert_eq!(state, State::new(3.0, [-12.0], [-17.0]));
    }
}
