//! One spelling for both input paths: the free functions [`accelerations`], [`mass_matrix`],
//! [`momenta`], [`energy_function`] and [`lagrangian`] take a body [`Model`] or a
//! [`RawModel`](crate::RawModel), each with its own workspace, through the sealed trait
//! [`Equations`].

use crate::seed::Tangent;
use crate::{Body, Error, Mechanism, Model, Scalar, Workspace};
use num_dual::Dual64;

mod sealed {
    /// Only the engine's two models implement [`Equations`](super::Equations).
    pub trait Sealed {}
    impl<M: crate::Mechanism> Sealed for crate::Model<M> {}
    impl<F: crate::LagrangianFunction> Sealed for crate::RawModel<F> {}
}

/// A model whose equations of motion the free functions evaluate: a body [`Model`] or a
/// [`RawModel`](crate::RawModel). Sealed: the user never implements it, and its methods are
/// the engine's own — call [`accelerations`], [`mass_matrix`], [`momenta`],
/// [`energy_function`] and [`lagrangian`] instead, which accept either model.
pub trait Equations: sealed::Sealed {
    /// Scratch space for evaluations in scalar `S`: [`Workspace<S>`] for a body model,
    /// [`RawWorkspace<F, S>`](crate::RawWorkspace) for a raw model. Both models allocate it
    /// with `workspace()` (`f64`) or `workspace_in::<S>()` (any scalar).
    type Workspace<S: Scalar>;

    #[doc(hidden)]
    fn workspace_in<S: Scalar>(&self) -> Self::Workspace<S>;

    #[doc(hidden)]
    fn eval_accelerations<'w, S: Scalar>(
        &self,
        ws: &'w mut Self::Workspace<S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error>;

    #[doc(hidden)]
    fn eval_mass_matrix<'w, S: Scalar>(
        &self,
        ws: &'w mut Self::Workspace<S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error>;

    #[doc(hidden)]
    fn eval_momenta<'w, S: Scalar>(
        &self,
        ws: &'w mut Self::Workspace<S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error>;

    #[doc(hidden)]
    fn eval_energy_function<S: Scalar>(
        &self,
        ws: &mut Self::Workspace<S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<S, Error>;

    #[doc(hidden)]
    fn eval_lagrangian<S: Scalar>(&self, ws: &mut Self::Workspace<S>, t: S, q: &[S], qdot: &[S]) -> Result<S, Error>;

    /// The `f64` workspace with the `Dual64` one of the Jacobian's tangent passes allocated.
    #[doc(hidden)]
    fn allocate_for_jacobian(&self) -> Self::Workspace<f64>;

    /// The exact acceleration Jacobian `∂q̈/∂(q, q̇)` (n × 2n) into `jacobian`.
    #[doc(hidden)]
    fn eval_acceleration_jacobian(
        &self,
        ws: &mut Self::Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
    ) -> Result<(), Error>;

    #[doc(hidden)]
    fn cyclic_coordinates(&self) -> &[bool];

    /// Whether generalized or applied forces act.
    #[doc(hidden)]
    fn has_external_forces(&self) -> bool;

    /// Whether the energy function is a constant of the motion.
    #[doc(hidden)]
    fn conserves_energy(&self) -> bool;

    #[doc(hidden)]
    fn bodies(&self) -> &[Body] {
        &[]
    }

    /// `(m, k)`: holonomic and velocity constraints.
    #[doc(hidden)]
    fn constraint_counts(&self) -> (usize, usize) {
        (0, 0)
    }

    #[doc(hidden)]
    fn eval_project(
        &self,
        ws: &mut Self::Workspace<f64>,
        t: f64,
        q: &mut [f64],
        qdot: &mut [f64],
    ) -> Result<(), Error> {
        let _ = (ws, t, q, qdot);
        Ok(())
    }

    #[doc(hidden)]
    fn eval_violation(
        &self,
        ws: &mut Self::Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<[f64; 2]>, Error> {
        let _ = (ws, t, q, qdot);
        Ok(None)
    }

    /// The constraint rows `G`, `Φ` and the velocity residuals at `(t, q, q̇)`, `false` without
    /// constraints.
    #[doc(hidden)]
    fn eval_constraint_rows(
        &self,
        ws: &mut Self::Workspace<f64>,
        state: (f64, &[f64], &[f64]),
        jacobian: &mut [f64],
        residual: &mut [f64],
        rate: &mut [f64],
    ) -> Result<bool, Error> {
        let _ = (ws, state, jacobian, residual, rate);
        Ok(false)
    }

    /// The name of constraint row `i` ([`Mechanism::constraint_name`]).
    #[doc(hidden)]
    fn name_constraint(&self, i: usize) -> String {
        format!("constraint {}", i + 1)
    }

    /// The constraint rows of a discrete step, `false` without constraints.
    #[doc(hidden)]
    fn eval_step_constraint_rows(
        &self,
        ws: &mut Self::Workspace<f64>,
        end: (f64, &[f64]),
        midpoint: (f64, &[f64], &[f64], f64),
        residual: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, Error> {
        let _ = (ws, end, midpoint, residual, jacobian);
        Ok(false)
    }

    /// The constraint multipliers into `multipliers` (`m + k`), `false` without constraints.
    #[doc(hidden)]
    fn eval_multipliers(
        &self,
        ws: &mut Self::Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        multipliers: &mut [f64],
    ) -> Result<bool, Error> {
        let _ = (ws, t, q, qdot, multipliers);
        Ok(false)
    }

    /// How far the equations determine the multipliers, `None` without constraints.
    #[doc(hidden)]
    fn eval_multiplier_rank(
        &self,
        ws: &mut Self::Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<crate::MultiplierRank>, Error> {
        let _ = (ws, t, q, qdot);
        Ok(None)
    }

    /// A consistent state near `approximate`, the `held` coordinates kept.
    #[doc(hidden)]
    fn eval_assemble(&self, approximate: &crate::State, held: &[bool]) -> Result<crate::State, Error> {
        let _ = held;
        Ok(approximate.clone())
    }

    /// The reaction forces into `reaction`, `false` for a model without bodies.
    #[doc(hidden)]
    fn eval_reaction_forces(
        &self,
        ws: &mut Self::Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        reaction: &mut [f64],
    ) -> Result<bool, Error> {
        let _ = (ws, t, q, qdot, reaction);
        Ok(false)
    }
}

/// Generalized accelerations `q̈` of a body [`Model`] or a [`RawModel`](crate::RawModel),
/// borrowed from the workspace. Generic over the scalar, so `q̈` itself can be differentiated.
///
/// For a body model, `q̈ = M(q, t)⁻¹ f(q, q̇, t)` with `M = Σ_b J_bᵀ D_b J_b` and
/// `f = Σ_b J_bᵀ (F_b − D_b γ_b) − ∂V/∂q + Q`: `n` first-order dual passes give `J` (and
/// `∂V/∂q`), one second-order pass along `(q̇, 1)` gives `γ`, then an in-place LDLᵀ solve. A
/// model with a constant mass matrix skips all of it but the potential gradient and the solve
/// with the stored factor. A model of a kinematic tree ([`Mechanism::tree`],
/// [`Model::uses_tree_path`]) runs the articulated-body algorithm instead: `O(n)`, with the
/// same result to round-off.
///
/// For a raw model, `∂²L/∂q̇² q̈ = ∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t + Q`, every derivative by
/// hyper-dual passes.
///
/// # Errors
/// [`Error::DimensionMismatch`], [`Error::NonFinite`] (naming the stage),
/// [`Error::SingularMassMatrix`] where the coordinates are not independent, or
/// [`Error::IndefiniteMassMatrix`] (a raw Lagrangian whose `∂²L/∂q̇²` is not positive here).
pub fn accelerations<'w, E: Equations, S: Scalar>(
    model: &E,
    ws: &'w mut E::Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<&'w [S], Error> {
    model.eval_accelerations(ws, t, q, qdot)
}

/// The mass matrix `M = ∂²L/∂q̇²` (n × n, row-major), borrowed from the workspace. For a body
/// model it is `Σ_b J_bᵀ D_b J_b` and does not depend on `q̇` (which is checked, then
/// ignored); for a raw Lagrangian it may.
///
/// # Errors
/// [`Error::DimensionMismatch`] or [`Error::NonFinite`] for a bad state.
pub fn mass_matrix<'w, E: Equations, S: Scalar>(
    model: &E,
    ws: &'w mut E::Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<&'w [S], Error> {
    model.eval_mass_matrix(ws, t, q, qdot)
}

/// Generalized momenta `p = ∂L/∂q̇` (for a body model `Σ_b J_bᵀ D_b ṗ_b`), borrowed from the
/// workspace.
///
/// # Errors
/// [`Error::DimensionMismatch`], or [`Error::NonFinite`] for a non-finite state or momenta
/// that overflow.
pub fn momenta<'w, E: Equations, S: Scalar>(
    model: &E,
    ws: &'w mut E::Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<&'w [S], Error> {
    model.eval_momenta(ws, t, q, qdot)
}

/// The energy function `h = q̇·∂L/∂q̇ − L` (Jacobi's integral). For scleronomic mechanisms it is
/// `T + V` ([`total_energy`](crate::total_energy)); it is conserved whenever `∂L/∂t = 0` and
/// `Q = 0`, and in general `dh/dt = Q·q̇ − ∂L/∂t`.
///
/// # Errors
/// As [`momenta`]; [`Error::NonFinite`] (stage [`Potential`](crate::error::Stage::Potential) or
/// [`Lagrangian`](crate::error::Stage::Lagrangian)) for an energy that is not finite here.
pub fn energy_function<E: Equations, S: Scalar>(
    model: &E,
    ws: &mut E::Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<S, Error> {
    model.eval_energy_function(ws, t, q, qdot)
}

/// The Lagrangian `L(q, q̇, t)` (for a body model `T − V`, gravity included).
///
/// # Errors
/// [`Error::DimensionMismatch`] or [`Error::NonFinite`] for a bad state.
pub fn lagrangian<E: Equations, S: Scalar>(
    model: &E,
    ws: &mut E::Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<S, Error> {
    model.eval_lagrangian(ws, t, q, qdot)
}

impl<M: Mechanism> Equations for Model<M> {
    type Workspace<S: Scalar> = Workspace<S>;

    fn workspace_in<S: Scalar>(&self) -> Workspace<S> {
        Workspace::new(self)
    }

    fn eval_accelerations<'w, S: Scalar>(
        &self,
        ws: &'w mut Workspace<S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error> {
        super::accelerations(self, ws, t, q, qdot)
    }

    fn eval_mass_matrix<'w, S: Scalar>(
        &self,
        ws: &'w mut Workspace<S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error> {
        super::check_state(self.n, t, q, Some(qdot))?;
        super::mass_matrix(self, ws, t, q)
    }

    fn eval_momenta<'w, S: Scalar>(
        &self,
        ws: &'w mut Workspace<S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error> {
        super::energy::momenta(self, ws, t, q, qdot)
    }

    fn eval_energy_function<S: Scalar>(&self, ws: &mut Workspace<S>, t: S, q: &[S], qdot: &[S]) -> Result<S, Error> {
        super::energy::energy_function(self, ws, t, q, qdot)
    }

    fn eval_lagrangian<S: Scalar>(&self, ws: &mut Workspace<S>, t: S, q: &[S], qdot: &[S]) -> Result<S, Error> {
        super::energy::lagrangian(self, ws, t, q, qdot)
    }

    fn allocate_for_jacobian(&self) -> Workspace<f64> {
        let mut ws = self.workspace_in();
        ws.tangent = Some(Tangent::new(self.workspace_in(), self.n));
        ws
    }

    fn eval_acceleration_jacobian(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
    ) -> Result<(), Error> {
        tangent_jacobian(self, self.n, &mut ws.tangent, t, q, qdot, jacobian)
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        self.cyclic_coordinates()
    }

    fn has_external_forces(&self) -> bool {
        self.has_force || self.has_applied
    }

    fn conserves_energy(&self) -> bool {
        self.conserves_energy()
    }

    fn bodies(&self) -> &[Body] {
        &self.mechanism.description().bodies
    }

    fn constraint_counts(&self) -> (usize, usize) {
        self.constraint_counts
    }

    fn eval_project(&self, ws: &mut Workspace<f64>, t: f64, q: &mut [f64], qdot: &mut [f64]) -> Result<(), Error> {
        super::constraints::project_step(self, ws, t, q, qdot)
    }

    fn eval_violation(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<[f64; 2]>, Error> {
        if !self.is_constrained() {
            return Ok(None);
        }
        super::constraints::violation(self, ws, t, q, qdot).map(Some)
    }

    fn eval_constraint_rows(
        &self,
        ws: &mut Workspace<f64>,
        state: (f64, &[f64], &[f64]),
        jacobian: &mut [f64],
        residual: &mut [f64],
        rate: &mut [f64],
    ) -> Result<bool, Error> {
        if !self.is_constrained() {
            return Ok(false);
        }
        super::constraints::rows_at(self, ws, state, jacobian, residual, rate).map(|()| true)
    }

    fn name_constraint(&self, i: usize) -> String {
        self.mechanism.description().constraint_name(i).to_string()
    }

    fn eval_step_constraint_rows(
        &self,
        ws: &mut Workspace<f64>,
        end: (f64, &[f64]),
        midpoint: (f64, &[f64], &[f64], f64),
        residual: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, Error> {
        if !self.is_constrained() {
            return Ok(false);
        }
        super::constraints::step_rows(self, ws, end, midpoint, residual, jacobian).map(|()| true)
    }

    fn eval_multipliers(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        multipliers: &mut [f64],
    ) -> Result<bool, Error> {
        if !self.is_constrained() {
            return Ok(false);
        }
        let lambda = super::constraints::constraint_multipliers(self, ws, t, q, qdot)?;
        multipliers.copy_from_slice(lambda);
        Ok(true)
    }

    fn eval_multiplier_rank(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<crate::MultiplierRank>, Error> {
        if !self.is_constrained() {
            return Ok(None);
        }
        super::constraints::multiplier_rank(self, ws, t, q, qdot).map(Some)
    }

    fn eval_assemble(&self, approximate: &crate::State, held: &[bool]) -> Result<crate::State, Error> {
        super::constraints::assemble(self, approximate, held)
    }

    fn eval_reaction_forces(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        reaction: &mut [f64],
    ) -> Result<bool, Error> {
        reaction.copy_from_slice(super::reactions::reaction_forces(self, ws, t, q, qdot)?);
        Ok(true)
    }
}

/// `∂q̈/∂(q, q̇)` by `2n` tangent passes: `q̈` evaluated in `Dual64` with one input seeded per
/// pass, in the `Dual64` workspace that hangs off the `f64` one (allocated here on the first
/// Jacobian of a workspace that does not have it yet).
pub(crate) fn tangent_jacobian<E: Equations>(
    model: &E,
    n: usize,
    tangent: &mut Option<Box<Tangent<E::Workspace<Dual64>>>>,
    t: f64,
    q: &[f64],
    qdot: &[f64],
    jacobian: &mut [f64],
) -> Result<(), Error> {
    let tangent = tangent.get_or_insert_with(|| Tangent::new(model.workspace_in(), n));
    let Tangent { workspace, seeds } = &mut **tangent;
    seeds.jacobian(t, q, qdot, jacobian, |t, q, qdot, column| {
        let qddot = model.eval_accelerations(workspace, t, q, qdot)?;
        for (c, a) in column.iter_mut().zip(qddot) {
            *c = a.eps;
        }
        Ok(())
    })
}
