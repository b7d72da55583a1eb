//! The interface integrators see: equations of motion in `f64` with caller-owned scratch,
//! and their exact Jacobian for the implicit integrators.
//!
//! Both models implement it by one blanket implementation over [`Equations`]: each method is
//! the free function of the same name ([`accelerations`](crate::accelerations),
//! [`mass_matrix`](crate::mass_matrix), …) in `f64`, copied into the caller's buffer.
//!
//! The Jacobian `∂q̈/∂(q, q̇)` is forward-mode AD through the engine's own generic evaluation:
//! `q̈` evaluated in `Dual64` with one input seeded per pass (`2n` passes). For a body
//! [`Model`](crate::Model) that is [`accelerations`](crate::accelerations) in a
//! [`Workspace<Dual64>`](crate::Workspace) (every path: assembled, constant mass matrix,
//! articulated-body tree); for a [`RawModel`](crate::RawModel),
//! whose accelerations already take second derivatives of `L` by hyper-dual numbers, the
//! Lagrangian is evaluated in `HyperDual<Dual64>` (see [`RawWorkspace`](crate::RawWorkspace)).
//! The dual workspace hangs off the `f64` one ([`Workspace`](crate::Workspace),
//! [`RawWorkspace`](crate::RawWorkspace)); [`Dynamics::workspace`] allocates it up front, so
//! a Jacobian allocates nothing.

pub(crate) mod jacobian;
#[cfg(test)]
pub(crate) mod tests;

use crate::eom::equations::{self, Equations};
use crate::{Body, Error, LagrangianFunction, State};

/// A system whose equations of motion `q̈ = a(t, q, q̇)` can be evaluated in `f64`, with its
/// energy function and momenta: a body [`Model`](crate::Model), a [`RawModel`](crate::RawModel),
/// or a system of the user's own.
///
/// This is the integrators' interface, not the user's spelling: every integrator is written
/// against it, and its methods write into caller-owned buffers. To evaluate a model, call the
/// free functions [`accelerations`](crate::accelerations), [`mass_matrix`](crate::mass_matrix),
/// [`momenta`](crate::momenta), [`energy_function`](crate::energy_function) (any scalar, results
/// borrowed from the workspace), which these methods run for both models. It extends
/// [`LagrangianFunction`] because the variational integrator works on `L` itself.
pub trait Dynamics: LagrangianFunction {
    /// Scratch space, allocated once by [`workspace`](Self::workspace).
    type Workspace;

    /// Number of coordinates `n`.
    fn dof(&self) -> usize {
        self.coordinates().len()
    }

    /// Allocate the scratch space.
    fn workspace(&self) -> Self::Workspace;

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
    /// accelerations; [`Error::NonFinite`] (stage [`Jacobian`](crate::error::Stage::Jacobian)) if a
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

    /// The numbers of holonomic and velocity constraints among the coordinates `(m, k)`;
    /// `(0, 0)` (the default) for independent coordinates.
    fn constraint_counts(&self) -> (usize, usize) {
        (0, 0)
    }

    /// Project `(q, q̇)` at time `t` onto the constraints, by the smallest change: Gauss–Newton
    /// on `Φ(t, q) = 0`, then `q̇` onto `G q̇ + Φ_t = 0` and `A q̇ + b = 0`
    /// ([`project`](crate::project)). Does nothing (the default) without constraints.
    ///
    /// # Errors
    /// [`Error::AssemblyFailed`] when the positions cannot be brought onto `Φ = 0`.
    fn project(&self, ws: &mut Self::Workspace, t: f64, q: &mut [f64], qdot: &mut [f64]) -> Result<(), Error> {
        let _ = (ws, t, q, qdot);
        Ok(())
    }

    /// The constraint violation `[max |Φ|, max |G q̇ + Φ_t, A q̇ + b|]` at `(t, q, q̇)`, `None`
    /// (the default) without constraints.
    ///
    /// # Errors
    /// On a malformed or non-finite state.
    fn constraint_violation(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<[f64; 2]>, Error> {
        let _ = (ws, t, q, qdot);
        Ok(None)
    }

    /// The constraint rows at `state = (t, q, q̇)`: the Jacobian `G = [Φ_q; A]` (c × n,
    /// row-major, `c = m + k`) into `jacobian`, the holonomic residuals `Φ(t, q)` (m) into
    /// `residual`, the velocity residuals `[Φ_q q̇ + Φ_t; A q̇ + b]` (c) into `rate`; `false`
    /// (the default) without constraints.
    ///
    /// # Errors
    /// On a malformed or non-finite state or non-finite constraint rows.
    fn constraint_rows(
        &self,
        ws: &mut Self::Workspace,
        state: (f64, &[f64], &[f64]),
        jacobian: &mut [f64],
        residual: &mut [f64],
        rate: &mut [f64],
    ) -> Result<bool, Error> {
        let _ = (ws, state, jacobian, residual, rate);
        Ok(false)
    }

    /// The name of constraint row `i` (holonomic rows first, then velocity rows) for messages:
    /// [`Description::constraint_name`](crate::Description::constraint_name) for a body model.
    fn constraint_name(&self, i: usize) -> String {
        format!("constraint {}", i + 1)
    }

    /// The constraint rows of one step of a discrete method (the variational integrator, see
    /// docs/method.md#constraints) from `q₀` to `q₁ = q₀ + Δq` over `h`: with `end = (t₁, q₁)`,
    /// the holonomic rows `Φ(t₁, q₁)` into `residual` and `Φ_q(t₁, q₁)` into `jacobian`; with
    /// `midpoint = (t_m, q_m, v, h)`, `q_m = q₀ + Δq/2`, `v = Δq/h`, the velocity rows
    /// `A(t_m, q_m) v + b(t_m, q_m)` and their derivative with respect to `Δq`,
    /// `½ ∂(A v + b)/∂q + A/h`. `false` (the default) without constraints.
    ///
    /// # Errors
    /// On non-finite constraint rows.
    fn step_constraint_rows(
        &self,
        ws: &mut Self::Workspace,
        end: (f64, &[f64]),
        midpoint: (f64, &[f64], &[f64], f64),
        residual: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, Error> {
        let _ = (ws, end, midpoint, residual, jacobian);
        Ok(false)
    }

    /// The constraint multipliers `λ` at `(t, q, q̇)` into `multipliers` (`m + k`: holonomic
    /// rows, then velocity rows), with `M q̈ + Gᵀ λ = f` ([`constraint_multipliers`](crate::constraint_multipliers));
    /// `false` (the default) without constraints.
    ///
    /// # Errors
    /// As [`accelerations`](Dynamics::accelerations).
    fn constraint_multipliers(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        multipliers: &mut [f64],
    ) -> Result<bool, Error> {
        let _ = (ws, t, q, qdot, multipliers);
        Ok(false)
    }

    /// How far the equations determine the constraint multipliers at `(t, q, q̇)`
    /// ([`multiplier_rank`](crate::multiplier_rank)); `None` (the default) without constraints.
    ///
    /// # Errors
    /// As [`accelerations`](Dynamics::accelerations).
    fn multiplier_rank(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<crate::MultiplierRank>, Error> {
        let _ = (ws, t, q, qdot);
        Ok(None)
    }

    /// A consistent state near `approximate`, the coordinates marked in `held` (and their
    /// rates) kept ([`assemble`](crate::assemble)); the state itself (the default) without
    /// constraints.
    ///
    /// # Errors
    /// [`Error::AssemblyFailed`], [`Error::DimensionMismatch`] for a `held` of the wrong length.
    fn assemble(&self, approximate: &State, held: &[bool]) -> Result<State, Error> {
        let _ = held;
        Ok(approximate.clone())
    }

    /// Which coordinates are cyclic.
    fn cyclic_coordinates(&self) -> &[bool];

    /// Whether forces act beyond gravity, the potential and the constraints: generalized
    /// forces `Q` or forces applied at points of bodies (`Model::has_generalized_force` and
    /// `Model::has_applied_forces` tell them apart).
    fn has_external_forces(&self) -> bool;

    /// Whether `h` is conserved (autonomous and no generalized forces).
    fn conserves_energy(&self) -> bool;

    /// The bodies, for systems described by bodies (empty for a raw Lagrangian).
    fn bodies(&self) -> &[Body] {
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

/// Both models: every method runs the free function of its name (through [`Equations`]).
impl<E: Equations + LagrangianFunction> Dynamics for E {
    type Workspace = E::Workspace<f64>;

    fn workspace(&self) -> Self::Workspace {
        self.allocate_for_jacobian()
    }

    fn accelerations(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        qddot: &mut [f64],
    ) -> Result<(), Error> {
        qddot.copy_from_slice(equations::accelerations(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn energy_function(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        equations::energy_function(self, ws, t, q, qdot)
    }

    fn mass_matrix(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        mass: &mut [f64],
    ) -> Result<(), Error> {
        mass.copy_from_slice(equations::mass_matrix(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn momenta(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64], p: &mut [f64]) -> Result<(), Error> {
        p.copy_from_slice(equations::momenta(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn acceleration_jacobian(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
    ) -> Result<(), Error> {
        self.eval_acceleration_jacobian(ws, t, q, qdot, jacobian)
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        Equations::cyclic_coordinates(self)
    }

    fn constraint_counts(&self) -> (usize, usize) {
        Equations::constraint_counts(self)
    }

    fn project(&self, ws: &mut Self::Workspace, t: f64, q: &mut [f64], qdot: &mut [f64]) -> Result<(), Error> {
        self.eval_project(ws, t, q, qdot)
    }

    fn constraint_violation(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<[f64; 2]>, Error> {
        self.eval_violation(ws, t, q, qdot)
    }

    fn constraint_rows(
        &self,
        ws: &mut Self::Workspace,
        state: (f64, &[f64], &[f64]),
        jacobian: &mut [f64],
        residual: &mut [f64],
        rate: &mut [f64],
    ) -> Result<bool, Error> {
        self.eval_constraint_rows(ws, state, jacobian, residual, rate)
    }

    fn constraint_name(&self, i: usize) -> String {
        self.name_constraint(i)
    }

    fn step_constraint_rows(
        &self,
        ws: &mut Self::Workspace,
        end: (f64, &[f64]),
        midpoint: (f64, &[f64], &[f64], f64),
        residual: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, Error> {
        self.eval_step_constraint_rows(ws, end, midpoint, residual, jacobian)
    }

    fn constraint_multipliers(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        multipliers: &mut [f64],
    ) -> Result<bool, Error> {
        self.eval_multipliers(ws, t, q, qdot, multipliers)
    }

    fn multiplier_rank(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<crate::MultiplierRank>, Error> {
        self.eval_multiplier_rank(ws, t, q, qdot)
    }

    fn assemble(&self, approximate: &State, held: &[bool]) -> Result<State, Error> {
        self.eval_assemble(approximate, held)
    }

    fn has_external_forces(&self) -> bool {
        Equations::has_external_forces(self)
    }

    fn conserves_energy(&self) -> bool {
        Equations::conserves_energy(self)
    }

    fn bodies(&self) -> &[Body] {
        Equations::bodies(self)
    }

    fn reaction_forces(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        reaction: &mut [f64],
    ) -> Result<bool, Error> {
        self.eval_reaction_forces(ws, t, q, qdot, reaction)
    }
}
