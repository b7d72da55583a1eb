//! The Cartesian system behind the solver's integrator interface ([`Dynamics`]), with the
//! Lagrangian the interface requires.

use super::{AppliedForce, CartesianSystem, CartesianWorkspace};
use crate::BodyState;
use lagrange::error::Stage;
use lagrange::{Body, Coordinate, Dynamics, Error, LagrangianFunction, Scalar};

/// `L(z, ż, t) = T − Σ m_b g y_b − V`, for the variational integrator's interface. The scene
/// potential enters by its value at the real parts only (its derivatives are not carried), and
/// the constraints not at all: this Lagrangian describes the unconstrained bodies, so the
/// Cartesian system is not meant for the variational integrator; it is integrated by
/// [`Dopri5`](lagrange::integrate::Dopri5) with projection.
impl LagrangianFunction for CartesianSystem {
    type Scratch<S: Scalar> = ();

    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    fn scratch<S: Scalar>(&self) -> Self::Scratch<S> {}

    fn lagrangian_with<S: Scalar>(&self, _: &mut (), t: S, z: &[S], zdot: &[S]) -> S {
        let mut lagrangian = S::zero();
        for (b, body) in self.bodies.iter().enumerate() {
            let v = &zdot[3 * b..3 * b + 3];
            lagrangian += (v[0] * v[0] + v[1] * v[1]) * (0.5 * body.mass) + v[2] * v[2] * (0.5 * body.inertia);
            lagrangian -= (z[3 * b + 1] + self.frame[1]) * (body.mass * self.gravity);
        }
        if self.has_potential {
            let states: Vec<BodyState> = (0..self.bodies.len())
                .map(|b| {
                    let pose = [z[3 * b].re() + self.frame[0], z[3 * b + 1].re() + self.frame[1], z[3 * b + 2].re()];
                    BodyState { pose, velocity: [0.0; 3] }
                })
                .collect();
            let value = self.scene_potential(t.re(), &states, None);
            lagrangian -= S::from(value);
        }
        if let Some(graph) = self.graph() {
            let poses: Vec<lagrange::Pose<f64>> = (0..self.bodies.len())
                .map(|b| lagrange::Pose::new(z[3 * b].re(), z[3 * b + 1].re(), z[3 * b + 2].re()))
                .collect();
            lagrangian -= S::from(graph.force_potential(&poses));
        }
        lagrangian
    }

    fn generalized_force_with<S: Scalar>(&self, _: &mut (), _t: S, _z: &[S], zdot: &[S], force: &mut [S]) -> bool {
        match self.applied {
            AppliedForce::None => false,
            AppliedForce::Lorentz { charge_field } => {
                force[0] += zdot[1] * charge_field;
                force[1] -= zdot[0] * charge_field;
                true
            }
        }
    }
}

/// The Cartesian system as the integrators see it: `q = z`, `q̇ = ż`, `q̈ = z̈` from the KKT
/// system; momenta `M ż`; the reaction forces are the constraint forces `−Jᵀλ`.
impl Dynamics for CartesianSystem {
    type Workspace = CartesianWorkspace;

    fn workspace(&self) -> CartesianWorkspace {
        self.workspace()
    }

    fn accelerations(
        &self,
        ws: &mut CartesianWorkspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        qddot: &mut [f64],
    ) -> Result<(), Error> {
        self.evaluate(ws, t, q, qdot)?;
        if !ws.zddot.iter().chain(&ws.multipliers).all(|v| v.is_finite()) {
            return Err(Error::NonFinite { stage: Stage::Accelerations, t, q: q.to_vec() });
        }
        qddot.copy_from_slice(&ws.zddot);
        Ok(())
    }

    fn energy_function(&self, ws: &mut CartesianWorkspace, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        self.total_energy(ws, t, q, qdot)
    }

    fn mass_matrix(
        &self,
        _ws: &mut CartesianWorkspace,
        _t: f64,
        _q: &[f64],
        _qdot: &[f64],
        mass: &mut [f64],
    ) -> Result<(), Error> {
        let n = self.n();
        mass.fill(0.0);
        for j in 0..n {
            mass[j * n + j] = self.mass[j];
        }
        Ok(())
    }

    fn momenta(
        &self,
        _ws: &mut CartesianWorkspace,
        _t: f64,
        _q: &[f64],
        qdot: &[f64],
        p: &mut [f64],
    ) -> Result<(), Error> {
        for ((p, &m), &v) in p.iter_mut().zip(&self.mass).zip(qdot) {
            *p = m * v;
        }
        Ok(())
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        &self.cyclic
    }

    fn has_external_forces(&self) -> bool {
        self.applied != AppliedForce::None || self.graph().is_some_and(|g| g.has_non_conservative_forces())
    }

    /// Energy is conserved by scleronomic constraints and forces that do no work (gravity,
    /// potentials, the Lorentz force); not by damping, a driven support, or a driving torque
    /// (which conserves `h − τ φ_b` instead).
    fn conserves_energy(&self) -> bool {
        !self.rheonomic && !self.graph().is_some_and(|g| g.has_non_conservative_forces())
    }

    fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    fn reaction_forces(
        &self,
        ws: &mut CartesianWorkspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        reaction: &mut [f64],
    ) -> Result<bool, Error> {
        self.evaluate(ws, t, q, qdot)?;
        self.constraint_forces(ws, reaction);
        Ok(true)
    }
}
