//! The raw-Lagrangian path: Lagrange's equations from second derivatives of `L(q, q̇, t)`.

use super::check_state;
use super::equations::{Equations, tangent_jacobian};
use crate::error::{Stage, bad_pivot};
use crate::linalg;
use crate::probe::{self, ProbeStates};
use crate::seed::Tangent;
use crate::{Coordinate, Error, LagrangianFunction, Scalar};
use num_dual::{Dual64, HyperDual};

/// A system given by its Lagrangian (a user's [`Lagrangian`](crate::Lagrangian), or the
/// Lagrangian of a [`Model`](crate::Model)), whose equations of motion are
///
/// `∂²L/∂q̇² q̈ = ∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t + Q`,
///
/// all derivatives exact (hyper-dual passes). For a body model this is an independent
/// assembly of the same equations: on every scene both paths must agree to round-off.
///
/// It is evaluated by the same free functions as a body model, with its own workspace:
/// [`accelerations`](crate::accelerations), [`mass_matrix`](crate::mass_matrix) (here
/// `∂²L/∂q̇²`, which may depend on `q̇`), [`momenta`](crate::momenta),
/// [`energy_function`](crate::energy_function) and [`lagrangian`](crate::lagrangian).
///
/// Every evaluation is generic over the scalar `S` of its [`RawWorkspace<F, S>`]: the
/// Lagrangian is evaluated in `HyperDual<S>` (second derivatives in `ε₁ε₂`, the outer
/// derivative in `S`), so with `S = Dual64` the accelerations themselves are differentiated —
/// that is how [`Dynamics::acceleration_jacobian`](crate::Dynamics::acceleration_jacobian)
/// gets `∂q̈/∂(q, q̇)` for implicit integrators, exactly.
#[derive(Clone, Debug)]
pub struct RawModel<F> {
    pub(crate) function: F,
    n: usize,
    has_force: bool,
    cyclic: Vec<bool>,
    autonomous: bool,
}

/// Scratch space for [`RawModel`] evaluations in scalar `S` (allocated once, by
/// [`RawModel::workspace`] for `f64` or [`RawModel::workspace_in`] for any scalar).
pub struct RawWorkspace<F: LagrangianFunction, S: Scalar = f64> {
    /// The Lagrangian's own scratch, in hyper-dual numbers over `S`.
    scratch: F::Scratch<HyperDual<S>>,
    /// Its scratch in `S`, for the generalized force.
    force_scratch: F::Scratch<S>,
    /// Seeded coordinates (n).
    q: Vec<HyperDual<S>>,
    /// Seeded velocities (n).
    qdot: Vec<HyperDual<S>>,
    /// `∂²L/∂q̇²` (n × n), filled by [`accelerations`](crate::accelerations) and
    /// [`mass_matrix`](crate::mass_matrix).
    pub hessian: Vec<S>,
    /// Its LDLᵀ factor (n × n).
    factor: Vec<S>,
    /// `∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t + Q` (n).
    pub rhs: Vec<S>,
    /// `q̈` (n), filled by [`accelerations`](crate::accelerations).
    pub qddot: Vec<S>,
    /// `Q` (n).
    pub generalized_force: Vec<S>,
    /// `p = ∂L/∂q̇` (n), filled by [`momenta`](crate::momenta).
    pub momenta: Vec<S>,
    /// The `Dual64` workspace and seeds of the tangent passes of
    /// [`Dynamics::acceleration_jacobian`](crate::Dynamics::acceleration_jacobian): allocated
    /// up front by [`Dynamics::workspace`](crate::Dynamics::workspace), otherwise by the
    /// first Jacobian.
    pub(crate) tangent: Option<Box<Tangent<RawWorkspace<F, Dual64>>>>,
}

impl<F: LagrangianFunction> RawModel<F> {
    /// Wrap a Lagrangian, after checking it at a few fixed, generic probe states (the body
    /// path's, see [`Model::new`](crate::Model::new)).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a system without coordinates, or a body model with
    /// constraints among its coordinates (the raw path takes none); [`Error::NonFinite`]
    /// (stage [`Lagrangian`](Stage::Lagrangian)) for a Lagrangian or first derivative that is
    /// not finite at a probe state; [`Error::LostDerivative`] if an exact first derivative of
    /// `L` disagrees with central differences (the Lagrangian reads `t.re()`, `q[i].re()` or
    /// `qdot[i].re()`); [`Error::IndefiniteMassMatrix`] if `∂²L/∂q̇²` is indefinite or negative
    /// definite at a probe state (a negative-definite `L` is refused although `−L` has the same
    /// equations: see the error), [`Error::SingularMassMatrix`] if it is singular there.
    pub fn new(function: F) -> Result<Self, Error> {
        let n = function.coordinates().len();
        if n == 0 {
            return Err(Error::InvalidParameter {
                name: "coordinates".into(),
                value: 0.0,
                why: "a system needs at least one coordinate".into(),
            });
        }
        let (m, k) = function.constraint_counts();
        if m + k > 0 {
            return Err(Error::InvalidParameter {
                name: "constraints".into(),
                value: (m + k) as f64,
                why: "the raw-Lagrangian path does not take constraints among the coordinates (it would drop \
                      them); evaluate the body Model itself, which does"
                    .into(),
            });
        }
        let probes = ProbeStates::new(n);
        probe::check_lagrangian(&function, &probes)?;
        let (q, qdot, t) = probes.state(0);
        let mut force = vec![0.0; n];
        let has_force = function.generalized_force_with(&mut function.scratch(), t, q, qdot, &mut force);
        let (cyclic, autonomous) = (probes.cyclic(&function), probes.autonomous(&function));
        let model = Self { function, n, has_force, cyclic, autonomous };
        model.check_mass_matrix(&probes)?;
        Ok(model)
    }

    /// `∂²L/∂q̇²` factored at every probe state, as [`accelerations`](crate::accelerations)
    /// factors it.
    fn check_mass_matrix(&self, probes: &ProbeStates) -> Result<(), Error> {
        let mut ws = self.workspace();
        for k in 0..probes.len() {
            let (q, qdot, t) = probes.state(k);
            Self::reset(&mut ws, q, qdot);
            self.fill_velocity_hessian(&mut ws, HyperDual::from_re(t));
            ws.factor.copy_from_slice(&ws.hessian);
            self.factor(&mut ws, t, q)?;
        }
        Ok(())
    }

    /// The LDLᵀ factor of `ws.hessian` into `ws.factor` (which holds a copy of it).
    fn factor<S: Scalar>(&self, ws: &mut RawWorkspace<F, S>, t: S, q: &[S]) -> Result<(), Error> {
        if let Err(bad) = linalg::ldlt_factor(self.n, &mut ws.factor) {
            if !super::all_finite(&ws.hessian) {
                return Err(super::non_finite(Stage::Lagrangian, t, q));
            }
            return Err(bad_pivot(t, q, &self.coordinates()[bad.index].name, bad.pivot, bad.diagonal));
        }
        Ok(())
    }

    /// The wrapped Lagrangian.
    pub fn function(&self) -> &F {
        &self.function
    }

    /// Number of coordinates.
    pub fn dof(&self) -> usize {
        self.n
    }

    /// The coordinates.
    pub fn coordinates(&self) -> &[Coordinate] {
        self.function.coordinates()
    }

    /// Cyclic coordinates (`∂L/∂q_j` exactly zero at the probe states).
    pub fn cyclic_coordinates(&self) -> &[bool] {
        &self.cyclic
    }

    /// `∂L/∂t` exactly zero at the probe states.
    pub fn is_autonomous(&self) -> bool {
        self.autonomous
    }

    /// Whether non-conservative generalized forces act.
    pub fn has_generalized_force(&self) -> bool {
        self.has_force
    }

    /// Allocate the scratch space for `f64` evaluations.
    pub fn workspace(&self) -> RawWorkspace<F> {
        self.workspace_in()
    }

    /// Allocate the scratch space for evaluations in scalar `S` (e.g. `Dual64`, to
    /// differentiate the accelerations).
    pub fn workspace_in<S: Scalar>(&self) -> RawWorkspace<F, S> {
        let n = self.n;
        let zero = S::zero();
        let dual_zero = HyperDual::from_re(zero);
        RawWorkspace {
            scratch: self.function.scratch(),
            force_scratch: self.function.scratch(),
            q: vec![dual_zero; n],
            qdot: vec![dual_zero; n],
            hessian: vec![zero; n * n],
            factor: vec![zero; n * n],
            rhs: vec![zero; n],
            qddot: vec![zero; n],
            generalized_force: vec![zero; n],
            momenta: vec![zero; n],
            tangent: None,
        }
    }

    /// Evaluate `L` with the seeds already written into `ws.q`, `ws.qdot`.
    fn eval<S: Scalar>(&self, ws: &mut RawWorkspace<F, S>, t: HyperDual<S>) -> HyperDual<S> {
        self.function.lagrangian_with(&mut ws.scratch, t, &ws.q, &ws.qdot)
    }

    fn reset<S: Scalar>(ws: &mut RawWorkspace<F, S>, q: &[S], qdot: &[S]) {
        for (d, v) in ws.q.iter_mut().zip(q) {
            *d = HyperDual::from_re(*v);
        }
        for (d, v) in ws.qdot.iter_mut().zip(qdot) {
            *d = HyperDual::from_re(*v);
        }
    }

    /// `∂²L/∂q̇_i∂q̇_j`: one pass per pair, seeding `q̇_i` (ε1) and `q̇_j` (ε2). Expects the
    /// unseeded state in `ws.q`, `ws.qdot`.
    fn fill_velocity_hessian<S: Scalar>(&self, ws: &mut RawWorkspace<F, S>, t: HyperDual<S>) {
        let n = self.n;
        let (zero, one) = (S::zero(), S::one());
        for i in 0..n {
            for j in i..n {
                ws.qdot[i].eps1 = one;
                ws.qdot[j].eps2 = one;
                let l = self.eval(ws, t);
                ws.hessian[i * n + j] = l.eps1eps2;
                ws.hessian[j * n + i] = l.eps1eps2;
                ws.qdot[i].eps1 = zero;
                ws.qdot[j].eps2 = zero;
            }
        }
    }
}

impl<F: LagrangianFunction> Equations for RawModel<F> {
    type Workspace<S: Scalar> = RawWorkspace<F, S>;

    fn workspace_in<S: Scalar>(&self) -> RawWorkspace<F, S> {
        self.workspace_in()
    }

    /// Generalized accelerations from the raw Lagrangian, borrowed from the workspace.
    fn eval_accelerations<'w, S: Scalar>(
        &self,
        ws: &'w mut RawWorkspace<F, S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error> {
        let n = self.n;
        check_state(n, t, q, Some(qdot))?;
        let (zero, one) = (S::zero(), S::one());
        Self::reset(ws, q, qdot);
        let t_plain = HyperDual::from_re(t);
        self.fill_velocity_hessian(ws, t_plain);
        // Σ_j ∂²L/∂q̇_i∂q_j q̇_j + ∂²L/∂q̇_i∂t: seed q̇_i (ε1) and the motion (q̇, 1) (ε2).
        for (d, v) in ws.q.iter_mut().zip(qdot) {
            d.eps2 = *v;
        }
        let t_moving = HyperDual::new(t, zero, one, zero);
        for i in 0..n {
            ws.qdot[i].eps1 = one;
            let l = self.eval(ws, t_moving);
            ws.rhs[i] = -l.eps1eps2;
            ws.qdot[i].eps1 = zero;
        }
        // ∂L/∂q_i: seed q_i (ε1).
        for d in ws.q.iter_mut() {
            d.eps2 = zero;
        }
        for i in 0..n {
            ws.q[i].eps1 = one;
            let l = self.eval(ws, t_plain);
            ws.rhs[i] += l.eps1;
            ws.q[i].eps1 = zero;
        }
        // + Q.
        if self.has_force {
            ws.generalized_force.fill(zero);
            self.function.generalized_force_with(&mut ws.force_scratch, t, q, qdot, &mut ws.generalized_force);
            for (r, f) in ws.rhs.iter_mut().zip(&ws.generalized_force) {
                *r += *f;
            }
        }
        // Solve.
        ws.factor.copy_from_slice(&ws.hessian);
        self.factor(ws, t, q)?;
        ws.qddot.copy_from_slice(&ws.rhs);
        linalg::ldlt_solve(n, &ws.factor, &mut ws.qddot);
        if !super::all_finite(&ws.qddot) {
            let stage = if super::all_finite(&ws.rhs) { Stage::Accelerations } else { Stage::Lagrangian };
            return Err(super::non_finite(stage, t, q));
        }
        Ok(&ws.qddot)
    }

    /// The generalized mass matrix `∂²L/∂q̇²` (n × n), borrowed from the workspace.
    fn eval_mass_matrix<'w, S: Scalar>(
        &self,
        ws: &'w mut RawWorkspace<F, S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error> {
        check_state(self.n, t, q, Some(qdot))?;
        Self::reset(ws, q, qdot);
        self.fill_velocity_hessian(ws, HyperDual::from_re(t));
        Ok(&ws.hessian)
    }

    /// Generalized momenta `p = ∂L/∂q̇`, borrowed from the workspace.
    fn eval_momenta<'w, S: Scalar>(
        &self,
        ws: &'w mut RawWorkspace<F, S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<&'w [S], Error> {
        check_state(self.n, t, q, Some(qdot))?;
        Self::reset(ws, q, qdot);
        for i in 0..self.n {
            ws.qdot[i].eps1 = S::one();
            ws.momenta[i] = self.eval(ws, HyperDual::from_re(t)).eps1;
            ws.qdot[i].eps1 = S::zero();
        }
        if !super::all_finite(&ws.momenta) {
            return Err(super::non_finite(Stage::Lagrangian, t, q));
        }
        Ok(&ws.momenta)
    }

    /// The energy function `h = q̇·∂L/∂q̇ − L`: one pass seeded along `q̇` in velocity space.
    fn eval_energy_function<S: Scalar>(
        &self,
        ws: &mut RawWorkspace<F, S>,
        t: S,
        q: &[S],
        qdot: &[S],
    ) -> Result<S, Error> {
        check_state(self.n, t, q, Some(qdot))?;
        Self::reset(ws, q, qdot);
        for (d, v) in ws.qdot.iter_mut().zip(qdot) {
            d.eps1 = *v;
        }
        let l = self.eval(ws, HyperDual::from_re(t));
        let energy = l.eps1 - l.re;
        if !energy.re().is_finite() {
            return Err(super::non_finite(Stage::Lagrangian, t, q));
        }
        Ok(energy)
    }

    /// `L(q, q̇, t)`.
    fn eval_lagrangian<S: Scalar>(&self, ws: &mut RawWorkspace<F, S>, t: S, q: &[S], qdot: &[S]) -> Result<S, Error> {
        check_state(self.n, t, q, Some(qdot))?;
        Self::reset(ws, q, qdot);
        Ok(self.eval(ws, HyperDual::from_re(t)).re)
    }

    /// The `Dual64` workspace of the tangent passes: the Lagrangian then runs in
    /// `HyperDual<Dual64>`.
    fn allocate_for_jacobian(&self) -> RawWorkspace<F> {
        let mut ws = self.workspace();
        ws.tangent = Some(Tangent::new(self.workspace_in(), self.n));
        ws
    }

    fn eval_acceleration_jacobian(
        &self,
        ws: &mut RawWorkspace<F>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
    ) -> Result<(), Error> {
        tangent_jacobian(self, self.n, &mut ws.tangent, t, q, qdot, jacobian)
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        &self.cyclic
    }

    fn has_external_forces(&self) -> bool {
        self.has_force
    }

    fn conserves_energy(&self) -> bool {
        self.autonomous && !self.has_force
    }
}

/// A raw model is itself a Lagrangian (the variational integrator works on `L`); its
/// generalized force is the one found at construction.
impl<F: LagrangianFunction> LagrangianFunction for RawModel<F> {
    type Scratch<S: Scalar> = F::Scratch<S>;

    fn coordinates(&self) -> &[Coordinate] {
        self.function.coordinates()
    }

    fn scratch<S: Scalar>(&self) -> Self::Scratch<S> {
        self.function.scratch()
    }

    fn lagrangian_with<S: Scalar>(&self, scratch: &mut Self::Scratch<S>, t: S, q: &[S], qdot: &[S]) -> S {
        self.function.lagrangian_with(scratch, t, q, qdot)
    }

    fn generalized_force_with<S: Scalar>(
        &self,
        scratch: &mut Self::Scratch<S>,
        t: S,
        q: &[S],
        qdot: &[S],
        force: &mut [S],
    ) -> bool {
        self.has_generalized_force() && self.function.generalized_force_with(scratch, t, q, qdot, force)
    }

    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut crate::Bounds) -> bool {
        self.function.admissible(t, q, qdot, bounds)
    }
}

#[cfg(test)]
mod tests;
