//! The spring pendulum in maximal coordinates: a free particle in the plane.

use super::{MaximalScene, angle_from_down};
use crate::cartesian::constraints::{Constraint, no_turning};
use crate::rapier::scenes::Draft;
use crate::sketch::{LinkKind, Sketch};
use lagrange::{Scalar, State};
use lagrange_scenes::SpringPendulum;

impl MaximalScene for SpringPendulum {
    /// Distance from the pivot and angle from the downward vertical.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![(z[0][0] * z[0][0] + z[0][1] * z[0][1]).sqrt(), angle_from_down(z[0][0], z[0][1])]
    }

    /// Only the point mass's orientation is fixed.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        vec![no_turning(0, names)]
    }

    /// θ from the downward vertical: the arm's slide axis is its local −y.
    fn rapier(&self, draft: &mut Draft, initial: &State) {
        draft.polar(initial, [0.0, -1.0]);
        draft.forces.potential = true;
    }

    /// The bob on a spring from the pivot.
    fn sketch(&self) -> Sketch {
        Sketch::particle_from_origin(Some(LinkKind::Spring))
    }
}
