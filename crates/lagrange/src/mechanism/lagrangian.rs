//! Lagrangians as functions: the user's raw `L(q, q̇, t)`, and what the raw path needs of one.

use super::{Bounds, Coordinate};
use crate::scalar::Scalar;

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

    /// Declare the region where `L` holds, bounding quantities of `(t, q, q̇)` in `bounds`, and
    /// return `true`; return `false` (the default: no region, no cost) if it holds everywhere.
    /// As for the generalized force, the answer must not depend on the inputs
    /// ([`Mechanism::admissible`](crate::Mechanism::admissible)).
    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        let _ = (t, q, qdot, bounds);
        false
    }
}

/// What the raw-Lagrangian path and the variational integrator need: `L` as a function that
/// can be evaluated in any scalar, with caller-owned scratch space (so that repeated
/// evaluations allocate nothing).
///
/// Implemented for every [`Lagrangian`] (no scratch) and for every [`Model`](crate::Model) (the Lagrangian
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

    /// `Q(t, q, q̇)` added to `force`, using `scratch` for any intermediate values; `false` if
    /// the system has none.
    fn generalized_force_with<S: Scalar>(
        &self,
        scratch: &mut Self::Scratch<S>,
        t: S,
        q: &[S],
        qdot: &[S],
        force: &mut [S],
    ) -> bool;

    /// Declare the admissible region at `(t, q, q̇)` in `bounds` and return `true`, or return
    /// `false` if there is none (the default); [`Bounds::check`] runs it.
    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        let _ = (t, q, qdot, bounds);
        false
    }

    /// The numbers of holonomic and velocity constraints among the coordinates that come with
    /// this Lagrangian (a body [`Model`](crate::Model)'s own); `(0, 0)` by default.
    /// [`RawModel::new`](crate::RawModel::new) refuses a Lagrangian that has any: the raw path
    /// would drop them.
    fn constraint_counts(&self) -> (usize, usize) {
        (0, 0)
    }
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

    fn generalized_force_with<S: Scalar>(&self, _: &mut (), t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        self.generalized_force(t, q, qdot, force)
    }

    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        Lagrangian::admissible(self, t, q, qdot, bounds)
    }
}
