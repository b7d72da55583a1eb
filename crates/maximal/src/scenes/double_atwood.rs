//! The double Atwood machine in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Constraint, Y, hanging, linear};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::{DOWN, Draft, NO_PULLEY_JOINT};
use lagrange::{Scalar, State};
use lagrange_scenes::DoubleAtwood;

impl MaximalScene for DoubleAtwood {
    /// Bodies m1, m2, m3, movable pulley P: x = depth of m1, x' = depth of m2 below P.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![-z[0][1], z[3][1] - z[1][1]]
    }

    /// m1 (0), m2 (1), m3 (2), movable pulley P (3), all on the vertical x = 0, not turning.
    /// Upper rope: x1 + x_P = l; lower rope: (x2 − x_P) + (x3 − x_P) = l' (depths).
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        let (l, l_lower) = (self.rope_length, self.lower_rope_length);
        let mut c: Vec<Constraint> = (0..4).flat_map(|b| hanging(b, 0.0, names)).collect();
        c.push(linear(&[(0, Y, -1.0), (3, Y, -1.0)], -l, "upper rope"));
        c.push(linear(&[(1, Y, -1.0), (2, Y, -1.0), (3, Y, 2.0)], -l_lower, "lower rope"));
        c
    }

    fn rapier_unbuildable(mode: JointMode) -> Option<&'static str> {
        (mode == JointMode::Impulse).then_some(NO_PULLEY_JOINT)
    }

    fn rapier_deviations(mode: JointMode) -> &'static [(&'static str, &'static str, &'static str)] {
        match mode {
            JointMode::Multibody => &[("lower_pulley_mass", "", "")],
            JointMode::Impulse => &[],
        }
    }

    /// Bodies m1, m2, m3, P: m1 and P on the upper rope, m2 and m3 hang from P.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let ground = draft.ground();
        let [m1, m2, m3, pulley] = [0, 1, 2, 3].map(|r| draft.reduced(r));
        let upper1 = draft.prismatic(ground, m1, DOWN, [0.0, 0.0], [0.0, 0.0]);
        let upper2 = draft.prismatic(ground, pulley, DOWN, [0.0, 0.0], [0.0, 0.0]);
        let lower2 = draft.prismatic(pulley, m2, DOWN, [0.0, 0.0], [0.0, 0.0]);
        let lower3 = draft.prismatic(pulley, m3, DOWN, [0.0, 0.0], [0.0, 0.0]);
        draft.couple(upper1, upper2, -1.0);
        draft.couple(lower2, lower3, -1.0);
    }
}
