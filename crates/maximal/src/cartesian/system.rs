//! The Cartesian system of a scene: bodies, constraints and applied forces; the multiplier
//! equations solved by the Schur complement on the block-diagonal mass matrix; the projection
//! onto `Φ = 0`, `Φ̇ = 0`.
//!
//! With `z` the poses of all `B` bodies (`n = 3B`), `m` constraint equations,
//! `M = diag(m_b, m_b, I_b)`, `J = Φ_z` (m × n) and `γ = d²/ds² Φ(z + s ż, t + s)`:
//!
//! ```text
//! [ M  Jᵀ ] [ z̈ ]   [  F ]
//! [ J  0  ] [ λ  ] = [ −γ ]
//! ```
//!
//! solved as `S λ = J M̃⁻¹ F̃ + γ`, `z̈ = M̃⁻¹ (F̃ − Jᵀ λ)` with `S = J M̃⁻¹ Jᵀ` sparse
//! ([`schur`]; `M̃ = M` but for the rows fixing coordinates without mass, [`sparsity`]): no
//! per-evaluation work grows faster than the nonzeros of `J` and of the factor of `S`, and
//! nothing is allocated per evaluation. `J` loses rank where a linkage passes a flat position and
//! has redundant rows everywhere for over-constrained linkages: the shifted and refined solve
//! goes through both, with the least `Σ S_ii λ_i²` multipliers at a redundancy, and a set of
//! rows that cannot hold together is [`Error::InconsistentConstraints`].
//!
//! Velocity (non-holonomic) constraints `A(z) ż = 0` (a knife edge, rolling contact) are rows
//! of `J` after the holonomic ones: `A` is `∂(A ż)/∂ż` and their convective term is
//! `γ_A = (∂(A ż)/∂z) ż`, one first-order dual pass along `ż` with `ż` held; the projection
//! moves positions onto the holonomic rows only and velocities onto all rows.
//!
//! `F` = gravity + the scene potential's forces `−∂V/∂p_b` + the scene's non-conservative
//! forces; `−Jᵀλ` is the force and torque the constraints exert on each body.

mod dynamics;
mod schur;
mod sparsity;

use super::constraints::{Constraint, Joint, VelocityConstraint, equation_names, evaluate_all, no_turning};
use crate::maps::ReadBack;
use crate::scenes::{MaximalScene, MaximalVisitor};
use crate::{BodyState, BuildError};
use lagrange::error::Stage;
use lagrange::graph::{ForceElement, GROUND, GraphMechanism, JointGraph};
use lagrange::num_dual::{Dual2_64, Dual64};
use lagrange::{Body, Coordinate, Error, Pose};
use lagrange_scenes::Params;
use schur::KktWorkspace;
use sparsity::Sparsity;
use std::sync::Arc;

/// Gauss–Newton on `Φ = 0` has converged when every equation satisfies
/// `|Φ_i| ≤ PROJECTION_RTOL · size_i`, `size_i` the magnitude of the positions, angles and
/// lever arms inside it ([`KktWorkspace::equation_sizes`]): 4 ε, four roundings of its largest
/// terms, the least that evaluating `Φ_i` can promise.
const PROJECTION_RTOL: f64 = 4.0 * f64::EPSILON;

/// Gauss–Newton converges quadratically from an accepted step's `O(tolerance)` violation:
/// 1–2 iterations; the cap only stops a stall that the progress test missed.
const PROJECTION_ITERATIONS: usize = 8;

/// A Gauss–Newton iteration that does not halve the largest relative violation has reached
/// round-off (or the partially enforced directions of a rank loss), and the projection stops
/// there.
const PROJECTION_PROGRESS: f64 = 0.5;

/// A projection that stops above [`PROJECTION_RTOL`] is accepted up to `PROJECTION_ACCEPT`
/// relative to each equation's size; a violation beyond that cannot come from an accepted step at
/// any usable tolerance, and is an error.
const PROJECTION_ACCEPT: f64 = 1e-10;

/// The constraint rows hold together when the residual of `S λ = b` after refinement is at most
/// this fraction of the largest term of `b` (both scaled by `D^(−1/2)`): consistent, independent
/// rows leave round-off (≈ 1e-15); a stage of the integrator near a rank loss, whose velocities
/// lie slightly across the branches, leaves what the shift does not enforce — measured at most
/// 1.1e-5 over every run of the tests (the 40-window chain at tolerance 1e-6 included). Rows that
/// contradict each other leave a residual of the size of `b`: 9.3e-2 for a bob passing the
/// bottom of its circle at 1.5 m/s on a tangent floor. 1e-3 lies a factor ~100 from both.
const CONSISTENT: f64 = 1e-3;

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
    /// The scene's read-back: its bodies, and its potential at body states (a joint graph's
    /// force elements are [`Self::graph`]'s).
    pub(crate) read_back: ReadBack,
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
    /// The sparsity of `J`, `M̃` and `S`, and the symbolic factorization of `S`.
    sparsity: Arc<Sparsity>,
    /// Where the origin of the system's frame is in the world (m): `z` holds positions relative
    /// to it ([`centred`](Self::centred)); `(0, 0)` unless moved.
    frame: [f64; 2],
}

/// Every buffer an evaluation needs, allocated once per simulation. Shapes use `n = 3B`
/// coordinates and `m` constraint equations.
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
    /// `J`, `M̃` and `S` with their factors; [`CartesianSystem::jacobian`], [`CartesianSystem::solve`].
    kkt: KktWorkspace,
    /// The `(t, z)` at which `J` and the blocks of `M̃` in `kkt` were computed, if they are
    /// current; [`CartesianSystem::prepare`].
    prepared: Option<f64>,
    /// The `z` of [`prepared`](Self::prepared) (n).
    prepared_z: Vec<f64>,
    /// `Φ̇ = J ż + Φ_t` (m); [`CartesianSystem::convective`], [`CartesianSystem::constraint_rate`].
    pub(crate) rate: Vec<f64>,
    /// `γ = d²/ds² Φ(z + s ż, t + s)` (m); [`CartesianSystem::convective`].
    pub(crate) convective: Vec<f64>,
    /// Applied forces `F` (n); [`CartesianSystem::applied_forces`].
    pub(crate) force: Vec<f64>,
    /// `F̃ = F − Σ_R w_i γ_i J_iᵀ` (n); [`CartesianSystem::solve`].
    augmented_force: Vec<f64>,
    /// Body poses for the scene potential (B); [`CartesianSystem::applied_forces`].
    states: Vec<BodyState>,
    /// Body poses for a joint graph's force elements and potential (B); [`CartesianSystem::applied_forces`].
    poses: Vec<Pose<f64>>,
    /// Body velocities for a joint graph's force elements (B); [`CartesianSystem::applied_forces`].
    velocities: Vec<[f64; 3]>,
    /// `∂V/∂p_b` (n); [`CartesianSystem::applied_forces`].
    potential_gradient: Vec<f64>,
    /// `M̃⁻¹ F̃`, then a projection's step `M̃⁻¹ Jᵀ ν` (n); [`CartesianSystem::solve`], [`CartesianSystem::project`].
    step: Vec<f64>,
    /// Size of each term sum: of `b = J M̃⁻¹ F̃ + γ`, or of each equation `Φ_i` (m);
    /// [`CartesianSystem::solve`], [`CartesianSystem::project`].
    sizes: Vec<f64>,
    /// A projection's multipliers `ν` (m); [`CartesianSystem::project`].
    correction: Vec<f64>,
    /// `z̈` (n); [`CartesianSystem::evaluate`].
    pub(crate) zddot: Vec<f64>,
    /// `λ` (m); [`CartesianSystem::evaluate`].
    pub(crate) multipliers: Vec<f64>,
}

impl CartesianSystem {
    /// The Cartesian system of `scene` with `params`.
    ///
    /// # Errors
    /// [`BuildError::Invalid`] for invalid parameters.
    pub(crate) fn new(scene: &dyn lagrange_scenes::Scene, params: &Params) -> Result<Self, BuildError> {
        let read_back = ReadBack::new(scene, params)?;
        if let Some(mechanism) = read_back.mechanism() {
            return Ok(Self::from_graph(scene.id(), Arc::clone(mechanism)));
        }
        let bodies = read_back.bodies().to_vec();
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
        let mass: Vec<f64> = bodies.iter().flat_map(|b| [b.mass, b.mass, b.inertia]).collect();
        // Whether the scene has a potential: ask it once, at rest at the origin.
        let probe = vec![BodyState::default(); bodies.len()];
        let (_, has_potential) = read_back.potential(0.0, &probe, None);
        let rheonomic = constraints.iter().any(Constraint::is_rheonomic);
        let holonomic = equation_names(&constraints).len();
        let sparsity = Arc::new(Sparsity::new(&constraints, &velocity, &mass, holonomic));
        Ok(Self {
            scene: scene.id().into(),
            cyclic: vec![false; 3 * bodies.len()],
            gravity: read_back.gravity(),
            read_back,
            equation_names: all_names(&constraints, &velocity),
            holonomic,
            velocity,
            bodies,
            coordinates,
            mass,
            constraints,
            applied,
            has_potential,
            rheonomic,
            graph: None,
            sparsity,
            frame: [0.0; 2],
        })
    }

    /// The Cartesian system of a joint graph: every joint (tree or loop-closing) as constraints
    /// between its bodies' poses ([`GraphMechanism::joint_residuals`]), the force elements as
    /// body wrenches ([`GraphMechanism::body_wrenches`]), and `φ_b = φ_b(0)` for a body without
    /// inertia whose angle no joint involves (its column of `Φ_z` vanishes identically: all
    /// its joints act at its centre).
    pub(crate) fn from_graph(name: &str, mechanism: Arc<GraphMechanism>) -> Self {
        use lagrange::Mechanism;
        let bodies = mechanism.description().bodies.clone();
        let names: Vec<String> = bodies.iter().map(|b| b.name.clone()).collect();
        let mut constraints: Vec<Constraint> = (0..mechanism.graph().joints.len())
            .map(|joint| Constraint {
                name: mechanism.graph().joints[joint].name.clone(),
                joint: Joint::Graph { mechanism: Arc::clone(&mechanism), joint },
            })
            .collect();
        // Which angles the joints involve, from Φ_z at a generic configuration.
        let q: Vec<f64> = (0..mechanism.description().coordinates.len()).map(|i| 0.37 + 0.11 * i as f64).collect();
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
        let mass: Vec<f64> = bodies.iter().flat_map(|b| [b.mass, b.mass, b.inertia]).collect();
        let holonomic = equation_names(&constraints).len();
        let sparsity = Arc::new(Sparsity::new(&constraints, &velocity, &mass, holonomic));
        Self {
            scene: name.into(),
            read_back: ReadBack::graph(Arc::clone(&mechanism)),
            cyclic: vec![false; 3 * bodies.len()],
            gravity: mechanism.graph().gravity,
            equation_names: all_names(&constraints, &velocity),
            holonomic,
            velocity,
            mass,
            bodies,
            coordinates,
            rheonomic: constraints.iter().any(Constraint::is_rheonomic),
            constraints,
            applied: AppliedForce::None,
            has_potential: false,
            graph: Some(mechanism),
            sparsity,
            frame: [0.0; 2],
        }
    }

    /// The joint graph's force elements, if the system was built from one.
    pub(crate) fn graph(&self) -> Option<&GraphMechanism> {
        self.graph.as_deref()
    }

    /// The same system in a frame whose origin is at `origin` (world coordinates, relative to
    /// the current frame): every fixed point of the constraints and force elements moves by
    /// `−origin`, and `z` then holds positions relative to `origin`. The equations are evaluated
    /// where their numbers are of the mechanism's own size, so that the motion does not depend on
    /// where the world's origin is, not even through round-off: near a rank loss (a linkage lying
    /// flat) the position projection turns the round-off of `Φ` (`ε |z|`) into motion across
    /// the branches, `ε |z| / √σ`, which at 1e3 m from the origin is 1e3 times larger than at the
    /// mechanism. The scene potential, gravity's energy and [`Self::frame`] still see world
    /// positions.
    ///
    /// # Errors
    /// A joint graph that the moved description no longer makes a mechanism of (it always does:
    /// moving the ground's points changes no joint's value).
    pub(crate) fn centred(mut self, origin: [f64; 2]) -> Result<Self, Error> {
        let moved = match &self.graph {
            Some(mechanism) => Some(Arc::new(GraphMechanism::new(moved_graph(mechanism.graph(), origin))?)),
            None => None,
        };
        self.constraints = self.constraints.iter().map(|c| c.moved(origin, moved.as_ref())).collect();
        if moved.is_some() {
            self.graph = moved;
        }
        self.frame = [self.frame[0] + origin[0], self.frame[1] + origin[1]];
        Ok(self)
    }

    /// Where the origin of the system's frame is in the world (m).
    pub(crate) fn frame(&self) -> [f64; 2] {
        self.frame
    }

    /// The same system with other constraints (tests of ill-posed constraint sets).
    #[cfg(test)]
    pub(crate) fn with_constraints(mut self, constraints: Vec<Constraint>) -> Self {
        self.equation_names = all_names(&constraints, &self.velocity);
        self.holonomic = equation_names(&constraints).len();
        self.rheonomic = constraints.iter().any(Constraint::is_rheonomic);
        self.sparsity = Arc::new(Sparsity::new(&constraints, &self.velocity, &self.mass, self.holonomic));
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
        let (n, m, h, b) = (self.n(), self.m(), self.holonomic, self.bodies.len());
        CartesianWorkspace {
            z_dual: vec![Dual64::from(0.0); n],
            phi_dual: vec![Dual64::from(0.0); h],
            z_dual2: vec![Dual2_64::from(0.0); n],
            phi_dual2: vec![Dual2_64::from(0.0); h],
            zdot_dual: vec![Dual64::from(0.0); n],
            phi: vec![0.0; h],
            kkt: KktWorkspace::new(&self.sparsity),
            prepared: None,
            prepared_z: vec![0.0; n],
            rate: vec![0.0; m],
            convective: vec![0.0; m],
            force: vec![0.0; n],
            augmented_force: vec![0.0; n],
            states: vec![BodyState::default(); b],
            poses: vec![Pose::new(0.0, 0.0, 0.0); b],
            velocities: vec![[0.0; 3]; b],
            potential_gradient: vec![0.0; n],
            step: vec![0.0; n],
            sizes: vec![0.0; m],
            correction: vec![0.0; m],
            zddot: vec![0.0; n],
            multipliers: vec![0.0; m],
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

    /// `J = Φ_z` into the workspace: for each constraint, one first-order dual pass per
    /// coordinate of the bodies it touches; then the velocity rows `A = ∂(A ż)/∂ż`, one dual
    /// pass per coordinate of their body. `J`'s cost grows with its nonzeros, not with `n m`.
    pub(crate) fn jacobian(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64]) {
        ws.prepared = None;
        let (sparsity, h) = (&*self.sparsity, self.holonomic);
        let values = &mut ws.kkt.jacobian;
        for (d, &zi) in ws.z_dual.iter_mut().zip(z) {
            *d = Dual64::from(zi);
        }
        let t = Dual64::from(t);
        let mut row = 0;
        for (constraint, bodies) in self.constraints.iter().zip(&sparsity.constraint_bodies) {
            let rows = constraint.equations();
            let out = &mut ws.phi_dual[row..row + rows];
            for (slot, &b) in bodies.iter().enumerate() {
                for c in 0..3 {
                    ws.z_dual[3 * b + c].eps = 1.0;
                    constraint.evaluate(&ws.z_dual, t, out);
                    ws.z_dual[3 * b + c].eps = 0.0;
                    for (i, value) in out.iter().enumerate() {
                        values[sparsity.row_start[row + i] + 3 * slot + c] = value.eps;
                    }
                }
            }
            row += rows;
        }
        if self.velocity.is_empty() {
            return;
        }
        ws.zdot_dual.fill(Dual64::from(0.0));
        for (r, constraint) in self.velocity.iter().enumerate() {
            let (start, b) = (sparsity.row_start[h + r], constraint.body);
            for c in 0..3 {
                ws.zdot_dual[3 * b + c].eps = 1.0;
                values[start + c] = constraint.evaluate(&ws.z_dual, &ws.zdot_dual).eps;
                ws.zdot_dual[3 * b + c].eps = 0.0;
            }
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

    /// Fill `states` with the body poses (in the world) and velocities of `(z, ż)`.
    fn fill_states(&self, states: &mut [BodyState], z: &[f64], zdot: &[f64]) {
        for (b, state) in states.iter_mut().enumerate() {
            state.pose = [z[3 * b] + self.frame[0], z[3 * b + 1] + self.frame[1], z[3 * b + 2]];
            state.velocity.copy_from_slice(&zdot[3 * b..3 * b + 3]);
        }
    }

    /// The scene potential `V` at body states (0 without one) and, with `gradient`, `∂V/∂p_b`.
    fn scene_potential(&self, t: f64, states: &[BodyState], gradient: Option<&mut [f64]>) -> f64 {
        self.read_back.potential(t, states, gradient).0
    }

    /// The applied forces `F` into `ws.force`: gravity `(0, −m_b g, 0)`, the potential's
    /// `−∂V/∂p_b` (from [`ReadBack::potential`]), and the scene's non-conservative forces.
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
            self.fill_states(&mut ws.states, z, zdot);
            self.scene_potential(t, &ws.states, Some(&mut ws.potential_gradient));
            if !ws.potential_gradient.iter().all(|g| g.is_finite()) {
                return Err(Error::NonFinite { stage: Stage::Potential, t, q: z.to_vec() });
            }
            for (f, g) in ws.force.iter_mut().zip(&ws.potential_gradient) {
                *f -= g;
            }
        }
        // A joint graph's force elements.
        if let Some(graph) = &self.graph {
            fill_poses(&mut ws.poses, z);
            for (v, w) in ws.velocities.iter_mut().zip(zdot.chunks_exact(3)) {
                *v = [w[0], w[1], w[2]];
            }
            graph.body_wrenches(t, &ws.poses, &ws.velocities, &mut ws.force);
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

    /// `J` and the factored blocks of `M̃` at `(t, z)` in the workspace, unless they are there
    /// already (the last stage of an accepted step is where its projection starts, and the
    /// projected state is where the integrator restarts).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `J`; [`Error::SingularMassMatrix`] naming a
    /// coordinate that moves no mass and that no constraint fixes.
    fn prepare(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64]) -> Result<(), Error> {
        if ws.prepared == Some(t) && ws.prepared_z == z {
            return Ok(());
        }
        self.jacobian(ws, t, z);
        if !ws.kkt.jacobian.iter().all(|v| v.is_finite()) {
            return Err(Error::NonFinite { stage: Stage::Kinematics, t, q: z.to_vec() });
        }
        ws.kkt.factor_mass(&self.sparsity, &self.mass).map_err(|(j, pivot)| Error::SingularMassMatrix {
            t,
            q: z.to_vec(),
            coordinate: format!("{} (moves no mass and no constraint fixes it)", self.coordinates[j].name),
            pivot,
        })?;
        ws.prepared = Some(t);
        ws.prepared_z.copy_from_slice(z);
        Ok(())
    }

    /// Factor `S` over the first `rows` rows at the prepared `(t, z)`.
    fn factor_schur(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64], rows: usize) -> Result<(), Error> {
        ws.kkt.factor_schur(&self.sparsity, &self.mass, rows).map_err(|()| Error::NonFinite {
            stage: Stage::Constraints,
            t,
            q: z.to_vec(),
        })
    }

    /// Solve the multiplier equations with `J` (prepared), `γ` and `F` in `ws`: `z̈` into
    /// `ws.zddot`, `λ` into `ws.multipliers` ([`schur`]).
    ///
    /// # Errors
    /// [`Error::InconsistentConstraints`] naming the rows whose residual after refinement
    /// exceeds [`CONSISTENT`] of the largest term of `b`; [`Error::NonFinite`] when `S` cannot
    /// be factored.
    fn solve(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64]) -> Result<(), Error> {
        let sparsity = &*self.sparsity;
        // F̃ = F − Σ_R w_i γ_i J_iᵀ and the unconstrained accelerations M̃⁻¹ F̃.
        ws.augmented_force.copy_from_slice(&ws.force);
        ws.kkt.augment_force(sparsity, &ws.convective, &mut ws.augmented_force);
        ws.step.copy_from_slice(&ws.augmented_force);
        ws.kkt.solve_mass(sparsity, &self.mass, &mut ws.step);
        // b = J M̃⁻¹ F̃ + γ, and the size of its terms.
        ws.kkt.product(sparsity, &ws.step, &mut ws.multipliers, Some(&mut ws.sizes));
        for ((b, size), gamma) in ws.multipliers.iter_mut().zip(ws.sizes.iter_mut()).zip(&ws.convective) {
            *b += gamma;
            *size += gamma.abs();
        }
        // S λ = b, shifted and refined.
        self.factor_schur(ws, t, z, self.m())?;
        ws.kkt.solve_schur(sparsity, &mut ws.multipliers);
        self.check_consistent(ws, t, z)?;
        // z̈ = M̃⁻¹ (F̃ − Jᵀ λ).
        ws.kkt.transpose_product(sparsity, &ws.multipliers, &mut ws.zddot);
        for (a, f) in ws.zddot.iter_mut().zip(&ws.augmented_force) {
            *a = f - *a;
        }
        ws.kkt.solve_mass(sparsity, &self.mass, &mut ws.zddot);
        Ok(())
    }

    /// The rows of `S λ = b` (solved; the sizes of `b`'s terms in `ws.sizes`) hold together:
    /// every scaled residual within [`CONSISTENT`] of the largest scaled term.
    ///
    /// # Errors
    /// [`Error::InconsistentConstraints`] naming the rows beyond it.
    fn check_consistent(&self, ws: &CartesianWorkspace, t: f64, z: &[f64]) -> Result<(), Error> {
        let work = ws.kkt.work(self.m());
        let largest = ws.sizes.iter().zip(&work.scale).fold(0.0_f64, |w, (size, s)| w.max(size * s));
        let beyond = |i: usize| work.residual[i].abs() > CONSISTENT * largest;

        if !(0..self.m()).any(beyond) {
            return Ok(());
        }
        let worst = (0..self.m()).fold(0.0_f64, |w, i| w.max(work.residual[i].abs() / work.scale[i]));

        Err(Error::InconsistentConstraints {
            t,
            q: z.to_vec(),
            constraints: (0..self.m()).filter(|&i| beyond(i)).map(|i| self.equation_names[i].clone()).collect(),
            residual: worst,
        })
    }

    /// Everything at `(t, z, ż)`: `J`, `γ`, `Φ̇`, `F`, then `z̈` and `λ` (into `ws`).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite state, potential or result;
    /// [`Error::SingularMassMatrix`] for a coordinate that moves no mass and that no constraint
    /// fixes; [`Error::InconsistentConstraints`] for constraint rows that cannot hold together.
    pub(crate) fn evaluate(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64], zdot: &[f64]) -> Result<(), Error> {
        debug_assert!(z.len() == self.n() && zdot.len() == self.n(), "z and ż have 3B entries");
        if !(t.is_finite() && z.iter().chain(zdot).all(|v| v.is_finite())) {
            return Err(Error::NonFinite { stage: Stage::State, t, q: z.to_vec() });
        }
        self.prepare(ws, t, z)?;
        self.convective(ws, t, z, zdot);
        if !ws.convective.iter().all(|v| v.is_finite()) {
            return Err(Error::NonFinite { stage: Stage::Kinematics, t, q: z.to_vec() });
        }
        self.applied_forces(ws, t, z, zdot)?;
        self.solve(ws, t, z)
    }

    /// The constraint forces `−Jᵀλ` (n) of the last [`evaluate`](Self::evaluate) into `out`.
    pub(crate) fn constraint_forces(&self, ws: &CartesianWorkspace, out: &mut [f64]) {
        ws.kkt.transpose_product(&self.sparsity, &ws.multipliers, out);
        for f in out.iter_mut() {
            *f = -*f;
        }
    }

    /// Check that the equations at `z` can be solved: every coordinate without mass is fixed by
    /// the constraints (the blocks of `M̃` are positive definite to a relative pivot of
    /// [`schur::PIVOT_RTOL`]). A rank-deficient `J` is not an error: the solve goes through it.
    /// Leaves `J` at `z` in `ws`.
    ///
    /// # Errors
    /// [`Error::SingularMassMatrix`] naming the coordinate (moves no mass and is fixed by no
    /// constraint); [`Error::NonFinite`] for a non-finite `J`.
    pub(crate) fn check_well_posed(&self, ws: &mut CartesianWorkspace, t: f64, z: &[f64]) -> Result<(), Error> {
        self.prepare(ws, t, z)
    }

    /// Project `(z, ż)` at `t` onto the constraint manifold, in the metric of the masses
    /// (the smallest change of kinetic energy; independent of units and of the world's
    /// origin): positions by Gauss–Newton `z ← z − M̃⁻¹ J_hᵀ S_hh⁻¹ Φ` on the holonomic rows
    /// until every `|Φ_i| ≤ PROJECTION_RTOL · size_i`
    /// ([`equation_sizes`](KktWorkspace::equation_sizes)) or an iteration no longer halves the largest `|Φ_i| / size_i` (round-off); then velocities in one exact step
    /// `ż ← ż − M̃⁻¹ Jᵀ S⁻¹ (J ż + Φ_t)` (`Φ̇` is linear in `ż`). Leaves `J` at the projected
    /// `z` in `ws`.
    ///
    /// # Errors
    /// [`Error::Diverged`] when the positions cannot be projected (a violation above
    /// [`PROJECTION_ACCEPT`] of an equation's size remains); [`Error::SingularMassMatrix`] for
    /// a coordinate without mass that no constraint fixes.
    pub(crate) fn project(
        &self,
        ws: &mut CartesianWorkspace,
        t: f64,
        z: &mut [f64],
        zdot: &mut [f64],
    ) -> Result<(), Error> {
        let (sparsity, m, h) = (&*self.sparsity, self.m(), self.holonomic);
        // Positions: Gauss–Newton on Φ(z, t) = 0 (the holonomic rows of J).
        if h > 0 {
            let (mut violation, mut previous) = (f64::INFINITY, f64::INFINITY);
            for iteration in 0..=PROJECTION_ITERATIONS {
                self.constraint_values(t, z, &mut ws.phi);
                self.prepare(ws, t, z)?;
                ws.kkt.equation_sizes(sparsity, z, &mut ws.sizes[..h]);
                let (phi, sizes) = (&ws.phi, &ws.sizes[..h]);
                if phi.iter().zip(sizes).all(|(v, size)| v.abs() <= PROJECTION_RTOL * size) {
                    violation = 0.0;
                    break;
                }
                violation = phi.iter().zip(sizes).fold(0.0_f64, |w, (v, size)| w.max(v.abs() / size));
                if violation.is_nan()
                    || violation > PROJECTION_PROGRESS * previous
                    || iteration == PROJECTION_ITERATIONS
                {
                    break;
                }
                previous = violation;
                // Δz = M̃⁻¹ J_hᵀ S_hh⁻¹ Φ: the mass-weighted least change that cancels Φ to first order.
                self.factor_schur(ws, t, z, h)?;
                ws.correction[..h].copy_from_slice(&ws.phi);
                ws.kkt.solve_schur(sparsity, &mut ws.correction[..h]);
                ws.kkt.transpose_product(sparsity, &ws.correction[..h], &mut ws.step);
                ws.kkt.solve_mass(sparsity, &self.mass, &mut ws.step);
                for (zi, d) in z.iter_mut().zip(&ws.step) {
                    *zi -= d;
                }
            }
            if violation.is_nan() || violation > PROJECTION_ACCEPT {
                return Err(Error::Diverged {
                    t,
                    step: 0,
                    quantity: format!(
                        "constraint violation {violation:e} (relative to the equations' sizes) after projection onto Φ = 0"
                    ),
                });
            }
        }
        // Velocities: ż ← ż − M̃⁻¹ Jᵀ S⁻¹ Φ̇, exact in one step.
        self.prepare(ws, t, z)?;
        self.constraint_rate(ws, t, z, zdot);
        self.factor_schur(ws, t, z, m)?;
        ws.correction.copy_from_slice(&ws.rate);
        ws.kkt.solve_schur(sparsity, &mut ws.correction);
        ws.kkt.transpose_product(sparsity, &ws.correction, &mut ws.step);
        ws.kkt.solve_mass(sparsity, &self.mass, &mut ws.step);
        for (v, d) in zdot.iter_mut().zip(&ws.step) {
            *v -= d;
        }
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
            energy += body.mass * self.gravity * (z[3 * b + 1] + self.frame[1]);
        }
        if self.has_potential {
            self.fill_states(&mut ws.states, z, zdot);
            energy += self.scene_potential(t, &ws.states, None);
        }
        if let Some(graph) = &self.graph {
            fill_poses(&mut ws.poses, z);
            energy += graph.force_potential(&ws.poses);
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

/// The body poses of `z` into `poses` (B).
fn fill_poses(poses: &mut [Pose<f64>], z: &[f64]) {
    for (pose, p) in poses.iter_mut().zip(z.chunks_exact(3)) {
        *pose = Pose::new(p[0], p[1], p[2]);
    }
}

/// `graph` seen from a frame whose origin is at `origin`: the ground's points (joint anchors on
/// the ground, ends of springs and dampers, points of application) move by `−origin`.
fn moved_graph(graph: &JointGraph, origin: [f64; 2]) -> JointGraph {
    let mut graph = graph.clone();
    let shift = |point: &mut [f64; 2]| *point = [point[0] - origin[0], point[1] - origin[1]];
    for joint in &mut graph.joints {
        if joint.parent == GROUND {
            shift(&mut joint.parent_anchor);
        }
        if joint.child == GROUND {
            shift(&mut joint.child_anchor);
        }
    }
    for force in &mut graph.forces {
        let points = match force {
            ForceElement::Spring { a, b, .. } | ForceElement::Damper { a, b, .. } => vec![a, b],
            ForceElement::Force { at, .. } => vec![at],
            _ => Vec::new(),
        };
        for point in points.into_iter().filter(|p| p.body == GROUND) {
            shift(&mut point.at);
        }
    }
    graph
}
