//! The harmonic oscillator in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Constraint, Y, fix, no_turning};
use crate::cartesian::system::AppliedForce;
use crate::rapier::plan::StepForces;
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::HarmonicOscillator;

impl MaximalScene for HarmonicOscillator {
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![z[0][0]]
    }

    /// The mass slides on the x axis: y = 0 and no turning.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        vec![fix(0, Y, 0.0, "mass on the x axis (y = 0)".into()), no_turning(0, names)]
    }

    /// Linear damping `−c ẋ`.
    fn applied_force(&self) -> AppliedForce {
        if self.damping != 0.0 { AppliedForce::Damping { coefficient: self.damping } } else { AppliedForce::None }
    }

    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (ground, mass) = (draft.ground(), draft.reduced(0));
        draft.prismatic(ground, mass, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
        draft.forces = StepForces { potential: true, damping: self.damping, ..StepForces::default() };
    }
}
