//! A mechanism's data: its coordinates, bodies, gravity and the names of its constraints.

use super::{Body, Coordinate};

/// What a mechanism *is*, as a plain value: the generalized coordinates in the order of `q`, the
/// bodies in the order of the poses, gravity, the names of the constraints among the
/// coordinates, and whether its mass matrix is constant. The physics — where the bodies are,
/// potentials, forces, the constraints' residuals — is code, in the [`Mechanism`](super::Mechanism)
/// implementation that returns this value from [`description`](super::Mechanism::description).
///
/// Build it field by field or with the chained methods:
///
/// ```
/// use lagrange::{Body, Coordinate, Description};
///
/// let chained = Description::new().angle("θ1").angle("θ2").point("bob 1", 1.0).point("bob 2", 2.0).gravity(9.81);
/// let literal = Description {
///     coordinates: vec![Coordinate::angle("θ1"), Coordinate::angle("θ2")],
///     bodies: vec![Body::point("bob 1", 1.0), Body::point("bob 2", 2.0)],
///     gravity: 9.81,
///     ..Description::default()
/// };
/// assert_eq!(chained, literal);
/// assert_eq!((chained.dof(), chained.constraint_counts()), (2, (0, 0)));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Description {
    /// The generalized coordinates, in the order of `q`.
    pub coordinates: Vec<Coordinate>,
    /// The bodies, in the order in which [`Mechanism::poses`](super::Mechanism::poses) writes them.
    pub bodies: Vec<Body>,
    /// Gravitational acceleration `g` (m/s²) along −y; 0 for none.
    pub gravity: f64,
    /// The names of the holonomic constraints `Φ(t, q) = 0` among the coordinates, one per
    /// residual that [`Mechanism::constraints`](super::Mechanism::constraints) writes (closed
    /// loops, a coordinate tied to a circle). Empty: the coordinates are independent.
    pub constraints: Vec<String>,
    /// The names of the velocity constraints `A(t, q) q̇ + b(t, q) = 0`, one per residual that
    /// [`Mechanism::velocity_constraint`](super::Mechanism::velocity_constraint) writes (a knife
    /// edge, rolling).
    pub velocity_constraints: Vec<String>,
    /// Every pose is affine in `q` with constant coefficients and independent of `t` (Atwood
    /// machines, wedge, oscillator): then `M` is constant and the convective term vanishes, so
    /// the engine factors `M` once and skips the convective pass.
    /// [`Model::new`](crate::Model::new) checks the declaration at probe states.
    pub constant_mass_matrix: bool,
}

impl Description {
    /// No coordinates, no bodies, no gravity, no constraints.
    pub fn new() -> Self {
        Self::default()
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

    /// Add a holonomic constraint `Φ_i(t, q) = 0` by name (its residual is the next entry that
    /// [`Mechanism::constraints`](super::Mechanism::constraints) writes).
    pub fn constraint(mut self, name: impl Into<String>) -> Self {
        self.constraints.push(name.into());
        self
    }

    /// Add a velocity constraint by name (its residual is the next entry that
    /// [`Mechanism::velocity_constraint`](super::Mechanism::velocity_constraint) writes).
    pub fn velocity_constraint(mut self, name: impl Into<String>) -> Self {
        self.velocity_constraints.push(name.into());
        self
    }

    /// Declare the mass matrix constant ([`constant_mass_matrix`](Self::constant_mass_matrix)
    /// the field).
    pub fn with_constant_mass_matrix(mut self) -> Self {
        self.constant_mass_matrix = true;
        self
    }

    /// Number of generalized coordinates `n`.
    pub fn dof(&self) -> usize {
        self.coordinates.len()
    }

    /// The numbers `(m, k)` of holonomic and of velocity constraints.
    pub fn constraint_counts(&self) -> (usize, usize) {
        (self.constraints.len(), self.velocity_constraints.len())
    }

    /// The name of constraint `i`: holonomic constraints first (`0 ≤ i < m`), then velocity
    /// constraints.
    ///
    /// # Panics
    /// If `i` is not below `m + k`.
    pub fn constraint_name(&self, i: usize) -> &str {
        let m = self.constraints.len();
        if i < m { &self.constraints[i] } else { &self.velocity_constraints[i - m] }
    }
}
