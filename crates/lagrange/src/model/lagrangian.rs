//! Lagrangians as functions: the user's raw `L(q, q̇, t)`, and the one a [`Model`] builds.

use crate::{Coordinate, Mechanism, Model, Pose, Scalar};
use num_dual::Dual;

/// A system given directly by its Lagrangian `L(q, q̇, t)`, written by the user.
///
/// This is the second input path: it admits velocity-dependent potentials (a charge in a
/// magnetic field, `L = ½ m |v|² + e A(r)·v − e φ(r)`), which a body description cannot express.
/// [`RawModel`](crate::RawModel) derives `∂²L/∂q̇² q̈ = ∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t + Q` by AD.
pub trait Lagrangian {
    /// The generalized coordinates, in the order of `q`.
    fn coordinates(&self) -> &[Coordinate];

    /// The Lagrangian `L(q, q̇, t)`.
    fn lagrangian<S: Scalar>(&self, t: S, q: &[S], qdot: &[S]) -> S;

    /// Add the non-conservative generalized forces `Q(t, q, q̇)` to `force` and return `true`,
    /// or return `false` if there are none (the answer must not depend on the inputs).
    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        let _ = (t, q, qdot, force);
        false
    }
}

/// What the raw-Lagrangian path and the variational integrator need: `L` as a function that
/// can be evaluated in any scalar, with caller-owned scratch space (so that repeated
/// evaluations allocate nothing).
///
/// Implemented for every [`Lagrangian`] (no scratch) and for every [`Model`] (the Lagrangian
/// `T − V` of its bodies, with a buffer of dual poses).
pub trait LagrangianFunction {
    /// Scratch space for one evaluation in scalar `S`.
    type Scratch<S: Scalar>;

    /// The generalized coordinates.
    fn coordinates(&self) -> &[Coordinate];

    /// Allocate scratch space for evaluations in `S`.
    fn scratch<S: Scalar>(&self) -> Self::Scratch<S>;

    /// `L(q, q̇, t)`.
    fn lagrangian_with<S: Scalar>(&self, scratch: &mut Self::Scratch<S>, t: S, q: &[S], qdot: &[S]) -> S;

    /// `Q(t, q, q̇)` added to `force`; `false` if the system has none.
    fn generalized_force_with<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool;
}

impl<L: Lagrangian> LagrangianFunction for L {
    type Scratch<S: Scalar> = ();

    fn coordinates(&self) -> &[Coordinate] {
        Lagrangian::coordinates(self)
    }

    fn scratch<S: Scalar>(&self) -> Self::Scratch<S> {}

    fn lagrangian_with<S: Scalar>(&self, _: &mut (), t: S, q: &[S], qdot: &[S]) -> S {
        self.lagrangian(t, q, qdot)
    }

    fn generalized_force_with<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        self.generalized_force(t, q, qdot, force)
    }
}

/// Scratch space for the Lagrangian of a body model: coordinates and poses as first-order duals
/// along the motion `(q̇, 1)`.
#[derive(Clone, Debug)]
pub struct BodyScratch<S> {
    q: Vec<Dual<S>>,
    poses: Vec<Pose<Dual<S>>>,
}

impl<M: Mechanism> LagrangianFunction for Model<M> {
    type Scratch<S: Scalar> = BodyScratch<S>;

    fn coordinates(&self) -> &[Coordinate] {
        self.mechanism.coordinates()
    }

    fn scratch<S: Scalar>(&self) -> BodyScratch<S> {
        BodyScratch { q: vec![Dual::from_re(S::zero()); self.n], poses: vec![Pose::default(); self.bodies()] }
    }

    fn lagrangian_with<S: Scalar>(&self, scratch: &mut BodyScratch<S>, t: S, q: &[S], qdot: &[S]) -> S {
        // Poses and their velocities: one dual pass along (q̇, 1).
        for ((d, &qi), &vi) in scratch.q.iter_mut().zip(q).zip(qdot) {
            *d = Dual::new(qi, vi);
        }
        let t_dual = Dual::new(t, S::one());
        self.mechanism.poses(&scratch.q, t_dual, &mut scratch.poses);
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
            && let Some(v) = self.mechanism.potential(&scratch.q, &scratch.poses, t_dual)
        {
            lagrangian -= v.re;
        }
        lagrangian
    }

    fn generalized_force_with<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        self.has_force && self.mechanism.generalized_force(t, q, qdot, force)
    }
}
