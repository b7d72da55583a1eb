//! Small mechanisms for the solver's own unit tests (the scenes crate has the real ones).

use crate::{Body, Coordinate, Lagrangian, Mechanism, Pose, Scalar};

/// Pendulum on a cart (lecture 27): q = (X, θ).
#[derive(Clone, Debug)]
pub(crate) struct Cart {
    pub bodies: [Body; 2],
    pub coordinates: [Coordinate; 2],
    pub r: f64,
    pub g: f64,
}

impl Cart {
    pub(crate) fn new(cart: f64, bob: f64, r: f64) -> Self {
        Self {
            bodies: [Body::point("cart", cart), Body::point("bob", bob)],
            coordinates: [Coordinate::length("X"), Coordinate::angle("θ")],
            r,
            g: 9.81,
        }
    }

    /// SYSTEMS.md §1 closed form.
    pub(crate) fn closed_form(&self, q: &[f64], v: &[f64]) -> [f64; 2] {
        let (big, m, r, g) = (self.bodies[0].mass, self.bodies[1].mass, self.r, self.g);
        let (s, c) = q[1].sin_cos();
        let den = big + m * s * s;
        [m * s * (r * v[1] * v[1] + g * c) / den, -((big + m) * g * s + m * r * v[1] * v[1] * s * c) / (r * den)]
    }
}

impl Mechanism for Cart {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn bodies(&self) -> &[Body] {
        &self.bodies
    }
    fn gravity(&self) -> f64 {
        self.g
    }
    fn poses<S: Scalar>(&self, q: &[S], _t: S, p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0], S::zero());
        p[1] = Pose::point(q[0] + q[1].sin() * self.r, -q[1].cos() * self.r);
    }
}

/// Harmonic oscillator `m ẍ = −k x − c ẋ`, potential through the pose: constant mass matrix.
#[derive(Clone, Debug)]
pub(crate) struct Spring {
    pub bodies: [Body; 1],
    pub coordinates: [Coordinate; 1],
    pub k: f64,
    pub c: f64,
}

impl Spring {
    pub(crate) fn new(m: f64, k: f64, c: f64) -> Self {
        Self { bodies: [Body::point("mass", m)], coordinates: [Coordinate::length("x")], k, c }
    }
}

impl Mechanism for Spring {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn bodies(&self) -> &[Body] {
        &self.bodies
    }
    fn poses<S: Scalar>(&self, q: &[S], _t: S, p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0], S::zero());
    }
    fn potential<S: Scalar>(&self, _q: &[S], p: &[Pose<S>], _t: S) -> Option<S> {
        Some(p[0].x * p[0].x * (0.5 * self.k))
    }
    fn generalized_force<S: Scalar>(&self, _t: S, _q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        if self.c == 0.0 {
            return false;
        }
        force[0] -= qdot[0] * self.c;
        true
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

/// A charge in a uniform magnetic field (symmetric gauge): a velocity-dependent potential.
pub(crate) struct Charge {
    pub coordinates: [Coordinate; 2],
    pub m: f64,
    pub e_b: f64,
}

impl Lagrangian for Charge {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], v: &[S]) -> S {
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m) + (q[0] * v[1] - q[1] * v[0]) * (0.5 * self.e_b)
    }
}
