//! The interface integrators see: equations of motion in `f64` with caller-owned scratch.

use crate::eom::{self, energy};
use crate::{Error, LagrangianFunction, Mechanism, Model, RawModel, RawWorkspace};

/// A system whose equations of motion `q̈ = a(t, q, q̇)` can be evaluated, with its energy
/// function and momenta: a body [`Model`] or a [`RawModel`].
///
/// Every integrator is written against this trait. It extends [`LagrangianFunction`] because
/// the variational integrator works on `L` itself.
pub trait Dynamics: LagrangianFunction {
    /// Scratch space, allocated once by [`new_workspace`](Self::new_workspace).
    type Workspace;

    /// Number of coordinates `n`.
    fn dof(&self) -> usize {
        self.coordinates().len()
    }

    /// Allocate the scratch space.
    fn new_workspace(&self) -> Self::Workspace;

    /// Write `q̈` into `qddot`.
    ///
    /// # Errors
    /// As [`accelerations`](crate::accelerations).
    fn accelerations(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        qddot: &mut [f64],
    ) -> Result<(), Error>;

    /// The energy function `h = q̇·∂L/∂q̇ − L`.
    ///
    /// # Errors
    /// On a malformed or non-finite state.
    fn energy(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error>;

    /// Write the mass matrix `M = ∂²L/∂q̇²` (n × n, row-major) at `(t, q, q̇)` into `mass`
    /// (for body models it does not depend on `q̇`).
    ///
    /// # Errors
    /// On a malformed or non-finite state.
    fn mass_matrix(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        mass: &mut [f64],
    ) -> Result<(), Error>;

    /// Write the generalized momenta `p = ∂L/∂q̇` into `p`.
    ///
    /// # Errors
    /// On a malformed or non-finite state.
    fn momenta(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64], p: &mut [f64]) -> Result<(), Error>;

    /// Which coordinates are cyclic.
    fn cyclic_coordinates(&self) -> &[bool];

    /// Whether non-conservative generalized forces act.
    fn has_generalized_force(&self) -> bool;

    /// Whether `h` is conserved (autonomous and no generalized forces).
    fn conserves_energy(&self) -> bool;

    /// The bodies, for systems described by bodies (empty for a raw Lagrangian).
    fn bodies(&self) -> &[crate::Body] {
        &[]
    }

    /// Write the constraint forces `(F_x, F_y, τ)` on every body (3B) into `reaction` and
    /// return `true`, or return `false` for systems without bodies.
    ///
    /// # Errors
    /// As [`reaction_forces`](crate::reaction_forces).
    fn reaction_forces(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        reaction: &mut [f64],
    ) -> Result<bool, Error> {
        let _ = (ws, t, q, qdot, reaction);
        Ok(false)
    }
}

impl<M: Mechanism> Dynamics for Model<M> {
    type Workspace = crate::Workspace<f64>;

    fn new_workspace(&self) -> Self::Workspace {
        self.workspace()
    }

    fn accelerations(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        qddot: &mut [f64],
    ) -> Result<(), Error> {
        qddot.copy_from_slice(eom::accelerations(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn energy(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        energy::energy(self, ws, t, q, qdot)
    }

    fn mass_matrix(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        _qdot: &[f64],
        mass: &mut [f64],
    ) -> Result<(), Error> {
        mass.copy_from_slice(eom::mass_matrix(self, ws, t, q)?);
        Ok(())
    }

    fn momenta(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64], p: &mut [f64]) -> Result<(), Error> {
        p.copy_from_slice(energy::momenta(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        Model::cyclic_coordinates(self)
    }

    fn has_generalized_force(&self) -> bool {
        self.has_force
    }

    fn conserves_energy(&self) -> bool {
        Model::conserves_energy(self)
    }

    fn bodies(&self) -> &[crate::Body] {
        self.mechanism.bodies()
    }

    fn reaction_forces(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        reaction: &mut [f64],
    ) -> Result<bool, Error> {
        reaction.copy_from_slice(crate::reaction_forces(self, ws, t, q, qdot)?);
        Ok(true)
    }
}

impl<F: LagrangianFunction> LagrangianFunction for RawModel<F> {
    type Scratch<S: crate::Scalar> = F::Scratch<S>;

    fn coordinates(&self) -> &[crate::Coordinate] {
        self.function.coordinates()
    }

    fn scratch<S: crate::Scalar>(&self) -> Self::Scratch<S> {
        self.function.scratch()
    }

    fn lagrangian_with<S: crate::Scalar>(&self, scratch: &mut Self::Scratch<S>, t: S, q: &[S], qdot: &[S]) -> S {
        self.function.lagrangian_with(scratch, t, q, qdot)
    }

    fn generalized_force_with<S: crate::Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        self.has_generalized_force() && self.function.generalized_force_with(t, q, qdot, force)
    }
}

impl<F: LagrangianFunction> Dynamics for RawModel<F> {
    type Workspace = RawWorkspace<F>;

    fn new_workspace(&self) -> Self::Workspace {
        self.workspace()
    }

    fn accelerations(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        qddot: &mut [f64],
    ) -> Result<(), Error> {
        qddot.copy_from_slice(RawModel::accelerations(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn energy(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        RawModel::energy(self, ws, t, q, qdot)
    }

    fn mass_matrix(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        mass: &mut [f64],
    ) -> Result<(), Error> {
        mass.copy_from_slice(RawModel::velocity_hessian(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn momenta(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64], p: &mut [f64]) -> Result<(), Error> {
        p.copy_from_slice(RawModel::momenta(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        RawModel::cyclic_coordinates(self)
    }

    fn has_generalized_force(&self) -> bool {
        RawModel::has_generalized_force(self)
    }

    fn conserves_energy(&self) -> bool {
        self.is_autonomous() && !RawModel::has_generalized_force(self)
    }
}
