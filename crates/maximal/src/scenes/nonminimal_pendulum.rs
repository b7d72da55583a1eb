//! The Cartesian pendulum in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Anchor, Constraint, pin};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::NonminimalPendulum;

impl MaximalScene for NonminimalPendulum {
    /// The bob's position is the coordinates.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![z[0][0], z[0][1]]
    }

    /// The rod from the origin to the bob: the rod end `(0, l)` in the bob's frame (which turns
    /// with the rod) is pinned to the origin — two equations for the bob's three pose
    /// coordinates, leaving the reduced model's `2 − 1` degrees of freedom.
    fn constraints(&self, _names: &[String]) -> Vec<Constraint> {
        vec![pin(Anchor::on(0, 0.0, self.length), Anchor::ORIGIN, "rod pinned at the origin".into())]
    }

    /// Impulse joints: a revolute joint would freeze the rotation of the point bob (no inertia)
    /// and the scene has no bob inertia to give it, so the rod is a rope from the origin to the
    /// bob's centre, exact while it is in tension (as the driven pendulum's). Multibody: a
    /// revolute joint at the origin with the bob's anchor at `(0, l)` in its frame, as the
    /// pendulum scenes.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (ground, bob) = (draft.ground(), draft.reduced(0));
        match draft.mode {
            JointMode::Impulse => {
                draft.rope(ground, bob, self.length);
            }
            JointMode::Multibody => {
                draft.revolute(ground, bob, [0.0, 0.0], [0.0, self.length]);
            }
        }
    }
}
