//! The slider-crank in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{ANGLE, Anchor, Constraint, Y, fix, pin};
use crate::cartesian::system::AppliedForce;
use crate::rapier::plan::JointMode;
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

    fn rapier_unbuildable(_mode: JointMode) -> Option<&'static str> {
        Some("the rapier construction of the closed loop is not written yet")
    }

    /// None yet ([`rapier_unbuildable`](MaximalScene::rapier_unbuildable)).
    fn rapier(&self, _draft: &mut Draft, _initial: &State) {}
}
