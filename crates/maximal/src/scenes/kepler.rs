//! The Kepler problem in maximal coordinates: a free particle in the plane.

use super::{MaximalScene, polar};
use crate::cartesian::constraints::{Constraint, no_turning};
use crate::rapier::scenes::Draft;
use crate::sketch::Sketch;
use lagrange::{Scalar, State};
use lagrange_scenes::Kepler;

impl MaximalScene for Kepler {
    /// Plane polar coordinates of the particle.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        polar(&z[0])
    }

    /// Only the point mass's orientation is fixed.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        vec![no_turning(0, names)]
    }

    /// Polar coordinates: an arm turning by θ, the particle sliding along it by r.
    fn rapier(&self, draft: &mut Draft, initial: &State) {
        draft.polar(initial, [1.0, 0.0]);
        draft.forces.potential = true;
    }

    /// The particle and the centre of attraction.
    fn sketch(&self) -> Sketch {
        Sketch::particle_from_origin(None)
    }
}
