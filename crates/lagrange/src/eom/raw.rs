//! The raw-Lagrangian path: Lagrange's equations from second derivatives of `L(q, q̇, t)`.

use super::{check_state, solve};
use crate::error::Stage;
use crate::model::probe::ProbeStates;
use crate::{Coordinate, Error, LagrangianFunction};
use num_dual::HyperDual64;

/// A system given by its Lagrangian (a user's [`Lagrangian`](crate::Lagrangian), or the
/// Lagrangian of a [`Model`](crate::Model)), whose equations of motion are
///
/// `∂²L/∂q̇² q̈ = ∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t + Q`,
///
/// all derivatives exact (hyper-dual passes). For a body model this is an independent
/// assembly of the same equations: on every scene both paths must agree to round-off.
#[derive(Clone, Debug)]
pub struct RawModel<F> {
    pub(crate) function: F,
    n: usize,
    has_force: bool,
    cyclic: Vec<bool>,
    autonomous: bool,
}

/// Scratch space for [`RawModel`] evaluations (allocated once).
pub struct RawWorkspace<F: LagrangianFunction> {
    /// The Lagrangian's own scratch, in hyper-dual numbers.
    scratch: F::Scratch<HyperDual64>,
    /// Seeded coordinates (n).
    q: Vec<HyperDual64>,
    /// Seeded velocities (n).
    qdot: Vec<HyperDual64>,
    /// `∂²L/∂q̇²` (n × n), filled by [`RawModel::accelerations`].
    pub hessian: Vec<f64>,
    /// Its LDLᵀ factor (n × n).
    factor: Vec<f64>,
    /// `∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t + Q` (n).
    pub rhs: Vec<f64>,
    /// `q̈` (n).
    pub qddot: Vec<f64>,
    /// `Q` (n).
    pub generalized_force: Vec<f64>,
    /// `p = ∂L/∂q̇` (n), filled by [`RawModel::momenta`].
    pub momenta: Vec<f64>,
}

impl<F: LagrangianFunction> RawModel<F> {
    /// Wrap a Lagrangian.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a system without coordinates.
    pub fn new(function: F) -> Result<Self, Error> {
        let n = function.coordinates().len();
        if n == 0 {
            return Err(Error::InvalidParameter {
                name: "coordinates".into(),
                value: 0.0,
                why: "a system needs at least one coordinate".into(),
            });
        }
        let probes = ProbeStates::new(n);
        let (q, qdot, t) = probes.state(0);
        let mut force = vec![0.0; n];
        let has_force = function.generalized_force_with(t, q, qdot, &mut force);
        let (cyclic, autonomous) = probes.lagrangian_structure(&function);
        Ok(Self { function, n, has_force, cyclic, autonomous })
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

    /// Allocate the scratch space.
    pub fn workspace(&self) -> RawWorkspace<F> {
        let n = self.n;
        let zero = HyperDual64::from(0.0);
        RawWorkspace {
            scratch: self.function.scratch(),
            q: vec![zero; n],
            qdot: vec![zero; n],
            hessian: vec![0.0; n * n],
            factor: vec![0.0; n * n],
            rhs: vec![0.0; n],
            qddot: vec![0.0; n],
            generalized_force: vec![0.0; n],
            momenta: vec![0.0; n],
        }
    }

    /// Evaluate `L` with the seeds already written into `ws.q`, `ws.qdot`.
    fn eval(&self, ws: &mut RawWorkspace<F>, t: HyperDual64) -> HyperDual64 {
        self.function.lagrangian_with(&mut ws.scratch, t, &ws.q, &ws.qdot)
    }

    fn reset(ws: &mut RawWorkspace<F>, q: &[f64], qdot: &[f64]) {
        for (d, v) in ws.q.iter_mut().zip(q) {
            *d = HyperDual64::from(*v);
        }
        for (d, v) in ws.qdot.iter_mut().zip(qdot) {
            *d = HyperDual64::from(*v);
        }
    }

    /// Generalized accelerations from the raw Lagrangian, borrowed from the workspace.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`], [`Error::NonFinite`], or [`Error::SingularMassMatrix`]
    /// when `∂²L/∂q̇²` is singular or indefinite.
    pub fn accelerations<'w>(
        &self,
        ws: &'w mut RawWorkspace<F>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<&'w [f64], Error> {
        let n = self.n;
        check_state(n, t, q, Some(qdot))?;
        Self::reset(ws, q, qdot);
        let t_plain = HyperDual64::from(t);
        self.fill_velocity_hessian(ws, t_plain);
        // Σ_j ∂²L/∂q̇_i∂q_j q̇_j + ∂²L/∂q̇_i∂t: seed q̇_i (ε1) and the motion (q̇, 1) (ε2).
        for (d, v) in ws.q.iter_mut().zip(qdot) {
            d.eps2 = *v;
        }
        let t_moving = HyperDual64::new(t, 0.0, 1.0, 0.0);
        for i in 0..n {
            ws.qdot[i].eps1 = 1.0;
            let l = self.eval(ws, t_moving);
            ws.rhs[i] = -l.eps1eps2;
            ws.qdot[i].eps1 = 0.0;
        }
        // ∂L/∂q_i: seed q_i (ε1).
        for d in ws.q.iter_mut() {
            d.eps2 = 0.0;
        }
        for i in 0..n {
            ws.q[i].eps1 = 1.0;
            let l = self.eval(ws, t_plain);
            ws.rhs[i] += l.eps1;
            ws.q[i].eps1 = 0.0;
        }
        // + Q.
        if self.has_force {
            ws.generalized_force.fill(0.0);
            self.function.generalized_force_with(t, q, qdot, &mut ws.generalized_force);
            for (r, f) in ws.rhs.iter_mut().zip(&ws.generalized_force) {
                *r += f;
            }
        }
        // Solve.
        ws.factor.copy_from_slice(&ws.hessian);
        if let Err((j, pivot)) = solve::ldlt_factor(n, &mut ws.factor) {
            if !super::all_finite(&ws.hessian) {
                return Err(super::non_finite(Stage::Lagrangian, t, q));
            }
            return Err(Error::SingularMassMatrix {
                t,
                q: q.to_vec(),
                coordinate: self.coordinates()[j].name.clone(),
                pivot,
            });
        }
        ws.qddot.copy_from_slice(&ws.rhs);
        solve::ldlt_solve(n, &ws.factor, &mut ws.qddot);
        if !super::all_finite(&ws.qddot) {
            let stage = if super::all_finite(&ws.rhs) { Stage::Accelerations } else { Stage::Lagrangian };
            return Err(super::non_finite(stage, t, q));
        }
        Ok(&ws.qddot)
    }

    /// `∂²L/∂q̇_i∂q̇_j`: one pass per pair, seeding `q̇_i` (ε1) and `q̇_j` (ε2). Expects the
    /// unseeded state in `ws.q`, `ws.qdot`.
    fn fill_velocity_hessian(&self, ws: &mut RawWorkspace<F>, t: HyperDual64) {
        let n = self.n;
        for i in 0..n {
            for j in i..n {
                ws.qdot[i].eps1 = 1.0;
                ws.qdot[j].eps2 = 1.0;
                let l = self.eval(ws, t);
                ws.hessian[i * n + j] = l.eps1eps2;
                ws.hessian[j * n + i] = l.eps1eps2;
                ws.qdot[i].eps1 = 0.0;
                ws.qdot[j].eps2 = 0.0;
            }
        }
    }

    /// The generalized mass matrix `∂²L/∂q̇²` (n × n), borrowed from the workspace.
    ///
    /// # Errors
    /// On a malformed or non-finite state.
    pub fn velocity_hessian<'w>(
        &self,
        ws: &'w mut RawWorkspace<F>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<&'w [f64], Error> {
        check_state(self.n, t, q, Some(qdot))?;
        Self::reset(ws, q, qdot);
        self.fill_velocity_hessian(ws, HyperDual64::from(t));
        Ok(&ws.hessian)
    }

    /// `L(q, q̇, t)`.
    pub fn lagrangian(&self, ws: &mut RawWorkspace<F>, t: f64, q: &[f64], qdot: &[f64]) -> f64 {
        Self::reset(ws, q, qdot);
        self.eval(ws, HyperDual64::from(t)).re
    }

    /// Generalized momenta `p = ∂L/∂q̇`, borrowed from the workspace.
    pub fn momenta<'w>(
        &self,
        ws: &'w mut RawWorkspace<F>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<&'w [f64], Error> {
        check_state(self.n, t, q, Some(qdot))?;
        Self::reset(ws, q, qdot);
        for i in 0..self.n {
            ws.qdot[i].eps1 = 1.0;
            ws.momenta[i] = self.eval(ws, HyperDual64::from(t)).eps1;
            ws.qdot[i].eps1 = 0.0;
        }
        Ok(&ws.momenta)
    }

    /// The energy function `h = q̇·∂L/∂q̇ − L`: one pass seeded along `q̇` in velocity space.
    pub fn energy(&self, ws: &mut RawWorkspace<F>, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        check_state(self.n, t, q, Some(qdot))?;
        Self::reset(ws, q, qdot);
        for (d, v) in ws.qdot.iter_mut().zip(qdot) {
            d.eps1 = *v;
        }
        let l = self.eval(ws, HyperDual64::from(t));
        Ok(l.eps1 - l.re)
    }
}
