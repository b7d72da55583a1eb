//! What a user writes: coordinates, bodies, and where each body is as a function of them.

use super::loads::Loads;
use super::{Bounds, Description};
use crate::pose::Pose;
use crate::scalar::Scalar;
use crate::tree::Tree;

/// What a generalized coordinate measures, for units and display.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordinateKind {
    /// A length, in metres.
    Length,
    /// An angle, in radians.
    Angle,
}

/// A named generalized coordinate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Coordinate {
    /// Name as the lecture writes it (`X`, `θ`, `x'`).
    pub name: String,
    /// Length or angle.
    pub kind: CoordinateKind,
}

impl Coordinate {
    /// A coordinate measuring a length.
    pub fn length(name: impl Into<String>) -> Self {
        Self { name: name.into(), kind: CoordinateKind::Length }
    }

    /// A coordinate measuring an angle.
    pub fn angle(name: impl Into<String>) -> Self {
        Self { name: name.into(), kind: CoordinateKind::Angle }
    }

    /// SI unit of the coordinate (`m` or `rad`).
    pub fn unit(&self) -> &'static str {
        match self.kind {
            CoordinateKind::Length => "m",
            CoordinateKind::Angle => "rad",
        }
    }
}

/// A rigid body: its mass and its rotational inertia about its centre of mass.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name, for reports and reaction forces.
    pub name: String,
    /// Mass `m_b` (kg), finite and ≥ 0.
    pub mass: f64,
    /// Moment of inertia `I_b` about the centre of mass (kg m²), finite and ≥ 0.
    /// Zero for a point mass.
    pub inertia: f64,
}

impl Body {
    /// A point mass.
    pub fn point(name: impl Into<String>, mass: f64) -> Self {
        Self { name: name.into(), mass, inertia: 0.0 }
    }

    /// A body with mass and rotational inertia about its centre of mass.
    pub fn rigid(name: impl Into<String>, mass: f64, inertia: f64) -> Self {
        Self { name: name.into(), mass, inertia }
    }
}

/// A planar mechanism in generalized coordinates, as the lecture sets it up.
///
/// The user chooses coordinates `q` and names the bodies in a [`Description`] (the data), and
/// writes each body's pose `(x_b, y_b, φ_b)` as a function of `(q, t)` **once**, generic over the
/// scalar, so that the engine can differentiate it exactly (the physics, this trait). Gravity `g` acts along −y on every body. An extra
/// potential `V(t, q, poses)` and non-conservative generalized forces `Q(t, q, q̇)` are optional.
///
/// The engine ([`Model`](crate::Model)) derives `T`, `V`, `L = T − V` and Lagrange's equations
/// `M(q, t) q̈ = Σ_b J_bᵀ (F_b − D_b γ_b) − ∂V/∂q + Q` from these functions.
pub trait Mechanism {
    /// The mechanism's data: coordinates, bodies, gravity, constraint names
    /// ([`Description`]). Build it once (e.g. in the mechanism's constructor) and return a
    /// reference to it.
    fn description(&self) -> &Description;

    /// Write `world_from_body[b]`, the pose of every body, at time `t` and coordinates `q`.
    ///
    /// Every function of the state takes its arguments in one order, time first: `(t, q)`
    /// here and in [`potential`](Self::potential), `(t, q, q̇)` in the forces and the
    /// algorithms ([`accelerations`](crate::accelerations) and the rest).
    fn poses<S: Scalar>(&self, t: S, q: &[S], world_from_body: &mut [Pose<S>]);

    /// An extra potential energy `V(t, q, poses)` beyond uniform gravity (springs, central
    /// forces), or `None` if the mechanism has none.
    ///
    /// Write the terms that act on a body through its pose (`world_from_body`), and the terms
    /// that act along coordinates (torsion springs, couplings) through `q`: the first kind is
    /// attributed to the body in [`reaction_forces`](crate::reaction_forces). Return `None` for
    /// every input or `Some` for every input: the engine asks once, at construction, and skips
    /// the potential entirely when it is `None`.
    fn potential<S: Scalar>(&self, t: S, q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        let _ = (q, world_from_body, t);
        None
    }

    /// Add the non-conservative generalized forces `Q(t, q, q̇)` (damping, drives) to `force`
    /// and return `true`; return `false` (writing nothing) if the mechanism has none. As for the
    /// potential, the answer must not depend on the inputs.
    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        let _ = (t, q, qdot, force);
        false
    }

    /// List the forces and torques applied at points of bodies (drives, drag, a push at a
    /// bob) as functions of `(t, q, q̇)` and the body poses `world_from_body`, adding each to
    /// `loads` ([`Loads::force`], [`Loads::force_at_centre`], [`Loads::torque`]), and return
    /// `true`; return `false` (writing nothing) if the mechanism has none (the default).
    ///
    /// The engine converts them to generalized forces, `Q += Σ J_pᵀ F + Σ (∂φ_b/∂q) τ`, with
    /// `J_p` the exact Jacobian of the point of application. As for the potential, the answer
    /// must not depend on the inputs: [`Model::new`](crate::Model::new) asks once, and models
    /// without applied forces skip the stage entirely. Applied forces are not reactions:
    /// [`reaction_forces`](crate::reaction_forces) subtracts them.
    ///
    /// ```
    /// use lagrange::{Description, Loads, Mechanism, Model, Pose, Scalar, accelerations};
    ///
    /// /// A pendulum (bob of mass m on a rod of length r) pushed sideways by a constant force F.
    /// struct Pushed { description: Description, r: f64, push: f64 }
    ///
    /// impl Mechanism for Pushed {
    ///     fn description(&self) -> &Description { &self.description }
    ///     fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
    ///         world_from_body[0] = Pose::point(q[0].sin() * self.r, -q[0].cos() * self.r);
    ///     }
    ///     fn applied_forces<S: Scalar>(
    ///         &self, _t: S, _q: &[S], _qdot: &[S], _world_from_body: &[Pose<S>], loads: &mut Loads<'_, S>,
    ///     ) -> bool {
    ///         loads.force_at_centre(0, [S::from(self.push), S::zero()]);
    ///         true
    ///     }
    /// }
    ///
    /// let (m, r, push, theta) = (0.5, 1.2, 2.0, 0.3_f64);
    /// let description = Description::new().angle("θ").point("bob", m).gravity(9.81);
    /// let model = Model::new(Pushed { description, r, push })?;
    /// let mut ws = model.workspace();
    /// let qddot = accelerations(&model, &mut ws, 0.0, &[theta], &[0.0])?;
    /// // m r² θ̈ = −m g r sinθ + F r cosθ.
    /// let expected = (-m * 9.81 * r * theta.sin() + push * r * theta.cos()) / (m * r * r);
    /// approx::assert_relative_eq!(qddot[0], expected, max_relative = 1e-14);
    /// # Ok::<(), lagrange::Error>(())
    /// ```
    fn applied_forces<S: Scalar>(
        &self,
        t: S,
        q: &[S],
        qdot: &[S],
        world_from_body: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        let _ = (t, q, qdot, world_from_body, loads);
        false
    }

    /// Declare the *admissible region*, where the model holds, as inequality bounds on the state
    /// `(t, q, q̇)` added to `bounds` ([`Bounds::above`], [`Bounds::at_least`],
    /// [`Bounds::at_most`], [`Bounds::below`]: a name for the bounded quantity, its value, the
    /// limit), and return `true`; return `false` (writing nothing) if the model holds everywhere
    /// (the default). A polar radius `r > 0`, every rope segment's length `≥ 0`, a block between
    /// the ends of its incline.
    ///
    /// As for the potential, the answer must not depend on the inputs:
    /// [`Model::new`](crate::Model::new) asks once, and a model without a region costs nothing.
    /// [`run`](crate::integrate::run) and [`simulate`](crate::simulate) check the initial state
    /// and the state after every accepted step of every integrator, and end the run with
    /// [`Error::Inadmissible`](crate::Error::Inadmissible) naming the quantity, the bound and
    /// the time when one fails; [`Bounds::check`] checks a single state
    /// (docs/method.md#admissible-regions).
    ///
    /// ```
    /// use lagrange::{Bounds, Description, Error, Mechanism, Method, Model, Output, Pose, Scalar, State, simulate};
    ///
    /// /// A particle in plane polar coordinates q = (r, θ), no force: the model breaks at r = 0.
    /// struct Polar { description: Description }
    ///
    /// impl Mechanism for Polar {
    ///     fn description(&self) -> &Description { &self.description }
    ///     fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
    ///         world_from_body[0] = Pose::point(q[0] * q[1].cos(), q[0] * q[1].sin());
    ///     }
    ///     fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
    ///         bounds.above("r", q[0], 0.0);
    ///         true
    ///     }
    /// }
    ///
    /// let model = Model::new(Polar { description: Description::new().length("r").angle("θ").point("particle", 1.0) })?;
    /// // Straight at the origin at 1 m/s from r = 1: steps of 0.3 s would carry it through r = 0
    /// // (at t = 1) into r < 0, where the coordinates no longer describe the particle.
    /// let initial = State::new(0.0, [1.0, 0.0], [-1.0, 0.0]);
    /// let run = simulate(&model, &initial, 2.0, Method::Rk4 { dt: 0.3 }, &Output::Ends);
    /// let Err(Error::Inadmissible { t, ref bound, value, .. }) = run else { panic!("{run:?}") };
    /// // The first step that ends outside: t = 1.2, r = −0.2.
    /// assert_eq!(bound, "r > 0");
    /// approx::assert_relative_eq!(t, 1.2, max_relative = 1e-15);
    /// approx::assert_relative_eq!(value, -0.2, max_relative = 1e-12);
    /// // A single state.
    /// assert_eq!(Bounds::check(&model, 0.0, &[0.5, 0.0], &[0.0, 0.0]), Ok(true));
    /// # Ok::<(), lagrange::Error>(())
    /// ```
    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        let _ = (t, q, qdot, bounds);
        false
    }

    /// Write the residuals `Φ(t, q)` of the holonomic constraints that the description names
    /// ([`Description::constraints`]) into `phi` (`m` entries, in that order). Generic over the scalar like [`poses`](Self::poses): the engine
    /// differentiates it exactly, `G = ∂Φ/∂q` by first-order dual passes and the convective
    /// term `γ = d²/ds² Φ(t + s, q + s q̇)` by one second-order pass. Never called when the
    /// count is 0.
    fn constraints<S: Scalar>(&self, t: S, q: &[S], phi: &mut [S]) {
        let _ = (t, q, phi);
    }

    /// Write the residuals `A(t, q) q̇ + b(t, q)` of the velocity constraints that the
    /// description names ([`Description::velocity_constraints`]) into `residual` (`k` entries). They
    /// must be linear (affine) in `q̇`, which [`Model::new`](crate::Model::new) checks at its
    /// probe states. Never called when the count is 0.
    fn velocity_constraint<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], residual: &mut [S]) {
        let _ = (t, q, qdot, residual);
    }

    /// Describe the mechanism as a planar kinematic [`Tree`] (body `i` hung from an earlier
    /// body or the ground by joint `i`, whose coordinate is `q_i`), or `None` (the default).
    ///
    /// Then [`Model::new`](crate::Model::new) checks at probe states that the tree has the
    /// mechanism's bodies and gravity and that its forward kinematics reproduce
    /// [`poses`](Self::poses) (positions, velocities and convective accelerations; the angle of
    /// a body without inertia and the position of a body without mass are not compared), and
    /// [`accelerations`](crate::accelerations) runs the articulated-body algorithm in `O(n)`
    /// instead of assembling and factoring `M`. Potentials, generalized forces and everything
    /// else keep using [`poses`](Self::poses) (so a potential's gradient still costs `n` dual
    /// passes of the poses, `O(n²)`; gravity costs nothing extra). A [`Tree`] is itself a
    /// mechanism. Construct the tree once (e.g. in the mechanism's constructor) and return a
    /// reference to it; the model keeps its own copy.
    fn tree(&self) -> Option<&Tree> {
        None
    }
}
