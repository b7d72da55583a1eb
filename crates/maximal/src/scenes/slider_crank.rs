//! The slider-crank in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{ANGLE, Anchor, Constraint, Y, fix, pin};
use crate::cartesian::system::AppliedForce;
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::SliderCrank;

impl MaximalScene for SliderCrank {
    /// Crank and rod angles, the slider's x.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![z[0][2], z[1][2], z[2][0]]
    }

    /// Three pins and a rail (8 equations on 9 body coordinates): the crank's end `(−r/2, 0)`
    /// at the origin, the crank pin `P` to the rod's start, the rod's end to the slider; the
    /// slider on the x axis (`y = 0`) without turning.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        let (r, l) = (self.crank, self.rod);
        vec![
            pin(Anchor::on(0, -r / 2.0, 0.0), Anchor::ORIGIN, "crank at the origin".into()),
            pin(Anchor::on(0, r / 2.0, 0.0), Anchor::on(1, -l / 2.0, 0.0), "crank pin to rod".into()),
            pin(Anchor::on(1, l / 2.0, 0.0), Anchor::on(2, 0.0, 0.0), "rod to slider".into()),
            fix(2, Y, 0.0, format!("{} on the x axis (y = 0)", names[2])),
            fix(2, ANGLE, 0.0, format!("{} does not turn", names[2])),
        ]
    }

    /// The crank torque `τ`.
    fn applied_force(&self) -> AppliedForce {
        if self.torque != 0.0 { AppliedForce::Torque { body: 0, torque: self.torque } } else { AppliedForce::None }
    }

    /// Revolute joints at the origin, at `P` and at the slider, and a prismatic joint along x
    /// from the ground to the slider (docs/rapier.md#loops). Impulse joints: all four; the
    /// slider is the scene's point mass (inertia 0, which rapier's impulse solver reads as
    /// infinite: harmless, since the prismatic joint locks its rotation and the rod's pin acts at
    /// its centre). Multibody joints: the tree ground → crank → rod, ground → slider (prismatic),
    /// and the rod–slider pin as the loop-closing impulse joint. The crank torque each step.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (r, l) = (self.crank, self.rod);
        let ground = draft.ground();
        let (crank, rod, slider) = (draft.reduced(0), draft.reduced(1), draft.reduced(2));
        draft.revolute(ground, crank, [0.0, 0.0], [-r / 2.0, 0.0]);
        draft.revolute(crank, rod, [r / 2.0, 0.0], [-l / 2.0, 0.0]);
        draft.prismatic(ground, slider, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
        let closing = draft.revolute(rod, slider, [l / 2.0, 0.0], [0.0, 0.0]);
        draft.close_loop(closing);
        draft.torque(crank, self.torque);
    }
}
