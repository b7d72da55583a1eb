//! The interface integrators see: equations of motion in `f64` with caller-owned scratch,
//! and their exact Jacobian for the implicit integrators.
//!
//! The Jacobian `∂q̈/∂(q, q̇)` is forward-mode AD through the engine's own generic evaluation:
//! `q̈` evaluated in `Dual64` with one input seeded per pass (`2n` passes). For a body
//! [`Model`](crate::Model) that is [`accelerations`](crate::accelerations) in a
//! [`Workspace<Dual64>`](crate::Workspace) (every path: assembled, constant mass matrix,
//! articulated-body tree); for a [`RawModel`](crate::RawModel),
//! whose accelerations already take second derivatives of `L` by hyper-dual numbers, the
//! Lagrangian is evaluated in `HyperDual<Dual64>` (see [`RawWorkspace`](crate::RawWorkspace)).
//! The dual workspace hangs off the `f64` one ([`Workspace`](crate::Workspace),
//! [`RawWorkspace`](crate::RawWorkspace)); [`Dynamics::new_workspace`] allocates it up front, so
//! a Jacobian allocates nothing.

pub(crate) mod jacobian;
mod model;
mod raw;
#[cfg(test)]
pub(crate) mod tests;

use crate::{Error, LagrangianFunction};

/// A system whose equations of motion `q̈ = a(t, q, q̇)` can be evaluated, with its energy
/// function and momenta: a body [`Model`](crate::Model) or a [`RawModel`](crate::RawModel).
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
    fn energy_function(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error>;

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

    /// Write the Jacobian of the accelerations, `∂q̈/∂(q, q̇)` at `(t, q, q̇)`, into `jacobian`
    /// (n × 2n, row-major: row `i` is `q̈_i`, columns `q_1 … q_n` then `q̇_1 … q̇_n`).
    ///
    /// Body and raw models override this with exact forward-mode AD (`2n` `Dual64` passes,
    /// no allocation). The default, for systems that only provide `f64` accelerations, is
    /// central finite differences with steps `ε^{1/3} max(|x_j|, 1)` (relative accuracy about
    /// `1e-10`; it allocates its four work vectors on every call).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a `jacobian` that is not `2n²` long; any error of the
    /// accelerations; [`Error::NonFinite`] (stage [`Jacobian`](crate::Stage::Jacobian)) if a
    /// derivative is not finite.
    fn acceleration_jacobian(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
    ) -> Result<(), Error> {
        jacobian::finite_differences(self, ws, t, q, qdot, jacobian)
    }

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
