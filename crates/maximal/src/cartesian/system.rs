//! The Cartesian system of a scene: bodies, constraints and applied forces; the multiplier
//! equations solved as one KKT system; the projection onto `Φ = 0`, `Φ̇ = 0`.
//!
//! With `z` the poses of all `B` bodies (`n = 3B`), `m` constraint equations,
//! `M = diag(m_b, m_b, I_b)`, `J = Φ_z` (m × n) and `γ = d²/ds² Φ(z + s ż, t + s)`:
//!
//! ```text
//! [ M  Jᵀ ] [ z̈ ]   [  F ]
//! [ J  0  ] [ λ  ] = [ −γ ]
//! ```
//!
//! Velocity (non-holonomic) constraints `A(z) ż = 0` (a knife edge, rolling contact) are rows
//! of `J` after the holonomic ones: `A` is `∂(A ż)/∂ż` and their convective term is
//! `γ_A = (∂(A ż)/∂z) ż`, one first-order dual pass along `ż` with `ż` held; the projection
//! moves positions onto the holonomic rows only and velocities onto all rows.
//!
//! `F` = gravity + the scene potential's forces `−∂V/∂p_b` + the scene's non-conservative
//! forces; `−Jᵀλ` is the force and torque the constraints exert on each body.

mod dynamics;

use super::constraints::{Constraint, Joint, VelocityConstraint, equation_names, evaluate_all, no_turning};
use crate::scenes::{MaximalScene, MaximalVisitor};
use crate::{BodyState, BuildError, maps};
use lagrange::graph::GraphMechanism;
use lagrange::num_dual::{Dual2_64, Dual64};
use lagrange::{Body, Coordinate, Error, Stage};
use lagrange_scenes::Params;
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

/// Relative pivot below which a symmetric positive (semi-)definite factorization is declared
/// singular: the pivot after eliminating the earlier rows, relative to its own diagonal entry
/// (the reduced solver's criterion, 1e-12 — well above the `~n ε` round-off of a
/// well-posed factorization, and far below the `O(1)` ratios of the scenes' matrices).
const PIVOT_RTOL: f64 = 1e-12;

/// Gauss–Newton projection onto `Φ = 0` stops at `max|Φ| ≤ PROJECTION_RTOL · scale`
/// (`scale = max(1, max|z_i|)`): a few ε above the round-off of evaluating `Φ` itself.
const PROJECTION_RTOL: f64 = 1e-14;

/// Gauss–Newton converges quadratically from an accepted step's `O(tolerance)` violation:
/// 2–3 iterations; the cap only stops a stall at round-off.
const PROJECTION_ITERATIONS: usize = 8;

/// A projection that stalls above [`PROJECTION_RTOL`] (round-off in long chains) is accepted up
/// to `PROJECTION_ACCEPT · scale`; a violation beyond that cannot come from an accepted step at
/// any usable tolerance, and is an error.
const PROJECTION_ACCEPT: f64 = 1e-10;

/// The scene's non-conservative forces, in Cartesian form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum AppliedForce {
    /// None.
    None,
    /// The Lorentz force `e B (ẏ, −ẋ)` on body 0 in the field `B ẑ` (the charged particle).
    Lorentz {
        /// `e B` (kg/s).
        charge_field: f64,
    },
}

/// A scene in Cartesian body coordinates with its constraints: immutable once built.
#[derive(Clone, Debug)]
pub(crate) struct CartesianSystem {
    /// Scene id.
    pub(crate) scene: String,
    /// The scene's parameters (validated).
    params: Params,
    /// The bodies (B), in the reduced model's order.
    bodies: Vec<Body>,
    /// `x[b]`, `y[b]`, `φ[b]` for every body (3B).
    coordinates: Vec<Coordinate>,
    /// Diagonal of `M`: `(m_b, m_b, I_b)` per body (3B).
    mass: Vec<f64>,
    /// No coordinate is cyclic here (3B, all false).
    cyclic: Vec<bool>,
    /// Gravity `g` along −y.
    gravity: f64,
    /// The constraints.
    pub(crate) constraints: Vec<Constraint>,
    /// The velocity constraints (rows of `J` after the holonomic ones).
    velocity: Vec<VelocityConstraint>,
    /// Number of holonomic equations (the first rows of `J`).
    holonomic: usize,
    /// Name of every scalar equation: `Φ` then the velocity constraints (m).
    equation_names: Vec<String>,
    /// Non-conservative forces.
    applied: AppliedForce,
    /// Whether the scene has a potential beyond gravity.
    has_potential: bool,
    /// Whether a constraint depends on time.
    rheonomic: bool,
    /// The joint graph the system was built from, whose force elements act on the bodies.
    graph: Option<Arc<GraphMechanism>>,
}

/// Every buffer an evaluation needs, allocated once per simulation. Shapes use `n = 3B`
/// coordinates and `m` constraint equations; matrices are row-major `Vec`s except the
/// nalgebra KKT matrix.
#[derive(Clone, Debug)]
pub(crate) struct CartesianWorkspace {
    /// `z` as first-order duals, one unit direction at a time (n); [`CartesianSystem::jacobian`].
    z_dual: Vec<Dual64>,
    /// `Φ` in first-order duals (holonomic rows); [`CartesianSystem::jacobian`], [`CartesianSystem::constraint_rate`].
    phi_dual: Vec<Dual64>,
    /// `z + s ż` as second-order duals (n); [`CartesianSystem::convective`].
    z_dual2: Vec<Dual2_64>,
    /// `Φ(z + s ż, t + s)` (holonomic rows); [`CartesianSystem::convective`].
    phi_dual2: Vec<Dual2_64>,
    /// `ż` in first-order duals with no derivative part (n); the velocity rows of
    /// [`CartesianSystem::jacobian`] and [`CartesianSystem::convective`].
    zdot_dual: Vec<Dual64>,
    /// `Φ` (holonomic rows); [`CartesianSystem::project`].
    pub(crate) phi: Vec<f64>,
    /// `J = Φ_z` (m × n); [`CartesianSystem::jacobian`].
    pub(crate) jacobian: Vec<f64>,
    /// `Φ̇ = J ż + Φ_t` (m); [`CartesianSystem::convective`], [`CartesianSystem::constraint_rate`].
    pub(crate) rate: Vec<f64>,
    /// `γ = d²/ds² Φ(z + s ż, t + s)` (m); [`CartesianSystem::convective`].
    pub(crate) convective: Vec<f64>,
    /// Applied forces `F` (n); [`CartesianSystem::applied_forces`].
    pub(crate) force: Vec<f64>,
    /// Body poses for the scene potential (B); [`CartesianSystem::applied_forces`].
    states: Vec<BodyState>,
    /// `∂V/∂p_b` (n); [`CartesianSystem::applied_forces`].
    potential_gradient: Vec<f64>,
    /// `[[M, Jᵀ], [J, 0]]` ((n + m) × (n + m)), then its LU factor's storage; [`CartesianSystem::solve`].
    kkt: DMatrix<f64>,
    /// `(F, −γ)`, then `(z̈, λ)` (n + m); [`CartesianSystem::solve`].
    kkt_rhs: DVector<f64>,
    /// `z̈` (n); [`CartesianSystem::evaluate`].
    pub(crate) zddot: Vec<f64>,
    /// `λ` (m); [`CartesianSystem::evaluate`].
    pub(crate) multipliers: Vec<f64>,
    /// `J Jᵀ` and its Cholesky factor (m × m); [`CartesianSystem::project`].
    gram: Vec<f64>,
    /// Right-hand side and solution of the Gram system (m); [`CartesianSystem::project`].
    gram_rhs: Vec<f64>,
    /// `M + w JᵀJ` and its Cholesky factor (n × n); [`CartesianSystem::check_well_posed`].
    augmented: Vec<f64>,
}

impl CartesianSystem {
    /// The Cartesian system of `scene` with `params`.
    ///
    /// # Errors
    /// [`BuildError::Invalid`] for invalid parameters or an unknown scene.
    pub(crate) fn new(scene: &str, params: &Params) -> Result<Self, BuildError> {
        // Validates the parameters (and the scene id) before any parameter is read by name.
        let bodies = maps::bodies(scene, params)?;
        if let Some(mechanism) = crate::scenes::graph(scene, params)? {
            return Ok(Self::from_graph(scene, params, mechanism));
        }
        let names: Vec<String> = bodies.iter().map(|b| b.name.clone()).collect();
        // The scene's constraints and non-conservative forces, from its maximal description.
        struct Description<'a>(&'a [String]);
        impl MaximalVisitor for Description<'_> {
            type Output = (Vec<Constraint>, Vec<VelocityConstraint>, AppliedForce);
            fn visit<T: MaximalScene>(self, scene: T) -> Self::Output {
                (scene.constraints(self.0), scene.velocity_constraints(), scene.applied_force())
            }
        }
        let (constraints, velocity, applied) = crate::scenes::visit(scene, params, Description(&names))?;
        let coordinates = body_coordinates(&names);
        let mass = bodies.iter().flat_map(|b| [b.mass, b.mass, b.inertia]).collect();
        // Whether the scene has a potential: ask it once, at rest at the origin.
        let probe = vec![BodyState::default(); bodies.len()];
        let (_, has_potential) = maps::potential(scene, params, 0.0, &probe, None)?;
        let rheonomic = constraints.iter().any(Constraint::is_rheonomic);
        Ok(Self {
            scene: scene.into(),
            params: params.clone(),
            cyclic: vec![false; 3 * bodies.len()],
            gravity: maps::gravity(params),
            equation_names: all_names(&constraints, &velocity),
            holonomic: equation_names(&constraints).len(),
            velocity,
            bodies,
            coordinates,
            mass,
            constraints,
            applied,
            has_potential,
            rheonomic,
            graph: None,
        })
    }

    /// The Cartesian system of a joint graph: every joint (tree or loop-closing) as constraints
    /// between its bodies' poses ([`GraphMechanism::joint_residuals`]), the force elements as
    /// body wrenches ([`GraphMechanism::body_wrenches`]), and `φ_b = φ_b(0)` for a body without
    /// inertia whose angle no joint involves (its column of `Φ_z` vanishes identically: all
    /// its joints act at its centre).
    pub(crate) fn from_graph(name: &str, params: &Params, mechanism: Arc<GraphMechanism>) -> Self {
        use lagrange::Mechanism;
        let bodies = mechanism.bodies().to_vec();
        let names: Vec<String> = bodies.iter().map(|b| b.name.clone()).collect();
        let mut constraints: Vec<Constraint> = (0..mechanism.joints().len())
            .map(|joint| Constraint {
                name: mechanism.graph().joints[joint].name.clone(),
                joint: Joint::Graph { mechanism: Arc::clone(&mechanism), joint },
            })
            .collect();
        // Which angles the joints involve, from Φ_z at a generic configuration.
        let q: Vec<f64> = (0..mechanism.coordinates().len()).map(|i| 0.37 + 0.11 * i as f64).collect();
        let mut z = vec![0.0; 3 * bodies.len()];
        for b in 0..bodies.len() {
            z[3 * b..3 * b + 3].copy_from_slice(&mechanism.body_pose(b, 0.23, &q).to_array());
        }
        let mut involved = vec![false; bodies.len()];
        for constraint in &constraints {
            let rows = constraint.equations();
            for b in 0..bodies.len() {
                let mut seeded: Vec<Dual64> = z.iter().map(|v| Dual64::from(*v)).collect();
                seeded[3 * b + 2].eps = 1.0;
                let mut out = vec![Dual64::from(0.0); rows];
                constraint.evaluate(&seeded, Dual64::from(0.23), &mut out);
                involved[b] |= out.iter().any(|v| v.eps != 0.0);
            }
        }
        for (b, body) in bodies.iter().enumerate() {
            if body.inertia == 0.0 && !involved[b] {
                constraints.push(no_turning(b, &names));
            }
        }
        let coordinates = body_coordinates(&names);
        let velocity = Vec::new();
        Self {
            scene: name.into(),
            params: params.clone(),
            cyclic: vec![false; 3 * bodies.len()],
            gravity: mechanism.graph().gravity,
            equation_names: all_names(&constraints, &velocity),
            holonomic: equation_names(&constraints).len(),
            velocity,
            mass: bodies.iter().flat_map(|b| [b.mass, b.mass, b.inertia]).collect(),
            bodies,
            coordinates,
            rheonomic: constraints.iter().any(Constraint::is_rheonomic),
            constraints,
            applied: AppliedForce::None,
            has_potential: false,
            graph: Some(mechanism),
        }
    }

    /// The joint graph's force elements, if the system was built from one.
    pub(crate) fn graph(&self) -> Option<&GraphMechanism> {
        self.graph.as_deref()
    }

    /// The same system with other constraints (tests of ill-posed constraint sets).
    #[cfg(test)]
    pub(crate) fn with_constraints(mut self, constraints: Vec<Constraint>) -> Self {
        self.equation_names = all_names(&constraints, &self.velocity);
        self.holonomic = equation_names(&constraints).len();
        self.rheonomic = constraints.iter().any(Constraint::is_rheonomic);
        self.constraints = constraints;
        self
    }

    /// Number of coordinates `n = 3B`.
    pub(crate) fn n(&self) -> usize {
        self.mass.len()
    }

    /// Number of constraint equations `m` (holonomic and velocity rows).
    pub(crate) fn m(&self) -> usize {
        self.equation_names.len()
    }

    /// The name of constraint equation `i`.
    pub(crate) fn equation_name(&self, i: usize) -> &str {
        &self.equation_names[i]
    }

    /// Allocate the workspace.
    pub(crate) fn workspace(&self) -> CartesianWorkspace {
        let (n, m, h) = (self.n(), self.m(), self.holonomic);
        CartesianWorkspace {
            z_dual: vec![Dual64::from(0.0); n],
            phi_dual: vec![Dual64::from(0.0); h],
            z_dual2: vec![Dual2_64::from(0.0); n],
            phi_dual2: vec![Dual2_64::from(0.0); h],
            zdot_dual: vec![Dual64::from(0.0); n],
            phi: vec![0.0; h],
            jacobian: vec![0.0; m * n],
            rate: vec![0.0; m],
            convective: vec![0.0; m],
            force: vec![0.0; n],
            states: vec![BodyState::default(); self.bodies.len()],
            potential_gradient: vec![0.0; n],
            kkt: DMatrix::zeros(n + m, n + m),
            kkt_rhs: DVector::zeros(n + m),
            zddot: vec![0.0; n],
            multipliers: vec![0.0; m],
            gram: vec![0.0; m * m],
            gram_rhs: vec![0.0; m],
            augmented: vec![0.0; n * n],
        }
    }

    /// `Φ(z, t)` (m) into `phi`.
    pub(crate) fn constraint_values(&self, t: f64, z: &[f64], phi: &mut [f64]) {
        evaluate_all(&self.constraints, z, t, phi);
    }

    /// Largest `|Φ_i(z, t)|`, without a workspace.
    pub(crate) fn violation(&self, t: f64, z: &[f64]) -> f64 {
        let mut worst = 0.0_f64;
        let mut values = [0.0; 4];
        for constraint in &self.constraints {
            let rows = constraint.equations();
            constraint.evaluate(z, t, &mut values[..rows]);
            worst = values[..rows].iter().fold(worst, |w, v| w.max(v.abs()));
        }
        worst
    }

    /// `J = Φ_z` into `ws.jacobian`: one first-order dual pass per coordinate of `z`; then the
    /// velocity rows `A = ∂(A ż)/∂ż`, one dual pass per coordinate of `ż`.
    pub(crate) fn jacobian(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64]) {
        let (n, h) = (self.n(), self.holonomic);
        for (d, &zi) in ws.z_dual.iter_mut().zip(z) {
            *d = Dual64::from(zi);
        }
        let t = Dual64::from(t);
        for j in 0..n {
            ws.z_dual[j].eps = 1.0;
            evaluate_all(&self.constraints, &ws.z_dual, t, &mut ws.phi_dual);
            ws.z_dual[j].eps = 0.0;
            for i in 0..h {
                ws.jacobian[i * n + j] = ws.phi_dual[i].eps;
            }
        }
        if self.velocity.is_empty() {
            return;
        }
        ws.zdot_dual.fill(Dual64::from(0.0));
        for j in 0..n {
            ws.zdot_dual[j].eps = 1.0;
            for (i, constraint) in self.velocity.iter().enumerate() {
                ws.jacobian[(h + i) * n + j] = constraint.evaluate(&ws.z_dual, &ws.zdot_dual).eps;
            }
            ws.zdot_dual[j].eps = 0.0;
        }
    }

    /// The velocity rows' values `A ż` (into `rate[h..]`) and, with `convective`, their
    /// convective term `(∂(A ż)/∂z) ż` (into `convective[h..]`): one dual pass along `ż` in `z`
    /// with `ż` held.
    fn velocity_rows(&self, ws: &mut CartesianWorkspace, z: &[f64], zdot: &[f64], convective: bool) {
        let h = self.holonomic;
        for (((d, v), &zi), &vi) in ws.z_dual.iter_mut().zip(ws.zdot_dual.iter_mut()).zip(z).zip(zdot) {
            *d = Dual64::new(zi, if convective { vi } else { 0.0 });
            *v = Dual64::from(vi);
        }
        for (i, constraint) in self.velocity.iter().enumerate() {
            let value = constraint.evaluate(&ws.z_dual, &ws.zdot_dual);
            ws.rate[h + i] = value.re;
            if convective {
                ws.convective[h + i] = value.eps;
            }
        }
    }

    /// `Φ̇ = J ż + Φ_t` into `ws.rate`: one first-order dual pass along `(ż, 1)`.
    pub(crate) fn constraint_rate(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64], zdot: &[f64]) {
        for ((d, &zi), &vi) in ws.z_dual.iter_mut().zip(z).zip(zdot) {
            *d = Dual64::new(zi, vi);
        }
        evaluate_all(&self.constraints, &ws.z_dual, Dual64::new(t, 1.0), &mut ws.phi_dual);
        for (rate, phi) in ws.rate.iter_mut().zip(&ws.phi_dual) {
            *rate = phi.eps;
        }
        if !self.velocity.is_empty() {
            self.velocity_rows(ws, z, zdot, false);
        }
    }

    /// `γ = d²/ds² Φ(z + s ż, t + s) = (J ż)_z ż + 2 Φ_zt ż + Φ_tt` into `ws.convective`, and
    /// `Φ̇` into `ws.rate`: one second-order dual pass along `(ż, 1)`.
    pub(crate) fn convective(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64], zdot: &[f64]) {
        for ((d, &zi), &vi) in ws.z_dual2.iter_mut().zip(z).zip(zdot) {
            *d = Dual2_64::new(zi, vi, 0.0);
        }
        evaluate_all(&self.constraints, &ws.z_dual2, Dual2_64::new(t, 1.0, 0.0), &mut ws.phi_dual2);
        for ((gamma, rate), phi) in ws.convective.iter_mut().zip(ws.rate.iter_mut()).zip(&ws.phi_dual2) {
            *gamma = phi.v2;
            *rate = phi.v1;
        }
        if !self.velocity.is_empty() {
            self.velocity_rows(ws, z, zdot, true);
        }
    }

    /// Fill `ws.states` with the body poses (and velocities) of `(z, ż)`.
    fn fill_states(states: &mut [BodyState], z: &[f64], zdot: &[f64]) {
        for (b, state) in states.iter_mut().enumerate() {
            state.pose.copy_from_slice(&z[3 * b..3 * b + 3]);
            state.velocity.copy_from_slice(&zdot[3 * b..3 * b + 3]);
        }
    }

    /// The applied forces `F` into `ws.force`: gravity `(0, −m_b g, 0)`, the potential's
    /// `−∂V/∂p_b` (from [`maps::potential`]), and the scene's non-conservative forces.
    ///
    /// # Errors
    /// A failing or non-finite potential.
    pub(crate) fn applied_forces(
        &self,
        ws: &mut CartesianWorkspace,
        t: f64,
        z: &[f64],
        zdot: &[f64],
    ) -> Result<(), Error> {
        // Gravity.
        for (b, body) in self.bodies.iter().enumerate() {
            ws.force[3 * b..3 * b + 3].copy_from_slice(&[0.0, -body.mass * self.gravity, 0.0]);
        }
        // The scene potential, through the body poses.
        if self.has_potential {
            Self::fill_states(&mut ws.states, z, zdot);
            maps::potential(&self.scene, &self.params, t, &ws.states, Some(&mut ws.potential_gradient))?;
            if !ws.potential_gradient.iter().all(|g| g.is_finite()) {
                return Err(Error::NonFinite { stage: Stage::Potential, t, q: z.to_vec() });
            }
            for (f, g) in ws.force.iter_mut().zip(&ws.potential_gradient) {
                *f -= g;
            }
        }
        // A joint graph's force elements.
        if let Some(graph) = &self.graph {
            let poses: Vec<lagrange::Pose<f64>> =
                (0..self.bodies.len()).map(|b| lagrange::Pose::new(z[3 * b], z[3 * b + 1], z[3 * b + 2])).collect();
            let velocities: Vec<[f64; 3]> =
                (0..self.bodies.len()).map(|b| [zdot[3 * b], zdot[3 * b + 1], zdot[3 * b + 2]]).collect();
            graph.body_wrenches(t, &poses, &velocities, &mut ws.force);
            if !ws.force.iter().all(|f| f.is_finite()) {
                return Err(Error::NonFinite { stage: Stage::AppliedForce, t, q: z.to_vec() });
            }
        }
        // Non-conservative forces.
        match self.applied {
            AppliedForce::None => {}
            AppliedForce::Lorentz { charge_field } => {
                ws.force[0] += charge_field * zdot[1];
                ws.force[1] -= charge_field * zdot[0];
            }
        }
        Ok(())
    }

    /// Solve the KKT system with the Jacobian, convective term and forces in `ws`: `z̈` into
    /// `ws.zddot`, `λ` into `ws.multipliers`. nalgebra's LU with partial pivoting factors the
    /// matrix in its own storage, which is handed back to the workspace afterwards (only its
    /// pivot sequence, n + m pairs, is allocated per solve).
    ///
    /// # Errors
    /// [`Error::SingularMassMatrix`] when the factorization meets a zero pivot or produces a
    /// non-finite solution.
    fn solve(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64]) -> Result<(), Error> {
        let (n, m) = (self.n(), self.m());
        // Assemble [[M, Jᵀ], [J, 0]] and (F, −γ).
        ws.kkt.fill(0.0);
        for j in 0..n {
            ws.kkt[(j, j)] = self.mass[j];
            ws.kkt_rhs[j] = ws.force[j];
        }
        for i in 0..m {
            for j in 0..n {
                let value = ws.jacobian[i * n + j];
                ws.kkt[(n + i, j)] = value;
                ws.kkt[(j, n + i)] = value;
            }
            ws.kkt_rhs[n + i] = -ws.convective[i];
        }
        // Factor and solve, then recycle the factor's storage.
        let lu = std::mem::replace(&mut ws.kkt, DMatrix::zeros(0, 0)).lu();
        let solved = lu.solve_mut(&mut ws.kkt_rhs);
        ws.kkt = lu.l_unpack();
        if !solved || !ws.kkt_rhs.iter().all(|v| v.is_finite()) {
            // Name what is singular where the structure says so; otherwise the whole matrix.
            self.check_well_posed(ws, t, z)?;
            return Err(Error::SingularMassMatrix {
                t,
                q: z.to_vec(),
                coordinate: format!("KKT matrix [[M, Φ_zᵀ], [Φ_z, 0]] of {}", self.scene),
                pivot: 0.0,
            });
        }
        ws.zddot.copy_from_slice(&ws.kkt_rhs.as_slice()[..n]);
        ws.multipliers.copy_from_slice(&ws.kkt_rhs.as_slice()[n..]);
        Ok(())
    }

    /// Everything at `(t, z, ż)`: `J`, `γ`, `Φ̇`, `F`, then `z̈` and `λ` (into `ws`).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite state, potential or result;
    /// [`Error::SingularMassMatrix`] for a singular KKT matrix.
    pub(crate) fn evaluate(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64], zdot: &[f64]) -> Result<(), Error> {
        debug_assert!(z.len() == self.n() && zdot.len() == self.n(), "z and ż have 3B entries");
        if !(t.is_finite() && z.iter().chain(zdot).all(|v| v.is_finite())) {
            return Err(Error::NonFinite { stage: Stage::State, t, q: z.to_vec() });
        }
        self.jacobian(ws, t, z);
        self.convective(ws, t, z, zdot);
        if !ws.jacobian.iter().chain(&ws.convective).all(|v| v.is_finite()) {
            return Err(Error::NonFinite { stage: Stage::Kinematics, t, q: z.to_vec() });
        }
        self.applied_forces(ws, t, z, zdot)?;
        self.solve(ws, t, z)
    }

    /// The constraint forces `−Jᵀλ` (n) of the last [`evaluate`](Self::evaluate) into `out`.
    pub(crate) fn constraint_forces(&self, ws: &CartesianWorkspace, out: &mut [f64]) {
        let (n, m) = (self.n(), self.m());
        for (j, f) in out.iter_mut().enumerate() {
            *f = -(0..m).map(|i| ws.jacobian[i * n + j] * ws.multipliers[i]).sum::<f64>();
        }
    }

    /// Check that the KKT matrix at `z` (with `J` in `ws`) is non-singular: `J` has full row
    /// rank (`J Jᵀ` positive definite) and `M` is positive definite on the null space of `J`
    /// (`M + w JᵀJ` positive definite, `w = max M_jj`), each to a relative pivot of
    /// [`PIVOT_RTOL`].
    ///
    /// # Errors
    /// [`Error::SingularMassMatrix`] naming the constraint equation (rank-deficient `J`) or
    /// the coordinate (moves no mass and is fixed by no constraint) whose pivot vanished.
    pub(crate) fn check_well_posed(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64]) -> Result<(), Error> {
        let (n, m) = (self.n(), self.m());
        let singular =
            |coordinate: String, pivot: f64| Error::SingularMassMatrix { t, q: z.to_vec(), coordinate, pivot };
        gram(n, m, &ws.jacobian, &mut ws.gram);
        cholesky(m, &mut ws.gram).map_err(|(i, pivot)| {
            singular(format!("constraint `{}` (Φ_z rank-deficient)", self.equation_names[i]), pivot)
        })?;
        let weight = self.mass.iter().fold(0.0_f64, |w, &v| w.max(v));
        let weight = if weight > 0.0 { weight } else { 1.0 };
        for a in 0..n {
            for b in 0..n {
                let product: f64 = (0..m).map(|i| ws.jacobian[i * n + a] * ws.jacobian[i * n + b]).sum();
                ws.augmented[a * n + b] = weight * product + if a == b { self.mass[a] } else { 0.0 };
            }
        }
        cholesky(n, &mut ws.augmented).map_err(|(j, pivot)| {
            singular(format!("{} (moves no mass and no constraint fixes it)", self.coordinates[j].name), pivot)
        })
    }

    /// Project `(z, ż)` at `t` onto the constraint manifold: positions by Gauss–Newton
    /// `z ← z − Jᵀ (J Jᵀ)⁻¹ Φ` until `max|Φ| ≤ PROJECTION_RTOL · max(1, max|z_i|)`, then
    /// velocities `ż ← ż − Jᵀ (J Jᵀ)⁻¹ (J ż + Φ_t)` (exact in one step: `Φ̇` is linear in `ż`).
    /// Leaves `J` at the projected `z` in `ws`.
    ///
    /// # Errors
    /// [`Error::SingularMassMatrix`] for a rank-deficient `J` or a KKT matrix that is not
    /// well posed; [`Error::Diverged`] when the positions cannot be projected.
    pub(crate) fn project(
        &self,
        ws: &mut CartesianWorkspace,
        t: f64,
        z: &mut [f64],
        zdot: &mut [f64],
    ) -> Result<(), Error> {
        let (n, m, h) = (self.n(), self.m(), self.holonomic);
        let scale = z.iter().fold(1.0_f64, |s, v| s.max(v.abs()));
        // Positions: Gauss–Newton on Φ(z, t) = 0 (the holonomic rows of J).
        let (mut violation, iterations) = if h == 0 { (0.0, 0) } else { (f64::INFINITY, PROJECTION_ITERATIONS) };
        for _ in 0..iterations {
            self.constraint_values(t, z, &mut ws.phi);
            violation = ws.phi.iter().fold(0.0_f64, |w, v| w.max(v.abs()));
            if violation <= PROJECTION_RTOL * scale {
                break;
            }
            self.jacobian(ws, t, z);
            ws.gram_rhs[..h].copy_from_slice(&ws.phi);
            self.gram_solve(ws, t, z, h)?;
            for j in 0..n {
                z[j] -= (0..h).map(|i| ws.jacobian[i * n + j] * ws.gram_rhs[i]).sum::<f64>();
            }
        }
        if violation.is_nan() || violation > PROJECTION_ACCEPT * scale {
            return Err(Error::Diverged {
                t,
                step: 0,
                quantity: format!("constraint violation {violation:e} after projection onto Φ = 0"),
            });
        }
        // Velocities: remove the component along the constraint normals.
        self.jacobian(ws, t, z);
        self.check_well_posed(ws, t, z)?;
        self.constraint_rate(ws, t, z, zdot);
        ws.gram_rhs.copy_from_slice(&ws.rate);
        self.gram_solve(ws, t, z, m)?;
        for j in 0..n {
            zdot[j] -= (0..m).map(|i| ws.jacobian[i * n + j] * ws.gram_rhs[i]).sum::<f64>();
        }
        Ok(())
    }

    /// Solve `J_r J_rᵀ x = ws.gram_rhs[..rows]` in place, `J_r` the first `rows` rows of `J`
    /// (in `ws`).
    fn gram_solve(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64], rows: usize) -> Result<(), Error> {
        let n = self.n();
        gram(n, rows, &ws.jacobian, &mut ws.gram);
        cholesky(rows, &mut ws.gram).map_err(|(i, pivot)| Error::SingularMassMatrix {
            t,
            q: z.to_vec(),
            coordinate: format!("constraint `{}` (Φ_z rank-deficient)", self.equation_names[i]),
            pivot,
        })?;
        cholesky_solve(rows, &ws.gram, &mut ws.gram_rhs[..rows]);
        Ok(())
    }

    /// `T + Σ m_b g y_b + V` at `(z, ż)`.
    ///
    /// # Errors
    /// A failing potential.
    pub(crate) fn total_energy(
        &self,
        ws: &mut CartesianWorkspace,
        t: f64,
        z: &[f64],
        zdot: &[f64],
    ) -> Result<f64, Error> {
        let mut energy = 0.0;
        for (b, body) in self.bodies.iter().enumerate() {
            let v = &zdot[3 * b..3 * b + 3];
            energy += 0.5 * body.mass * (v[0] * v[0] + v[1] * v[1]) + 0.5 * body.inertia * v[2] * v[2];
            energy += body.mass * self.gravity * z[3 * b + 1];
        }
        if self.has_potential {
            Self::fill_states(&mut ws.states, z, zdot);
            energy += maps::potential(&self.scene, &self.params, t, &ws.states, None)?.0;
        }
        if let Some(graph) = &self.graph {
            let poses: Vec<lagrange::Pose<f64>> =
                (0..self.bodies.len()).map(|b| lagrange::Pose::new(z[3 * b], z[3 * b + 1], z[3 * b + 2])).collect();
            energy += graph.force_potential(&poses);
        }
        Ok(energy)
    }
}

/// `x[b]`, `y[b]`, `φ[b]` for every body `b` of `names`.
fn body_coordinates(names: &[String]) -> Vec<Coordinate> {
    names
        .iter()
        .flat_map(|name| {
            [
                Coordinate::length(format!("x[{name}]")),
                Coordinate::length(format!("y[{name}]")),
                Coordinate::angle(format!("φ[{name}]")),
            ]
        })
        .collect()
}

/// The names of the holonomic equations followed by those of the velocity constraints.
fn all_names(constraints: &[Constraint], velocity: &[VelocityConstraint]) -> Vec<String> {
    let mut names = equation_names(constraints);
    names.extend(velocity.iter().map(|v| v.name.clone()));
    names
}

/// `J Jᵀ` (m × m) of `J` (m × n), both row-major.
fn gram(n: usize, m: usize, jacobian: &[f64], out: &mut [f64]) {
    for a in 0..m {
        for b in 0..m {
            out[a * m + b] = (0..n).map(|j| jacobian[a * n + j] * jacobian[b * n + j]).sum();
        }
    }
}

/// In-place Cholesky `A = L Lᵀ` of a symmetric matrix (k × k, row-major; `L` in the lower
/// triangle). Returns `Err((j, ratio))` at the first pivot `j` that is not positive relative
/// to its diagonal entry by more than [`PIVOT_RTOL`].
fn cholesky(k: usize, a: &mut [f64]) -> Result<(), (usize, f64)> {
    for j in 0..k {
        let diagonal = a[j * k + j];
        let pivot = diagonal - (0..j).map(|p| a[j * k + p] * a[j * k + p]).sum::<f64>();
        let ratio = if diagonal > 0.0 { pivot / diagonal } else { 0.0 };
        if ratio.is_nan() || ratio <= PIVOT_RTOL {
            return Err((j, ratio));
        }
        let root = pivot.sqrt();
        a[j * k + j] = root;
        for i in j + 1..k {
            let dot: f64 = (0..j).map(|p| a[i * k + p] * a[j * k + p]).sum();
            a[i * k + j] = (a[i * k + j] - dot) / root;
        }
    }
    Ok(())
}

/// Solve `L Lᵀ x = b` in place with the factor of [`cholesky`].
fn cholesky_solve(k: usize, factor: &[f64], b: &mut [f64]) {
    for i in 0..k {
        let dot: f64 = (0..i).map(|p| factor[i * k + p] * b[p]).sum();
        b[i] = (b[i] - dot) / factor[i * k + i];
    }
    for i in (0..k).rev() {
        let dot: f64 = (i + 1..k).map(|p| factor[p * k + i] * b[p]).sum();
        b[i] = (b[i] - dot) / factor[i * k + i];
    }
}
