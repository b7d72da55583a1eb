//! The four-bar linkage in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Anchor, Constraint, pin};
use crate::cartesian::system::AppliedForce;
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::FourBar;

impl MaximalScene for FourBar {
    /// The links' angles are the coordinates.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![z[0][2], z[1][2], z[2][2]]
    }

    /// Four pins (8 equations on 9 body coordinates): the crank's end `(−a/2, 0)` at `O2`,
    /// crank tip `A` to the coupler's start, the coupler's end `B` to the rocker's tip, the
    /// rocker's end `(−c/2, 0)` at `O4 = (d, 0)`.
    fn constraints(&self, _names: &[String]) -> Vec<Constraint> {
        let (a, b, c, d) = (self.crank, self.coupler, self.rocker, self.ground);
        vec![
            pin(Anchor::on(0, -a / 2.0, 0.0), Anchor::ORIGIN, "crank at O2".into()),
            pin(Anchor::on(0, a / 2.0, 0.0), Anchor::on(1, -b / 2.0, 0.0), "crank to coupler at A".into()),
            pin(Anchor::on(1, b / 2.0, 0.0), Anchor::on(2, c / 2.0, 0.0), "coupler to rocker at B".into()),
            pin(Anchor::on(2, -c / 2.0, 0.0), Anchor::World { x: d, y: 0.0 }, "rocker at O4".into()),
        ]
    }

    /// The crank torque `τ`.
    fn applied_force(&self) -> AppliedForce {
        if self.torque != 0.0 { AppliedForce::Torque { body: 0, torque: self.torque } } else { AppliedForce::None }
    }

    /// Revolute joints at `O2`, `A`, `O4` and `B` (docs/rapier.md#loops). Impulse joints: all
    /// four. Multibody joints: the tree ground → crank → coupler, ground → rocker, and the pin at
    /// `B` (coupler–rocker) as the loop-closing impulse joint. The crank torque each step.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (a, b, c, d) = (self.crank, self.coupler, self.rocker, self.ground);
        let ground = draft.ground();
        let (crank, coupler, rocker) = (draft.reduced(0), draft.reduced(1), draft.reduced(2));
        draft.revolute(ground, crank, [0.0, 0.0], [-a / 2.0, 0.0]);
        draft.revolute(crank, coupler, [a / 2.0, 0.0], [-b / 2.0, 0.0]);
        draft.revolute(ground, rocker, [d, 0.0], [-c / 2.0, 0.0]);
        let closing = draft.revolute(coupler, rocker, [b / 2.0, 0.0], [c / 2.0, 0.0]);
        draft.close_loop(closing);
        draft.torque(crank, self.torque);
    }
}
