//! The charged particle in maximal coordinates: its coordinates are already Cartesian.

use super::MaximalScene;
use crate::BodyState;
use crate::cartesian::constraints::{Constraint, no_turning};
use crate::cartesian::system::AppliedForce;
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::Draft;
use crate::sketch::Sketch;
use lagrange::{Scalar, State};
use lagrange_scenes::ChargedParticle;

impl MaximalScene for ChargedParticle {
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![z[0][0], z[0][1]]
    }

    /// Only the point mass's orientation is fixed.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        vec![no_turning(0, names)]
    }

    /// The Lorentz force `e B (ẏ, −ẋ)`.
    fn applied_force(&self) -> AppliedForce {
        AppliedForce::Lorentz { charge_field: self.charge * self.field }
    }

    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        if draft.mode == JointMode::Multibody {
            // Cartesian coordinates: a massless slider along x carrying the particle along y.
            let ground = draft.ground();
            let [x, _, _] = draft.states[0].pose;
            let [vx, _, _] = draft.states[0].velocity;
            let slider = draft.massless(BodyState { pose: [x, 0.0, 0.0], velocity: [vx, 0.0, 0.0] });
            let particle = draft.reduced(0);
            draft.prismatic(ground, slider, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
            draft.prismatic(slider, particle, [0.0, 1.0], [0.0, 0.0], [0.0, 0.0]);
        } else {
            draft.reduced(0);
        }
        draft.forces.lorentz = self.charge * self.field;
    }

    /// The particle alone (the field is uniform, out of the plane).
    fn sketch(&self) -> Sketch {
        Sketch::of_bodies(&[lagrange::Body::point("particle", 1.0)])
    }
}
