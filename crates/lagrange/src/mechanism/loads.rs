//! Forces and torques applied at points of bodies, as a mechanism lists them.

use crate::pose::Pose;
use crate::scalar::Scalar;

/// Where a mechanism lists the forces and torques applied to its bodies
/// ([`Mechanism::applied_forces`](crate::Mechanism::applied_forces)).
///
/// Each call adds to the *wrench* `w_b = (F_x, F_y, τ)` of a body about its centre of mass: a
/// force `F` (world frame) at the point `r` (body frame, from the centre of mass) adds `F` and
/// the moment `d × F` with `d = R(φ_b) r`. The engine then adds `Q = Σ_b J_bᵀ w_b` — which is
/// `Σ J_pᵀ F` with `J_p = ∂x_p/∂q = ∂x_b/∂q + ∂R/∂φ r ∂φ_b/∂q` the Jacobian of the point of
/// application, and `Σ (∂φ_b/∂q) τ` for torques (docs/method.md#forces-applied-at-points-of-bodies).
///
/// A body index outside the mechanism is ignored here and reported by
/// [`Model::new`](crate::Model::new) as [`Error::InvalidParameter`](crate::Error::InvalidParameter).
#[derive(Debug)]
pub struct Loads<'a, S> {
    poses: &'a [Pose<S>],
    wrench: &'a mut [S],
    bad_body: Option<usize>,
}

impl<'a, S: Scalar> Loads<'a, S> {
    /// A sink adding to `wrench` (3B, body-major `(F_x, F_y, τ)`), for bodies at `poses`.
    pub(crate) fn new(poses: &'a [Pose<S>], wrench: &'a mut [S]) -> Self {
        Self { poses, wrench, bad_body: None }
    }

    /// The first body index outside the mechanism that a call named, if any.
    pub(crate) fn bad_body(&self) -> Option<usize> {
        self.bad_body
    }

    fn check(&mut self, body: usize) -> bool {
        let ok = body < self.poses.len();
        if !ok && self.bad_body.is_none() {
            self.bad_body = Some(body);
        }
        ok
    }

    /// The pose of body `b` (the same poses as the `world_from_body` argument).
    pub fn pose(&self, body: usize) -> Option<Pose<S>> {
        self.poses.get(body).copied()
    }

    /// A force `force = (F_x, F_y)` in the world frame applied at `point = (r_x, r_y)`, a point
    /// fixed in `body` given in the body's frame (from its centre of mass, rotated with it by
    /// the pose angle).
    pub fn force(&mut self, body: usize, point: [S; 2], force: [S; 2]) {
        if !self.check(body) {
            return;
        }
        let (s, c) = self.poses[body].angle.sin_cos();
        let dx = c * point[0] - s * point[1];
        let dy = s * point[0] + c * point[1];
        let w = &mut self.wrench[3 * body..3 * body + 3];
        w[0] += force[0];
        w[1] += force[1];
        w[2] += dx * force[1] - dy * force[0];
    }

    /// A force `(F_x, F_y)` in the world frame applied at the centre of mass of `body`.
    pub fn force_at_centre(&mut self, body: usize, force: [S; 2]) {
        if !self.check(body) {
            return;
        }
        self.wrench[3 * body] += force[0];
        self.wrench[3 * body + 1] += force[1];
    }

    /// A torque `τ` (counter-clockwise) on `body`.
    pub fn torque(&mut self, body: usize, torque: S) {
        if !self.check(body) {
            return;
        }
        self.wrench[3 * body + 2] += torque;
    }
}

/// `force = Σ_b J_bᵀ w_b` (overwritten), `J` 3B × n body-major, `w` 3B.
pub(crate) fn project<S: Scalar>(jacobian: &[S], wrench: &[S], n: usize, force: &mut [S]) {
    force.fill(S::zero());
    for (r, &w) in wrench.iter().enumerate() {
        let row = &jacobian[r * n..(r + 1) * n];
        for (f, &j) in force.iter_mut().zip(row) {
            *f += j * w;
        }
    }
}
