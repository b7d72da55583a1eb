//! The exact motion and the constants of the motion under constant generalized accelerations
//! (Atwood machines, the wedge).

use crate::{Conserved, Invariant, SceneType};
use lagrange::State;
use std::sync::Arc;

/// `q(t) = q₀ + q̇₀ τ + ½ q̈ τ²`, `q̇(t) = q̇₀ + q̈ τ` with `τ = t − t₀`: the exact solution of
/// `q̈ = const` (docs/scenes.md#constant-accelerations: every pulley and wedge system there has constant `q̈`).
pub(crate) fn uniformly_accelerated(initial: &State, qddot: &[f64], t: f64) -> State {
    debug_assert!(initial.q.len() == qddot.len() && initial.qdot.len() == qddot.len());
    let tau = t - initial.t;
    let q = initial.q.iter().zip(&initial.qdot).zip(qddot).map(|((q0, v0), a)| q0 + tau * (v0 + 0.5 * a * tau));
    let qdot = initial.qdot.iter().zip(qddot).map(|(v0, a)| v0 + a * tau);
    State::new(t, q.collect::<Vec<_>>(), qdot.collect::<Vec<_>>())
}

/// The constants of the motion of a scene with a constant mass matrix `M` (`n × n`, row-major)
/// and a constant generalized force `F = −∂V/∂q`, so `V = V₀ − F·q`
/// (docs/scenes.md#constant-accelerations): the energy `E = ½ q̇ᵀ M q̇ − F·q + V₀`, and for
/// each coordinate `p_j − F_j t` with `p = M q̇`, since Lagrange's equation reads `ṗ_j = F_j`:
/// the momentum `p_j` of a coordinate in `cyclic`, absent from `L` (a force that vanishes only
/// for some parameter values, as for `m1 = m2` in the Atwood machine, leaves `p_j − 0 t`).
pub(crate) fn constant_force_invariants<T: SceneType>(
    scene: &T,
    (mass, force): (Vec<f64>, Vec<f64>),
    potential_at_zero: f64,
    cyclic: &[usize],
) -> Vec<Conserved> {
    let (mass, force): (Arc<[f64]>, Arc<[f64]>) = (mass.into(), force.into());
    let momentum = |mass: &[f64], j: usize, qdot: &[f64]| -> f64 {
        qdot.iter().enumerate().map(|(k, v)| mass[j * qdot.len() + k] * v).sum()
    };
    let (m, f) = (mass.clone(), force.clone());
    let mut list = vec![Conserved::energy(scene, move |_, q, qdot| {
        let terms = (0..q.len()).map(|j| 0.5 * qdot[j] * momentum(&m, j, qdot) - f[j] * q[j]);
        terms.sum::<f64>() + potential_at_zero
    })];
    for (j, coordinate) in scene.generalized_coordinates().iter().enumerate() {
        let (m, f_j, name) = (mass.clone(), force[j], &coordinate.name);
        let value = move |_: &T, t: f64, _: &[f64], qdot: &[f64]| momentum(&m, j, qdot) - f_j * t;
        list.push(if cyclic.contains(&j) {
            Conserved::new(scene, format!("p_{name}"), "cyclic coordinate", Invariant::CyclicMomentum(j), value)
        } else {
            Conserved::new(scene, format!("p_{name} − F_{name} t"), "ṗ = F is constant", Invariant::Other, value)
        });
    }
    list
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
