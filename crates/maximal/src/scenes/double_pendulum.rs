//! The double pendulum in maximal coordinates.

use super::{MaximalScene, angle_from_down};
use crate::cartesian::constraints::{Anchor, Constraint, pin};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::DoublePendulum;

impl MaximalScene for DoublePendulum {
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![angle_from_down(z[0][0], z[0][1]), angle_from_down(z[1][0] - z[0][0], z[1][1] - z[0][1])]
    }

    /// Rod 1 from the origin to bob 1: the rod end (0, l1) in bob 1's frame is pinned to the
    /// origin; rod 2's end (0, l2) in bob 2's frame is pinned to bob 1's centre. Valid for point
    /// and compound bobs (the bobs turn with their rods).
    fn constraints(&self, _names: &[String]) -> Vec<Constraint> {
        let (l1, l2) = (self.length_1, self.length_2);
        vec![
            pin(Anchor::on(0, 0.0, l1), Anchor::ORIGIN, "rod 1 pinned at the origin".into()),
            pin(Anchor::on(1, 0.0, l2), Anchor::on(0, 0.0, 0.0), "rod 2 pinned at bob 1".into()),
        ]
    }

    fn rapier_deviations(mode: JointMode) -> &'static [(&'static str, &'static str, &'static str)] {
        match mode {
            JointMode::Impulse => &[("inertia_1", "mass_1", "length_1"), ("inertia_2", "mass_2", "length_2")],
            JointMode::Multibody => &[],
        }
    }

    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (ground, bob1, bob2) = (draft.ground(), draft.reduced(0), draft.reduced(1));
        draft.revolute(ground, bob1, [0.0, 0.0], [0.0, self.length_1]);
        draft.revolute(bob1, bob2, [0.0, 0.0], [0.0, self.length_2]);
    }
}
