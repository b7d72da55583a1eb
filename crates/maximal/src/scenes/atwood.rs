//! The Atwood machine in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{ANGLE, Constraint, X, Y, fix, hanging, linear};
use crate::rapier::plan::{JointMode, RopePulley};
use crate::rapier::scenes::{DOWN, Draft, NO_PULLEY_JOINT};
use lagrange::{Scalar, State};
use lagrange_scenes::Atwood;
use std::f64::consts::PI;

impl MaximalScene for Atwood {
    /// Depth of m1 below the axle.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![-z[0][1]]
    }

    /// m1 (0) hangs at x = −a, m2 (1) at x = +a, the pulley (2) turns about the origin.
    /// Rope: depths x1 + x2 = l − πa, i.e. −y1 − y2 − (l − πa) = 0. No slip: the pulley turns
    /// by x1/a (φ = x/a with x = −y1), i.e. a φ_pulley + y1 = 0.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        let (a, l) = (self.pulley_radius, self.rope_length);
        let mut c: Vec<Constraint> = hanging(0, -a, names).into_iter().chain(hanging(1, a, names)).collect();
        c.push(fix(2, X, 0.0, "pulley axle at x = 0".into()));
        c.push(fix(2, Y, 0.0, "pulley axle at y = 0".into()));
        c.push(linear(&[(0, Y, -1.0), (1, Y, -1.0)], -(l - PI * a), "rope over the pulley"));
        c.push(linear(&[(2, ANGLE, a), (0, Y, 1.0)], 0.0, "rope does not slip on the pulley"));
        c
    }

    fn rapier_unbuildable(mode: JointMode) -> Option<&'static str> {
        (mode == JointMode::Impulse).then_some(NO_PULLEY_JOINT)
    }

    /// Depths below the axle on vertical slides; the rope keeps x₁ + x₂ = l − πa and the pulley
    /// turns by φ = x₁/a.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (ground, m1, m2) = (draft.ground(), draft.reduced(0), draft.reduced(1));
        let a = self.pulley_radius;
        let rope1 = draft.prismatic(ground, m1, DOWN, [-a, 0.0], [0.0, 0.0]);
        let rope2 = draft.prismatic(ground, m2, DOWN, [a, 0.0], [0.0, 0.0]);
        draft.couple(rope1, rope2, -1.0);
        if self.pulley_inertia > 0.0 {
            let pulley = draft.reduced(2);
            let turn = draft.revolute(ground, pulley, [0.0, 0.0], [0.0, 0.0]);
            draft.couple(rope1, turn, 1.0 / a);
        } else {
            // A pulley link without inertia would move no mass: leave it out.
            draft.rope_pulleys.push(RopePulley { reduced: 2, source: m1, radius: a });
        }
    }
}
