//! The disc rolling down an incline in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Constraint, Frame, VelocityConstraint, X, Y, linear};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::RollingDisc;

/// Why rapier does not build the disc yet.
const NO_CONTACT_BUILD: &str = "the rapier build of the rolling disc is a contact (a ball collider on an \
     inclined cuboid with friction), which is not written yet; rapier has no rolling joint";

impl MaximalScene for RollingDisc {
    /// `s` = the centre's distance down the incline direction `(−cosα, −sinα)` from the origin;
    /// `φ` = the disc's angle.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        let (sin, cos) = self.incline.sin_cos();
        vec![-(z[0][0] * cos + z[0][1] * sin), z[0][2]]
    }

    /// The contact: the centre stays on the line through the origin parallel to the incline,
    /// `R` above its surface: `sinα x − cosα y = 0`.
    fn constraints(&self, _names: &[String]) -> Vec<Constraint> {
        let (sin, cos) = self.incline.sin_cos();
        vec![linear(&[(0, X, sin), (0, Y, -cos)], 0.0, "disc centre on the line R above the incline")]
    }

    /// Rolling without slipping: the material point of the disc at the contact,
    /// `R (sinα, −cosα)` from the centre, has no velocity along the incline `(cosα, sinα)`.
    fn velocity_constraints(&self) -> Vec<VelocityConstraint> {
        let (sin, cos) = self.incline.sin_cos();
        vec![VelocityConstraint {
            name: "rolling: the contact point does not slide".into(),
            body: 0,
            arm: ([self.radius * sin, -self.radius * cos], Frame::World),
            direction: ([cos, sin], Frame::World),
        }]
    }

    fn rapier_unbuildable(_mode: JointMode) -> Option<&'static str> {
        Some(NO_CONTACT_BUILD)
    }

    /// Not reached: [`rapier_unbuildable`](MaximalScene::rapier_unbuildable) refuses every mode.
    fn rapier(&self, _draft: &mut Draft, _initial: &State) {}
}
