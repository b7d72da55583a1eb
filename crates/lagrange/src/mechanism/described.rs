//! The short form of a mechanism: names and masses in a builder, the poses in a small trait.

use super::{Body, Bounds, Coordinate, Loads, Mechanism};
use crate::pose::Pose;
use crate::scalar::Scalar;

/// The physics of a mechanism without its bookkeeping: the poses (and, optionally, a potential,
/// generalized forces and applied forces), with the same meaning and arguments as the
/// [`Mechanism`] methods of the same names. [`Described`] adds the names, masses and gravity.
pub trait Poses {
    /// Write `world_from_body[b]`, the pose of every body, at coordinates `q` and time `t`
    /// ([`Mechanism::poses`]).
    fn poses<S: Scalar>(&self, t: S, q: &[S], world_from_body: &mut [Pose<S>]);

    /// An extra potential `V(t, q, poses)`, or `None` ([`Mechanism::potential`]).
    fn potential<S: Scalar>(&self, t: S, q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        let _ = (q, world_from_body, t);
        None
    }

    /// Add generalized forces `Q(t, q, q̇)` and return `true`, or return `false`
    /// ([`Mechanism::generalized_force`]).
    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        let _ = (t, q, qdot, force);
        false
    }

    /// List forces and torques applied at points of bodies and return `true`, or return
    /// `false` ([`Mechanism::applied_forces`]).
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

    /// Declare the admissible region in `bounds` and return `true`, or return `false`
    /// ([`Mechanism::admissible`]).
    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        let _ = (t, q, qdot, bounds);
        false
    }

    /// The number of holonomic constraints ([`Mechanism::holonomic_constraints`]); default 0.
    fn holonomic_constraints(&self) -> usize {
        0
    }

    /// The holonomic constraints' residuals ([`Mechanism::constraints`]).
    fn constraints<S: Scalar>(&self, t: S, q: &[S], phi: &mut [S]) {
        let _ = (t, q, phi);
    }

    /// The number of velocity constraints ([`Mechanism::velocity_constraints`]); default 0.
    fn velocity_constraints(&self) -> usize {
        0
    }

    /// The velocity constraints' residuals ([`Mechanism::velocity_constraint`]).
    fn velocity_constraint<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], residual: &mut [S]) {
        let _ = (t, q, qdot, residual);
    }
}

/// A [`Mechanism`] built from a [`Poses`] implementation plus names, masses and gravity:
/// coordinates and bodies are listed in the order of `q` and of the poses.
///
/// ```
/// use lagrange::{Described, Model, Pose, Poses, Scalar};
///
/// struct Pendulum { r: f64 }
///
/// impl Poses for Pendulum {
///     fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
///         world_from_body[0] = Pose::point(q[0].sin() * self.r, -q[0].cos() * self.r);
///     }
/// }
///
/// let model = Model::new(Described::new(Pendulum { r: 1.0 }).angle("θ").point("bob", 1.0).gravity(9.81))?;
/// assert_eq!((model.dof(), model.bodies().len()), (1, 1));
/// # Ok::<(), lagrange::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Described<P> {
    poses: P,
    coordinates: Vec<Coordinate>,
    bodies: Vec<Body>,
    gravity: f64,
}

impl<P> Described<P> {
    /// No coordinates, no bodies, no gravity yet.
    pub fn new(poses: P) -> Self {
        Self { poses, coordinates: Vec::new(), bodies: Vec::new(), gravity: 0.0 }
    }

    /// Add a coordinate measuring an angle ([`Coordinate::angle`]).
    pub fn angle(mut self, name: impl Into<String>) -> Self {
        self.coordinates.push(Coordinate::angle(name));
        self
    }

    /// Add a coordinate measuring a length ([`Coordinate::length`]).
    pub fn length(mut self, name: impl Into<String>) -> Self {
        self.coordinates.push(Coordinate::length(name));
        self
    }

    /// Add a point mass ([`Body::point`]).
    pub fn point(mut self, name: impl Into<String>, mass: f64) -> Self {
        self.bodies.push(Body::point(name, mass));
        self
    }

    /// Add a body with rotational inertia about its centre of mass ([`Body::rigid`]).
    pub fn rigid(mut self, name: impl Into<String>, mass: f64, inertia: f64) -> Self {
        self.bodies.push(Body::rigid(name, mass, inertia));
        self
    }

    /// Set the gravitational acceleration `g` (m/s²) along −y.
    pub fn gravity(mut self, g: f64) -> Self {
        self.gravity = g;
        self
    }

    /// The user's [`Poses`] implementation.
    pub fn poses(&self) -> &P {
        &self.poses
    }
}

impl<P: Poses> Mechanism for Described<P> {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    fn gravity(&self) -> f64 {
        self.gravity
    }

    fn poses<S: Scalar>(&self, t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        self.poses.poses(t, q, world_from_body);
    }

    fn potential<S: Scalar>(&self, t: S, q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        self.poses.potential(t, q, world_from_body)
    }

    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        self.poses.generalized_force(t, q, qdot, force)
    }

    fn applied_forces<S: Scalar>(
        &self,
        t: S,
        q: &[S],
        qdot: &[S],
        world_from_body: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        self.poses.applied_forces(t, q, qdot, world_from_body, loads)
    }

    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        self.poses.admissible(t, q, qdot, bounds)
    }

    fn holonomic_constraints(&self) -> usize {
        self.poses.holonomic_constraints()
    }

    fn constraints<S: Scalar>(&self, t: S, q: &[S], phi: &mut [S]) {
        self.poses.constraints(t, q, phi)
    }

    fn velocity_constraints(&self) -> usize {
        self.poses.velocity_constraints()
    }

    fn velocity_constraint<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], residual: &mut [S]) {
        self.poses.velocity_constraint(t, q, qdot, residual)
    }
}
