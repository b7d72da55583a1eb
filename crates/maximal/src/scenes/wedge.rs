//! The block on a movable wedge in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Constraint, X, Y, fix, linear, no_turning};
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::Wedge;

impl MaximalScene for Wedge {
    /// Wedge at (x, 0); x' = distance of the block from the top corner along the slope
    /// direction (cos α, −sin α), the corner being at (x, L sin α).
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        let (sin, cos) = self.angle.sin_cos();
        let length = self.incline_length;
        vec![z[0][0], (z[1][0] - z[0][0]) * cos - (z[1][1] - length * sin) * sin]
    }

    /// Wedge (0) on the floor, not turning; the block (1) on the incline through the top corner
    /// (x_w, L sin α) with direction (cos α, −sin α), i.e. normal (sin α, cos α):
    /// (sin α, cos α)·(p_block − (x_w, L sin α)) = 0.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        let (sin, cos) = self.angle.sin_cos();
        let length = self.incline_length;
        vec![
            fix(0, Y, 0.0, "wedge on the floor (y = 0)".into()),
            no_turning(0, names),
            linear(&[(1, X, sin), (0, X, -sin), (1, Y, cos)], -length * sin * cos, "block on the incline"),
            no_turning(1, names),
        ]
    }

    /// The block slides down the incline from the top corner (0, L sinα) of the wedge.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (ground, wedge, block) = (draft.ground(), draft.reduced(0), draft.reduced(1));
        let (sin, cos) = self.angle.sin_cos();
        draft.prismatic(ground, wedge, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
        draft.prismatic(wedge, block, [cos, -sin], [0.0, self.incline_length * sin], [0.0, 0.0]);
    }
}
