//! Identities every body model must satisfy (RigidBodyDynamics.jl's mechanism tests):
//! `½ q̇ᵀ M q̇ = T`, `M` symmetric positive definite, power balance `dh/dt = Q·q̇ − ∂L/∂t` (`Q`
//! with the generalized forces of loads applied at points of bodies).

use lagrange::num_dual::Dual64;
use lagrange::{Mechanism, Model, State};
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, visit_mechanism};
use lagrange_tests::{rng, sampling, tolerance};

struct Identities<'a> {
    states: &'a [State],
}

impl MechanismVisitor for Identities<'_> {
    type Output = ();

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) {
        let model = Model::new(mechanism).expect("valid");
        let n = model.dof();
        let mut ws = model.workspace();
        let mut dual = model.workspace_in::<Dual64>();
        for s in self.states {
            let m = lagrange::mass_matrix(&model, &mut ws, s.t, &s.q, &s.qdot).expect("valid").to_vec();
            // M is symmetric (assembled from one triangle) and positive definite.
            for i in 0..n {
                for j in 0..n {
                    assert_eq!(m[i * n + j], m[j * n + i], "M not symmetric at ({i}, {j})");
                }
            }
            let matrix = nalgebra::DMatrix::from_row_slice(n, n, &m);
            assert!(matrix.clone().cholesky().is_some(), "M not positive definite: {matrix}");
            // ½ q̇ᵀ M q̇ = T for scleronomic mechanisms (a moving support adds terms linear in q̇).
            let kinetic = lagrange::kinetic_energy(&model, &mut ws, s.t, &s.q, &s.qdot).expect("valid");
            let quadratic =
                0.5 * (0..n).map(|i| (0..n).map(|j| s.qdot[i] * m[i * n + j] * s.qdot[j]).sum::<f64>()).sum::<f64>();
            if model.is_autonomous() {
                assert!(
                    (kinetic - quadratic).abs() <= tolerance::ROUNDOFF * kinetic.abs().max(1e-300),
                    "T = {kinetic} but ½ q̇ᵀ M q̇ = {quadratic}"
                );
            }
            // Power balance along the motion: differentiate h(t, q, q̇) in the direction (1, q̇, q̈).
            let qddot = lagrange::accelerations(&model, &mut ws, s.t, &s.q, &s.qdot).expect("valid").to_vec();
            let applied_at_state = ws.applied_force.clone();
            let seeded = |x: &[f64], dx: &[f64]| x.iter().zip(dx).map(|(a, b)| Dual64::new(*a, *b)).collect::<Vec<_>>();
            let plain = |x: &[f64]| x.iter().map(|a| Dual64::from(*a)).collect::<Vec<_>>();
            // dh/dt as the sum of its three partial contributions, each kept for the scale.
            let parts = [
                lagrange::energy_function(&model, &mut dual, Dual64::new(s.t, 1.0), &plain(&s.q), &plain(&s.qdot))
                    .expect("valid")
                    .eps,
                lagrange::energy_function(
                    &model,
                    &mut dual,
                    Dual64::from(s.t),
                    &seeded(&s.q, &s.qdot),
                    &plain(&s.qdot),
                )
                .expect("valid")
                .eps,
                lagrange::energy_function(&model, &mut dual, Dual64::from(s.t), &plain(&s.q), &seeded(&s.qdot, &qddot))
                    .expect("valid")
                    .eps,
            ];
            let dh_dt: f64 = parts.iter().sum();
            let dl_dt = lagrange::lagrangian(&model, &mut dual, Dual64::new(s.t, 1.0), &plain(&s.q), &plain(&s.qdot))
                .expect("valid")
                .eps;
            let mut force = vec![0.0; n];
            model.mechanism().generalized_force(s.t, &s.q, &s.qdot, &mut force);
            // Forces applied at points of bodies (a crank's driving torque) as generalized
            // forces, which `accelerations` left in the workspace.
            let applied = applied_at_state;
            for (f, a) in force.iter_mut().zip(&applied) {
                *f += a;
            }
            let power: f64 = force.iter().zip(&s.qdot).map(|(f, v)| f * v).sum();
            let mut scale = parts.iter().map(|p| p.abs()).sum::<f64>() + power.abs() + dl_dt.abs();
            if model.constraint_counts() != (0, 0) {
                // The constraint forces' power −λ·(G q̇) vanishes on the constraints (the sampled
                // states are on them) by cancellation among the terms of q̇ᵀ M q̈: their size.
                scale += (0..n)
                    .map(|i| (s.qdot[i] * (0..n).map(|j| m[i * n + j] * qddot[j]).sum::<f64>()).abs())
                    .sum::<f64>();
            }
            assert!(
                (dh_dt - (power - dl_dt)).abs() <= tolerance::ROUNDOFF * scale.max(1e-300),
                "dh/dt = {dh_dt} but Q·q̇ − ∂L/∂t = {} (parts {parts:?})",
                power - dl_dt
            );
        }
    }
}

#[test]
fn mass_matrix_kinetic_energy_and_power_balance_identities_hold_on_every_scene() {
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(5000 + index as u64);
        for set in 0..3 {
            let params = if set == 0 { scene.default_params() } else { sampling::regular_params(*scene, &mut rng) };
            let states: Vec<State> = (0..6).map(|k| sampling::state(*scene, &params, &mut rng, k)).collect();
            visit_mechanism(scene.id(), &params, Identities { states: &states }).expect("valid");
        }
    }
}
