//! The Chaplygin sleigh in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Constraint, Frame, VelocityConstraint};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::Draft;
use crate::sketch::{Anchor, Figure, Sketch, Slide};
use lagrange::{Scalar, State};
use lagrange_scenes::ChaplyginSleigh;

/// Why rapier cannot build the sleigh.
const NO_KNIFE_EDGE: &str = "rapier has no non-holonomic joint: its joints (impulse and multibody) lock \
     relative positions and angles, never a velocity alone, so none can say that the knife-edge point \
     moves only along the body axis (v_P · n = 0) while leaving the position free; a contact with \
     anisotropic friction cannot either, since its friction is bounded by μ N and acts through the \
     normal force of a surface the sleigh would have to be pressed on";

impl MaximalScene for ChaplyginSleigh {
    /// The body's pose is the coordinates.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        z[0].to_vec()
    }

    /// No holonomic constraint: the sleigh's three pose coordinates are the reduced ones.
    fn constraints(&self, _names: &[String]) -> Vec<Constraint> {
        Vec::new()
    }

    /// The knife edge: the point `(a, 0)` of the body frame does not move along the body's
    /// normal `(0, 1)`.
    fn velocity_constraints(&self) -> Vec<VelocityConstraint> {
        vec![VelocityConstraint {
            name: "knife edge: v_P · n = 0".into(),
            body: 0,
            arm: ([self.offset, 0.0], Frame::Body),
            direction: ([0.0, 1.0], Frame::Body),
        }]
    }

    fn rapier_unbuildable(_mode: JointMode) -> Option<&'static str> {
        Some(NO_KNIFE_EDGE)
    }

    /// Not reached: [`rapier_unbuildable`](MaximalScene::rapier_unbuildable) refuses every mode.
    fn rapier(&self, _draft: &mut Draft, _initial: &State) {}

    /// The sleigh as a bar from its centre of mass to the knife edge, and the blade along its
    /// axis there.
    fn sketch(&self) -> Sketch {
        let blade = Slide { at: Anchor::Body { body: 0, at: [self.offset, 0.0] }, axis: [1.0, 0.0] };
        let body = Figure::Link { points: vec![[0.0, 0.0], [self.offset, 0.0]] };
        Sketch { bodies: vec![body], slides: vec![blade], ..Sketch::of_bodies(&[]) }
    }
}
