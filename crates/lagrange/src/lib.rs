//! # lagrange — exact Lagrangian equations of motion for planar mechanisms
//!
//! You choose generalized coordinates `q`, write where every body is as a function of them,
//! `p_b(q, t) = (x_b, y_b, φ_b)`, and name masses `m_b`, inertias `I_b`, an optional potential
//! `V`, optional non-conservative forces `Q` and optional forces applied at points of bodies
//! ([`Mechanism::applied_forces`]). The engine forms
//! `T = Σ_b ½ m_b (ẋ_b² + ẏ_b²) + ½ I_b φ̇_b²`, `L = T − V` and solves Lagrange's equations
//! `d/dt ∂L/∂q̇ − ∂L/∂q = Q` exactly — by automatic differentiation (num-dual), with no finite
//! differences and no hand-derived formulas — in the form
//!
//! ```text
//! M(q, t) q̈ = Σ_b J_bᵀ (F_b − D_b γ_b) − ∂V/∂q + Q,     M = Σ_b J_bᵀ D_b J_b,
//! ```
//!
//! where `J_b = ∂p_b/∂q`, `D_b = diag(m_b, m_b, I_b)`, `γ_b = p̈_b − J_b q̈` (the convective
//! acceleration) and `F_b = (0, −m_b g, 0)`.
//!
//! A second path takes a raw Lagrangian `L(q, q̇, t)` ([`Lagrangian`], [`RawModel`]) for
//! velocity-dependent potentials, and solves `∂²L/∂q̇² q̈ = ∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t + Q`
//! (example below); the same functions evaluate both.
//!
//! # The short form: a double pendulum
//!
//! The data — coordinates, bodies, gravity — is a plain value, a [`Description`]; only the
//! physics is code: the poses, in a [`Mechanism`] implementation that holds the description.
//!
//! ```
//! use lagrange::{Description, Mechanism, Model, Pose, Scalar, accelerations};
//!
//! struct DoublePendulum { description: Description, l1: f64, l2: f64 }
//!
//! impl Mechanism for DoublePendulum {
//!     fn description(&self) -> &Description { &self.description }
//!     fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
//!         let (x1, y1) = (q[0].sin() * self.l1, -q[0].cos() * self.l1);
//!         world_from_body[0] = Pose::point(x1, y1);
//!         world_from_body[1] = Pose::point(x1 + q[1].sin() * self.l2, y1 - q[1].cos() * self.l2);
//!     }
//! }
//!
//! let (m1, m2, l1, l2, g) = (1.0, 2.0, 1.0, 0.5, 9.81);
//! let description = Description::new().angle("θ1").angle("θ2").point("bob 1", m1).point("bob 2", m2).gravity(g);
//! let model = Model::new(DoublePendulum { description, l1, l2 })?;
//! let mut ws = model.workspace();
//! let (q, qdot) = ([0.4_f64, -0.3], [0.0_f64, 0.0]);
//! let qddot = accelerations(&model, &mut ws, 0.0, &q, &qdot)?;
//!
//! // At rest: θ̈1 = −g ((2 m1 + m2) sinθ1 + m2 sin(θ1 − 2θ2)) / (l1 (2 m1 + m2 − m2 cos 2(θ1 − θ2))).
//! let den = 2.0 * m1 + m2 - m2 * (2.0 * (q[0] - q[1])).cos();
//! let expected = -g * ((2.0 * m1 + m2) * q[0].sin() + m2 * (q[0] - 2.0 * q[1]).sin()) / (l1 * den);
//! approx::assert_relative_eq!(qddot[0], expected, max_relative = 1e-14);
//! # Ok::<(), lagrange::Error>(())
//! ```
//!
//! # Example: the pendulum on a movable support (docs/scenes.md#cart_pendulum)
//!
//! ```
//! use lagrange::{Body, Coordinate, Description, Mechanism, Model, Pose, Scalar, accelerations};
//!
//! /// Cart of mass M on a rail, bob of mass m on a rod of length r; q = (X, θ).
//! struct CartPendulum { description: Description, r: f64 }
//!
//! impl Mechanism for CartPendulum {
//!     fn description(&self) -> &Description { &self.description }
//!     fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
//!         let (x, theta) = (q[0], q[1]);
//!         world_from_body[0] = Pose::point(x, S::zero());
//!         world_from_body[1] = Pose::point(x + theta.sin() * self.r, -theta.cos() * self.r);
//!     }
//! }
//!
//! let (cart_mass, bob_mass, r) = (2.0, 1.0, 1.5);
//! // The description as a struct literal (the double pendulum above chains its methods).
//! let description = Description {
//!     coordinates: vec![Coordinate::length("X"), Coordinate::angle("θ")],
//!     bodies: vec![Body::point("cart", cart_mass), Body::point("bob", bob_mass)],
//!     gravity: 9.81,
//!     ..Description::default()
//! };
//! let model = Model::new(CartPendulum { description, r })?;
//! let mut ws = model.workspace();
//! let (q, qdot) = ([0.0_f64, 0.3], [0.0_f64, 0.5]);
//! let qddot = accelerations(&model, &mut ws, 0.0, &q, &qdot)?;
//!
//! // The closed form (docs/scenes.md#cart_pendulum): Ẍ = m sinθ (r θ̇² + g cosθ) / (M + m sin²θ).
//! let (s, c) = q[1].sin_cos();
//! let expected = bob_mass * s * (r * qdot[1] * qdot[1] + 9.81 * c) / (cart_mass + bob_mass * s * s);
//! approx::assert_relative_eq!(qddot[0], expected, max_relative = 1e-14);
//! # Ok::<(), lagrange::Error>(())
//! ```
//!
//! # Example: a rheonomic mechanism (poses that depend on time)
//!
//! The time `t` is a scalar like the coordinates: the engine differentiates the poses through
//! it, so `∂p/∂t` enters the velocities, the convective term and the energy function. Use `t`
//! itself in the formulas; `t.re()` would make it a constant and silently drop `∂p/∂t`
//! ([`Model::new`] compares the exact derivatives with finite differences at probe states and
//! returns [`Error::LostDerivative`] when that happens).
//!
//! ```
//! use lagrange::{Description, Mechanism, Model, Pose, Scalar, accelerations};
//!
//! /// A pendulum (bob on a rod of length r) whose pivot is driven, x_p = A sin(ω t); q = (θ).
//! struct Driven { description: Description, r: f64, a: f64, omega: f64 }
//!
//! impl Mechanism for Driven {
//!     fn description(&self) -> &Description { &self.description }
//!     fn poses<S: Scalar>(&self, t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
//!         let pivot = (t * self.omega).sin() * self.a;
//!         world_from_body[0] = Pose::point(pivot + q[0].sin() * self.r, -q[0].cos() * self.r);
//!     }
//! }
//!
//! let (r, a, omega) = (1.2, 0.1, 3.0);
//! let description = Description::new().angle("θ").point("bob", 0.5).gravity(9.81);
//! let model = Model::new(Driven { description, r, a, omega })?;
//! let mut ws = model.workspace();
//! let (t, theta) = (0.4_f64, 0.3_f64);
//! let qddot = accelerations(&model, &mut ws, t, &[theta], &[0.0])?;
//!
//! // r θ̈ = −g sinθ − ẍ_p cosθ, with ẍ_p = −A ω² sin(ω t).
//! let expected = (-9.81 * theta.sin() + a * omega * omega * (omega * t).sin() * theta.cos()) / r;
//! approx::assert_relative_eq!(qddot[0], expected, max_relative = 1e-14);
//! # Ok::<(), lagrange::Error>(())
//! ```
//!
//! # Example: a raw Lagrangian (a charge in a magnetic field)
//!
//! A velocity-dependent potential is no force on a body: write `L` itself ([`Lagrangian`]) and
//! wrap it in a [`RawModel`], which the same functions evaluate. [`RawModel::new`] checks `L`
//! at probe states as [`Model::new`] checks poses: finite, no derivative lost to `.re()`, and
//! `∂²L/∂q̇²` positive definite.
//!
//! ```
//! use lagrange::{Coordinate, Lagrangian, RawModel, Scalar, accelerations, momenta};
//!
//! /// Mass m, charge e, field B along z: L = ½ m |v|² + (e B / 2)(x ẏ − y ẋ); q = (x, y).
//! struct Charge { coordinates: [Coordinate; 2], m: f64, e_b: f64 }
//!
//! impl Lagrangian for Charge {
//!     fn coordinates(&self) -> &[Coordinate] { &self.coordinates }
//!     fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], qdot: &[S]) -> S {
//!         let (x, y, vx, vy) = (q[0], q[1], qdot[0], qdot[1]);
//!         (vx * vx + vy * vy) * (0.5 * self.m) + (x * vy - y * vx) * (0.5 * self.e_b)
//!     }
//! }
//!
//! let (m, e_b) = (2.0, 3.0);
//! let coordinates = [Coordinate::length("x"), Coordinate::length("y")];
//! let raw = RawModel::new(Charge { coordinates, m, e_b })?;
//! let mut ws = raw.workspace();
//! let (q, qdot) = ([0.3_f64, -0.2], [0.7_f64, 1.1]);
//! let qddot = accelerations(&raw, &mut ws, 0.0, &q, &qdot)?.to_vec();
//!
//! // The Lorentz force: m ẍ = e B ẏ, m ÿ = −e B ẋ; the canonical momentum p = m v + e A.
//! approx::assert_relative_eq!(qddot[0], e_b * qdot[1] / m, max_relative = 1e-14);
//! approx::assert_relative_eq!(qddot[1], -e_b * qdot[0] / m, max_relative = 1e-14);
//! let p = momenta(&raw, &mut ws, 0.0, &q, &qdot)?;
//! approx::assert_relative_eq!(p[0], m * qdot[0] - 0.5 * e_b * q[1], max_relative = 1e-14);
//! # Ok::<(), lagrange::Error>(())
//! ```
//!
//! # Constraints among the coordinates: closed loops and rolling
//!
//! Coordinates may be related by holonomic constraints `Φ(t, q) = 0`
//! (named in [`Description::constraints`], written by [`Mechanism::constraints`]: a four-bar's
//! loop, a bob on a circle) and by velocity constraints `A(t, q) q̇ + b(t, q) = 0`
//! ([`Description::velocity_constraints`], [`Mechanism::velocity_constraint`]: a knife edge,
//! rolling). The engine then solves `M q̈ + Gᵀ λ = f`, `G q̈ = −γ` with `G = [Φ_q; A]` and `γ` the
//! constraints' convective term, by the Schur complement on the factor of `M`;
//! [`constraint_multipliers`] gives `λ` (`−Gᵀ λ` is the generalized constraint force), [`assemble`]
//! makes a consistent state from an approximate one, and every integrator keeps a run on the
//! constraints (docs/method.md#constraints).
//!
//! ```
//! use lagrange::{Description, Mechanism, Model, Pose, Scalar, State, accelerations, assemble, constraint_multipliers};
//!
//! /// A bob at (x, y) held on the circle x² + y² = l² (a pendulum in Cartesian coordinates).
//! struct Bob { description: Description, l: f64 }
//!
//! impl Mechanism for Bob {
//!     fn description(&self) -> &Description { &self.description }
//!     fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
//!         world_from_body[0] = Pose::point(q[0], q[1]);
//!     }
//!     fn constraints<S: Scalar>(&self, _t: S, q: &[S], phi: &mut [S]) {
//!         phi[0] = q[0] * q[0] + q[1] * q[1] - self.l * self.l;
//!     }
//! }
//!
//! let (m, l, g) = (1.0, 2.0, 9.81);
//! let description = Description::new().length("x").length("y").point("bob", m).gravity(g).constraint("on the circle");
//! let model = Model::new(Bob { description, l })?;
//! // A rough start, moved onto the circle with x held.
//! let state = assemble(&model, &State::new(0.0, [1.0, -1.5], [0.5, 0.0]), &[true, false])?;
//! let theta = state.q[0].atan2(-state.q[1]);
//! approx::assert_relative_eq!(state.q[1], -(l * l - 1.0_f64).sqrt(), max_relative = 1e-14);
//!
//! let mut ws = model.workspace();
//! let qddot = accelerations(&model, &mut ws, 0.0, &state.q, &state.qdot)?.to_vec();
//! // The pendulum in its angle: θ̈ = −(g/l) sinθ, and ẍ = l (θ̈ cosθ − θ̇² sinθ).
//! let theta_dot = (state.q[0] * state.qdot[1] - state.q[1] * state.qdot[0]) / (l * l);
//! let theta_ddot = -g / l * theta.sin();
//! approx::assert_relative_eq!(qddot[0], l * (theta_ddot * theta.cos() - theta_dot * theta_dot * theta.sin()), max_relative = 1e-12);
//! // λ is the rod's tension over 2l (Φ_q = 2 (x, y)): T = m (g cosθ + l θ̇²).
//! let lambda = constraint_multipliers(&model, &mut ws, 0.0, &state.q, &state.qdot)?[0];
//! approx::assert_relative_eq!(2.0 * l * lambda, m * (g * theta.cos() + l * theta_dot * theta_dot), max_relative = 1e-12);
//! # Ok::<(), lagrange::Error>(())
//! ```
//!
//! # Constants in generic code
//!
//! For a generic scalar `S`, `S * f64`, `S + f64` and `S - f64` compile but `f64 * S` and
//! `f64 - S` do not: keep the scalar on the left (`x * k`, as in `t * self.omega` above) or
//! lift the constant first (`S::from(k) * x`, `S::from(k) - x`).
//!
//! # Kinematic trees: `O(n)` forward dynamics
//!
//! A mechanism whose bodies hang from each other by revolute and prismatic joints, one
//! coordinate each, can say so ([`Mechanism::tree`] returning a [`Tree`]; a [`Tree`] is also a
//! mechanism by itself). [`Model::new`] checks the tree against the mechanism's poses, and
//! [`accelerations`] then runs Featherstone's articulated-body algorithm — three `O(n)` passes
//! in planar spatial algebra — instead of assembling and factoring `M`; everything else uses the
//! pose passes as before. [`Model::new_generic`] ignores the tree, for validation.
//!
//! # Layout
//!
//! A user writes at most three traits: [`Mechanism`] (the physics of a body description, beside
//! its data, a [`Description`]) or [`Lagrangian`] (a raw `L`), and uses [`Scalar`] to write them
//! once for every number type. The rest — [`Equations`], [`Dynamics`], [`System`] — are the
//! engine's layers, implemented by the models.
//!
//! Model, state, workspace and algorithms are kept apart (as in Pinocchio and MuJoCo):
//! [`Model`] is what the user describes, validated and immutable; [`State`] is `(t, q, q̇)`;
//! [`Workspace`] holds every buffer an evaluation needs, allocated once; the algorithms are free
//! functions ([`accelerations`], [`energy_function`], [`total_energy`], [`reaction_forces`], …) and the integrators in
//! [`integrate`]. Everything is generic over the scalar ([`Scalar`]), so the engine's own
//! results can be differentiated again.
//!
//! One name per operation, for both input paths: [`accelerations`], [`mass_matrix`],
//! [`momenta`], [`energy_function`] and [`lagrangian`] take a body [`Model`] or a [`RawModel`]
//! (through the sealed trait [`Equations`]) with its workspace, which both models allocate by
//! `workspace()` for `f64` and `workspace_in::<S>()` for any scalar. The energies `T`, `V`,
//! `T + V` ([`kinetic_energy`], [`potential_energy`], [`total_energy`]) and [`reaction_forces`]
//! need bodies and take a body model only. [`Dynamics`] (the integrators' `f64` interface) and
//! [`System`] (an object-safe facade for systems picked at run time) run the same functions
//! under the same method names.

// Modules from the bottom layer up; a module uses only modules of its layer or below
// (checked by the `layering` test of `lagrange-tests`).
pub mod error;
mod linalg;
mod pose;
mod scalar;
mod seed;
mod state;

pub mod graph;
mod mechanism;
pub mod tree;

mod passes;
mod probe;

mod model;

mod eom;
mod workspace;

mod ode;

pub mod integrate;
pub mod modes;

mod system;

#[cfg(test)]
mod test_support;

/// What most programs using the engine import: `use lagrange::prelude::*;`.
///
/// A mechanism's data and physics ([`Description`], [`Mechanism`], [`Body`], [`Coordinate`],
/// [`Pose`], [`Scalar`]),
/// the validated [`Model`] and its [`State`], the evaluations ([`accelerations`],
/// [`total_energy`], [`assemble`]) and the integrators ([`simulate`], [`Method`], [`Output`],
/// [`Tolerances`]), with the [`Error`] they return.
///
/// ```
/// use lagrange::prelude::*;
///
/// struct Pendulum { description: Description }
///
/// impl Mechanism for Pendulum {
///     fn description(&self) -> &Description { &self.description }
///     fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
///         world_from_body[0] = Pose::point(q[0].sin(), -q[0].cos());
///     }
/// }
///
/// let model = Model::new(Pendulum { description: Description::new().angle("θ").point("bob", 1.0).gravity(9.81) })?;
/// let run = simulate(&model, &State::new(0.0, [0.1], [0.0]), 1.0, Method::Rk4 { dt: 1e-3 }, &Output::Ends)?;
/// assert!((run.q(1)[0] - 0.1 * 9.81_f64.sqrt().cos()).abs() < 1e-3);
/// # Ok::<(), lagrange::Error>(())
/// ```
pub mod prelude {
    pub use crate::integrate::{Method, Output, Tolerances, simulate};
    pub use crate::{
        Body, Coordinate, Description, Error, Mechanism, Model, Pose, Scalar, State, accelerations, assemble,
        total_energy,
    };
}

pub use eom::constraints::{MultiplierRank, assemble, constraint_multipliers, multiplier_rank, project};
pub use eom::energy::{kinetic_energy, potential_energy, total_energy};
pub use eom::equations::{Equations, accelerations, energy_function, lagrangian, mass_matrix, momenta};
pub use eom::point::{PointMotion, point_motion};
pub use eom::raw::{RawModel, RawWorkspace};
pub use eom::reactions::reaction_forces;
pub use error::Error;
/// Former path of [`error::Derived`].
#[deprecated(since = "0.1.0", note = "moved to lagrange::error::Derived")]
pub type Derived = error::Derived;
/// Former path of [`error::Stage`].
#[deprecated(since = "0.1.0", note = "moved to lagrange::error::Stage")]
pub type Stage = error::Stage;
pub use integrate::{Method, Output, Tolerances, Trajectory, simulate};
pub use mechanism::{
    Body, Bounds, Coordinate, CoordinateKind, Description, Lagrangian, LagrangianFunction, Loads, Mechanism, Side,
};
pub use model::Model;
pub use ode::Dynamics;
pub use pose::Pose;
pub use scalar::Scalar;
pub use state::State;
pub use system::{Buffered, System};
pub use tree::Tree;
pub use workspace::Workspace;

/// Re-exported dual-number types, for users who differentiate the engine's results.
pub use num_dual;

// The README's Rust blocks (the quickstart) run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
