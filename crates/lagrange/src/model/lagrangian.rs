//! The Lagrangian `T − V` that a [`Model`] builds from its bodies.

use crate::mechanism::{Bounds, Coordinate, LagrangianFunction, Mechanism};
use crate::model::Model;
use crate::pose::Pose;
use crate::scalar::Scalar;
use crate::seed;
use num_dual::Dual;

/// Scratch space for the Lagrangian of a body model: coordinates and poses as first-order duals
/// (along the motion `(q̇, 1)` for `L`, along one coordinate for the Jacobian of applied
/// forces), and, for a mechanism with applied forces only, the pose Jacobian, the poses, the
/// body wrenches and their generalized force.
#[derive(Clone, Debug)]
pub struct BodyScratch<S> {
    q: Vec<Dual<S>>,
    poses: Vec<Pose<Dual<S>>>,
    jacobian: Vec<S>,
    real_poses: Vec<Pose<S>>,
    wrench: Vec<S>,
    applied: Vec<S>,
}

impl<M: Mechanism> LagrangianFunction for Model<M> {
    type Scratch<S: Scalar> = BodyScratch<S>;

    fn coordinates(&self) -> &[Coordinate] {
        &self.mechanism.description().coordinates
    }

    fn constraint_counts(&self) -> (usize, usize) {
        self.constraint_counts
    }

    fn scratch<S: Scalar>(&self) -> BodyScratch<S> {
        let (n, b, zero) = (self.n, self.description().bodies.len(), S::zero());
        let sized = |len: usize| if self.has_applied { vec![zero; len] } else { Vec::new() };
        BodyScratch {
            q: vec![Dual::from_re(zero); n],
            poses: vec![Pose::default(); b],
            jacobian: sized(3 * b * n),
            real_poses: if self.has_applied { vec![Pose::default(); b] } else { Vec::new() },
            wrench: sized(3 * b),
            applied: sized(n),
        }
    }

    fn lagrangian_with<S: Scalar>(&self, scratch: &mut BodyScratch<S>, t: S, q: &[S], qdot: &[S]) -> S {
        // Poses and their velocities: one dual pass along (q̇, 1).
        seed::along(&mut scratch.q, q, qdot);
        let t_dual = Dual::new(t, S::one());
        self.mechanism.poses(t_dual, &scratch.q, &mut scratch.poses);
        // T − V_gravity, body by body.
        let mut lagrangian = S::zero();
        for (b, pose) in scratch.poses.iter().enumerate() {
            let (m, inertia) = (self.mass[b], self.inertia[b]);
            let speed2 = pose.x.eps * pose.x.eps + pose.y.eps * pose.y.eps;
            lagrangian += speed2 * (0.5 * m) - pose.y.re * (m * self.gravity);
            if inertia != 0.0 {
                lagrangian += pose.angle.eps * pose.angle.eps * (0.5 * inertia);
            }
        }
        // − V (its value is the real part of the dual evaluation).
        if self.has_potential
            && let Some(v) = self.mechanism.potential(t_dual, &scratch.q, &scratch.poses)
        {
            lagrangian -= v.re;
        }
        lagrangian
    }

    fn generalized_force_with<S: Scalar>(
        &self,
        scratch: &mut BodyScratch<S>,
        t: S,
        q: &[S],
        qdot: &[S],
        force: &mut [S],
    ) -> bool {
        let has_force = self.has_force && self.mechanism.generalized_force(t, q, qdot, force);
        if self.has_applied {
            let BodyScratch { q: q_dual, poses, jacobian, real_poses, wrench, applied } = scratch;
            crate::passes::applied_force(&self.mechanism, (q_dual, poses), (jacobian, real_poses, wrench), t, q, qdot);
            crate::mechanism::project(jacobian, wrench, self.n, applied);
            for (f, a) in force.iter_mut().zip(applied.iter()) {
                *f += *a;
            }
        }
        has_force || self.has_applied
    }

    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        self.has_region && self.mechanism.admissible(t, q, qdot, bounds)
    }
}
