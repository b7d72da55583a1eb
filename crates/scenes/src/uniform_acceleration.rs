//! The exact motion and the constants of the motion under constant generalized accelerations
//! (Atwood machines, the wedge).

use crate::{Conserved, Invariant, SceneType};
use lagrange::{Pose, Scalar, State};

/// `q(t) = q₀ + q̇₀ τ + ½ q̈ τ²`, `q̇(t) = q̇₀ + q̈ τ` with `τ = t − t₀`: the exact solution of
/// `q̈ = const` (docs/scenes.md#constant-accelerations: every pulley and wedge system there has constant `q̈`).
pub(crate) fn uniformly_accelerated(initial: &State, qddot: &[f64], t: f64) -> State {
    debug_assert!(initial.q.len() == qddot.len() && initial.qdot.len() == qddot.len());
    let tau = t - initial.t;
    let q = initial.q.iter().zip(&initial.qdot).zip(qddot).map(|((q0, v0), a)| q0 + tau * (v0 + 0.5 * a * tau));
    let qdot = initial.qdot.iter().zip(qddot).map(|(v0, a)| v0 + a * tau);
    State::new(t, q.collect::<Vec<_>>(), qdot.collect::<Vec<_>>())
}

/// A scene whose mass matrix `M` and generalized forces `F = −∂V/∂q` are constant, so that
/// `V = V₀ − F·q` and `q̈` is constant (docs/scenes.md#constant-accelerations): the Atwood
/// machines and the wedge. [`constant_force_scene!`] derives from it the scene's closed form, its
/// exact solution (uniform acceleration) and its constants of the motion
/// ([`constant_force_invariants`]).
pub(crate) trait ConstantForce<const N: usize>: SceneType {
    /// The coordinates absent from `L`, whose momenta the engine finds conserved.
    const CYCLIC: &'static [usize] = &[];

    /// The constant `q̈`, in closed form.
    fn qddot(&self) -> [f64; N];

    /// `(M, F, V₀)`.
    fn constant_terms(&self) -> ([[f64; N]; N], [f64; N], f64);
}

/// The [`SceneType`] methods of a [`ConstantForce`] scene (a body mechanism).
macro_rules! constant_force_scene {
    () => {
        fn closed_form(&self, _t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
            let n = qddot.len();
            assert!(
                q.len() == n && qdot.len() == n,
                "q and q̇ must have {n} entries, got {} and {}",
                q.len(),
                qdot.len()
            );
            qddot.copy_from_slice(&self.qddot());
        }

        /// Uniform acceleration: `q = q₀ + q̇₀ τ + ½ q̈ τ²`.
        fn exact_solution(&self, initial: &lagrange::State, t: f64) -> Option<lagrange::State> {
            Some($crate::uniform_acceleration::uniformly_accelerated(initial, &self.qddot(), t))
        }

        /// The energy `E = ½ q̇ᵀ M q̇ − F·q + V₀` and `p_j − F_j t` (docs/scenes.md#constant-accelerations).
        fn conserves_energy(&self) -> Vec<$crate::Conserved> {
            $crate::uniform_acceleration::constant_force_invariants(self)
        }

        $crate::scene::body_scene!(engine);
    };
}

pub(crate) use constant_force_scene;

/// Bodies hanging below the upper pulley at these depths: at `(0, −depth)`.
pub(crate) fn hang_at_depths<S: Scalar>(world_from_body: &mut [Pose<S>], depths: impl IntoIterator<Item = S>) {
    for (pose, depth) in world_from_body.iter_mut().zip(depths) {
        *pose = Pose::point(S::zero(), -depth);
    }
}

/// The constants of the motion of a [`ConstantForce`] scene: the energy
/// `E = ½ q̇ᵀ M q̇ − F·q + V₀`, and for each coordinate `p_j − F_j t` with `p = M q̇`, since
/// Lagrange's equation reads `ṗ_j = F_j`: the momentum `p_j` of a cyclic coordinate (a force
/// that vanishes only for some parameter values, as for `m1 = m2` in the Atwood machine,
/// leaves `p_j − 0 t`).
pub(crate) fn constant_force_invariants<T: ConstantForce<N>, const N: usize>(scene: &T) -> Vec<Conserved> {
    let (mass, force, potential_at_zero) = scene.constant_terms();
    let momentum = move |j: usize, qdot: &[f64]| -> f64 { mass[j].iter().zip(qdot).map(|(m, v)| m * v).sum() };
    let mut list = vec![Conserved::energy(scene, move |_, q, qdot| {
        let terms = (0..N).map(|j| 0.5 * qdot[j] * momentum(j, qdot) - force[j] * q[j]);
        terms.sum::<f64>() + potential_at_zero
    })];
    for (j, coordinate) in scene.generalized_coordinates().iter().enumerate() {
        let (f_j, name) = (force[j], &coordinate.name);
        let value = move |_: &T, t: f64, _: &[f64], qdot: &[f64]| momentum(j, qdot) - f_j * t;
        list.push(if T::CYCLIC.contains(&j) {
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
